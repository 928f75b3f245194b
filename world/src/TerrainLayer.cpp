#include "orbis/world/TerrainLayer.h"

#include "JsonLocator.h"
#include "TerrainJson.h"

#include "orbis/world/FileAccess.h"

#include <orbis/core/Error.h>
#include <orbis/core/Math.h>
#include <orbis/core/TilingScheme.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>

namespace orbis::world {

namespace {

using Json = nlohmann::json;

constexpr std::size_t kMaximumDepth = 32;
/// The most rectangles a layer.json may list in all, and error grid cells per level.
constexpr std::size_t kMaximumRectangles = std::size_t{1} << 22;
constexpr std::uint64_t kMaximumErrorCells = std::uint64_t{1} << 24;

/// Parses JSON whose nesting is bounded first (parsing and freeing recurse once per level).
Json parseBoundedJson(std::string_view text, std::string_view name)
{
    std::size_t depth = 0;
    bool inString = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (c == '\\') {
                ++i;
            } else if (c == '"') {
                inString = false;
            }
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaximumDepth) {
                const auto position = detail::textPositionOf(text, i);
                throw Error(cutForMessage(name) + ":" + std::to_string(position.line) + ":" +
                            std::to_string(position.column) + ": JSON nested deeper than " +
                            std::to_string(kMaximumDepth) + " levels");
            }
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        } else if (c == '\0') {
            const auto position = detail::textPositionOf(text, i);
            throw Error(cutForMessage(name) + ":" + std::to_string(position.line) + ":" + std::to_string(position.column) +
                        ": a NUL byte in JSON text");
        }
    }
    try {
        return Json::parse(text.begin(), text.end());
    } catch (const Json::parse_error& error) {
        const auto position = detail::textPositionOf(text, error.byte > 0 ? error.byte - 1 : 0);
        std::string detail = error.what();
        if (const std::size_t colon = detail.find(": "); colon != std::string::npos) {
            detail = detail.substr(colon + 2);
        }
        throw Error(cutForMessage(name) + ":" + std::to_string(position.line) + ":" + std::to_string(position.column) +
                    ": invalid JSON: " + cutForMessage(detail, 200));
    } catch (const Json::exception& error) {
        throw Error(cutForMessage(name) + ": invalid JSON: " + cutForMessage(error.what(), 200));
    }
}

/// Messages: "name: /available/3/0/endX: ...".
class Reader {
public:
    explicit Reader(std::string_view name) : _name(cutForMessage(name)) {}

    [[noreturn]] void fail(const std::string& pointer, const std::string& what) const
    {
        throw Error(_name + ": " + (pointer.empty() ? std::string("/") : pointer) + ": " + what);
    }

    std::string text(const Json& value, const std::string& pointer, std::size_t maximumLength = 4096) const
    {
        if (!value.is_string()) {
            fail(pointer, "expected a string");
        }
        const auto& string = value.get_ref<const std::string&>();
        if (string.size() > maximumLength) {
            fail(pointer, "a string of " + std::to_string(string.size()) + " bytes, more than " +
                              std::to_string(maximumLength));
        }
        return string;
    }

    std::uint32_t whole(const Json& value, const std::string& pointer, std::uint64_t maximum) const
    {
        if (value.is_number_unsigned() || (value.is_number_integer() && value.get<std::int64_t>() >= 0)) {
            const auto number = value.get<std::uint64_t>();
            if (number <= maximum) {
                return static_cast<std::uint32_t>(number);
            }
        } else if (value.is_number_float()) {
            const double number = value.get<double>();
            if (number >= 0.0 && number <= static_cast<double>(maximum) && number == std::floor(number)) {
                return static_cast<std::uint32_t>(number);
            }
        }
        fail(pointer, "expected a whole number from 0 to " + std::to_string(maximum));
    }

    double number(const Json& value, const std::string& pointer) const
    {
        if (!value.is_number() || !std::isfinite(value.get<double>())) {
            fail(pointer, "expected a finite number");
        }
        return value.get<double>();
    }

    const Json& array(const Json& value, const std::string& pointer) const
    {
        if (!value.is_array()) {
            fail(pointer, "expected an array");
        }
        return value;
    }

