#include "orbis/world/GeoJson.h"

#include "orbis/core/Error.h"
#include "orbis/core/Math.h"

#include "orbis/world/TopoJson.h"

#include "JsonDepth.h"
#include "RingConvention.h"
#include "TopoJsonDocument.h"
#include "ReadFile.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>

namespace orbis::world {

using Json = nlohmann::json;

const PropertyValue* Feature::property(std::string_view name) const
{
    const auto found = properties.find(name);
    return found == properties.end() ? nullptr : &found->second;
}

std::optional<std::string> Feature::stringProperty(std::string_view name) const
{
    const PropertyValue* value = property(name);
    if (const auto* text = value ? std::get_if<std::string>(value) : nullptr) {
        return *text;
    }
    return std::nullopt;
}

std::optional<double> Feature::numberProperty(std::string_view name) const
{
    const PropertyValue* value = property(name);
    if (const auto* number = value ? std::get_if<double>(value) : nullptr) {
        return *number;
    }
    return std::nullopt;
}

namespace {

/// One step of the JSON path to the value being read; rendered only when something is wrong, so
/// valid files pay nothing for the messages.
struct PathNode {
    const PathNode* parent = nullptr;
    std::string_view key; ///< member name; empty for an array element
    std::size_t index = 0;

    PathNode member(std::string_view name) const { return {this, name, 0}; }
    PathNode element(std::size_t i) const { return {this, {}, i}; }
};

std::string render(const PathNode* node)
{
    std::vector<const PathNode*> chain;
    for (; node && (node->parent || !node->key.empty()); node = node->parent) {
        chain.push_back(node);
    }
    std::string text;
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
        if ((*it)->key.empty()) {
            text += '[' + std::to_string((*it)->index) + ']';
        } else {
            if (!text.empty()) {
                text += '.';
            }
            text += (*it)->key;
        }
    }
    return text;
}

/// What is wrong inside one feature (or a top-level geometry), before the feature prefix is added.
struct Invalid {
    std::string path;
    std::string message;
};

[[noreturn]] void fail(const PathNode& at, std::string message)
{
    throw Invalid{render(&at), std::move(message)};
}

std::string formatNumber(double value)
{
    std::array<char, 32> buffer{};
    const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
    return std::string(buffer.data(), result.ptr);
}

/// A short description of a JSON value for messages: `string "NaN"`, `array of 3`, `null`, ...
std::string describe(const Json& j)
{
    switch (j.type()) {
    case Json::value_t::null:
        return "null";
    case Json::value_t::boolean:
        return j.get<bool>() ? "true" : "false";
    case Json::value_t::string: {
        std::string text = j.get_ref<const std::string&>();
        if (text.size() > 40) {
            text = text.substr(0, 40) + "...";
        }
        return "string \"" + text + "\"";
    }
    case Json::value_t::array:
        return "array of " + std::to_string(j.size());
    case Json::value_t::object:
        return "object";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float:
        return "number " + formatNumber(j.get<double>());
    default:
        return "unreadable value";
    }
}

const Json& requireArray(const Json& j, const PathNode& at, const char* what)
{
    if (!j.is_array()) {
        fail(at, std::string("expected ") + what + ", got " + describe(j));
    }
    return j;
}

double readNumber(const Json& j, const PathNode& at, const char* what)
{
    if (!j.is_number()) {
        fail(at, std::string("expected a number (") + what + "), got " + describe(j));
    }
    const double value = j.get<double>();
    if (!std::isfinite(value)) {
        fail(at, std::string(what) + " is not finite");
    }
    return value;
}

struct PositionDegrees {
    double longitude;
    double latitude;
    double height;

