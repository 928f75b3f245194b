#include "VectorSupport.h"

#include <orbis/core/EllipsoidalOccluder.h>
#include <orbis/core/EmulatedDouble.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace orbis::detail {

namespace {

/// a (a / b)^2: the arc an angle at the centre can span, over the smallest radius of curvature.
double curvatureScale(const Ellipsoid& ellipsoid) noexcept
{
    const double a = ellipsoid.maximumRadius();
    const double b = ellipsoid.minimumRadius();
    return a * (a / b) * (a / b);
}

constexpr double kSagMargin = 1.01;

} // namespace

double centralAngle(const glm::dvec3& a, const glm::dvec3& b) noexcept
{
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

double chordSagBound(const Ellipsoid& ellipsoid, double angle) noexcept
{
    return kSagMargin * curvatureScale(ellipsoid) * (1.0 - std::cos(0.5 * std::min(angle, kPi)));
}

double triangleSagBound(const Ellipsoid& ellipsoid, double angle) noexcept
{
    const double s = std::sin(0.5 * std::min(angle, kPi));
    return kSagMargin * curvatureScale(ellipsoid) * (1.0 - std::sqrt(std::max(0.0, 1.0 - 4.0 / 3.0 * s * s)));
}

std::vector<std::vector<std::uint32_t>> groupByRegion(const Ellipsoid& ellipsoid, std::span<const BoundingSphere> items)
{
    if (items.empty()) {
        return {};
    }
    BoundingSphere all = items[0];
    for (const BoundingSphere& item : items.subspan(1)) {
        all = BoundingSphere::merge(all, item);
    }
    const double large = 0.25 * ellipsoid.minimumRadius();
    if (all.radius < large) {
        std::vector<std::uint32_t> one(items.size());
        for (std::uint32_t i = 0; i < one.size(); ++i) {
            one[i] = i;
        }
        return {std::move(one)};
    }
    // 24 cells of small items, then 6 of large ones.
    std::array<std::vector<std::uint32_t>, 30> cells;
    for (std::uint32_t i = 0; i < items.size(); ++i) {
        const glm::dvec3 d = items[i].centre * ellipsoid.oneOverRadii();
        const glm::dvec3 m = glm::abs(d);
        const int axis = m.x >= m.y && m.x >= m.z ? 0 : (m.y >= m.z ? 1 : 2);
        const int face = 2 * axis + (d[axis] < 0.0 ? 1 : 0);
        if (items[i].radius >= large) {
            cells[24 + face].push_back(i);
            continue;
        }
        const double u = d[(axis + 1) % 3];
        const double v = d[(axis + 2) % 3];
        cells[4 * face + (u >= 0.0 ? 1 : 0) + (v >= 0.0 ? 2 : 0)].push_back(i);
    }
    std::vector<std::vector<std::uint32_t>> groups;
    for (std::vector<std::uint32_t>& cell : cells) {
        if (!cell.empty()) {
            groups.push_back(std::move(cell));
        }
    }
    return groups;
}

GroupBounds boundsOf(const Ellipsoid& ellipsoid, std::span<const glm::dvec3> positions)
{
    GroupBounds bounds;
    bounds.sphere = BoundingSphere::fromPoints(positions);
    const double length = glm::length(bounds.sphere.centre);
    if (length > 0.0) {
        // The occluder's camera does not matter for the point (see EllipsoidalOccluder).
        const EllipsoidalOccluder occluder(ellipsoid, glm::dvec3(0.0));
        bounds.occlusionPoint = occluder.horizonOcclusionPoint(bounds.sphere.centre / length, positions);
    }
    return bounds;
}

void boundDepth(DrawCommand& command, const Ellipsoid& ellipsoid, const glm::dvec3& eye, double eyeHeight,
                double maxHeight) noexcept
{
    if (!(eyeHeight > 0.0)) {
        return;
    }
    const double b = ellipsoid.minimumRadius();
    const double top = ellipsoid.maximumRadius() + std::max(maxHeight, 0.0);
    const double eyeDistance = glm::length(eye);
    command.nearestDistance = std::max(0.0, eyeHeight - maxHeight);
    command.farthestDistance =
        std::sqrt(std::max(0.0, eyeDistance * eyeDistance - b * b)) + std::sqrt(top * top - b * b);
}

void appendPosition(std::vector<float>& out, const glm::dvec3& position, bool relativeToEye, const glm::dvec3& centre)
{
    if (relativeToEye) {
        const EmulatedDVec3 encoded = EmulatedDVec3::fromDVec3(position);
        out.insert(out.end(), {encoded.high.x, encoded.high.y, encoded.high.z, encoded.low.x, encoded.low.y,
                               encoded.low.z});
    } else {
        const glm::vec3 offset(position - centre);
        out.insert(out.end(), {offset.x, offset.y, offset.z});
    }
}

std::array<std::uint8_t, 4> packColor(const glm::vec4& color) noexcept
{
    std::array<std::uint8_t, 4> bytes{};
    for (int i = 0; i < 4; ++i) {
        const float c = std::isfinite(color[i]) ? std::clamp(color[i], 0.0f, 1.0f) : 0.0f;
        bytes[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(std::lround(c * 255.0f));
    }
    return bytes;
}

glm::vec4 depthOffsetUniform(const Ellipsoid& ellipsoid, bool enabled, double steps, double fractionOfDistance,
                             double meters) noexcept
{
    const auto radius = static_cast<float>(ellipsoid.maximumRadius());
    if (!enabled) {
        return {0.0f, 0.0f, 0.0f, radius};
    }
    return {static_cast<float>(steps), static_cast<float>(fractionOfDistance), static_cast<float>(meters), radius};
}

RenderState vectorRenderState(Pass pass, bool cullBackFaces, bool blend) noexcept
{
    RenderState state;
    state.facetCulling.enabled = cullBackFaces;
    if (blend || pass == Pass::Translucent) {
        state.blending = Blending::alphaBlending();
        state.blending.sourceAlphaFactor = SourceBlendingFactor::One;
    }
    state.depthMask = pass != Pass::Translucent;
    return state;
}

} // namespace orbis::detail
