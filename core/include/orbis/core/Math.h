#pragma once

#include <glm/vec3.hpp>

#include <cmath>
#include <numbers>

namespace orbis {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kTwoPi = 2.0 * std::numbers::pi;
inline constexpr double kHalfPi = 0.5 * std::numbers::pi;

/// Degrees to radians.
constexpr double toRadians(double angleDegrees) noexcept { return angleDegrees * (kPi / 180.0); }

/// Radians to degrees.
constexpr double toDegrees(double angleRadians) noexcept { return angleRadians * (180.0 / kPi); }

/// True when every component is finite (neither NaN nor infinite).
inline bool isFinite(const glm::dvec3& v) noexcept
{
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// A unit vector perpendicular to v (v need not be normalised); the x axis when v is zero.
glm::dvec3 anyPerpendicular(const glm::dvec3& v) noexcept;

} // namespace orbis
