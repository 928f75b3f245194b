#pragma once

// A primitive's shader program in each depth strategy and pass. Private.

#include "orbis/scene/FrameState.h"

#include <orbis/renderer/ShaderProgram.h>

#include <array>
#include <functional>
#include <memory>

namespace orbis::scene::detail {

/// The variants of one program across depth strategies and passes (depthStrategyDefines differs by
/// both: blended draws under MultiFrustum keep to their frustum's own depths). Each is taken from
/// the device's shader cache the first time a frame asks for it and kept, so that frames with an
/// unchanged strategy neither compile nor look anything up.
///
/// ```
/// DepthPrograms programs([](DepthStrategy, Pass) { return description; });
/// command.shaderProgram = &programs.get(frameState, command.pass);
/// ```
class DepthPrograms {
public:
    /// The program's description under a strategy (before its depth defines, which get() adds, with
    /// the strategy's name after the program's).
    using Describe = std::function<renderer::ShaderProgramDescription(DepthStrategy strategy, Pass pass)>;

    explicit DepthPrograms(Describe describe);

    /// The variant for frameState.depthStrategy and `pass` (Overlay draws as Opaque). Throws
    /// orbis::Error when it does not compile.
    renderer::ShaderProgram& get(FrameState& frameState, Pass pass = Pass::Opaque);

private:
    Describe _describe;
    /// By DepthStrategy, then opaque and translucent.
    std::array<std::array<std::shared_ptr<renderer::ShaderProgram>, 2>, 6> _programs;
};

} // namespace orbis::scene::detail
