#include "orbis/core/BoundingRegion.h"

#include "orbis/core/EllipsoidalOccluder.h"
#include "orbis/core/Transforms.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>

namespace orbis {

namespace {

constexpr int kSamples = BoundingRegion::kSamplesPerSide;

/// The grid of kSamples x kSamples positions over the extent at one height.
template <typename Visit>
void forEachSample(const Ellipsoid& ellipsoid, const GeodeticExtent& extent, double height, Visit&& visit)
{
    const double width = extent.width();
    for (int j = 0; j < kSamples; ++j) {
        const double latitude = j + 1 == kSamples ? extent.north : extent.south + extent.height() * j / (kSamples - 1);
        for (int i = 0; i < kSamples; ++i) {
            const double longitude = extent.west + width * i / (kSamples - 1);
            visit(ellipsoid.toCartesian(Geodetic3D(longitude, latitude, height)));
        }
    }
}

} // namespace

BoundingRegion::BoundingRegion(const Ellipsoid& ellipsoid, const GeodeticExtent& extent, double minimumHeight,
                               double maximumHeight) noexcept
    : _extent(extent)
    , _minimumHeight(minimumHeight)
    , _maximumHeight(maximumHeight)
{
    assert(minimumHeight <= maximumHeight);
    // Between samples an angle `step` apart, a linear function of position (the box's extent along
    // an axis) or the surface itself rises at most r step^2 / 2 above its value at the nearest
    // sample, r the largest radius of curvature (a^2 / b on an oblate ellipsoid) plus the height.
    const double step = std::max(extent.width(), extent.height()) / (kSamples - 1);
    const glm::dvec3& radii = ellipsoid.radii();
    const double largestRadius = std::max({radii.x, radii.y, radii.z});
    const double smallestRadius = std::min({radii.x, radii.y, radii.z});
    const double curvatureRadius = largestRadius * largestRadius / smallestRadius + std::max(0.0, maximumHeight);
    _padding = 0.5 * curvatureRadius * step * step;

    // The box: extremes along east, north and up at the centre, over both heights.
    const glm::dvec3 origin = ellipsoid.toCartesian(extent.centre());
    const glm::dmat3 axes = eastNorthUpAxes(ellipsoid, origin);
    glm::dvec3 low(std::numeric_limits<double>::infinity());
    glm::dvec3 high(-std::numeric_limits<double>::infinity());
    for (const double height : {minimumHeight, maximumHeight}) {
        forEachSample(ellipsoid, extent, height, [&](const glm::dvec3& p) {
            const glm::dvec3 local = glm::transpose(axes) * (p - origin);
            low = glm::min(low, local);
            high = glm::max(high, local);
        });
    }
    low -= _padding;
    high += _padding;
    const glm::dvec3 middle = 0.5 * (low + high);
    const glm::dvec3 half = 0.5 * (high - low);
    _box.centre = origin + axes * middle;
    _box.halfAxes = glm::dmat3(axes[0] * half.x, axes[1] * half.y, axes[2] * half.z);
    _sphere = _box.boundingSphere();

    // The horizon occlusion point: the samples raised by the padding, so that the surface between
    // them is covered too, against the ellipsoid that can hide what reaches below the surface.
    std::array<glm::dvec3, kSamples * kSamples> raised;
    std::size_t count = 0;
    forEachSample(ellipsoid, extent, maximumHeight + _padding, [&](const glm::dvec3& p) { raised[count++] = p; });
    const EllipsoidalOccluder occluder(EllipsoidalOccluder::occludingEllipsoid(ellipsoid, minimumHeight), glm::dvec3(0.0));
    _horizonOcclusionPoint = occluder.horizonOcclusionPoint(_sphere.centre, raised);
}

double BoundingRegion::distanceTo(const glm::dvec3& p) const noexcept
{
    return std::sqrt(_box.distanceSquaredTo(p));
}

} // namespace orbis
