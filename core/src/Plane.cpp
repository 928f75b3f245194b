#include "orbis/core/Plane.h"

#include <cassert>
#include <cmath>

namespace orbis {

Plane Plane::fromPointNormal(const glm::dvec3& point, const glm::dvec3& normal) noexcept
{
    const double length = glm::length(normal);
    assert(length > 0.0 && "Plane::fromPointNormal: zero normal");
    const glm::dvec3 n = length > 0.0 && std::isfinite(length) ? normal / length : glm::dvec3(0.0, 0.0, 1.0);
    return {n, -glm::dot(n, point)};
}

} // namespace orbis
