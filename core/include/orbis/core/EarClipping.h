#pragma once

#include <glm/vec2.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace orbis {

/// A hole a triangulation left out because it was invalid with the rest of its polygon (see
/// earClip's leftOutHoles).
struct LeftOutHole {
    std::size_t ring = 0; ///< its index in the rings given
    std::string reason;   ///< e.g. "it lies outside the outer ring (or on it)"
};

/// The triangles of a polygon, as indices into its vertices.
struct PolygonTriangles {
    /// Three indices per triangle, counter-clockwise (seen from above the plane, or from outside
    /// the ellipsoid), into the polygon's rings concatenated in order (outer ring first).
    std::vector<std::uint32_t> indices;
    /// Vertices triangulated: those left after the clean-up (duplicates removed).
    std::size_t vertexCount = 0;
    /// Holes triangulated: those left after the clean-up (holes with no area are dropped).
    std::size_t holeCount = 0;
    /// Vertices removed to undo crossings next to spikes (see earClip); not in vertexCount.
    std::size_t repairedVertices = 0;
    /// The area those removals took away (the triangles each removed vertex made with its
    /// neighbours), in the units of the plane squared: the triangles cover that much less than the
    /// rings' signed area. For earClipOnEllipsoid, square metres of the tangent plane: about the
    /// area on the ellipsoid, a little more away from the plane's origin (the projection enlarges).
    double repairedArea = 0.0;

    /// indices.size() / 3. Equals vertexCount + 2 holeCount - 2 unless the rings touch themselves
    /// or each other, or contain zero-width spikes (each such place takes two triangles fewer).
    std::size_t triangleCount() const noexcept { return indices.size() / 3; }
};

/// Default limit of earClip's repair of twisted loops: the area each removed vertex takes, relative
/// to the outer ring's (a small island quantized to 1e5 steps, as TopoJSON files are, can twist by
/// one step at 0.1% of its area).
inline constexpr double kSpikeRepairRelativeArea = 1e-2;

/// Triangulates a planar polygon by ear clipping (book section 8.2.1). Ears are clipped shortest
/// diagonal first, each tested against the vertices in its triangle that could be in its way (the
/// reflex ones, and those sharing a position) through a spatial index, and tested again only when
/// a vertex near it goes; the rings are checked for crossing and touching edges through a grid,
/// or, where long edges lie close together, a sweep line: about n log n for rings of similar edges
/// (a ring of 100,000 vertices in a tenth of a second), whatever their shape. A strictly convex
/// ring without holes needs no check; one of up to 32 vertices is triangulated at once (its
/// triangles zig-zag across it). A ring without holes that is strictly star-shaped (round its
/// vertices' mean, or, from 256 vertices, round a point of its kernel found by linear
/// programming; checked exactly) needs no check either, and its ears no search, in the same order,
/// until the ears left span half a turn or more from the centre: a round coast or a star of
/// 100,000 vertices in some 30 ms. Polygons of up to 32 vertices are tested without an index, and
/// each thread keeps the working memory between calls.
///
/// rings[0] is the outer boundary, the others are holes inside it; either winding is accepted
/// (the outer ring is made counter-clockwise, holes clockwise). A ring may repeat its first vertex
/// at the end, as GeoJSON does; consecutive duplicate vertices are removed. Collinear vertices are
/// kept and triangulated, exactly: orientation tests are exact, so no input makes it loop or emit
/// overlapping triangles. Holes are joined to the outer ring by bridges from their rightmost vertex
/// to a visible vertex (Eberly's method), checked exactly. Rings may touch at vertices, or a vertex
/// may touch an edge; they may not cross, with one exception: two edges with at most 16 edges
/// between them that cross (a small twisted loop: a spike whose tip has twisted over, as when data
/// simplified with straight edges in longitude and latitude is drawn with great-circle edges, or a
/// step back in quantized data) are repaired by removing vertices between them one at a time, each
/// time the one whose triangle with its neighbours is smallest, if that triangle holds at most
/// repairRelativeArea of the outer ring's area (0 turns the repair off).
///
/// An outer ring with fewer than 3 distinct vertices, or all of them on one line, gives no
/// triangles (and vertexCount the distinct vertices); holes with no area are dropped. Throws orbis::Error, with a message naming
/// `name` and the rings and vertices concerned, when a vertex is not finite, edges cross, a hole
/// lies outside the outer ring or inside another hole, or no triangulation is found.
///
/// With leftOutHoles given, a faulty hole is left out instead, and listed there, as data invalid
/// as published has them (OpenStreetMap's lakes): a hole outside the outer ring or inside another
/// hole (leaving it out changes nothing: it removes nothing from the polygon), or one whose edges
/// cross another ring's beyond repair (the smaller of two crossing holes goes: the polygon then
/// covers that hole's area inside the outer ring). Edges of the outer ring crossing each other
/// still throw.
PolygonTriangles earClip(std::span<const std::vector<glm::dvec2>> rings, std::string_view name = "polygon",
                         double repairRelativeArea = kSpikeRepairRelativeArea,
                         std::vector<LeftOutHole>* leftOutHoles = nullptr);

} // namespace orbis
