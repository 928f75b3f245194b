#include "ProceduralTileSource.h"

#include <orbis/world/ImageCodec.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace orbis::test {

namespace {

std::uint8_t triangle(double x)
{
    const double f = x - std::floor(x);
    return static_cast<std::uint8_t>(std::lround(255.0 * (1.0 - std::abs(2.0 * f - 1.0))));
}

} // namespace

std::array<std::uint8_t, 4> placePattern(std::uint32_t, double u, double v)
{
    return {triangle(8.0 * u), triangle(4.0 * v), static_cast<std::uint8_t>(std::lround(255.0 * u)), 255};
}

ProceduralTileSource::ProceduralTileSource(ProceduralTileSourceOptions options)
    : _options(std::move(options))
{
    _info.name = "procedural tiles";
    _info.scheme = TilingScheme::geographic();
    _info.minimumLevel = _options.minimumLevel;
    _info.maximumLevel = _options.maximumLevel;
    _info.tileWidth = _info.tileHeight = _options.tileSize;
    _info.format = "png";
}

std::string ProceduralTileSource::locate(const TileKey& key) const
{
    return "procedural/" + std::to_string(key.level) + "/" + std::to_string(key.x) + "/" + std::to_string(key.y) + ".png";
}

Image ProceduralTileSource::tileImage(const TileKey& key) const
{
    const int size = _options.tileSize;
    Image image(size, size, 4);
    const double across = static_cast<double>(_info.scheme.tilesX(key.level)) * size;
    const double up = static_cast<double>(_info.scheme.tilesY(key.level)) * size;
    for (int row = 0; row < size; ++row) {
        // Tile rows from the north; the scheme's rows from the south.
        const double v = (static_cast<double>(key.y) * size + (size - 1 - row) + 0.5) / up;
        for (int column = 0; column < size; ++column) {
            const double u = (static_cast<double>(key.x) * size + column + 0.5) / across;
            const std::array<std::uint8_t, 4> texel = _options.pattern(key.level, u, v);
            std::copy(texel.begin(), texel.end(), image.pixel(column, row));
        }
    }
    return image;
}

world::TileFetch ProceduralTileSource::fetch(const TileKey& key)
{
    ++_fetches;
    world::TileFetch result;
    if (key.level < _info.minimumLevel || key.level > _info.maximumLevel || !_info.scheme.isValid(key) ||
        (_options.missing && _options.missing(key))) {
        result.status = world::TileFetch::Status::Missing;
        return result;
    }
    if (_options.failing && _options.failing(key)) {
        result.status = world::TileFetch::Status::Failed;
        result.message = locate(key) + ": the test says this tile fails";
        return result;
    }
    result.status = world::TileFetch::Status::Ok;
    result.bytes = world::encodePng(tileImage(key), 1);
    return result;
}

} // namespace orbis::test