    /// Levels of availability from `firstLevel` on, each an array of rectangles within its level.
    std::vector<LevelAvailability> availability(const Json& value, const std::string& pointer, std::uint32_t firstLevel,
                                                const TilingScheme& scheme, std::size_t& rectangles) const
    {
        array(value, pointer);
        if (firstLevel + value.size() > kMaximumTileLevel + 1) {
            fail(pointer, std::to_string(value.size()) + " levels of availability from level " +
                              std::to_string(firstLevel) + " go beyond level " + std::to_string(kMaximumTileLevel));
        }
        std::vector<LevelAvailability> levels;
        levels.reserve(value.size());
        for (std::size_t i = 0; i < value.size(); ++i) {
            const std::uint32_t level = firstLevel + static_cast<std::uint32_t>(i);
            const std::string levelPointer = pointer + "/" + std::to_string(i);
            const Json& list = array(value[i], levelPointer);
            rectangles += list.size();
            if (rectangles > kMaximumRectangles) {
                fail(levelPointer, "more than " + std::to_string(kMaximumRectangles) + " rectangles");
            }
            LevelAvailability rectanglesOfLevel;
            rectanglesOfLevel.reserve(list.size());
            for (std::size_t j = 0; j < list.size(); ++j) {
                const std::string at = levelPointer + "/" + std::to_string(j);
                const Json& object = list[j];
                if (!object.is_object()) {
                    fail(at, "expected an object with startX, startY, endX, endY");
                }
                TileRectangle rectangle;
                std::uint32_t* fields[] = {&rectangle.startX, &rectangle.startY, &rectangle.endX, &rectangle.endY};
                const char* names[] = {"startX", "startY", "endX", "endY"};
                for (int k = 0; k < 4; ++k) {
                    const auto found = object.find(names[k]);
                    if (found == object.end()) {
                        fail(at, std::string("no ") + names[k]);
                    }
                    const bool isX = k % 2 == 0;
                    *fields[k] = whole(*found, at + "/" + names[k],
                                       (isX ? scheme.tilesX(level) : scheme.tilesY(level)) - std::uint64_t{1});
                }
                if (rectangle.startX > rectangle.endX || rectangle.startY > rectangle.endY) {
                    fail(at, "start beyond end");
                }
                rectanglesOfLevel.push_back(rectangle);
            }
            levels.push_back(std::move(rectanglesOfLevel));
        }
        return levels;
    }

private:
    std::string _name;
};

std::string formatDouble(double value)
{
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    return std::string(buffer, result.ptr);
}

/// An error for layer.json: centimetres (the tiler rounds up to them before storing).
std::string formatError(float value)
{
    if (!std::isfinite(value)) {
        return "null";
    }
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.2f", static_cast<double>(value));
    return buffer;
}

} // namespace

namespace detail {

std::vector<LevelAvailability> parseMetadataAvailability(std::string_view json, std::uint32_t firstLevel,
                                                         std::string_view nameForMessages)
{
    const Json document = parseBoundedJson(json, nameForMessages);
    const Reader reader(nameForMessages);
    if (!document.is_object()) {
        reader.fail("", "the metadata is not a JSON object");
    }
    const auto available = document.find("available");
    if (available == document.end()) {
        return {};
    }
    std::size_t rectangles = 0;
    return reader.availability(*available, "/available", firstLevel, TilingScheme::geographic(), rectangles);
}

} // namespace detail

std::optional<double> LevelGeometricErrors::at(std::uint32_t x, std::uint32_t y) const noexcept
{
    if (x < startX || y < startY || x - startX >= width || y - startY >= height) {
        return std::nullopt;
    }
    const float value = errors[std::size_t{y - startY} * width + (x - startX)];
    if (!std::isfinite(value)) {
        return std::nullopt;
    }
    return value;
}

std::optional<double> TerrainLayer::geometricError(const TileKey& key) const noexcept
{
    for (const LevelGeometricErrors& level : geometricErrors) {
        if (level.level == key.level) {
            return level.at(key.x, key.y);
        }
    }
    return std::nullopt;
}

bool layerHasTile(const TerrainLayer& layer, const TileKey& key) noexcept
{
    if (key.level < layer.minimumLevel || key.level > layer.maximumLevel) {
        return false;
    }
    if (!layer.hasAvailable) {
        return true;
    }
    if (key.level < layer.available.size()) {
        const LevelAvailability& level = layer.available[key.level];
        return std::any_of(level.begin(), level.end(), [&](const TileRectangle& r) { return r.contains(key.x, key.y); });
    }
    return layer.metadataAvailability.has_value();
}

