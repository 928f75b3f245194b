#pragma once

#include "orbis/core/BoundingSphere.h"
#include "orbis/core/Ellipsoid.h"
#include "orbis/core/GeodeticExtent.h"
#include "orbis/core/OrientedBoundingBox.h"

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <optional>

namespace orbis {

/// The volume of a tile: a longitude-latitude rectangle of an ellipsoid between two heights, with
/// what tile selection asks of it (Rendering Massive Virtual Worlds, 3.3 and 3.6): an oriented box
/// for distances and frustum culling, a sphere, and a horizon occlusion point. All three contain
/// the whole curved volume, not only sample points of it: they are computed from a grid of
/// samples and padded by the most the surface can bulge between samples.
///
/// ```
/// const BoundingRegion region(Ellipsoid::wgs84(), scheme.tileExtent(key), -50.0, 4800.0);
/// const double sse = screenSpaceError(error, region.distanceTo(eye), width, fovX);
/// const bool hidden = region.horizonOcclusionPoint() &&
///     !occluder.isScaledSpacePointVisible(*region.horizonOcclusionPoint(), region.minimumHeight());
/// ```
class BoundingRegion final {
public:
    /// minimumHeight <= maximumHeight (asserted), metres above the ellipsoid; the extent may cross
    /// the antimeridian.
    BoundingRegion(const Ellipsoid& ellipsoid, const GeodeticExtent& extent, double minimumHeight,
                   double maximumHeight) noexcept;

    const GeodeticExtent& extent() const noexcept { return _extent; }
    double minimumHeight() const noexcept { return _minimumHeight; }
    double maximumHeight() const noexcept { return _maximumHeight; }

    /// A box in the east-north-up frame at the extent's centre.
    const OrientedBoundingBox& orientedBox() const noexcept { return _box; }
    /// The box's circumscribed sphere.
    const BoundingSphere& boundingSphere() const noexcept { return _sphere; }
    /// In the scaled space of EllipsoidalOccluder::occludingEllipsoid(ellipsoid, minimumHeight()),
    /// along the direction of the sphere's centre; test it with
    /// EllipsoidalOccluder::isScaledSpacePointVisible(point, minimumHeight()). Empty when no such
    /// point exists (a region wider than a hemisphere): the region is then never horizon-culled.
    const std::optional<glm::dvec3>& horizonOcclusionPoint() const noexcept { return _horizonOcclusionPoint; }

    /// Metres from p to the box, 0 inside: the distance the screen-space error is taken at.
    double distanceTo(const glm::dvec3& p) const noexcept;

    /// How far (metres) the surface may rise above the chords between samples at most: the
    /// padding added to the box and to the heights of the horizon samples.
    double padding() const noexcept { return _padding; }

    /// Samples along each side of the grid the volumes are computed from: 17 for regions wider or
    /// taller than 5 degrees, 9 for smaller ones.
    static constexpr int kMaximumSamplesPerSide = 17;

private:
    GeodeticExtent _extent;
    double _minimumHeight;
    double _maximumHeight;
    double _padding = 0.0;
    OrientedBoundingBox _box;
    glm::dmat3 _unitAxes{1.0};     ///< the box's axes, unit length (columns)
    glm::dvec3 _halfLengths{0.0};  ///< the box's half-axes' lengths
    BoundingSphere _sphere;
    std::optional<glm::dvec3> _horizonOcclusionPoint;
};

} // namespace orbis