    bool operator==(const PositionDegrees&) const = default;
    Geodetic3D toGeodetic() const { return Geodetic3D::fromDegrees(longitude, latitude, height); }
};

PositionDegrees readPosition(const Json& j, const PathNode& at)
{
    if (!j.is_array()) {
        fail(at, "expected a position [longitude, latitude], got " + describe(j));
    }
    if (j.size() < 2) {
        fail(at, "a position needs longitude and latitude, got " + describe(j));
    }
    PositionDegrees p{readNumber(j[0], at.element(0), "longitude"), readNumber(j[1], at.element(1), "latitude"),
                      j.size() > 2 ? readNumber(j[2], at.element(2), "height") : 0.0};
    if (p.longitude < -180.0 || p.longitude > 180.0) {
        fail(at, "longitude " + formatNumber(p.longitude) + " out of range [-180, 180]");
    }
    if (p.latitude < -90.0 || p.latitude > 90.0) {
        fail(at, "latitude " + formatNumber(p.latitude) + " out of range [-90, 90]");
    }
    return p;
}

class GeometryReader {
public:
    GeometryReader(const GeoJsonOptions& options, std::vector<Invalid>& notes) : _options(options), _notes(notes) {}

    Geometry read(const Json& j, const PathNode& at)
    {
        if (!j.is_object()) {
            fail(at, "expected a geometry object, got " + describe(j));
        }
        const auto type = j.find("type");
        if (type == j.end()) {
            fail(at, "missing \"type\"");
        }
        if (!type->is_string()) {
            fail(at.member("type"), "expected a geometry type name, got " + describe(*type));
        }
        const std::string& name = type->get_ref<const std::string&>();
        if (name == "GeometryCollection") {
            const PathNode geometriesAt = at.member("geometries");
            const auto geometries = j.find("geometries");
            if (geometries == j.end()) {
                fail(at, "missing \"geometries\" for a GeometryCollection");
            }
            requireArray(*geometries, geometriesAt, "an array of geometries");
            GeometryCollection collection;
            collection.geometries.reserve(geometries->size());
            for (std::size_t i = 0; i < geometries->size(); ++i) {
                collection.geometries.push_back(read((*geometries)[i], geometriesAt.element(i)));
            }
            return {std::move(collection)};
        }

        const auto coordinates = j.find("coordinates");
        const PathNode coordinatesAt = at.member("coordinates");
        if (coordinates == j.end() || coordinates->is_null()) {
            if (name == "Point" || name == "MultiPoint" || name == "LineString" || name == "MultiLineString" ||
                name == "Polygon" || name == "MultiPolygon") {
                fail(at, "missing \"coordinates\" for a " + name);
            }
        }
        const Json& c = coordinates == j.end() ? j : *coordinates;
        if (name == "Point") {
            return {Point{readPosition(c, coordinatesAt).toGeodetic()}};
        }
        if (name == "MultiPoint") {
            return {MultiPoint{readPositions(c, coordinatesAt)}};
        }
        if (name == "LineString") {
            return {readLine(c, coordinatesAt)};
        }
        if (name == "MultiLineString") {
            requireArray(c, coordinatesAt, "an array of lines");
            MultiLineString lines;
            lines.lines.reserve(c.size());
            for (std::size_t i = 0; i < c.size(); ++i) {
                lines.lines.push_back(readLine(c[i], coordinatesAt.element(i)));
            }
            return {std::move(lines)};
        }
        if (name == "Polygon") {
            return {readPolygon(c, coordinatesAt)};
        }
        if (name == "MultiPolygon") {
            requireArray(c, coordinatesAt, "an array of polygons");
            MultiPolygon polygons;
            polygons.polygons.reserve(c.size());
            for (std::size_t i = 0; i < c.size(); ++i) {
                polygons.polygons.push_back(readPolygon(c[i], coordinatesAt.element(i)));
            }
            return {std::move(polygons)};
        }
        fail(at.member("type"), "unknown geometry type \"" + name +
                                    "\" (expected Point, MultiPoint, LineString, MultiLineString, Polygon, "
                                    "MultiPolygon or GeometryCollection)");
    }

private:
    std::vector<Geodetic3D> readPositions(const Json& j, const PathNode& at)
    {
        requireArray(j, at, "an array of positions");
        std::vector<Geodetic3D> positions;
        positions.reserve(j.size());
        for (std::size_t i = 0; i < j.size(); ++i) {
            positions.push_back(readPosition(j[i], at.element(i)).toGeodetic());
        }
        return positions;
    }

    LineString readLine(const Json& j, const PathNode& at)
    {
        LineString line{readPositions(j, at)};
        if (line.positions.size() == 1) {
            fail(at, "a LineString needs at least 2 positions, got 1");
        }
        return line;
    }

