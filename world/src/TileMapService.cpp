#include "orbis/world/TileMapService.h"

#include "orbis/world/FileAccess.h"
#include "orbis/world/ImageCodec.h"
#include "orbis/world/ImageFile.h"
#include "orbis/world/TileSource.h"

#include <orbis/core/Error.h>

#include <algorithm>

namespace orbis::world {

Image readTileMapMosaic(const std::filesystem::path& folder, std::optional<int> level)
{
    const std::string where = cutForMessage(folder.string());
    const std::unique_ptr<TileSource> source = openTileSource(folder.string());
    const TileSourceInfo& info = source->info();
    if (info.scheme != TilingScheme::geographic()) {
        throw Error(where + ": a mercator pyramid does not join into a whole-globe image (only geodetic ones do)");
    }
    const int first = static_cast<int>(info.minimumLevel);
    const int last = static_cast<int>(info.maximumLevel);
    const int z = level.value_or(last);
    if (z < first || z > last) {
        throw Error(where + ": level " + std::to_string(z) + " is not in the pyramid (" + std::to_string(first) + ".." +
                    std::to_string(last) + ")");
    }
    const TilingScheme scheme = info.scheme;
    const auto columns = static_cast<int>(scheme.tilesX(static_cast<std::uint32_t>(z)));
    const auto rows = static_cast<int>(scheme.tilesY(static_cast<std::uint32_t>(z)));
    // In 64 bits: a level and tile size a description allows can overflow an int here.
    const std::int64_t width = std::int64_t{columns} * info.tileWidth;
    const std::int64_t height = std::int64_t{rows} * info.tileHeight;
    if (width > kMaximumMosaicSide || height > kMaximumMosaicSide) {
        throw Error(where + ": level " + std::to_string(z) + " joins into " + std::to_string(width) + "x" +
                    std::to_string(height) + " pixels, more than the " + std::to_string(kMaximumMosaicSide) +
                    " a side allowed (ask for a shallower level)");
    }
    Image mosaic(static_cast<int>(width), static_cast<int>(height), 3);
    for (int x = 0; x < columns; ++x) {
        for (int y = 0; y < rows; ++y) {
            const TileKey key{static_cast<std::uint32_t>(z), static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y)};
            const TileFetch fetched = source->fetch(key);
            if (fetched.status == TileFetch::Status::Missing) {
                throw Error(source->locate(key) + ": no such tile (the mosaic needs every tile of level " +
                            std::to_string(z) + ")");
            }
            if (fetched.status == TileFetch::Status::Failed) {
                throw Error(fetched.message);
            }
            const Image tile = decodeImage(fetched.bytes, source->locate(key), 3);
            if (tile.width != info.tileWidth || tile.height != info.tileHeight) {
                throw Error(source->locate(key) + ": a " + std::to_string(tile.width) + "x" + std::to_string(tile.height) +
                            " tile, expected " + std::to_string(info.tileWidth) + "x" + std::to_string(info.tileHeight));
            }
            // TMS counts rows from the bottom; images from the top.
            const int top = (rows - 1 - y) * info.tileHeight;
            for (int row = 0; row < tile.height; ++row) {
                std::copy_n(tile.pixel(0, row), static_cast<std::size_t>(tile.width) * 3,
                            mosaic.pixel(x * info.tileWidth, top + row));
            }
        }
    }
    return mosaic;
}

Image readGlobeImage(const std::filesystem::path& path)
{
    std::error_code error;
    if (std::filesystem::is_directory(path, error)) {
        return readTileMapMosaic(path);
    }
    return readImage(path, 3);
}

} // namespace orbis::world
