#pragma once

#include <orbis/core/Image.h>

#include <filesystem>

namespace orbis::world {

/// Reads a JPEG, PNG or WebP file (decodeImage on readFileBytes: a regular file, at most
/// kMaximumDecodedPixels). Throws orbis::Error naming the file when it cannot be read or decoded.
Image readImage(const std::filesystem::path& path, int desiredChannels = 4);

/// Writes a PNG at zlib level `compressionLevel` (0..9; the default 1 is fast, for frames). The
/// file appears whole or not at all: it is written to a temporary name and renamed. Throws
/// orbis::Error naming the file on failure.
void writePng(const Image& image, const std::filesystem::path& path, int compressionLevel = 1);

} // namespace orbis::world
