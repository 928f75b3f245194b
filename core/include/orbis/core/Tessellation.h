#pragma once

// What every tessellator shares: the attributes it can emit, its result, and the measure of how far
// a triangle mesh departs from an ellipsoid.
//
//     const TessellationResult r = SubdivisionEllipsoidTessellator::compute(
//         Ellipsoid::wgs84(), 5, EllipsoidProjection::Geocentric, VertexAttributes::Normal);
//     // r.mesh has 4098 vertices and 8192 triangles; *r.maxDeviationMeters is about 6.2 km.

#include "orbis/core/Mesh.h"

#include <cstdint>
#include <optional>

namespace orbis {

class Ellipsoid;

/// Per-vertex attributes a tessellator emits besides positions; combine them with |.
enum class VertexAttributes : std::uint8_t {
    Position = 0,          ///< positions only
    Normal = 1,            ///< unit surface normals (floats)
    TextureCoordinate = 2, ///< (u, v) in [0, 1]; for the globe meshes u from longitude, v from latitude
    All = Normal | TextureCoordinate,
};

/// The union of two attribute sets.
constexpr VertexAttributes operator|(VertexAttributes a, VertexAttributes b) noexcept
{
    return static_cast<VertexAttributes>(static_cast<std::uint8_t>(a) | static_cast<std::uint8_t>(b));
}

/// True when set includes every attribute of wanted (always true for Position).
constexpr bool contains(VertexAttributes set, VertexAttributes wanted) noexcept
{
    return (static_cast<std::uint8_t>(set) & static_cast<std::uint8_t>(wanted)) == static_cast<std::uint8_t>(wanted);
}

/// Whether a tessellator measures its deviation: measuring samples every triangle about a hundred
/// times, which costs far more than building the mesh.
enum class Deviation : bool { Skip, Measure };

/// A tessellated mesh and how far it departs from the surface it stands for.
struct TessellationResult {
    Mesh mesh;
    /// Greatest distance in metres between the triangles and the surface, as maxDeviationFromEllipsoid
    /// measures it; empty when Deviation::Skip was asked for.
    std::optional<double> maxDeviationMeters;
};

/// Greatest distance in metres between a point of mesh's triangles and ellipsoid's surface; 0 for a
/// mesh with no triangles (only PrimitiveType::Triangles is read).
///
/// Method: each triangle is sampled on a barycentric grid of 6 steps per edge (28 points: the
/// corners, the edge midpoints and thirds, the centroid), plus the point where the triangle is
/// deepest if the ellipsoid were scaled to a unit sphere. The distance of a point is the absolute
/// value of its height from Ellipsoid::toGeodetic3D (exact to nanometres). From the best sample a
/// compass search in barycentric coordinates refines the maximum down to steps of 2^-13 of the
/// edges. A triangle whose corners lie on the surface lies inside the ellipsoid, where the depth is
/// a concave function, so the search finds its global maximum to about 1e-7 relative; for a
/// triangle outside (a box, a tangent plane) the distance is convex and its maximum is at a
/// corner, which is sampled exactly.
double maxDeviationFromEllipsoid(const Mesh& mesh, const Ellipsoid& ellipsoid);

/// Which surface point stands for a direction from the centre, for the tessellators that start
/// from a unit sphere or a cube.
enum class EllipsoidProjection {
    Geocentric, ///< where the ray from the centre meets the surface (Ellipsoid::scaleToGeocentricSurface)
    Geodetic,   ///< the surface point whose geodetic normal is the direction (so latitude = the direction's)
};

} // namespace orbis
