#pragma once

#include "orbis/renderer/RenderState.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace orbis {

/// What the automatic og_ uniforms are computed from: the camera, viewport, sun and time of the
/// frame being drawn. Matrices are in double precision (world coordinates in metres); the
/// Context computes the products in double and sends floats. The defaults (identity matrices)
/// make model coordinates clip coordinates, which is what a first triangle wants.
struct SceneState {
    glm::dmat4 viewMatrix{1.0};       ///< world to eye
    glm::dmat4 projectionMatrix{1.0}; ///< eye to clip (GL conventions, depth -1..1)
    glm::dvec3 cameraEye{0.0};        ///< the camera position in world coordinates (metres)
    Rectangle viewport;               ///< width or height 0: the whole target framebuffer
    double nearDistance = 1.0;        ///< og_nearDistance, metres
    double farDistance = 1000.0;      ///< og_farDistance, metres
    glm::dvec3 sunDirection{0.0, 0.0, 1.0}; ///< towards the sun, world coordinates; normalised when sent
    double timeSeconds = 0.0;         ///< og_time (sent as float: wrap long-running clocks)
};

} // namespace orbis
