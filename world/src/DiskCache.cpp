#include "DiskCache.h"

#include "orbis/world/FileAccess.h"

#include <orbis/core/Error.h>

namespace orbis::world::detail {

DiskCache::DiskCache(std::filesystem::path folder, const std::string& sourceName) : _folder(std::move(folder))
{
    const std::filesystem::path claim = _folder / "source.txt";
    const std::string expected = sourceName + "\n";
    if (const auto existing = readFileBytesIfExists(claim, "cache claim", 64 * 1024)) {
        std::string owner(existing->begin(), existing->end());
        if (owner != expected) {
            if (owner.ends_with("\n")) {
                owner.pop_back();
            }
            throw Error(cutForMessage(_folder.string()) + ": the cache folder belongs to " + cutForMessage(owner) +
                        ", not to " + cutForMessage(sourceName) + " (give each source its own folder)");
        }
        return;
    }
    writeFileAtomically(claim, expected);
}

std::filesystem::path DiskCache::tilePath(const TileKey& key, const std::string& extension) const
{
    return _folder / std::to_string(key.level) / std::to_string(key.x) /
           (std::to_string(key.y) + "." + (extension.empty() ? std::string("tile") : extension));
}

std::optional<TileFetch> DiskCache::load(const TileKey& key, const std::string& extension, std::size_t maximumBytes) const
{
    try {
        TileFetch fetch;
        fetch.fromCache = true;
        if (auto bytes = readFileBytesIfExists(tilePath(key, extension), "cached tile", maximumBytes)) {
            fetch.status = TileFetch::Status::Ok;
            fetch.bytes = std::move(*bytes);
            return fetch;
        }
        if (readFileBytesIfExists(tilePath(key, "missing"), "cached missing tile", 0)) {
            fetch.status = TileFetch::Status::Missing;
            return fetch;
        }
    } catch (const Error&) {
        // An unreadable entry is fetched again (and rewritten).
    }
    return std::nullopt;
}

void DiskCache::store(const TileKey& key, const std::string& extension, const TileFetch& fetch) const
{
    try {
        if (fetch.status == TileFetch::Status::Ok) {
            writeFileAtomically(tilePath(key, extension), fetch.bytes);
        } else if (fetch.status == TileFetch::Status::Missing) {
            writeFileAtomically(tilePath(key, "missing"), std::string_view());
        }
    } catch (const Error&) {
        // A full or read-only disk costs the next run the download, nothing more.
    }
}

std::optional<std::vector<std::uint8_t>> DiskCache::loadFile(const std::string& name, std::size_t maximumBytes) const
{
    try {
        return readFileBytesIfExists(_folder / name, "cached file", maximumBytes);
    } catch (const Error&) {
        return std::nullopt;
    }
}

void DiskCache::storeFile(const std::string& name, const std::vector<std::uint8_t>& bytes) const
{
    try {
        writeFileAtomically(_folder / name, bytes);
    } catch (const Error&) {
        // As for tiles: the next run downloads it again.
    }
}

} // namespace orbis::world::detail
