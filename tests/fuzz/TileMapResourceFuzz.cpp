// libFuzzer target for tilemapresource.xml: any input either reads into a description that keeps
// the documented invariants or throws orbis::Error with a message naming the file. Any other
// exception, a crash, a sanitizer report or a broken invariant is a bug.
// Built and run by scripts/fuzz.sh --target tms (clang, -fsanitize=fuzzer,address,undefined).
#include <orbis/core/Error.h>
#include <orbis/core/TileKey.h>
#include <orbis/world/TileMapResource.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

namespace {

void require(bool condition)
{
    if (!condition) {
        std::abort();
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const std::string_view xml(reinterpret_cast<const char*>(data), size);
    try {
        const orbis::world::TileMapResource resource = orbis::world::parseTileMapResource(xml, "fuzz.xml");
        require(!resource.tileSets.empty() && resource.tileSets.size() <= orbis::kMaximumTileLevel + 1);
        for (std::size_t i = 0; i < resource.tileSets.size(); ++i) {
            require(resource.tileSets[i].level == resource.tileSets.front().level + i);
            require(resource.tileSets[i].level <= orbis::kMaximumTileLevel);
            require(std::isfinite(resource.tileSets[i].unitsPerPixel) && resource.tileSets[i].unitsPerPixel > 0.0);
        }
        require(resource.tileWidth >= 1 && resource.tileWidth <= orbis::world::kMaximumTileSide);
        require(resource.tileHeight >= 1 && resource.tileHeight <= orbis::world::kMaximumTileSide);
        require(!resource.extension.empty() && resource.extension.size() <= 8);
        const orbis::GeodeticExtent& extent = resource.extent;
        require(std::isfinite(extent.west) && std::isfinite(extent.east) && std::isfinite(extent.south) &&
                std::isfinite(extent.north) && extent.south < extent.north);
        // What is written reads back.
        require(orbis::world::parseTileMapResource(orbis::world::formatTileMapResource(resource), "again").tileSets.size() ==
                resource.tileSets.size());
    } catch (const orbis::Error& error) {
        require(std::string_view(error.what()).starts_with("fuzz.xml"));
        require(std::string_view(error.what()).size() < 2000);
    }
    return 0;
}
