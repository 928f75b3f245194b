#include "orbis/world/ImageCodec.h"

#include "orbis/world/FileAccess.h"

#include <orbis/core/Error.h>

#include <spng.h>
#include <zlib.h>
#include <turbojpeg.h>
#include <webp/decode.h>
#include <webp/encode.h>

#include <algorithm>
#include <cassert>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

namespace orbis::world {

namespace {

std::string prefix(std::string_view name)
{
    return cutForMessage(name) + ": ";
}

/// The first bytes in hex, which tell an HTML error page or a truncated download at a glance.
std::string leadingBytes(std::span<const std::uint8_t> bytes)
{
    if (bytes.empty()) {
        return "it is empty";
    }
    std::string text = "it starts with";
    const std::size_t count = std::min<std::size_t>(bytes.size(), 8);
    for (std::size_t i = 0; i < count; ++i) {
        char hex[4];
        std::snprintf(hex, sizeof hex, " %02x", bytes[i]);
        text += hex;
    }
    return text + (bytes.size() > count ? " ..." : "");
}

void checkPixelCount(std::uint64_t width, std::uint64_t height, std::uint64_t maximumPixels, std::string_view name,
                     const char* format)
{
    if (width == 0 || height == 0) {
        throw Error(prefix(name) + format + " header gives an empty image (" + std::to_string(width) + "x" +
                    std::to_string(height) + ")");
    }
    // Both sides fit 32 bits in every format here, so the product cannot overflow 64 bits.
    if (width * height > maximumPixels || width > 0x7fffffff || height > 0x7fffffff) {
        throw Error(prefix(name) + format + " header claims " + std::to_string(width) + "x" + std::to_string(height) +
                    " pixels, more than the " + std::to_string(maximumPixels) + " allowed");
    }
}

std::uint8_t luminance(const std::uint8_t* rgb)
{
    // Rec. 601 weights in 8-bit fixed point (sum 256), rounded.
    return static_cast<std::uint8_t>((77 * rgb[0] + 150 * rgb[1] + 29 * rgb[2] + 128) >> 8);
}

/// The image with `channels` channels: grey spread to RGB, RGB reduced to its luminance, alpha
/// added as opaque or dropped.
Image convertChannels(Image source, int channels)
{
    if (channels == 0 || channels == source.channels) {
        return source;
    }
    Image result(source.width, source.height, channels);
    const std::size_t count = static_cast<std::size_t>(source.width) * static_cast<std::size_t>(source.height);
    const int from = source.channels;
    for (std::size_t i = 0; i < count; ++i) {
        const std::uint8_t* s = source.pixels.data() + i * static_cast<std::size_t>(from);
        std::uint8_t* d = result.pixels.data() + i * static_cast<std::size_t>(channels);
        const bool sourceGrey = from <= 2;
        const std::uint8_t alpha = (from == 2 || from == 4) ? s[from - 1] : 255;
        if (channels <= 2) {
            d[0] = sourceGrey ? s[0] : luminance(s);
        } else {
            d[0] = s[0];
            d[1] = sourceGrey ? s[0] : s[1];
            d[2] = sourceGrey ? s[0] : s[2];
        }
        if (channels == 2 || channels == 4) {
            d[channels - 1] = alpha;
        }
    }
    return result;
}

void checkDesiredChannels(int desiredChannels, std::string_view name)
{
    if (desiredChannels < 0 || desiredChannels > 4) {
        throw Error(prefix(name) + "cannot decode into " + std::to_string(desiredChannels) + " channels (0 to 4)");
    }
}

// ---- JPEG (TurboJPEG) ----------------------------------------------------------------------------

/// One TurboJPEG handle per thread and direction: creating one costs more than decoding a small
/// tile. A handle that failed is replaced: libjpeg leaves it mid-stream after an error, and the
/// next image it reads would come out garbled.
class TurboHandle {
public:
    explicit TurboHandle(bool compress) : _compress(compress) {}
    ~TurboHandle() { reset(); }
    TurboHandle(const TurboHandle&) = delete;
    TurboHandle& operator=(const TurboHandle&) = delete;

    tjhandle get(std::string_view name)
    {
        if (!_handle) {
            _handle = _compress ? tjInitCompress() : tjInitDecompress();
        }
        if (!_handle) {
            throw Error(prefix(name) + "cannot start TurboJPEG: " + tjGetErrorStr2(nullptr));
        }
        return _handle;
    }
    /// The handle's error message; the handle is then discarded.
    std::string fail()
    {
        std::string message = tjGetErrorStr2(_handle);
        reset();
        return message;
    }

private:
    void reset() noexcept
    {
        if (_handle) {
            tjDestroy(_handle);
            _handle = nullptr;
        }
    }

