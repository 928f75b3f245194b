#pragma once

#include <orbis/world/GeoJson.h>

#include <filesystem>
#include <string_view>

namespace orbis::world {

/// Reads a TopoJSON Topology (the TopoJSON 1.0 specification; world-atlas's Natural Earth files
/// are such) into the features topojson-client's feature() makes of it: a GeometryCollection
/// object gives one feature per geometry (with its "properties" and "id"), any other object one
/// feature; `objectName` picks one object ("countries"), empty takes them all in the order of their names.
/// Quantized arcs (a "transform") are decoded; each line or ring is its arcs joined. The features
/// are then checked and converted as loadGeoJson does (GeoJsonOptions apply alike, and polygons
/// get their outer ring first whichever way the file winds them), so errors read alike too.
/// loadGeoJson reads a Topology as well (all its objects). Throws orbis::Error naming the file.
FeatureCollection loadTopoJson(const std::filesystem::path& path, std::string_view objectName = {},
                               const GeoJsonOptions& options = {});

/// Parses TopoJSON text already in memory; `sourceName` stands for the file in messages.
FeatureCollection parseTopoJson(std::string_view text, std::string_view sourceName, std::string_view objectName = {},
                                const GeoJsonOptions& options = {});

} // namespace orbis::world
