#pragma once

// The raw-GL side of the benchmark that measures what the renderer layer costs
// (RendererOverhead.cpp): the same draws issued with plain GL calls through the renderer's
// loader, with the state changes a careful hand-written loop makes. Not for rendering, and not
// part of the library: compiled into orbis_bench with the renderer's private headers.

#include <orbis/renderer/Context.h>
#include <orbis/renderer/ShaderProgram.h>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <span>

namespace orbis::bench {

/// One draw of the benchmark: which program and vertex array (indices into the lists given), three
/// render-state switches, and two uniforms (vec2 u_offset, vec4 u_color).
struct BaselineDraw {
    int program = 0;
    int vertexArray = 0;
    bool blending = false;          ///< alpha blending on
    bool depthLessOrEqual = false;  ///< depth function LessOrEqual instead of Less
    bool culling = true;            ///< back faces culled
    glm::vec2 offset{0.0f};
    glm::vec4 color{1.0f};
};

/// The RenderState a BaselineDraw stands for.
renderer::RenderState baselineRenderState(const BaselineDraw& draw) noexcept;

/// Issues the draws into the framebuffer with raw GL (driver entry points from the loader, state and
/// uniform values tracked by hand: only what differs from the previous draw is set), then waits for
/// the GPU (glFinish). Programs must have the uniforms u_offset and u_color and may read og_modelViewProjectionMatrix (set to
/// identity once); arrays must be indexed. Afterwards the context's state tracking is reset.
/// Returns the number of GL calls made.
std::uint64_t drawWithRawGl(renderer::Context& context, renderer::Framebuffer& framebuffer,
                            std::span<renderer::ShaderProgram* const> programs,
                            std::span<const renderer::VertexArray* const> arrays, std::span<const BaselineDraw> draws);

} // namespace orbis::bench