    bool _compress;
    tjhandle _handle = nullptr;
};

TurboHandle& decompressor()
{
    thread_local TurboHandle handle(false);
    return handle;
}

TurboHandle& compressor()
{
    thread_local TurboHandle handle(true);
    return handle;
}

Image decodeJpeg(std::span<const std::uint8_t> bytes, std::string_view name, int desiredChannels,
                 std::uint64_t maximumPixels)
{
    TurboHandle& turbo = decompressor();
    tjhandle handle = turbo.get(name);
    int width = 0;
    int height = 0;
    int subsampling = 0;
    int colorspace = 0;
    if (tjDecompressHeader3(handle, bytes.data(), static_cast<unsigned long>(bytes.size()), &width, &height, &subsampling,
                            &colorspace) != 0) {
        throw Error(prefix(name) + "corrupt JPEG header: " + turbo.fail());
    }
    checkPixelCount(static_cast<std::uint64_t>(std::max(width, 0)), static_cast<std::uint64_t>(std::max(height, 0)),
                    maximumPixels, name, "JPEG");
    if (colorspace == TJCS_CMYK || colorspace == TJCS_YCCK) {
        throw Error(prefix(name) + "CMYK JPEGs are not supported (convert the image to RGB)");
    }
    const bool fileGrey = colorspace == TJCS_GRAY;
    const int channels = desiredChannels == 0 ? (fileGrey ? 1 : 3) : desiredChannels;
    // TurboJPEG writes grey, RGB or RGBA (alpha 255); grey + alpha is made from grey.
    const int decodeChannels = channels == 2 ? 1 : channels;
    const TJPF pixelFormat = decodeChannels == 1 ? TJPF_GRAY : decodeChannels == 3 ? TJPF_RGB : TJPF_RGBA;
    Image image(width, height, decodeChannels);
    // A warning (a premature end of data, bytes missing from a segment) still yields a picture,
    // half of it grey; for tiles that is a corrupt tile, so warnings stop the decoder. Limiting the
    // progressive scans keeps a hostile file from taking minutes.
    if (tjDecompress2(handle, bytes.data(), static_cast<unsigned long>(bytes.size()), image.pixels.data(), width, 0,
                      height, pixelFormat, TJFLAG_STOPONWARNING | TJFLAG_LIMITSCANS) != 0) {
        throw Error(prefix(name) + "corrupt JPEG: " + turbo.fail());
    }
    return convertChannels(std::move(image), channels);
}

// ---- PNG (libspng) -------------------------------------------------------------------------------

struct SpngContext {
    spng_ctx* context;
    explicit SpngContext(int flags) : context(spng_ctx_new(flags)) {}
    ~SpngContext() { spng_ctx_free(context); }
    SpngContext(const SpngContext&) = delete;
    SpngContext& operator=(const SpngContext&) = delete;
};

/// Reads the header of a PNG in memory, after setting the limits that bound what libspng allocates.
spng_ihdr readPngHeader(SpngContext& png, std::span<const std::uint8_t> bytes, std::string_view name,
                        std::uint64_t maximumPixels)
{
    if (!png.context) {
        throw Error(prefix(name) + "cannot start libspng");
    }
    // Ancillary chunks (text, ICC profiles) up to 4 MiB each, 16 MiB in all: enough for any real
    // file, and a bound on what a hostile one can make libspng keep.
    spng_set_chunk_limits(png.context, std::size_t{4} << 20, std::size_t{16} << 20);
    spng_set_png_buffer(png.context, bytes.data(), bytes.size());
    spng_ihdr header{};
    if (const int error = spng_get_ihdr(png.context, &header)) {
        throw Error(prefix(name) + "corrupt PNG header: " + spng_strerror(error));
    }
    checkPixelCount(header.width, header.height, maximumPixels, name, "PNG");
    return header;
}

Image decodePng(std::span<const std::uint8_t> bytes, std::string_view name, int desiredChannels,
                std::uint64_t maximumPixels)
{
    SpngContext png(0);
    const spng_ihdr header = readPngHeader(png, bytes, name, maximumPixels);
    spng_trns transparency{};
    const bool hasTransparency = spng_get_trns(png.context, &transparency) == 0;
    int fileChannels = 3;
    switch (header.color_type) {
    case SPNG_COLOR_TYPE_GRAYSCALE: fileChannels = hasTransparency ? 2 : 1; break;
    case SPNG_COLOR_TYPE_GRAYSCALE_ALPHA: fileChannels = 2; break;
    case SPNG_COLOR_TYPE_TRUECOLOR_ALPHA: fileChannels = 4; break;
    default: fileChannels = hasTransparency ? 4 : 3; break;
    }
    const int channels = desiredChannels == 0 ? fileChannels : desiredChannels;
    // libspng converts every PNG to RGB8 or RGBA8 (16-bit samples reduced, palettes expanded,
    // tRNS applied); grey results are made from those.
    const int decodeChannels = channels == 3 ? 3 : 4;
    const int format = decodeChannels == 3 ? SPNG_FMT_RGB8 : SPNG_FMT_RGBA8;
    Image image(static_cast<int>(header.width), static_cast<int>(header.height), decodeChannels);
    if (const int error =
            spng_decode_image(png.context, image.pixels.data(), image.pixels.size(), format, SPNG_DECODE_TRNS)) {
        throw Error(prefix(name) + "corrupt PNG: " + spng_strerror(error));
    }
    return convertChannels(std::move(image), channels);
}

/// The PNG bytes libspng made in an encoder context, copied out.
std::vector<std::uint8_t> takePngBuffer(SpngContext& png)
{
    std::size_t size = 0;
    int error = 0;
    void* buffer = spng_get_png_buffer(png.context, &size, &error);
    if (!buffer || error) {
        std::free(buffer);
        throw Error(std::string("PNG encoding failed: ") + spng_strerror(error));
    }
    const auto* begin = static_cast<const std::uint8_t*>(buffer);
    std::vector<std::uint8_t> bytes(begin, begin + size);
    std::free(buffer);
    return bytes;
}

std::vector<std::uint8_t> encodePngSamples(const void* samples, std::size_t size, int width, int height,
                                           std::uint8_t colorType, std::uint8_t bitDepth, int compressionLevel)
{
    SpngContext png(SPNG_CTX_ENCODER);
    if (!png.context) {
        throw Error("PNG encoding failed: cannot start libspng");
    }
    spng_set_option(png.context, SPNG_ENCODE_TO_BUFFER, 1);
    const int level = std::clamp(compressionLevel, 0, 9);
    spng_set_option(png.context, SPNG_IMG_COMPRESSION_LEVEL, level);
    if (level == 0) {
        // Nothing to compress: filtering would only cost time.
        spng_set_option(png.context, SPNG_FILTER_CHOICE, SPNG_FILTER_CHOICE_NONE);
    } else if (level == 1) {
        // The fast level, for frames: one filter instead of trying all five on every row, and
        // run-length matches only. A 1280x720 rendered frame: 61 ms and 704 KB here against 207 ms
        // and 767 KB with every filter at zlib level 1.
        spng_set_option(png.context, SPNG_FILTER_CHOICE, SPNG_FILTER_CHOICE_SUB);
        spng_set_option(png.context, SPNG_IMG_COMPRESSION_STRATEGY, Z_RLE);
    }
    spng_ihdr header{};
    header.width = static_cast<std::uint32_t>(width);
    header.height = static_cast<std::uint32_t>(height);
    header.bit_depth = bitDepth;
    header.color_type = colorType;
    if (int error = spng_set_ihdr(png.context, &header)) {
        throw Error(std::string("PNG encoding failed: ") + spng_strerror(error));
    }
    // SPNG_FMT_PNG: samples in the PNG's own layout, 16-bit ones in host byte order.
    if (int error = spng_encode_image(png.context, samples, size, SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE)) {
        throw Error(std::string("PNG encoding failed: ") + spng_strerror(error));
    }
    return takePngBuffer(png);
}

// ---- WebP (libwebp) ------------------------------------------------------------------------------

Image decodeWebp(std::span<const std::uint8_t> bytes, std::string_view name, int desiredChannels,
                 std::uint64_t maximumPixels)
{
    WebPBitstreamFeatures features{};
    if (const VP8StatusCode status = WebPGetFeatures(bytes.data(), bytes.size(), &features); status != VP8_STATUS_OK) {
        throw Error(prefix(name) + (status == VP8_STATUS_NOT_ENOUGH_DATA ? "truncated WebP header"
                                                                         : "corrupt WebP header (libwebp status " +
                                                                               std::to_string(status) + ")"));
    }
    checkPixelCount(static_cast<std::uint64_t>(std::max(features.width, 0)),
                    static_cast<std::uint64_t>(std::max(features.height, 0)), maximumPixels, name, "WebP");
    if (features.has_animation) {
        throw Error(prefix(name) + "animated WebP images are not supported");
    }
    const int channels = desiredChannels == 0 ? (features.has_alpha ? 4 : 3) : desiredChannels;
    const int decodeChannels = channels == 3 ? 3 : 4;
    Image image(features.width, features.height, decodeChannels);
    const int stride = features.width * decodeChannels;
    const std::uint8_t* decoded =
        decodeChannels == 3
            ? WebPDecodeRGBInto(bytes.data(), bytes.size(), image.pixels.data(), image.pixels.size(), stride)
            : WebPDecodeRGBAInto(bytes.data(), bytes.size(), image.pixels.data(), image.pixels.size(), stride);
    if (!decoded) {
        throw Error(prefix(name) + "corrupt or truncated WebP data");
    }
    return convertChannels(std::move(image), channels);
}

void checkEncodable(const Image& image)
{
    assert(image.width > 0 && image.height > 0 && image.channels >= 1 && image.channels <= 4);
    assert(image.pixels.size() ==
           static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * image.channels);
    if (image.width <= 0 || image.height <= 0 ||
        image.pixels.size() !=
            static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * image.channels) {
        throw Error("cannot encode an image of " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                    " pixels from " + std::to_string(image.pixels.size()) + " bytes");
    }
}

} // namespace

ImageFormat detectImageFormat(std::span<const std::uint8_t> bytes) noexcept
{
    auto startsWith = [&](std::initializer_list<std::uint8_t> signature, std::size_t offset = 0) {
        return bytes.size() >= offset + signature.size() && std::equal(signature.begin(), signature.end(), bytes.begin() + offset);
    };
    if (startsWith({0xFF, 0xD8, 0xFF})) {
        return ImageFormat::Jpeg;
    }
    if (startsWith({0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'})) {
        return ImageFormat::Png;
    }
    if (startsWith({'R', 'I', 'F', 'F'}) && startsWith({'W', 'E', 'B', 'P'}, 8)) {
        return ImageFormat::Webp;
    }
    return ImageFormat::Unknown;
}

std::string_view imageFormatExtension(ImageFormat format) noexcept
{
    switch (format) {
    case ImageFormat::Jpeg: return "jpg";
    case ImageFormat::Png: return "png";
    case ImageFormat::Webp: return "webp";
    case ImageFormat::Unknown: break;
    }
    return "";
}

ImageFormat imageFormatFromName(std::string_view name) noexcept
{
    if (name.size() > 16) {
        return ImageFormat::Unknown;
    }
    std::string lower(name);
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](char c) { return static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c); });
    if (lower == "jpg" || lower == "jpeg" || lower == "image/jpeg" || lower == "image/jpg") {
        return ImageFormat::Jpeg;
    }
    if (lower == "png" || lower == "image/png") {
        return ImageFormat::Png;
    }
    if (lower == "webp" || lower == "image/webp") {
        return ImageFormat::Webp;
    }
    return ImageFormat::Unknown;
}