    LinearRing readRing(const Json& j, const PathNode& at)
    {
        requireArray(j, at, "a ring (an array of positions)");
        LinearRing ring;
        ring.reserve(j.size() + 1);
        PositionDegrees first{};
        PositionDegrees last{};
        for (std::size_t i = 0; i < j.size(); ++i) {
            last = readPosition(j[i], at.element(i));
            if (i == 0) {
                first = last;
            }
            ring.push_back(last.toGeodetic());
        }
        if (!ring.empty() && !(first == last)) {
            const std::string where = "first position (" + formatNumber(first.longitude) + ", " +
                                      formatNumber(first.latitude) + ") differs from the last (" +
                                      formatNumber(last.longitude) + ", " + formatNumber(last.latitude) + ")";
            if (!_options.closeOpenRings) {
                fail(at, "ring is not closed: " + where);
            }
            ring.push_back(ring.front());
            _notes.push_back({render(&at), "closed an open ring: " + where});
        }
        if (ring.size() < 4) {
            fail(at, "a ring needs at least 4 positions (3 corners and the first repeated), got " +
                         std::to_string(ring.size()));
        }
        return ring;
    }

    Polygon readPolygon(const Json& j, const PathNode& at)
    {
        requireArray(j, at, "an array of rings");
        Polygon polygon;
        polygon.rings.reserve(j.size());
        for (std::size_t i = 0; i < j.size(); ++i) {
            polygon.rings.push_back(readRing(j[i], at.element(i)));
        }
        return polygon;
    }

    const GeoJsonOptions& _options;
    std::vector<Invalid>& _notes;
};

PropertyValue toPropertyValue(const Json& j)
{
    switch (j.type()) {
    case Json::value_t::boolean:
        return j.get<bool>();
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float:
        return j.get<double>();
    case Json::value_t::string:
        return j.get<std::string>();
    case Json::value_t::array:
    case Json::value_t::object:
        return j.dump();
    default:
        return std::monostate{};
    }
}

/// Reads features and formats their errors with the file, the feature index and its name.
class FeatureReader {
public:
    FeatureReader(std::string_view source, const GeoJsonOptions& options, FeatureCollection& result)
        : _source(source), _options(options), _result(result)
    {
    }

    /// Reads one Feature object; with skipInvalidFeatures, a bad one becomes a warning.
    void readFeature(const Json& j, std::size_t index)
    {
        Feature feature;
        feature.index = index;
        std::vector<Invalid> notes;
        const PathNode root;
        try {
            if (!j.is_object()) {
                fail(root, "expected a Feature object, got " + describe(j));
            }
            readIdAndProperties(j, root, feature);
            const auto type = j.find("type");
            if (type == j.end()) {
                fail(root, "missing \"type\" (expected \"Feature\")");
            }
            if (!type->is_string() || type->get_ref<const std::string&>() != "Feature") {
                fail(root.member("type"), "expected \"Feature\", got " + describe(*type));
            }
            const auto geometry = j.find("geometry");
            if (geometry == j.end()) {
                fail(root, "missing \"geometry\" (use null for a feature without one)");
            }
            if (!geometry->is_null()) {
                feature.geometry = GeometryReader(_options, notes).read(*geometry, root.member("geometry"));
            }
        } catch (const Invalid& invalid) {
            report(invalid, feature);
            return;
        }
        for (const Invalid& note : notes) {
            _result.warnings.push_back(prefix(feature) + note.path + ": " + note.message);
        }
        _result.features.push_back(std::move(feature));
    }

    /// Reads a bare geometry at top level as a feature without properties.
    void readTopLevelGeometry(const Json& j)
    {
        Feature feature;
        std::vector<Invalid> notes;
        try {
            feature.geometry = GeometryReader(_options, notes).read(j, PathNode{});
        } catch (const Invalid& invalid) {
            const std::string message = std::string(_source) + ": " + joinPath(invalid);
            if (!_options.skipInvalidFeatures) {
                throw Error(message);
            }
            _result.warnings.push_back("skipped the geometry: " + message);
            return;
        }
        for (const Invalid& note : notes) {
            _result.warnings.push_back(std::string(_source) + ": " + joinPath(note));
        }
        _result.features.push_back(std::move(feature));
    }

private:
    static std::string joinPath(const Invalid& invalid)
    {
        return invalid.path.empty() ? invalid.message : invalid.path + ": " + invalid.message;
    }

