#include "orbis/core/Transforms.h"

#include <glm/geometric.hpp>

#include <cmath>

namespace orbis {

glm::dmat3 eastNorthUpAxes(const Ellipsoid& ellipsoid, const glm::dvec3& origin) noexcept
{
    // The normal at the foot below origin: above the surface, the gradient at origin itself belongs
    // to a scaled ellipsoid and leans by up to a few hundredths of a degree.
    const glm::dvec3 up = ellipsoid.geodeticSurfaceNormal(ellipsoid.scaleToGeodeticSurface(origin));
    glm::dvec3 east(-up.y, up.x, 0.0); // z x up
    const double eastLength = glm::length(east);
    east = eastLength > 1e-15 ? east / eastLength : glm::dvec3(0.0, 1.0, 0.0);
    const glm::dvec3 north = glm::cross(up, east);
    return {east, north, up};
}

glm::dmat4 eastNorthUpToFixedFrame(const Ellipsoid& ellipsoid, const glm::dvec3& origin) noexcept
{
    const glm::dmat3 axes = eastNorthUpAxes(ellipsoid, origin);
    glm::dmat4 frame(axes);
    frame[3] = glm::dvec4(origin, 1.0);
    return frame;
}

ViewOrientation headingPitchRollToView(const Ellipsoid& ellipsoid, const glm::dvec3& position, double heading,
                                       double pitch, double roll) noexcept
{
    const glm::dmat3 enu = eastNorthUpAxes(ellipsoid, position);
    const double cosPitch = std::cos(pitch);
    // Heading turns clockwise from north as seen from above: north is heading 0, east is pi/2.
    const glm::dvec3 localDirection(std::sin(heading) * cosPitch, std::cos(heading) * cosPitch, std::sin(pitch));
    const glm::dvec3 localUpNoRoll(-std::sin(heading) * std::sin(pitch), -std::cos(heading) * std::sin(pitch),
                                   cosPitch);
    const glm::dvec3 localRight = glm::cross(localDirection, localUpNoRoll);
    // Roll turns the up vector clockwise about the view direction, towards the right.
    const glm::dvec3 localUp = std::cos(roll) * localUpNoRoll + std::sin(roll) * localRight;
    return {glm::normalize(enu * localDirection), glm::normalize(enu * localUp)};
}

HeadingPitch viewToHeadingPitch(const Ellipsoid& ellipsoid, const glm::dvec3& position,
                                const glm::dvec3& direction) noexcept
{
    const glm::dmat3 enu = eastNorthUpAxes(ellipsoid, position);
    const glm::dvec3 local = glm::transpose(enu) * direction; // the axes are orthonormal
    const double horizontal = std::hypot(local.x, local.y);
    // Within rounding of the vertical the heading is noise (the axes themselves are good to an ulp
    // or so): call it north. atan2 rather than asin: finite for any direction, zero included.
    const bool vertical = horizontal <= 1e-12 * std::abs(local.z);
    return {vertical ? 0.0 : std::atan2(local.x, local.y), std::atan2(local.z, horizontal)};
}

} // namespace orbis
