#include "DepthPlan.h"

namespace orbis::scene::detail {

DepthPlan DepthPlan::of(DepthStrategy strategy, const MultiFrustumOptions& limits) noexcept
{
    DepthPlan plan;
    plan.strategy = strategy;
    plan.binning = limits;
    if (strategy == DepthStrategy::MultiFrustum || strategy == DepthStrategy::Automatic) {
        plan.strategy = DepthStrategy::MultiFrustum;
        plan.ownedRanges = true;
        return plan;
    }
    plan.binning.farToNearRatio = 1e300; // one frustum over whatever range the commands span
    switch (strategy) {
    case DepthStrategy::Single: plan.fixedRange = true; break;
    case DepthStrategy::Complementary:
        plan.convention = renderer::DepthConvention::Complementary;
        plan.clearDepth = 0.0;
        plan.needsFloatDepth = true;
        break;
    default: break;
    }
    return plan;
}

glm::dmat4 DepthPlan::projection(const Camera& camera, double aspect, const FrustumRange& range) const noexcept
{
    glm::dmat4 p = camera.projectionMatrix(aspect, range.nearDistance, range.farDistance);
    if (convention == renderer::DepthConvention::Complementary) {
        p[2][2] = 0.0;
        p[3][2] = range.nearDistance;
        p[2][3] = -1.0;
        p[3][3] = 0.0;
    }
    return p;
}

DepthStrategy resolveAutomaticDepth(const AutoInputs& inputs, const MultiFrustumOptions& limits) noexcept
{
    if (MultiFrustum::frustumCount(inputs.nearDistance, inputs.farDistance, limits.farToNearRatio) == 1) {
        return DepthStrategy::MultiFrustum;
    }
    if (inputs.complementaryAvailable) {
        return DepthStrategy::Complementary;
    }
    if (inputs.logarithmicAvailable) {
        return DepthStrategy::Logarithmic;
    }
    return DepthStrategy::MultiFrustum;
}

} // namespace orbis::scene::detail
