#pragma once

// The og_ uniforms the Context fills at draw time from the SceneState and the command's model
// matrix. Private; the list is documented in docs/renderer.md.

#include "orbis/renderer/UniformValue.h"

#include <string_view>

namespace orbis::renderer::detail {

enum class AutomaticUniform : int {
    ModelMatrix,
    ViewMatrix,
    ProjectionMatrix,
    ModelViewMatrix,
    ViewProjectionMatrix,
    ModelViewProjectionMatrix,
    NormalMatrix,                           ///< inverse transpose of the model-view's upper 3x3
    ModelViewMatrixRelativeToEye,           ///< model-view with its translation removed
    ModelViewProjectionMatrixRelativeToEye, ///< projection x the above
    CameraEye,
    CameraEyeHigh, ///< float(eye)
    CameraEyeLow,  ///< float(eye - double(float(eye)))
    CameraEyeHigh65536, ///< eye truncated to multiples of 65536 m (the book's first GPU RTE encoding)
    CameraEyeLow65536,  ///< float(eye - that)
    Viewport,      ///< x, y, width, height
    InverseViewportDimensions,
    ViewportTransformationMatrix, ///< normalised device coordinates to window coordinates
    NearDistance,
    FarDistance,
    LogarithmicDepth,  ///< (1 / near, 1 / log2(far / near)): window depth log2(w / near) / log2(far / near)
    OwnedDepthRange,   ///< SceneState::ownedNearDistance, ownedFarDistance
    SunDirection,    ///< world, unit
    SunDirectionEye, ///< eye coordinates, unit
    Time,
    OpaqueOne, ///< 1.0, which the GLSL compiler cannot fold (keeps float expressions as written)
    Count
};

struct AutomaticUniformInfo {
    const char* name;
    UniformType type;
};

inline constexpr AutomaticUniformInfo kAutomaticUniforms[] = {
    {"og_modelMatrix", UniformType::FloatMat4},
    {"og_viewMatrix", UniformType::FloatMat4},
    {"og_projectionMatrix", UniformType::FloatMat4},
    {"og_modelViewMatrix", UniformType::FloatMat4},
    {"og_viewProjectionMatrix", UniformType::FloatMat4},
    {"og_modelViewProjectionMatrix", UniformType::FloatMat4},
    {"og_normalMatrix", UniformType::FloatMat3},
    {"og_modelViewMatrixRelativeToEye", UniformType::FloatMat4},
    {"og_modelViewProjectionMatrixRelativeToEye", UniformType::FloatMat4},
    {"og_cameraEye", UniformType::FloatVec3},
    {"og_cameraEyeHigh", UniformType::FloatVec3},
    {"og_cameraEyeLow", UniformType::FloatVec3},
    {"og_cameraEyeHigh65536", UniformType::FloatVec3},
    {"og_cameraEyeLow65536", UniformType::FloatVec3},
    {"og_viewport", UniformType::FloatVec4},
    {"og_inverseViewportDimensions", UniformType::FloatVec2},
    {"og_viewportTransformationMatrix", UniformType::FloatMat4},
    {"og_nearDistance", UniformType::Float},
    {"og_farDistance", UniformType::Float},
    {"og_logarithmicDepth", UniformType::FloatVec2},
    {"og_ownedDepthRange", UniformType::FloatVec2},
    {"og_sunDirection", UniformType::FloatVec3},
    {"og_sunDirectionEye", UniformType::FloatVec3},
    {"og_time", UniformType::Float},
    {"og_opaqueOne", UniformType::Float},
};
static_assert(std::size(kAutomaticUniforms) == static_cast<std::size_t>(AutomaticUniform::Count));

/// The automatic uniform of that name; -1 when there is none.
inline int automaticUniformId(std::string_view name) noexcept
{
    for (int i = 0; i < static_cast<int>(AutomaticUniform::Count); ++i) {
        if (name == kAutomaticUniforms[i].name) {
            return i;
        }
    }
    return -1;
}

} // namespace orbis::renderer::detail