TerrainLayer parseTerrainLayer(std::string_view text, std::string_view nameForMessages)
{
    const Reader reader(nameForMessages);
    if (text.size() > kMaximumTerrainLayerBytes) {
        reader.fail("", std::to_string(text.size()) + " bytes, more than the " + std::to_string(kMaximumTerrainLayerBytes) +
                            " a layer.json may have");
    }
    const Json document = parseBoundedJson(text, nameForMessages);
    if (!document.is_object()) {
        reader.fail("", "a layer.json is a JSON object");
    }
    TerrainLayer layer;
    auto field = [&](const char* key) -> const Json* {
        const auto found = document.find(key);
        return found == document.end() || found->is_null() ? nullptr : &*found;
    };
    if (const Json* value = field("name")) {
        layer.name = reader.text(*value, "/name");
    }
    if (const Json* value = field("description")) {
        layer.description = reader.text(*value, "/description", 1 << 16);
    }
    if (const Json* value = field("attribution")) {
        layer.attribution = reader.text(*value, "/attribution", 1 << 16);
    }
    if (const Json* value = field("version")) {
        layer.version = reader.text(*value, "/version", 64);
    }
    if (const Json* value = field("format")) {
        layer.format = reader.text(*value, "/format", 64);
    }
    if (layer.format != "quantized-mesh-1.0" && layer.format != "heightmap-1.0") {
        reader.fail("/format", "\"" + cutForMessage(layer.format, 40) +
                                   "\" is not a tile format this reader knows (quantized-mesh-1.0, heightmap-1.0)");
    }
    if (const Json* value = field("tiles")) {
        reader.array(*value, "/tiles");
        layer.tiles.clear();
        for (std::size_t i = 0; i < value->size() && i < 64; ++i) {
            layer.tiles.push_back(reader.text((*value)[i], "/tiles/" + std::to_string(i)));
        }
    }
    if (layer.tiles.empty()) {
        reader.fail("/tiles", "no tile URL template");
    }
    if (const Json* value = field("scheme")) {
        const std::string scheme = reader.text(*value, "/scheme", 64);
        if (scheme != "tms" && scheme != "slippyMap" && scheme != "xyz") {
            reader.fail("/scheme", "\"" + cutForMessage(scheme, 40) + "\" is neither \"tms\" nor \"slippyMap\"");
        }
        layer.rowsFromSouth = scheme == "tms";
    }
    if (const Json* value = field("projection")) {
        layer.projection = reader.text(*value, "/projection", 64);
        if (layer.projection != "EPSG:4326" && layer.projection != "EPSG:3857") {
            reader.fail("/projection", "\"" + cutForMessage(layer.projection, 40) +
                                           "\" is neither EPSG:4326 nor EPSG:3857");
        }
    }
    const TilingScheme scheme =
        layer.projection == "EPSG:3857" ? TilingScheme::webMercator() : TilingScheme::geographic();
    if (const Json* value = field("bounds")) {
        reader.array(*value, "/bounds");
        if (value->size() != 4) {
            reader.fail("/bounds", "expected [west, south, east, north]");
        }
        double b[4];
        for (int i = 0; i < 4; ++i) {
            b[i] = reader.number((*value)[static_cast<std::size_t>(i)], "/bounds/" + std::to_string(i));
        }
        if (!(b[0] >= -180.0 && b[2] <= 180.0 && b[0] < b[2] && b[1] >= -90.0 && b[3] <= 90.0 && b[1] < b[3])) {
            reader.fail("/bounds", "not a rectangle within -180..180, -90..90 with west < east and south < north");
        }
        layer.bounds = GeodeticExtent::fromDegrees(b[0], b[1], b[2], b[3]);
    }
    if (const Json* value = field("metadataAvailability")) {
        const std::uint32_t levels = reader.whole(*value, "/metadataAvailability", kMaximumTileLevel);
        if (levels == 0) {
            reader.fail("/metadataAvailability", "0 levels between metadata tiles");
        }
        layer.metadataAvailability = levels;
    }
    if (const Json* value = field("available")) {
        std::size_t rectangles = 0;
        layer.available = reader.availability(*value, "/available", 0, scheme, rectangles);
        layer.hasAvailable = true;
    }
    if (const Json* value = field("extensions")) {
        reader.array(*value, "/extensions");
        for (std::size_t i = 0; i < value->size() && i < 64; ++i) {
            layer.extensions.push_back(reader.text((*value)[i], "/extensions/" + std::to_string(i), 64));
        }
    }
    layer.minimumLevel = 0;
    if (const Json* value = field("minzoom")) {
        layer.minimumLevel = reader.whole(*value, "/minzoom", kMaximumTileLevel);
    }
    if (const Json* value = field("maxzoom")) {
        layer.maximumLevel = reader.whole(*value, "/maxzoom", kMaximumTileLevel);
    } else if (layer.hasAvailable && !layer.metadataAvailability && !layer.available.empty()) {
        layer.maximumLevel = static_cast<std::uint32_t>(layer.available.size() - 1);
    } else {
        layer.maximumLevel = kMaximumTileLevel;
    }
    if (layer.minimumLevel > layer.maximumLevel) {
        reader.fail("/minzoom", "minzoom " + std::to_string(layer.minimumLevel) + " is above maxzoom " +
                                    std::to_string(layer.maximumLevel));
    }
    if (const Json* value = field("orbis:geometricError")) {
        reader.array(*value, "/orbis:geometricError");
        for (std::size_t i = 0; i < value->size(); ++i) {
            const std::string at = "/orbis:geometricError/" + std::to_string(i);
            const Json& object = (*value)[i];
            if (!object.is_object()) {
                reader.fail(at, "expected an object");
            }
            auto member = [&](const char* key) -> const Json& {
                const auto found = object.find(key);
                if (found == object.end()) {
                    reader.fail(at, std::string("no ") + key);
                }
                return *found;
            };
            LevelGeometricErrors level;
            level.level = reader.whole(member("level"), at + "/level", kMaximumTileLevel);
            level.startX = reader.whole(member("startX"), at + "/startX", scheme.tilesX(level.level) - 1u);
            level.startY = reader.whole(member("startY"), at + "/startY", scheme.tilesY(level.level) - 1u);
            level.width = reader.whole(member("width"), at + "/width", scheme.tilesX(level.level) - level.startX);
            level.height = reader.whole(member("height"), at + "/height", scheme.tilesY(level.level) - level.startY);
            const std::uint64_t cells = std::uint64_t{level.width} * level.height;
            if (cells > kMaximumErrorCells) {
                reader.fail(at, std::to_string(cells) + " tiles, more than " + std::to_string(kMaximumErrorCells));
            }
            const Json& errors = reader.array(member("errors"), at + "/errors");
            if (errors.size() != cells) {
                reader.fail(at + "/errors", std::to_string(errors.size()) + " errors for " + std::to_string(level.width) +
                                                " x " + std::to_string(level.height) + " tiles");
            }
            level.errors.resize(errors.size());
            for (std::size_t j = 0; j < errors.size(); ++j) {
                if (errors[j].is_null()) {
                    level.errors[j] = std::numeric_limits<float>::quiet_NaN();
                } else {
                    const double error = reader.number(errors[j], at + "/errors/" + std::to_string(j));
                    if (error < 0.0) {
                        reader.fail(at + "/errors/" + std::to_string(j), "a negative error");
                    }
                    level.errors[j] = static_cast<float>(error);
                }
            }
            if (std::any_of(layer.geometricErrors.begin(), layer.geometricErrors.end(),
                            [&](const LevelGeometricErrors& other) { return other.level == level.level; })) {
                reader.fail(at + "/level", "level " + std::to_string(level.level) + " given twice");
            }
            layer.geometricErrors.push_back(std::move(level));
        }
    }
    return layer;
}

