#pragma once

#include "orbis/world/Diagnostics.h" // cutForMessage, which these messages use

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace orbis::world {

/// The largest file readFileBytes reads unless told otherwise: 1 GiB.
inline constexpr std::size_t kMaximumFileBytes = std::size_t{1} << 30;

/// The whole of a regular file. Anything else (a folder, a named pipe, a device) is refused before a
/// byte is read, so nothing blocks. Throws orbis::Error naming the path and `kind` ("tile",
/// "tilemapresource.xml") when the file is missing, not a regular file, larger than maximumBytes
/// or unreadable.
std::vector<std::uint8_t> readFileBytes(const std::filesystem::path& path, std::string_view kind,
                                        std::size_t maximumBytes = kMaximumFileBytes);

/// As readFileBytes, but empty when there is no such file (the path or a folder on it does not
/// exist), which for a tile means the tile is missing rather than broken.
std::optional<std::vector<std::uint8_t>> readFileBytesIfExists(const std::filesystem::path& path, std::string_view kind,
                                                               std::size_t maximumBytes = kMaximumFileBytes);

/// Writes `bytes` to `path` whole or not at all: into a temporary file beside it (unique to this
/// process and thread), then renamed over it, so readers never see part of a file, also when
/// several threads or processes write the same path. Creates missing parent folders. Throws
/// orbis::Error naming the path on failure, leaving no temporary file behind.
void writeFileAtomically(const std::filesystem::path& path, std::span<const std::uint8_t> bytes);
void writeFileAtomically(const std::filesystem::path& path, std::string_view text);

/// Confines every file Orbis reads (readFileBytes and all the readers built on it: scene data,
/// GeoJSON, TopoJSON, CSV, glTF and its buffers and images, images, tiles, TMS descriptions) to
/// one folder, for rendering files from elsewhere: a path that resolves (symbolic links followed)
/// outside it is refused. Process-wide, set before reading starts (the orbis command's --sandbox);
/// empty (the default) allows any path. Throws orbis::Error when the folder does not exist.
void setFileSandbox(const std::optional<std::filesystem::path>& folder);

/// The sandbox folder (canonical), or empty when there is none.
std::optional<std::filesystem::path> fileSandbox();

/// path with symbolic links and "." and ".." resolved, as far as it exists. Throws orbis::Error
/// naming the path and `kind` when a sandbox is set and the resolved path lies outside it, or
/// when the links loop.
std::filesystem::path resolveInSandbox(const std::filesystem::path& path, std::string_view kind);

} // namespace orbis::world
