#include "orbis/scene/SceneDescription.h"

#include <orbis/core/Transforms.h>

#include <glm/geometric.hpp>

#include <algorithm>

namespace orbis {

Camera makeCamera(const CameraDescription& description, const Ellipsoid& ellipsoid)
{
    const glm::dvec3 eye = ellipsoid.toCartesian(description.position);
    // The local frame is taken on the surface below the eye: eastNorthUpAxes reads a point's normal
    // as the normal of the ellipsoid scaled through it, which tilts away from the geodetic normal
    // with height.
    const glm::dvec3 ground =
        ellipsoid.toCartesian(Geodetic3D(description.position.longitude, description.position.latitude, 0.0));
    if (const auto* orientation = std::get_if<HeadingPitchRoll>(&description.aim)) {
        const ViewOrientation view =
            headingPitchRollToView(ellipsoid, ground, orientation->heading, orientation->pitch, orientation->roll);
        // A target far ahead keeps the direction's rounding small next to the eye's coordinates.
        const double reach = std::max(1.0, glm::length(eye));
        return Camera(eye, eye + reach * view.direction, view.up, description.fieldOfViewY);
    }
    const glm::dvec3 target = ellipsoid.toCartesian(std::get<Geodetic3D>(description.aim));
    const glm::dmat3 eastNorthUp = eastNorthUpAxes(ellipsoid, ground);
    // The local vertical as up, unless the view runs along it; then north (the top of a map).
    const glm::dvec3 direction = target - eye;
    const glm::dvec3 side = glm::cross(direction, eastNorthUp[2]);
    const bool vertical = glm::dot(side, side) <= 1e-12 * glm::dot(direction, direction);
    return Camera(eye, target, vertical ? eastNorthUp[1] : eastNorthUp[2], description.fieldOfViewY);
}

} // namespace orbis