std::string formatTerrainLayer(const TerrainLayer& layer)
{
    auto quoted = [](const std::string& text) { return Json(text).dump(); };
    std::string out = "{\n";
    out += "  \"tilejson\": \"2.1.0\",\n";
    out += "  \"name\": " + quoted(layer.name) + ",\n";
    out += "  \"description\": " + quoted(layer.description) + ",\n";
    out += "  \"version\": " + quoted(layer.version) + ",\n";
    out += "  \"format\": " + quoted(layer.format) + ",\n";
    out += "  \"attribution\": " + quoted(layer.attribution) + ",\n";
    out += "  \"scheme\": " + quoted(layer.rowsFromSouth ? "tms" : "slippyMap") + ",\n";
    out += "  \"tiles\": [";
    for (std::size_t i = 0; i < layer.tiles.size(); ++i) {
        out += (i ? ", " : "") + quoted(layer.tiles[i]);
    }
    out += "],\n";
    out += "  \"projection\": " + quoted(layer.projection) + ",\n";
    out += "  \"bounds\": [" + formatDouble(toDegrees(layer.bounds.west)) + ", " + formatDouble(toDegrees(layer.bounds.south)) +
           ", " + formatDouble(toDegrees(layer.bounds.east)) + ", " + formatDouble(toDegrees(layer.bounds.north)) + "],\n";
    out += "  \"minzoom\": " + std::to_string(layer.minimumLevel) + ",\n";
    out += "  \"maxzoom\": " + std::to_string(layer.maximumLevel) + ",\n";
    out += "  \"extensions\": [";
    for (std::size_t i = 0; i < layer.extensions.size(); ++i) {
        out += (i ? ", " : "") + quoted(layer.extensions[i]);
    }
    out += "]";
    if (layer.metadataAvailability) {
        out += ",\n  \"metadataAvailability\": " + std::to_string(*layer.metadataAvailability);
    }
    if (layer.hasAvailable) {
        out += ",\n  \"available\": [";
        for (std::size_t level = 0; level < layer.available.size(); ++level) {
            out += level ? ",\n    [" : "\n    [";
            const LevelAvailability& rectangles = layer.available[level];
            for (std::size_t i = 0; i < rectangles.size(); ++i) {
                const TileRectangle& r = rectangles[i];
                out += (i ? ", " : "") + std::string("{\"startX\": ") + std::to_string(r.startX) +
                       ", \"startY\": " + std::to_string(r.startY) + ", \"endX\": " + std::to_string(r.endX) +
                       ", \"endY\": " + std::to_string(r.endY) + "}";
            }
            out += "]";
        }
        out += layer.available.empty() ? "]" : "\n  ]";
    }
    if (!layer.geometricErrors.empty()) {
        out += ",\n  \"orbis:geometricError\": [";
        for (std::size_t i = 0; i < layer.geometricErrors.size(); ++i) {
            const LevelGeometricErrors& level = layer.geometricErrors[i];
            out += i ? ",\n    {" : "\n    {";
            out += "\"level\": " + std::to_string(level.level) + ", \"startX\": " + std::to_string(level.startX) + ", \"startY\": " + std::to_string(level.startY) +
                   ", \"width\": " + std::to_string(level.width) + ", \"height\": " + std::to_string(level.height) +
                   ", \"errors\": [";
            for (std::size_t j = 0; j < level.errors.size(); ++j) {
                if (j) {
                    out += ',';
                }
                out += formatError(level.errors[j]);
            }
            out += "]}";
        }
        out += "\n  ]";
    }
    out += "\n}\n";
    return out;
}

