#pragma once

// Which ring of a polygon is its outside: GeoJSON files come in two conventions, and the rest of
// Orbis reads rings[0] as the outer boundary. Internal to orbis::world.

#include "orbis/world/Feature.h"

namespace orbis::world::detail {

/// How a file winds its rings: RFC 7946 runs an outer ring counter-clockwise round the region it
/// bounds (the region on its left), d3 and TopoJSON clockwise (on its right: their spherical
/// convention, where the winding rather than the order says which side is inside).
enum class RingConvention { Rfc7946, Spherical };

/// The convention of a collection's polygons, from the winding on the sphere of each polygon's
/// first ring round the smaller region it bounds: Spherical when more of them run clockwise.
RingConvention detectRingConvention(const FeatureCollection& features);

/// Puts the outer ring first where a polygon's first ring, by the convention, bounds no area of
/// the polygon but another ring does (as in Natural Earth's Antarctica at 1:50m from world-atlas:
/// a small ring round the pole, then the coastline). A polygon with several rings that bound area
/// becomes that many polygons (a MultiPolygon), each hole going to the one that holds it. Polygons
/// whose first ring bounds area, or none does, stay as they are (holes are then read by their
/// place, whatever their winding, as files that follow no convention need).
void putOuterRingsFirst(FeatureCollection& features, RingConvention convention);

} // namespace orbis::world::detail