Image decodeImage(std::span<const std::uint8_t> bytes, std::string_view nameForMessages, int desiredChannels,
                  std::uint64_t maximumPixels)
{
    checkDesiredChannels(desiredChannels, nameForMessages);
    switch (detectImageFormat(bytes)) {
    case ImageFormat::Jpeg: return decodeJpeg(bytes, nameForMessages, desiredChannels, maximumPixels);
    case ImageFormat::Png: return decodePng(bytes, nameForMessages, desiredChannels, maximumPixels);
    case ImageFormat::Webp: return decodeWebp(bytes, nameForMessages, desiredChannels, maximumPixels);
    case ImageFormat::Unknown: break;
    }
    throw Error(prefix(nameForMessages) + "not a JPEG, PNG or WebP image (" + leadingBytes(bytes) + ")");
}

GreyImage16 decodePng16(std::span<const std::uint8_t> bytes, std::string_view nameForMessages, std::uint64_t maximumPixels)
{
    if (detectImageFormat(bytes) != ImageFormat::Png) {
        throw Error(prefix(nameForMessages) + "not a PNG (" + leadingBytes(bytes) + ")");
    }
    SpngContext png(0);
    const spng_ihdr header = readPngHeader(png, bytes, nameForMessages, maximumPixels);
    if (header.color_type != SPNG_COLOR_TYPE_GRAYSCALE || header.bit_depth != 16) {
        throw Error(prefix(nameForMessages) + "expected a 16-bit greyscale PNG, found " +
                    std::to_string(header.bit_depth) + "-bit samples of colour type " +
                    std::to_string(header.color_type));
    }
    GreyImage16 image;
    image.width = static_cast<int>(header.width);
    image.height = static_cast<int>(header.height);
    image.samples.resize(static_cast<std::size_t>(header.width) * header.height);
    // SPNG_FMT_PNG keeps the file's layout and turns its big-endian samples into host order.
    if (const int error = spng_decode_image(png.context, image.samples.data(), image.samples.size() * 2, SPNG_FMT_PNG, 0)) {
        throw Error(prefix(nameForMessages) + "corrupt PNG: " + spng_strerror(error));
    }
    return image;
}

