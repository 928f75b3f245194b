#include "orbis/core/BoundingRegion.h"

#include "orbis/core/EllipsoidalOccluder.h"
#include "GeodeticGrid.h"
#include "orbis/core/Transforms.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>

namespace orbis {

namespace {

/// Samples per side: fewer for small regions, where the padding they need is small anyway.
int samplesPerSide(const GeodeticExtent& extent) noexcept
{
    return std::max(extent.width(), extent.height()) > toRadians(5.0) ? BoundingRegion::kMaximumSamplesPerSide : 9;
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
    const int samples = samplesPerSide(extent);
    const double step = std::max(extent.width(), extent.height()) / (samples - 1);
    const glm::dvec3& radii = ellipsoid.radii();
    const double largestRadius = std::max({radii.x, radii.y, radii.z});
    const double smallestRadius = std::min({radii.x, radii.y, radii.z});
    const double curvatureRadius = largestRadius * largestRadius / smallestRadius + std::max(0.0, maximumHeight);
    _padding = 0.5 * curvatureRadius * step * step;

    // The box: extremes along east, north and up at the centre, over both heights.
    const glm::dvec3 origin = ellipsoid.toCartesian(extent.centre());
    const glm::dmat3 axes = eastNorthUpAxes(ellipsoid, origin);
    const glm::dmat3 toLocal = glm::transpose(axes);
    const GeodeticGrid grid(ellipsoid, extent, samples, samples);
    glm::dvec3 low(std::numeric_limits<double>::infinity());
    glm::dvec3 high(-std::numeric_limits<double>::infinity());
    // The horizon occlusion point's samples, raised by the padding so that the surface between
    // them is covered too.
    std::array<glm::dvec3, kMaximumSamplesPerSide * kMaximumSamplesPerSide> raised;
    for (int j = 0; j < samples; ++j) {
        for (int i = 0; i < samples; ++i) {
            const glm::dvec3 n = grid.normal(i, j);
            const glm::dvec3 surface = grid.surface(n);
            for (const double height : {minimumHeight, maximumHeight}) {
                const glm::dvec3 local = toLocal * (surface + height * n - origin);
                low = glm::min(low, local);
                high = glm::max(high, local);
            }
            raised[static_cast<std::size_t>(j * samples + i)] = surface + (maximumHeight + _padding) * n;
        }
    }
    low -= _padding;
    high += _padding;
    const glm::dvec3 middle = 0.5 * (low + high);
    const glm::dvec3 half = 0.5 * (high - low);
    _box.centre = origin + axes * middle;
    _box.halfAxes = glm::dmat3(axes[0] * half.x, axes[1] * half.y, axes[2] * half.z);
    _unitAxes = axes;
    _halfLengths = half;
    _sphere = _box.boundingSphere();

    // Against the ellipsoid that can hide what reaches below the surface.
    const EllipsoidalOccluder occluder(EllipsoidalOccluder::occludingEllipsoid(ellipsoid, minimumHeight), glm::dvec3(0.0));
    _horizonOcclusionPoint =
        occluder.horizonOcclusionPoint(_sphere.centre, std::span(raised.data(), static_cast<std::size_t>(samples * samples)));
}

double BoundingRegion::distanceTo(const glm::dvec3& p) const noexcept
{
    // The box's distance, with its axes' directions and lengths kept from construction: selection
    // asks this of every tile it visits.
    const glm::dvec3 local = glm::transpose(_unitAxes) * (p - _box.centre);
    const glm::dvec3 outside = glm::max(glm::abs(local) - _halfLengths, glm::dvec3(0.0));
    return glm::length(outside);
}

} // namespace orbis
