#pragma once

// The on-disk cache of an HTTP tile source: FOLDER/z/x/y.EXT for tiles, FOLDER/z/x/y.missing
// (empty) for tiles the server said do not exist, written atomically; FOLDER/source.txt names the
// source the folder belongs to. Private to orbis::world.

#include "orbis/world/TileSource.h"

#include <filesystem>
#include <optional>
#include <string>

namespace orbis::world::detail {

class DiskCache {
public:
    /// Claims `folder` for `sourceName` (creating it and source.txt), or checks an existing claim.
    /// Throws orbis::Error when the folder cannot be written or belongs to another source.
    DiskCache(std::filesystem::path folder, const std::string& sourceName);

    /// The cached outcome (Ok with the bytes, or Missing), marked fromCache; empty when the tile is
    /// not cached or its file cannot be read. `extension` names the tiles' files ("tile" if empty).
    std::optional<TileFetch> load(const orbis::TileKey& key, const std::string& extension, std::size_t maximumBytes) const;
    /// Keeps an Ok or Missing outcome; a Failed one is not kept. A write that fails is skipped:
    /// the cache only saves time.
    void store(const orbis::TileKey& key, const std::string& extension, const TileFetch& fetch) const;

    /// A file of the source other than its tiles (its tilemapresource.xml), by name.
    std::optional<std::vector<std::uint8_t>> loadFile(const std::string& name, std::size_t maximumBytes) const;
    void storeFile(const std::string& name, const std::vector<std::uint8_t>& bytes) const;

private:
    std::filesystem::path tilePath(const orbis::TileKey& key, const std::string& extension) const;

    std::filesystem::path _folder;
};

} // namespace orbis::world::detail
