#include "orbis/core/Math.h"

#include <glm/geometric.hpp>

namespace orbis {

glm::dvec3 anyPerpendicular(const glm::dvec3& v) noexcept
{
    const glm::dvec3 a = glm::abs(v);
    if (a.x == 0.0 && a.y == 0.0 && a.z == 0.0) {
        return {1.0, 0.0, 0.0};
    }
    // Cross with the axis least aligned with v, so the result is far from zero.
    const glm::dvec3 axis = (a.x <= a.y && a.x <= a.z) ? glm::dvec3(1, 0, 0)
                            : (a.y <= a.z)              ? glm::dvec3(0, 1, 0)
                                                        : glm::dvec3(0, 0, 1);
    return glm::normalize(glm::cross(v, axis));
}

} // namespace orbis
