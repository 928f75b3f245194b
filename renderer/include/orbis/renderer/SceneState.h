#pragma once

#include "orbis/renderer/RenderState.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <limits>

namespace orbis::renderer {

/// How clip-space depth becomes window depth in a frame; the projection matrix must match.
enum class DepthConvention : std::uint8_t {
    /// GL's own: clip depth -1..1, window depth 0 at the near plane and 1 at the far plane; each
    /// command's depth comparison as it says.
    Standard,
    /// Complementary (reversed) depth: clip depth 0..1 through glClipControl, near at 1 and far at
    /// 0 (the projection maps them so), each command's depth comparison mirrored (Less becomes
    /// Greater), polygon offsets negated; clear the depth to 0. With a Depth32F buffer the float's
    /// exponent then gives about 2^-24 of the distance at every distance. Needs
    /// DeviceInfo::clipControl: without it Context::draw throws orbis::Error naming
    /// GL_ARB_clip_control (GL's -1..1 clip depth maps through 0.5 z + 0.5, whose rounding near 0
    /// would throw that precision away).
    Complementary,
};

/// What the automatic og_ uniforms are computed from: the camera, viewport, sun and time of the
/// frame being drawn. Matrices are in double precision (world coordinates in metres); the
/// Context computes the products in double and sends floats. The defaults (identity matrices)
/// make model coordinates clip coordinates, which is what a first triangle wants.
struct SceneState {
    glm::dmat4 viewMatrix{1.0};       ///< world to eye
    glm::dmat4 projectionMatrix{1.0}; ///< eye to clip (GL conventions, depth -1..1)
    glm::dvec3 cameraEye{0.0};        ///< the camera position in world coordinates (metres)
    PixelRectangle viewport;          ///< origin bottom left; width or height 0: the whole target framebuffer
    double nearDistance = 1.0;        ///< og_nearDistance, metres
    double farDistance = 1000.0;      ///< og_farDistance, metres
    glm::dvec3 sunDirection{0.0, 0.0, 1.0}; ///< towards the sun, world coordinates; normalised when sent
    double timeSeconds = 0.0;         ///< og_time (sent as float: wrap long-running clocks)
    DepthConvention depthConvention = DepthConvention::Standard;
    /// The eye depths (metres along the view direction) this pass owns, og_ownedDepthRange: where
    /// frustums overlap, blended draws keep only the fragments their own frustum owns, so that
    /// none is blended twice. Infinity is sent as the largest float.
    double ownedNearDistance = 0.0;
    double ownedFarDistance = std::numeric_limits<double>::infinity();
};

} // namespace orbis::renderer
