#include "orbis/core/AxisAlignedBoundingBox.h"

#include <glm/common.hpp>

namespace orbis {

AxisAlignedBoundingBox AxisAlignedBoundingBox::fromPoints(std::span<const glm::dvec3> points) noexcept
{
    if (points.empty()) {
        return {};
    }
    AxisAlignedBoundingBox box{points.front(), points.front()};
    for (const glm::dvec3& p : points) {
        box.minimum = glm::min(box.minimum, p);
        box.maximum = glm::max(box.maximum, p);
    }
    return box;
}

glm::dvec3 AxisAlignedBoundingBox::centre() const noexcept
{
    // Halving each corner first cannot overflow; the sum of the (exact) halves is the correctly
    // rounded midpoint.
    return 0.5 * minimum + 0.5 * maximum;
}

bool AxisAlignedBoundingBox::contains(const glm::dvec3& p) const noexcept
{
    return p.x >= minimum.x && p.x <= maximum.x && p.y >= minimum.y && p.y <= maximum.y && p.z >= minimum.z &&
           p.z <= maximum.z;
}

} // namespace orbis
