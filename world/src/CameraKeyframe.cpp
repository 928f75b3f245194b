#include "orbis/world/CameraKeyframe.h"

#include <orbis/core/Math.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace orbis::world {

namespace {

Geodetic3D interpolate(const Geodetic3D& a, const Geodetic3D& b, double t) noexcept
{
    const double deltaLongitude = std::remainder(b.longitude - a.longitude, kTwoPi);
    return {std::remainder(a.longitude + t * deltaLongitude, kTwoPi), a.latitude + t * (b.latitude - a.latitude),
            a.height + t * (b.height - a.height)};
}

} // namespace

CameraKeyframe interpolateKeyframes(const CameraKeyframe& a, const CameraKeyframe& b, double t) noexcept
{
    return {a.seconds + t * (b.seconds - a.seconds), interpolate(a.eye, b.eye, t), interpolate(a.target, b.target, t)};
}

std::optional<double> eyeMeetsTarget(const Ellipsoid& ellipsoid, const CameraKeyframe& a, const CameraKeyframe& b,
                                     double tolerance) noexcept
{
    auto gap = [&](double t) {
        const CameraKeyframe at = interpolateKeyframes(a, b, t);
        return glm::distance(ellipsoid.toCartesian(at.eye), ellipsoid.toCartesian(at.target));
    };
    // Eye and target each move linearly in longitude, latitude and height, so their gap has few
    // local minima: the samples find the deepest one's neighbourhood, golden sections its bottom.
    constexpr int kSamples = 64;
    int closest = 0;
    double closestGap = gap(0.0);
    for (int i = 1; i <= kSamples; ++i) {
        const double g = gap(static_cast<double>(i) / kSamples);
        if (g < closestGap) {
            closest = i;
            closestGap = g;
        }
    }
    double low = std::max(0, closest - 1) / static_cast<double>(kSamples);
    double high = std::min(kSamples, closest + 1) / static_cast<double>(kSamples);
    constexpr double kInverseGolden = 0.6180339887498949;
    double left = high - kInverseGolden * (high - low);
    double right = low + kInverseGolden * (high - low);
    double leftGap = gap(left);
    double rightGap = gap(right);
    for (int iteration = 0; iteration < 80 && high - low > 1e-15; ++iteration) {
        if (leftGap < rightGap) {
            high = right;
            right = left;
            rightGap = leftGap;
            left = high - kInverseGolden * (high - low);
            leftGap = gap(left);
        } else {
            low = left;
            left = right;
            leftGap = rightGap;
            right = low + kInverseGolden * (high - low);
            rightGap = gap(right);
        }
    }
    const double t = leftGap < rightGap ? left : right;
    const double bottom = std::min({closestGap, leftGap, rightGap});
    if (!(bottom < tolerance)) {
        return std::nullopt;
    }
    const double at = bottom == closestGap ? static_cast<double>(closest) / kSamples : t;
    return a.seconds + at * (b.seconds - a.seconds);
}

} // namespace orbis::world