std::vector<std::uint8_t> encodePng(const Image& image, int compressionLevel)
{
    checkEncodable(image);
    static constexpr std::uint8_t kColorTypes[] = {SPNG_COLOR_TYPE_GRAYSCALE, SPNG_COLOR_TYPE_GRAYSCALE_ALPHA,
                                                   SPNG_COLOR_TYPE_TRUECOLOR, SPNG_COLOR_TYPE_TRUECOLOR_ALPHA};
    return encodePngSamples(image.pixels.data(), image.pixels.size(), image.width, image.height,
                            kColorTypes[image.channels - 1], 8, compressionLevel);
}

std::vector<std::uint8_t> encodePng16(const GreyImage16& image, int compressionLevel)
{
    assert(image.samples.size() == static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height));
    if (image.width <= 0 || image.height <= 0 ||
        image.samples.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height)) {
        throw Error("cannot encode a 16-bit image of " + std::to_string(image.width) + "x" +
                    std::to_string(image.height) + " samples from " + std::to_string(image.samples.size()));
    }
    return encodePngSamples(image.samples.data(), image.samples.size() * 2, image.width, image.height,
                            SPNG_COLOR_TYPE_GRAYSCALE, 16, compressionLevel);
}

std::vector<std::uint8_t> encodeJpeg(const Image& image, int quality)
{
    checkEncodable(image);
    const bool grey = image.channels <= 2;
    // TurboJPEG reads grey, RGB or RGBA (alpha ignored); grey + alpha loses its alpha first.
    const Image converted = image.channels == 2 ? convertChannels(image, 1) : Image();
    const Image& source = image.channels == 2 ? converted : image;
    const TJPF pixelFormat = grey ? TJPF_GRAY : source.channels == 3 ? TJPF_RGB : TJPF_RGBA;
    TurboHandle& turbo = compressor();
    tjhandle handle = turbo.get("JPEG encoder");
    unsigned char* buffer = nullptr;
    unsigned long size = 0;
    if (tjCompress2(handle, source.pixels.data(), source.width, 0, source.height, pixelFormat, &buffer, &size,
                    grey ? TJSAMP_GRAY : TJSAMP_420, std::clamp(quality, 1, 100), TJFLAG_ACCURATEDCT) != 0) {
        tjFree(buffer);
        throw Error("JPEG encoding failed: " + turbo.fail());
    }
    std::vector<std::uint8_t> bytes(buffer, buffer + size);
    tjFree(buffer);
    return bytes;
}

