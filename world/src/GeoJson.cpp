#include "orbis/world/GeoJson.h"

#include "orbis/core/Error.h"
#include "orbis/core/Math.h"
#include "orbis/world/Diagnostics.h"
#include "orbis/world/FileAccess.h"

#include "orbis/world/TopoJson.h"

#include "JsonText.h"
#include "RingConvention.h"
#include "TopoJsonDocument.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>

namespace orbis::world {

using Json = nlohmann::json;
using detail::describeJson;

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

std::optional<std::pair<std::string_view, std::string>> Feature::nameProperty() const
{
    // What common datasets call a feature: Natural Earth's and OpenStreetMap's keys, then the
    // country codes of datasets that carry only those (@geo-maps: A3).
    for (const std::string_view key : {"name", "NAME", "Name", "name_en", "NAME_EN", "admin", "ADMIN", "NAME_LONG", "title",
                                       "A3", "ISO_A3", "iso_a3", "ADM0_A3"}) {
        if (std::optional<std::string> text = stringProperty(key); text && !text->empty()) {
            return std::pair{key, std::move(*text)};
        }
    }
    return std::nullopt;
}

std::optional<std::string> Feature::name() const
{
    if (auto named = nameProperty()) {
        return std::move(named->second);
    }
    return id;
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

/// The JSON pointer of a path, relative to the feature (or top-level geometry).
std::string pointerOf(const PathNode* node)
{
    std::string pointer;
    for (; node && (node->parent || !node->key.empty()); node = node->parent) {
        // Appended rather than "/" + to_string: GCC 12 -O3 warns falsely (-Wrestrict) on that.
        std::string step = "/";
        if (node->key.empty()) {
            step.append(std::to_string(node->index));
        } else {
            step = detail::appendToPointer("", node->key);
        }
        pointer.insert(0, step);
    }
    return pointer;
}

/// What is wrong inside one feature (or a top-level geometry), before the feature is named.
struct Invalid {
    std::string path;    ///< "geometry.coordinates[0][3]"
    std::string pointer; ///< "/geometry/coordinates/0/3", to find it in the text
    std::string message;
};

[[noreturn]] void fail(const PathNode& at, std::string message)
{
    throw Invalid{render(&at), pointerOf(&at), std::move(message)};
}

const Json& requireArray(const Json& j, const PathNode& at, const char* what)
{
    if (!j.is_array()) {
        fail(at, std::string("expected ") + what + ", got " + describeJson(j));
    }
    return j;
}

double readNumber(const Json& j, const PathNode& at, const char* what)
{
    if (!j.is_number()) {
        fail(at, std::string("expected a number (") + what + "), got " + describeJson(j));
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
        fail(at, "expected a position [longitude, latitude], got " + describeJson(j));
    }
    if (j.size() < 2) {
        fail(at, "a position needs longitude and latitude, got " + describeJson(j));
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
            fail(at, "expected a geometry object, got " + describeJson(j));
        }
        const auto type = j.find("type");
        if (type == j.end()) {
            fail(at, "missing \"type\"");
        }
        if (!type->is_string()) {
            fail(at.member("type"), "expected a geometry type name, got " + describeJson(*type));
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
            _notes.push_back({render(&at), pointerOf(&at), "closed an open ring: " + where});
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
    FeatureReader(std::string_view text, std::string_view source, const GeoJsonOptions& options,
                  FeatureCollection& result)
        : _text(text), _source(source), _options(options), _result(result)
    {
    }

    /// Reads one Feature object (at `pointer` in the text); with skipInvalidFeatures, a bad one
    /// becomes a warning.
    void readFeature(const Json& j, std::size_t index, std::string pointer)
    {
        _pointer = std::move(pointer);
        Feature feature;
        feature.index = index;
        std::vector<Invalid> notes;
        const PathNode root;
        try {
            if (!j.is_object()) {
                fail(root, "expected a Feature object, got " + describeJson(j));
            }
            readIdAndProperties(j, root, feature);
            const auto type = j.find("type");
            if (type == j.end()) {
                fail(root, "missing \"type\" (expected \"Feature\")");
            }
            if (!type->is_string() || type->get_ref<const std::string&>() != "Feature") {
                fail(root.member("type"), "expected \"Feature\", got " + describeJson(*type));
            }
            const auto geometry = j.find("geometry");
            if (geometry == j.end()) {
                fail(root, "missing \"geometry\" (use null for a feature without one)");
            }
            if (!geometry->is_null()) {
                feature.geometry = GeometryReader(_options, notes).read(*geometry, root.member("geometry"));
            }
        } catch (const Invalid& invalid) {
            report(fault(featureName(feature), invalid));
            return;
        }
        for (const Invalid& note : notes) {
            _result.warnings.push_back(fault(featureName(feature), note));
        }
        _result.features.push_back(std::move(feature));
    }

    /// Reads a bare geometry at top level as a feature without properties.
    void readTopLevelGeometry(const Json& j)
    {
        Feature feature;
        std::vector<Invalid> notes;
        _pointer.clear();
        try {
            feature.geometry = GeometryReader(_options, notes).read(j, PathNode{});
        } catch (const Invalid& invalid) {
            const std::string message = fault("", invalid);
            if (!_options.skipInvalidFeatures) {
                throw Error(message);
            }
            _result.warnings.push_back("skipped the geometry: " + message);
            return;
        }
        for (const Invalid& note : notes) {
            _result.warnings.push_back(fault("", note));
        }
        _result.features.push_back(std::move(feature));
    }

private:
    /// As every reader states a fault: the file, the line and column of the value at fault, the
    /// feature and the path inside it, and what is wrong.
    std::string fault(const std::string& feature, const Invalid& invalid) const
    {
        const detail::TextPosition position = detail::positionOf(_text, _pointer + invalid.pointer, false);
        std::string where = feature;
        if (!invalid.path.empty()) {
            where += (where.empty() ? "" : ": ") + invalid.path;
        }
        return Diagnostic{std::string(_source), position.line, position.column, where, invalid.message}.text();
    }

    void readIdAndProperties(const Json& j, const PathNode& root, Feature& feature)
    {
        if (const auto id = j.find("id"); id != j.end()) {
            if (id->is_string()) {
                feature.id = id->get<std::string>();
            } else if (id->is_number()) {
                feature.id = id->dump();
            } else {
                fail(root.member("id"), "expected a string or a number, got " + describeJson(*id));
            }
        }
        const auto properties = j.find("properties");
        if (properties == j.end() || properties->is_null()) {
            return;
        }
        if (!properties->is_object()) {
            fail(root.member("properties"), "expected an object or null, got " + describeJson(*properties));
        }
        for (const auto& [key, value] : properties->items()) {
            feature.properties.emplace(key, toPropertyValue(value));
        }
    }

    /// `feature 12 (name "Fiji")`
    static std::string featureName(const Feature& feature)
    {
        const std::string text = "feature " + std::to_string(feature.index);
        if (const auto named = feature.nameProperty()) {
            return text + " (" + std::string(named->first) + " " + quote(named->second) + ")";
        }
        if (feature.id) {
            return text + " (id " + quote(*feature.id) + ")";
        }
        return text;
    }

    void report(const std::string& message)
    {
        if (!_options.skipInvalidFeatures) {
            throw Error(message);
        }
        _result.warnings.push_back("skipped " + message);
    }

    std::string_view _text;
    std::string_view _source;
    std::string _pointer; ///< of the feature being read
    const GeoJsonOptions& _options;
    FeatureCollection& _result;
};

/// A fault of the document as a whole, at the value a pointer names.
[[noreturn]] void failDocument(std::string_view text, const std::string& source, const std::string& pointer,
                               std::string where, std::string what)
{
    const detail::TextPosition position = detail::positionOf(text, pointer, false);
    throw Error(Diagnostic{source, position.line, position.column, std::move(where), std::move(what)}.text());
}

/// The JSON document of GeoJSON or TopoJSON text, or an Error naming the file, line and column.
Json parseDocument(std::string_view text, const std::string& source)
{
    constexpr std::size_t kMaxDepth = 256;
    std::variant<Json, Diagnostic> parsed = detail::parseJson<Json>(text, source, kMaxDepth);
    if (const auto* fault = std::get_if<Diagnostic>(&parsed)) {
        throw Error(fault->text());
    }
    return std::move(std::get<Json>(parsed));
}

bool isTopology(const Json& document)
{
    const auto type = document.is_object() ? document.find("type") : document.end();
    return type != document.end() && type->is_string() && type->get_ref<const std::string&>() == "Topology";
}

/// The features of a GeoJSON document, each polygon's outer ring first (see putOuterRingsFirst);
/// `text` is the document's text, for positions in messages (empty for a converted topology).
FeatureCollection readFeatures(std::string_view text, const Json& document, const std::string& source,
                               const GeoJsonOptions& options)
{
    FeatureCollection result;
    FeatureReader reader(text, source, options, result);
    if (!document.is_object()) {
        failDocument(text, source, "", "", "expected a GeoJSON object at top level, got " + describeJson(document));
    }
    const auto type = document.find("type");
    if (type == document.end() || !type->is_string()) {
        failDocument(text, source, "", "",
                     "the top-level object has no \"type\" string (expected FeatureCollection, Feature or a geometry)");
    }
    const std::string& name = type->get_ref<const std::string&>();
    if (name == "FeatureCollection") {
        const auto features = document.find("features");
        if (features == document.end() || !features->is_array()) {
            failDocument(text, source, "/features", "features",
                         "expected an array of features, got " +
                             (features == document.end() ? std::string("nothing") : describeJson(*features)));
        }
        result.features.reserve(features->size());
        for (std::size_t i = 0; i < features->size(); ++i) {
            reader.readFeature((*features)[i], i, "/features/" + std::to_string(i));
        }
    } else if (name == "Feature") {
        reader.readFeature(document, 0, "");
    } else if (name == "Point" || name == "MultiPoint" || name == "LineString" || name == "MultiLineString" ||
               name == "Polygon" || name == "MultiPolygon" || name == "GeometryCollection") {
        reader.readTopLevelGeometry(document);
    } else {
        failDocument(text, source, "/type", "type",
                     "unknown GeoJSON type " + quote(name) +
                         " (expected FeatureCollection, Feature, a geometry type or a TopoJSON Topology)");
    }
    detail::putOuterRingsFirst(result, detail::detectRingConvention(result));
    return result;
}

FeatureCollection readTopology(const Json& topology, const std::string& source, std::string_view objectName,
                               const GeoJsonOptions& options)
{
    std::vector<std::string> warnings;
    const Json features = detail::topologyToGeoJson(topology, source, objectName, warnings);
    FeatureCollection result = readFeatures({}, features, source, options);
    result.warnings.insert(result.warnings.begin(), warnings.begin(), warnings.end());
    return result;
}

} // namespace

FeatureCollection parseGeoJson(std::string_view text, std::string_view sourceName, const GeoJsonOptions& options)
{
    const std::string source(sourceName);
    const Json document = parseDocument(text, source);
    return isTopology(document) ? readTopology(document, source, {}, options) : readFeatures(text, document, source, options);
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
    const std::vector<std::uint8_t> bytes = readFileBytes(path, "TopoJSON file");
    return parseTopoJson(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path.string(),
                         objectName, options);
}

FeatureCollection loadGeoJson(const std::filesystem::path& path, const GeoJsonOptions& options)
{
    const std::vector<std::uint8_t> bytes = readFileBytes(path, "GeoJSON file");
    return parseGeoJson(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path.string(),
                        options);
}

} // namespace orbis::world