LevelAvailability rectanglesOf(std::vector<std::pair<std::uint32_t, std::uint32_t>> tiles)
{
    // Sorted by row, then column; duplicates dropped.
    std::sort(tiles.begin(), tiles.end(), [](const auto& a, const auto& b) {
        return a.second != b.second ? a.second < b.second : a.first < b.first;
    });
    tiles.erase(std::unique(tiles.begin(), tiles.end()), tiles.end());
    LevelAvailability done;
    // Rectangles still growing northwards, by their column run.
    std::map<std::pair<std::uint32_t, std::uint32_t>, TileRectangle> open;
    std::size_t i = 0;
    while (i < tiles.size()) {
        const std::uint32_t row = tiles[i].second;
        std::map<std::pair<std::uint32_t, std::uint32_t>, TileRectangle> next;
        while (i < tiles.size() && tiles[i].second == row) {
            const std::uint32_t start = tiles[i].first;
            std::uint32_t end = start;
            while (i + 1 < tiles.size() && tiles[i + 1].second == row && tiles[i + 1].first == end + 1) {
                ++end;
                ++i;
            }
            ++i;
            const auto run = std::pair(start, end);
            const auto found = open.find(run);
            if (found != open.end() && found->second.endY + 1 == row) {
                TileRectangle grown = found->second;
                grown.endY = row;
                next[run] = grown;
                open.erase(found);
            } else {
                next[run] = TileRectangle{start, row, end, row};
            }
        }
        for (const auto& [run, rectangle] : open) {
            done.push_back(rectangle);
        }
        open = std::move(next);
    }
    for (const auto& [run, rectangle] : open) {
        done.push_back(rectangle);
    }
    std::sort(done.begin(), done.end(), [](const TileRectangle& a, const TileRectangle& b) {
        return a.startY != b.startY ? a.startY < b.startY : a.startX < b.startX;
    });
    return done;
}

} // namespace orbis::world
