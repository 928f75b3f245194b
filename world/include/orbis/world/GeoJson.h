#pragma once

#include <orbis/world/Feature.h>

#include <filesystem>
#include <string_view>

namespace orbis::world {

/// How loadGeoJson treats bad features and open rings.
struct GeoJsonOptions {
    /// false: the first invalid feature throws. true: invalid features are left out and each is
    /// described in FeatureCollection::warnings; errors outside any feature still throw.
    bool skipInvalidFeatures = false;
    /// false: a ring whose last position differs from its first is an error (RFC 7946 requires
    /// closed rings; an open ring often means a truncated or mangled file). true: the first
    /// position is appended to close it and a warning says so.
    bool closeOpenRings = false;
};

/// Reads a GeoJSON file (RFC 7946): a FeatureCollection, a single Feature or a bare Geometry (a
/// Feature or Geometry at top level gives a collection of one). Positions are [longitude,
/// latitude(, height)] in degrees and metres, converted to radians; longitudes must lie in
/// [-180, 180], latitudes in [-90, 90]; numbers must be finite; a LineString needs 2 positions, a
/// ring 4 and closed (see GeoJsonOptions::closeOpenRings); members beyond the third of a position,
/// "bbox" and foreign members are ignored. Throws orbis::Error naming the file, the feature index
/// (and its name when it has one), the JSON path inside the feature and what is wrong, e.g.
///   countries.geojson: feature 12 (name "Fiji"): geometry.coordinates[0][3]: latitude 95 out of range [-90, 90]
/// JSON syntax errors name the file, line, column and byte offset.
///
/// Polygons come with their outer ring first (Polygon::rings[0]) whichever convention the file
/// follows: RFC 7946's (outer rings counter-clockwise) or d3's and TopoJSON's spherical one
/// (clockwise), told apart by how the polygons' first rings wind on the sphere; where a first ring
/// bounds no area of its polygon by that convention and another does (Antarctica in files made by
/// topojson-client: a small ring round the pole, then the coast), the one that does goes first.
/// A TopoJSON Topology is read too, all its objects (see loadTopoJson).
FeatureCollection loadGeoJson(const std::filesystem::path& path, const GeoJsonOptions& options = {});

/// Parses GeoJSON text already in memory; `sourceName` stands for the file in messages.
FeatureCollection parseGeoJson(std::string_view text, std::string_view sourceName,
                               const GeoJsonOptions& options = {});

} // namespace orbis::world
