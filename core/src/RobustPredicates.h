#pragma once

// Exact geometric predicates on doubles for the polygon code: the sign of the orientation
// determinant is decided exactly (a floating-point filter, then exact expansion arithmetic when the
// filter cannot decide), so that decisions taken at different times never contradict each other.
// Internal to orbis::core.

#include <glm/vec2.hpp>

namespace orbis::detail {

/// +1 when c lies to the left of the directed line a->b, -1 to the right, 0 when exactly collinear.
int orient2d(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) noexcept;

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
