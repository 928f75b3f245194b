#pragma once

// Vector features as loaded from files (GeoJSON, CSV): geometries on the ellipsoid plus properties.
// Plain data, no GPU resources; polylines, polygons and billboards are built from them.

#include <orbis/core/Geodetic.h>

#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

namespace orbis::world {

/// A feature property: null, a boolean, a number or a string. GeoJSON arrays and objects are kept
/// as their compact JSON text in the string alternative; integers beyond 2^53 lose precision.
using PropertyValue = std::variant<std::monostate, bool, double, std::string>;

/// Properties by name; find() takes a std::string_view without allocating.
using Properties = std::map<std::string, PropertyValue, std::less<>>;

/// One position. Longitude and latitude in radians, height in metres (0 when the file has none).
struct Point {
    Geodetic3D position;
};

/// Unconnected positions.
struct MultiPoint {
    std::vector<Geodetic3D> positions;
};

/// A line through at least two positions.
struct LineString {
    std::vector<Geodetic3D> positions;
};

/// Several lines.
struct MultiLineString {
    std::vector<LineString> lines;
};

/// A closed ring: at least four positions, the last equal to the first.
using LinearRing = std::vector<Geodetic3D>;

/// rings[0] is the outer boundary, the others are holes. Winding is kept as in the file (the readers
/// put the outer ring first whichever convention the file follows: see loadGeoJson).
struct Polygon {
    std::vector<LinearRing> rings;
};

/// Several polygons.
struct MultiPolygon {
    std::vector<Polygon> polygons;
};

struct Geometry;

/// Geometries of any kind, nested collections included.
struct GeometryCollection {
    std::vector<Geometry> geometries;
};

/// One geometry of any GeoJSON kind. Use std::get_if / std::visit on `value`.
struct Geometry {
    std::variant<Point, MultiPoint, LineString, MultiLineString, Polygon, MultiPolygon, GeometryCollection> value;
};

/// A geometry (absent for an unlocated feature, "geometry": null) with its properties.
struct Feature {
    std::optional<Geometry> geometry;
    Properties properties;
    std::optional<std::string> id; ///< the feature's "id"; a number id is kept as its JSON text
    std::size_t index = 0;         ///< position of the feature in the file, counted from 0

    /// The property's value, or nullptr when the feature has no property of that name.
    const PropertyValue* property(std::string_view name) const;
    /// The property when it is a string, otherwise empty (absent, null, number or bool).
    std::optional<std::string> stringProperty(std::string_view name) const;
    /// The property that names the feature, for messages, and its value: the first non-empty
    /// string among "name", "NAME", "Name", "name_en", "NAME_EN", "admin", "ADMIN", "NAME_LONG",
    /// "title", "A3", "ISO_A3", "iso_a3" and "ADM0_A3"; empty when it has none of them.
    std::optional<std::pair<std::string_view, std::string>> nameProperty() const;
    /// What the feature is called, for messages: nameProperty's value, else its id.
    std::optional<std::string> name() const;
    /// The property when it is a number, otherwise empty.
    std::optional<double> numberProperty(std::string_view name) const;
};

/// Features in file order, plus what was skipped when the loader was asked to skip bad ones.
struct FeatureCollection {
    std::vector<Feature> features;
    std::vector<std::string> warnings; ///< one line per skipped feature or repaired ring, naming the file
};

} // namespace orbis::world
