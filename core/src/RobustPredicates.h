#pragma once

// Exact geometric predicates on doubles for the polygon code: the sign of the orientation
// determinant is decided exactly (a floating-point filter, then exact expansion arithmetic when the
// filter cannot decide), so that decisions taken at different times never contradict each other.
// Internal to orbis::core.

#include <glm/vec2.hpp>

#include <cmath>

namespace orbis::detail {

/// orient2d by exact expansion arithmetic, for when the floating-point filter cannot decide.
int exactOrient2d(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) noexcept;

/// +1 when c lies to the left of the directed line a->b, -1 to the right, 0 when exactly collinear.
[[gnu::always_inline]] inline int orient2d(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) noexcept
{
    const double left = (a.x - c.x) * (b.y - c.y);
    const double right = (a.y - c.y) * (b.x - c.x);
    const double det = left - right;
    // A bound on the rounding error of det, a little looser than Shewchuk's (3 + 16u)u so that it
    // is safe without a proof of our own; below it the exact evaluation decides. Inline: this
    // filter decides nearly always, and the polygon code calls it millions of times.
    const double bound = 1e-15 * (std::abs(left) + std::abs(right));
    if (det > bound) {
        return 1;
    }
    if (-det > bound) {
        return -1;
    }
    return exactOrient2d(a, b, c);
}

/// True when p lies on the closed segment [a, b] (exactly).
bool onSegment(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& p) noexcept;

/// True when the closed segments [a, b] and [c, d] share at least one point (exactly).
bool segmentsIntersect(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, const glm::dvec2& d) noexcept;

/// True when p lies inside or on the boundary of the counter-clockwise triangle a, b, c (exactly).
inline bool inClosedTriangle(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, const glm::dvec2& p) noexcept
{
    return orient2d(a, b, p) >= 0 && orient2d(b, c, p) >= 0 && orient2d(c, a, p) >= 0;
}

} // namespace orbis::detail