    void readIdAndProperties(const Json& j, const PathNode& root, Feature& feature)
    {
        if (const auto id = j.find("id"); id != j.end()) {
            if (id->is_string()) {
                feature.id = id->get<std::string>();
            } else if (id->is_number()) {
                feature.id = id->dump();
            } else {
                fail(root.member("id"), "expected a string or a number, got " + describe(*id));
            }
        }
        const auto properties = j.find("properties");
        if (properties == j.end() || properties->is_null()) {
            return;
        }
        if (!properties->is_object()) {
            fail(root.member("properties"), "expected an object or null, got " + describe(*properties));
        }
        for (const auto& [key, value] : properties->items()) {
            feature.properties.emplace(key, toPropertyValue(value));
        }
    }

    /// `file: feature 12 (name "Fiji"): `
    std::string prefix(const Feature& feature) const
    {
        std::string text = std::string(_source) + ": feature " + std::to_string(feature.index);
        static constexpr std::string_view kNameKeys[] = {"name", "NAME", "Name", "name_en", "NAME_EN",
                                                         "admin", "ADMIN", "title"};
        for (std::string_view key : kNameKeys) {
            if (auto name = feature.stringProperty(key)) {
                return text + " (" + std::string(key) + " \"" + *name + "\"): ";
            }
        }
        if (feature.id) {
            return text + " (id \"" + *feature.id + "\"): ";
        }
        return text + ": ";
    }

    void report(const Invalid& invalid, const Feature& feature)
    {
        const std::string message = prefix(feature) + joinPath(invalid);
        if (!_options.skipInvalidFeatures) {
            throw Error(message);
        }
        _result.warnings.push_back("skipped " + message);
    }

