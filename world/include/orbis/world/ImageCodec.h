#pragma once

#include <orbis/core/Image.h>

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace orbis::world {

/// The image formats tiles come in, told apart by their first bytes.
enum class ImageFormat { Unknown, Jpeg, Png, Webp };

/// The format of encoded bytes from their signature; Unknown when they match none.
ImageFormat detectImageFormat(std::span<const std::uint8_t> bytes) noexcept;

/// The usual file extension: "jpg", "png", "webp"; "" for Unknown.
std::string_view imageFormatExtension(ImageFormat format) noexcept;

/// The format a file extension or a TMS/MBTiles format name stands for ("jpg", "jpeg", "png",
/// "webp", any case); Unknown for anything else.
ImageFormat imageFormatFromName(std::string_view name) noexcept;

/// The most pixels a decoder allocates unless told otherwise: 2^26 (8192 x 8192; 256 MiB as RGBA).
/// A header claiming more is refused before anything is allocated.
inline constexpr std::uint64_t kMaximumDecodedPixels = std::uint64_t{1} << 26;

/// Decodes a JPEG (TurboJPEG), PNG (libspng) or WebP (libwebp) image, detected from the bytes, into
/// `desiredChannels` channels (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA; 0 keeps the file's own),
/// rows top to bottom. Safe from several threads at once. Throws orbis::Error naming
/// `nameForMessages` and what was wrong for an unknown format, truncated or corrupt data (a JPEG
/// warning such as a premature end counts as corrupt), or a header claiming more than
/// maximumPixels pixels.
Image decodeImage(std::span<const std::uint8_t> bytes, std::string_view nameForMessages, int desiredChannels = 4,
                  std::uint64_t maximumPixels = kMaximumDecodedPixels);

/// One channel of 16-bit samples (heights), rows top to bottom.
struct GreyImage16 {
    int width = 0;
    int height = 0;
    std::vector<std::uint16_t> samples; ///< native endian, width * height of them

    std::uint16_t at(int x, int y) const { return samples[static_cast<std::size_t>(y) * width + x]; }
};

/// Decodes a 16-bit greyscale PNG (as the height tiles are stored) into native-endian samples.
/// Throws orbis::Error naming `nameForMessages` for anything else (another bit depth or colour
/// type, not a PNG), for corrupt data, or for more than maximumPixels pixels.
GreyImage16 decodePng16(std::span<const std::uint8_t> bytes, std::string_view nameForMessages,
                        std::uint64_t maximumPixels = kMaximumDecodedPixels);

/// PNG of any of Image's channel counts; compressionLevel is zlib's, 0 (none) to 9 (smallest).
/// Level 1, for frames, is the fastest that compresses: the Sub filter and run-length matching
/// (about 3x faster than adaptive filtering, and smaller on rendered frames). Throws
/// orbis::Error if libspng fails.
std::vector<std::uint8_t> encodePng(const Image& image, int compressionLevel);
/// A 16-bit greyscale PNG of the samples.
std::vector<std::uint8_t> encodePng16(const GreyImage16& image, int compressionLevel);
/// Baseline JPEG, quality 1..100, 4:2:0 chroma (grey images stay grey; alpha is dropped).
std::vector<std::uint8_t> encodeJpeg(const Image& image, int quality);
/// WebP, lossy at quality 0..100, or lossless; alpha is kept (grey images become RGB).
std::vector<std::uint8_t> encodeWebp(const Image& image, int quality, bool lossless = false);
/// One of the three by format; quality is the JPEG/WebP quality or, for PNG, the zlib level.
std::vector<std::uint8_t> encodeImage(const Image& image, ImageFormat format, int quality);

} // namespace orbis::world
