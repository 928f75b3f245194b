#pragma once

// One depth strategy's part in a frame: everything Scene::render does differently per strategy is
// answered here, so the frame itself has no branches on the strategy. Private.

#include "orbis/scene/Camera.h"
#include "orbis/scene/DepthStrategy.h"
#include "orbis/scene/MultiFrustum.h"

#include <orbis/renderer/SceneState.h>

#include <glm/mat4x4.hpp>

namespace orbis::scene::detail {

struct DepthPlan {
    DepthStrategy strategy = DepthStrategy::MultiFrustum;
    renderer::DepthConvention convention = renderer::DepthConvention::Standard;
    double clearDepth = 1.0;
    /// The options commands are binned with: the scene's for MultiFrustum; an unbounded ratio (one
    /// frustum over the frame's near and far) for the others.
    MultiFrustumOptions binning;
    bool fixedRange = false;      ///< Single: the near and far limits, whatever the commands
    bool ownedRanges = false;     ///< MultiFrustum: blended draws keep only their frustum's fragments
    bool needsFloatDepth = false; ///< Complementary: a Depth32F buffer and glClipControl

    /// The plan of a resolved strategy (not Auto).
    static DepthPlan of(DepthStrategy strategy, const MultiFrustumOptions& limits) noexcept;
    /// The projection of one frustum: GL's perspective, or for Complementary the reversed one with
    /// its far plane at infinity (clip z = near, clip w = distance: window depth near / distance).
    glm::dmat4 projection(const Camera& camera, double aspect, const FrustumRange& range) const noexcept;
};

/// What Auto weighs, known before the primitives update.
struct AutoInputs {
    double nearDistance = 1.0; ///< from the primitives' bounding spheres, clamped to the limits
    double farDistance = 1.0;
    bool complementaryAvailable = false; ///< glClipControl and a target with texture attachments
    bool logarithmicAvailable = false;   ///< every primitive writes logarithmic depth
};

/// Automatic's choice: one multi-frustum frustum when far/near fits the ratio, else Complementary, else
/// Logarithmic, else MultiFrustum (see DepthStrategy::Automatic).
DepthStrategy resolveAutomaticDepth(const AutoInputs& inputs, const MultiFrustumOptions& limits) noexcept;

} // namespace orbis::scene::detail
