#include "orbis/scene/SceneDescription.h"

#include <orbis/core/Transforms.h>

#include <glm/geometric.hpp>

#include <algorithm>

namespace orbis {

Camera makeCamera(const CameraDescription& description, const Ellipsoid& ellipsoid)
{
    const glm::dvec3 eye = ellipsoid.toCartesian(description.position);
    if (const auto* orientation = std::get_if<HeadingPitchRoll>(&description.aim)) {
        const ViewOrientation view =
            headingPitchRollToView(ellipsoid, eye, orientation->heading, orientation->pitch, orientation->roll);
        // A target far ahead keeps the direction's rounding small next to the eye's coordinates.
        const double reach = std::max(1.0, glm::length(eye));
        return Camera(eye, eye + reach * view.direction, view.up, description.fieldOfViewY);
    }
    const glm::dvec3 target = ellipsoid.toCartesian(std::get<Geodetic3D>(description.aim));
    const glm::dmat3 eastNorthUp = eastNorthUpAxes(ellipsoid, eye);
    // The local vertical as up, unless the view runs along it; then north (the top of a map).
    const glm::dvec3 direction = target - eye;
    const glm::dvec3 side = glm::cross(direction, eastNorthUp[2]);
    const bool vertical = glm::dot(side, side) <= 1e-12 * glm::dot(direction, direction);
    return Camera(eye, target, vertical ? eastNorthUp[1] : eastNorthUp[2], description.fieldOfViewY);
}

} // namespace orbis
