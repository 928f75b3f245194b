#pragma once

#include <glm/vec3.hpp>

namespace orbis {

/// A half-line origin + t * direction for t >= 0 (metres). Distances along a ray are values of
/// t: metres when direction is a unit vector, fractions of the segment when it is end - origin.
struct Ray {
    glm::dvec3 origin{0.0};
    glm::dvec3 direction{0.0, 0.0, 1.0};

    /// origin + t * direction.
    glm::dvec3 pointAt(double t) const noexcept { return origin + t * direction; }
};

} // namespace orbis
