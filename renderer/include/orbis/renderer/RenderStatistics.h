#pragma once

#include <cstdint>

namespace orbis::renderer {

/// What a Context did since its statistics were last reset (the caller resets, e.g. per frame).
struct RenderStatistics {
    std::uint64_t drawCalls = 0;
    std::uint64_t primitives = 0; ///< triangles, lines or points drawn (restarts not subtracted)
    std::uint64_t vertices = 0;   ///< vertices (or indices) drawn
    std::uint64_t clears = 0;
    std::uint64_t stateChangesMade = 0;    ///< render-state GL calls issued
    std::uint64_t stateChangesAvoided = 0; ///< render-state items found already set, so skipped
    std::uint64_t programBinds = 0;
    std::uint64_t vertexArrayBinds = 0;
    std::uint64_t textureBinds = 0; ///< texture and sampler binds
    std::uint64_t framebufferBinds = 0;
    std::uint64_t bindsAvoided = 0; ///< program, vertex array, texture, sampler and framebuffer binds skipped
    std::uint64_t uniformUploads = 0;
    std::uint64_t uniformUploadsAvoided = 0; ///< uniforms set to the value they already had
    std::uint64_t glCalls = 0; ///< every GL call made on the context's thread, resources included
};

} // namespace orbis::renderer
