#pragma once

#include <orbis/core/Image.h>

#include <filesystem>

namespace orbis::world {

/// Reads a PNG or JPEG file. Throws orbis::Error naming the file when it cannot be read or decoded.
Image readImage(const std::filesystem::path& path, int desiredChannels = 4);

/// Writes a PNG. The file appears whole or not at all: it is written to a temporary name and
/// renamed. Throws orbis::Error naming the file on failure.
void writePng(const Image& image, const std::filesystem::path& path);

} // namespace orbis::world
