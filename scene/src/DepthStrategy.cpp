#include "orbis/scene/DepthStrategy.h"

#include "orbis/scene/SceneCommand.h"

#include <orbis/renderer/ShaderProgram.h>

#include <cmath>
#include <limits>

namespace orbis::scene {

std::vector<renderer::ShaderDefine> depthStrategyDefines(DepthStrategy strategy, Pass pass)
{
    switch (strategy) {
    case DepthStrategy::Logarithmic: return {{"OG_DEPTH_LOGARITHMIC"}};
    case DepthStrategy::LogarithmicVertex: return {{"OG_DEPTH_LOGARITHMIC_VERTEX"}};
    case DepthStrategy::Complementary: return {{"OG_DEPTH_COMPLEMENTARY"}};
    case DepthStrategy::MultiFrustum:
        if (pass == Pass::Translucent) {
            return {{"OG_DEPTH_OWNED_RANGE"}};
        }
        return {};
    case DepthStrategy::Automatic:
    case DepthStrategy::Single: break;
    }
    return {};
}

double analyticMinimumSeparation(DepthStrategy strategy, double distance, double nearDistance, double farDistance,
                                 double farToNearRatio) noexcept
{
    constexpr double steps = 16777216.0; // 2^24
    constexpr double infinity = std::numeric_limits<double>::infinity();
    auto baker = [&](double n) {
        const double denominator = steps * n - distance;
        return denominator > 0.0 ? distance * distance / denominator : infinity;
    };
    switch (strategy) {
    case DepthStrategy::Single: return baker(nearDistance);
    case DepthStrategy::Automatic:
    case DepthStrategy::MultiFrustum: {
        // The frustum holding `distance`: near ratio^k < distance <= near ratio^(k + 1).
        const double k = std::max(
            0.0, std::ceil(std::log(std::max(distance / nearDistance, 1.0)) / std::log(farToNearRatio) - 1e-12) - 1.0);
        return baker(nearDistance * std::pow(farToNearRatio, k));
    }
    case DepthStrategy::Logarithmic:
    case DepthStrategy::LogarithmicVertex: return distance / steps * std::log(std::max(farDistance / nearDistance, 2.0));
    case DepthStrategy::Complementary: return 2.0 * distance / steps;
    }
    return infinity;
}

} // namespace orbis::scene
