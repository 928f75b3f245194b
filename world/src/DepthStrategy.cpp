#include "orbis/world/DepthStrategy.h"

namespace orbis::world {

const char* depthStrategyName(DepthStrategy strategy) noexcept
{
    switch (strategy) {
    case DepthStrategy::Automatic: return "auto";
    case DepthStrategy::MultiFrustum: return "multi-frustum";
    case DepthStrategy::Logarithmic: return "logarithmic";
    case DepthStrategy::LogarithmicVertex: return "logarithmic (vertex)";
    case DepthStrategy::Complementary: return "complementary";
    case DepthStrategy::Single: return "single";
    }
    return "?";
}

} // namespace orbis::world
