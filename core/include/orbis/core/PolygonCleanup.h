#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

namespace orbis {

/// Default tolerance of cleanRing in the plane, relative to the diagonal of the ring's bounding
/// box: a vertex that close to the line through its neighbours, or to its neighbour, is dropped.
inline constexpr double kPlanarRingTolerance = 1e-12;

/// Default tolerance of cleanRing on the ellipsoid, an angle seen from the centre: a vertex that
/// close to the curve through its neighbours is dropped. 1e-9 rad is about 6 mm on the Earth.
inline constexpr double kEllipsoidCollinearToleranceRadians = 1e-9;

/// Consecutive positions closer than this angle seen from the centre are one vertex on the
/// ellipsoid (about 6 micrometres on the Earth; (180, y) and (-180, y) in degrees are one vertex).
inline constexpr double kEllipsoidDuplicateToleranceRadians = 1e-12;

/// Which way a ring turns, seen from above the plane (or from outside the ellipsoid).
enum class Winding { CounterClockwise, Clockwise };

/// Indices of the vertices of ring that remain, in ring order, after removing consecutive duplicates
/// (the closing duplicate of a GeoJSON ring included), then collinear and near-collinear vertices
/// and the tips of zero-width spikes, repeatedly until none is left; a vertex is near-collinear when
/// it lies within relativeTolerance x (bounding-box diagonal) of the line through its neighbours.
/// Fewer than 3 indices means the ring has no area. Non-finite vertices are the caller's to reject.
std::vector<std::size_t> cleanRing(std::span<const glm::dvec2> ring, double relativeTolerance = kPlanarRingTolerance);

/// cleanRing on the ellipsoid (any ellipsoid centred at the origin): positions are compared by
/// their directions from the centre; duplicates are closer than kEllipsoidDuplicateToleranceRadians;
/// a vertex is near-collinear when it lies within toleranceRadians of the plane through the centre
/// and its neighbours (the plane whose cut is the edge the tessellators draw), and goes if the ring
/// turns back there (a spike) or if the short way between its neighbours passes it (so a ring
/// around a great circle keeps at least three vertices). Vertices flagged in keep (one flag per
/// vertex, or none) are never dropped as collinear, only merged with a duplicate neighbour: the
/// places where another ring touches this one, which must stay vertices of both.
std::vector<std::size_t> cleanRing(std::span<const glm::dvec3> ring,
                                   double toleranceRadians = kEllipsoidCollinearToleranceRadians,
                                   std::span<const bool> keep = {});

/// Signed area by the shoelace formula (relative to the first vertex, for precision): positive
/// when counter-clockwise, 0 for fewer than 3 vertices. The ring may or may not repeat its first vertex.
double signedArea(std::span<const glm::dvec2> ring) noexcept;

/// The winding of a planar ring by its signed area; nullopt when the area is 0.
std::optional<Winding> winding(std::span<const glm::dvec2> ring) noexcept;

/// Reverses ring in place if needed so that it has the given winding (as winding() judges it);
/// false, and the ring unchanged, when it has none (no area).
bool setWinding(std::span<glm::dvec2> ring, Winding wanted) noexcept;

/// Area, in steradians of the unit sphere of directions from the centre, of the region to the left
/// of the ring walked in order and seen from outside, its edges being cut by planes through the
/// centre. In [0, 4 pi); 0 for fewer than 3 vertices. Accurate to about 1e-15 x the number of edges;
/// an edge between antipodal vertices has no defined path and makes the result meaningless.
double leftSolidAngle(std::span<const glm::dvec3> ring) noexcept;

/// The winding of a ring on the ellipsoid around the smaller of the two regions it bounds
/// (by leftSolidAngle): counter-clockwise when that region is on its left seen from outside.
/// nullopt when the two regions are equal within 1e-9 sr, or the ring has no area.
std::optional<Winding> winding(std::span<const glm::dvec3> ring) noexcept;

/// Reverses ring in place if needed so that it winds as wanted around the smaller region it bounds
/// (as winding() on the ellipsoid judges it); false, and the ring unchanged, when that is ambiguous.
bool setWinding(std::span<glm::dvec3> ring, Winding wanted) noexcept;

} // namespace orbis
