#pragma once

// TopoJSON as the GeoJSON reader reads it: a Topology turned into the FeatureCollection it stands
// for, so that one reader checks the geometries of both formats and their errors read alike.
// Internal to orbis::world.

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace orbis::world::detail {

/// The GeoJSON FeatureCollection of a TopoJSON Topology (the TopoJSON 1.0 specification): each
/// object's geometries as features, the way topojson-client's feature() makes them (a
/// GeometryCollection object gives a feature per geometry, with its "properties" and "id"; any
/// other object one feature); `objectName` picks one object, empty takes them all in the order of
/// their names. Arcs are decoded (with a "transform", delta-encoded integers times "scale" plus
/// "translate"), and each line or ring is its arcs joined, an arc's first position dropped after
/// the first arc, arc ~i being arc i reversed. Quantization collapses small islands and lakes to
/// rings of fewer than 4 positions: those rings are left out (a polygon whose outer ring goes, goes
/// with it), each with a line in `warnings`. Throws orbis::Error naming `source`, the JSON path
/// and what is wrong (an arc index out of range, a transform that is no pair of numbers, ...).
nlohmann::json topologyToGeoJson(const nlohmann::json& topology, const std::string& source, std::string_view objectName,
                                 std::vector<std::string>& warnings);

} // namespace orbis::world::detail