    std::string_view _source;
    const GeoJsonOptions& _options;
    FeatureCollection& _result;
};

/// Line and column (both from 1) of a byte offset (from 0) in `text`.
std::pair<std::size_t, std::size_t> lineAndColumn(std::string_view text, std::size_t offset)
{
    offset = std::min(offset, text.size());
    const std::string_view before = text.substr(0, offset);
    const std::size_t line = 1 + static_cast<std::size_t>(std::count(before.begin(), before.end(), '\n'));
    const std::size_t lastNewline = before.rfind('\n');
    const std::size_t column = lastNewline == std::string_view::npos ? offset + 1 : offset - lastNewline;
    return {line, column};
}

/// The JSON document of GeoJSON or TopoJSON text, or an Error naming the file, line and column.
Json parseDocument(std::string_view text, const std::string& source)
{
    constexpr std::size_t kMaxDepth = 256;
    if (const std::size_t offset = detail::firstBracketDeeperThan(text, kMaxDepth); offset != std::string_view::npos) {
        const auto [line, column] = lineAndColumn(text, offset);
        throw Error(source + ": JSON nested deeper than " + std::to_string(kMaxDepth) + " levels at line " +
                    std::to_string(line) + ", column " + std::to_string(column) + " (byte " + std::to_string(offset) +
                    ")");
    }
    Json document;
    try {
        document = Json::parse(text.begin(), text.end());
    } catch (const Json::parse_error& error) {
        // nlohmann counts the bytes read, so the offending byte is the one before.
        const std::size_t offset = error.byte > 0 ? error.byte - 1 : 0;
        const auto [line, column] = lineAndColumn(text, offset);
        std::string detail = error.what();
        if (const std::size_t colon = detail.find(": "); colon != std::string::npos) {
            detail = detail.substr(colon + 2);
        }
        throw Error(source + ": JSON syntax error at line " + std::to_string(line) + ", column " +
                    std::to_string(column) + " (byte " + std::to_string(offset) + "): " + detail);
    } catch (const Json::out_of_range& error) {
        // "number overflow parsing '1e999'": nlohmann gives no offset, so find the number's text.
        const std::string detail = error.what();
        const std::size_t open = detail.find('\'');
        const std::size_t close = detail.rfind('\'');
        const std::string number =
            open == std::string::npos || close <= open ? std::string() : detail.substr(open + 1, close - open - 1);
        const std::size_t offset = number.empty() ? std::string_view::npos : text.find(number);
        if (offset == std::string_view::npos) {
            throw Error(source + ": JSON number out of range: " + detail);
        }
        const auto [line, column] = lineAndColumn(text, offset);
        throw Error(source + ": JSON number out of range at line " + std::to_string(line) + ", column " +
                    std::to_string(column) + " (byte " + std::to_string(offset) + "): " + number);
    }
    return document;
}

bool isTopology(const Json& document)
{
    const auto type = document.is_object() ? document.find("type") : document.end();
    return type != document.end() && type->is_string() && type->get_ref<const std::string&>() == "Topology";
}

/// The features of a GeoJSON document, each polygon's outer ring first (see putOuterRingsFirst).
FeatureCollection readFeatures(const Json& document, const std::string& source, const GeoJsonOptions& options)
{
    FeatureCollection result;
    FeatureReader reader(source, options, result);
    if (!document.is_object()) {
        throw Error(source + ": expected a GeoJSON object at top level, got " + describe(document));
    }
    const auto type = document.find("type");
    if (type == document.end() || !type->is_string()) {
        throw Error(source + ": the top-level object has no \"type\" string (expected FeatureCollection, "
                             "Feature or a geometry)");
    }
    const std::string& name = type->get_ref<const std::string&>();
    if (name == "FeatureCollection") {
        const auto features = document.find("features");
        if (features == document.end() || !features->is_array()) {
            throw Error(source + ": features: expected an array of features, got " +
                        (features == document.end() ? std::string("nothing") : describe(*features)));
        }
        result.features.reserve(features->size());
        for (std::size_t i = 0; i < features->size(); ++i) {
            reader.readFeature((*features)[i], i);
        }
    } else if (name == "Feature") {
        reader.readFeature(document, 0);
    } else if (name == "Point" || name == "MultiPoint" || name == "LineString" || name == "MultiLineString" ||
               name == "Polygon" || name == "MultiPolygon" || name == "GeometryCollection") {
        reader.readTopLevelGeometry(document);
    } else {
        throw Error(source + ": type: unknown GeoJSON type \"" + name +
                    "\" (expected FeatureCollection, Feature, a geometry type or a TopoJSON Topology)");
    }
    detail::putOuterRingsFirst(result, detail::detectRingConvention(result));
    return result;
}

FeatureCollection readTopology(const Json& topology, const std::string& source, std::string_view objectName,
                               const GeoJsonOptions& options)
{
    std::vector<std::string> warnings;
    const Json features = detail::topologyToGeoJson(topology, source, objectName, warnings);
    FeatureCollection result = readFeatures(features, source, options);
    result.warnings.insert(result.warnings.begin(), warnings.begin(), warnings.end());
    return result;
}

} // namespace

FeatureCollection parseGeoJson(std::string_view text, std::string_view sourceName, const GeoJsonOptions& options)
{
    const std::string source(sourceName);
    const Json document = parseDocument(text, source);
    return isTopology(document) ? readTopology(document, source, {}, options) : readFeatures(document, source, options);
}

FeatureCollection parseTopoJson(std::string_view text, std::string_view sourceName, std::string_view objectName,
                                const GeoJsonOptions& options)
{
    const std::string source(sourceName);
    const Json document = parseDocument(text, source);
    if (!isTopology(document)) {
        throw Error(source + ": expected a TopoJSON Topology (\"type\": \"Topology\")");
    }
    return readTopology(document, source, objectName, options);
}

FeatureCollection loadTopoJson(const std::filesystem::path& path, std::string_view objectName, const GeoJsonOptions& options)
{
    return parseTopoJson(readTextFile(path, "TopoJSON"), path.string(), objectName, options);
}

FeatureCollection loadGeoJson(const std::filesystem::path& path, const GeoJsonOptions& options)
{
    return parseGeoJson(readTextFile(path, "GeoJSON"), path.string(), options);
}

} // namespace orbis::world
