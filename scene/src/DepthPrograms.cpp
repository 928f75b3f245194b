#include "DepthPrograms.h"

#include <orbis/renderer/Device.h>
#include <orbis/renderer/ShaderCache.h>

#include <utility>

namespace orbis::scene::detail {

DepthPrograms::DepthPrograms(Describe describe)
    : _describe(std::move(describe))
{
}

renderer::ShaderProgram& DepthPrograms::get(FrameState& frameState, Pass pass)
{
    const DepthStrategy strategy = frameState.depthStrategy;
    const Pass drawn = pass == Pass::Translucent ? Pass::Translucent : Pass::Opaque;
    std::shared_ptr<renderer::ShaderProgram>& program =
        _programs[static_cast<std::size_t>(strategy)][drawn == Pass::Translucent ? 1 : 0];
    if (!program) {
        renderer::ShaderProgramDescription description = _describe(strategy, drawn);
        description.name += std::string(" (") + depthStrategyName(strategy) + ")";
        for (renderer::ShaderDefine& define : depthStrategyDefines(strategy, drawn)) {
            description.defines.push_back(std::move(define));
        }
        program = frameState.device.shaderCache().get(description);
    }
    return *program;
}

} // namespace orbis::scene::detail
