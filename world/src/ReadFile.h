#pragma once

#include <filesystem>
#include <string>

namespace orbis::world {

/// The whole file as bytes. Throws orbis::Error naming the file and `kind` ("GeoJSON", "CSV")
/// when it cannot be opened or read.
std::string readTextFile(const std::filesystem::path& path, const char* kind);

} // namespace orbis::world