std::vector<std::uint8_t> encodeWebp(const Image& image, int quality, bool lossless)
{
    checkEncodable(image);
    const Image converted = image.channels <= 2 ? convertChannels(image, image.channels == 2 ? 4 : 3) : Image();
    const Image& source = image.channels <= 2 ? converted : image;
    const int stride = source.width * source.channels;
    const float factor = static_cast<float>(std::clamp(quality, 0, 100));
    std::uint8_t* output = nullptr;
    std::size_t size = 0;
    if (source.channels == 4) {
        size = lossless ? WebPEncodeLosslessRGBA(source.pixels.data(), source.width, source.height, stride, &output)
                        : WebPEncodeRGBA(source.pixels.data(), source.width, source.height, stride, factor, &output);
    } else {
        size = lossless ? WebPEncodeLosslessRGB(source.pixels.data(), source.width, source.height, stride, &output)
                        : WebPEncodeRGB(source.pixels.data(), source.width, source.height, stride, factor, &output);
    }
    if (size == 0 || !output) {
        WebPFree(output);
        throw Error("WebP encoding failed for a " + std::to_string(source.width) + "x" + std::to_string(source.height) +
                    " image (WebP allows at most 16383 pixels a side)");
    }
    std::vector<std::uint8_t> bytes(output, output + size);
    WebPFree(output);
    return bytes;
}

std::vector<std::uint8_t> encodeImage(const Image& image, ImageFormat format, int quality)
{
    switch (format) {
    case ImageFormat::Jpeg: return encodeJpeg(image, quality);
    case ImageFormat::Png: return encodePng(image, quality);
    case ImageFormat::Webp: return encodeWebp(image, quality);
    case ImageFormat::Unknown: break;
    }
    throw Error("cannot encode an image in an unknown format");
}

} // namespace orbis::world
