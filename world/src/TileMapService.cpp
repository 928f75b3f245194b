#include "orbis/world/TileMapService.h"

#include "orbis/world/ImageFile.h"

#include <orbis/core/Error.h>

#include <algorithm>
#include <fstream>
#include <regex>
#include <sstream>

namespace orbis::world {

namespace {

std::string readText(const std::filesystem::path& path)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw Error(path.string() + ": cannot open");
    }
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

/// The value of attribute `name` in the first element `element` of a small XML text.
std::optional<std::string> attribute(const std::string& xml, const std::string& element, const std::string& name)
{
    const std::regex pattern("<" + element + "\\b[^>]*\\b" + name + "=\"([^\"]*)\"");
    std::smatch match;
    if (std::regex_search(xml, match, pattern)) {
        return match[1].str();
    }
    return std::nullopt;
}

} // namespace

TileMapDescription readTileMapDescription(const std::filesystem::path& folder)
{
    const std::filesystem::path file = folder / "tilemapresource.xml";
    const std::string xml = readText(file);
    auto fail = [&](const std::string& what) { return Error(file.string() + ": " + what); };

    if (xml.find("<SRS>EPSG:4326</SRS>") == std::string::npos) {
        throw fail("only the geodetic EPSG:4326 profile is supported (SRS)");
    }
    const auto originX = attribute(xml, "Origin", "x");
    const auto originY = attribute(xml, "Origin", "y");
    if (!originX || !originY || std::stod(*originX) != -180.0 || std::stod(*originY) != -90.0) {
        throw fail("expected the origin at the lower left (-180, -90)");
    }
    TileMapDescription description;
    const auto width = attribute(xml, "TileFormat", "width");
    const auto height = attribute(xml, "TileFormat", "height");
    const auto extension = attribute(xml, "TileFormat", "extension");
    if (!width || !height || !extension) {
        throw fail("TileFormat needs width, height and extension");
    }
    description.tileWidth = std::stoi(*width);
    description.tileHeight = std::stoi(*height);
    description.extension = *extension;
    std::size_t position = 0;
    while ((position = xml.find("<TileSet ", position)) != std::string::npos) {
        ++description.levelCount;
        ++position;
    }
    if (description.levelCount == 0 || description.tileWidth <= 0 || description.tileHeight <= 0) {
        throw fail("no TileSet, or an empty tile size");
    }
    return description;
}

Image readTileMapMosaic(const std::filesystem::path& folder, std::optional<int> level)
{
    const TileMapDescription description = readTileMapDescription(folder);
    const int z = level.value_or(description.levelCount - 1);
    if (z < 0 || z >= description.levelCount) {
        throw Error(folder.string() + ": level " + std::to_string(z) + " is not in the pyramid (0.." +
                    std::to_string(description.levelCount - 1) + ")");
    }
    // The geodetic profile has 2 x 1 tiles at level 0, doubling both ways at each level.
    const int columns = 2 << z;
    const int rows = 1 << z;
    Image mosaic(columns * description.tileWidth, rows * description.tileHeight, 3);
    for (int x = 0; x < columns; ++x) {
        for (int y = 0; y < rows; ++y) {
            const std::filesystem::path tilePath = folder / std::to_string(z) / std::to_string(x) /
                                                   (std::to_string(y) + "." + description.extension);
            const Image tile = readImage(tilePath, 3);
            if (tile.width != description.tileWidth || tile.height != description.tileHeight) {
                throw Error(tilePath.string() + ": expected a " + std::to_string(description.tileWidth) + "x" +
                            std::to_string(description.tileHeight) + " tile");
            }
            // TMS counts rows from the bottom; images from the top.
            const int top = (rows - 1 - y) * description.tileHeight;
            for (int row = 0; row < tile.height; ++row) {
                std::copy_n(tile.pixel(0, row), static_cast<std::size_t>(tile.width) * 3,
                            mosaic.pixel(x * description.tileWidth, top + row));
            }
        }
    }
    return mosaic;
}

Image readGlobeImage(const std::filesystem::path& path)
{
    if (std::filesystem::is_directory(path)) {
        return readTileMapMosaic(path);
    }
    return readImage(path, 3);
}

} // namespace orbis::world
