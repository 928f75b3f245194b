#pragma once

#include "orbis/renderer/RenderState.h"

#include <glm/vec4.hpp>

#include <cstdint>

namespace orbis::renderer {

/// Which buffers a clear writes (combine with |).
enum class ClearBuffers : std::uint8_t { None = 0, Color = 1, Depth = 2, Stencil = 4, ColorAndDepth = 3, All = 7 };

constexpr ClearBuffers operator|(ClearBuffers a, ClearBuffers b) noexcept
{
    return static_cast<ClearBuffers>(static_cast<std::uint8_t>(a) | static_cast<std::uint8_t>(b));
}
constexpr bool hasAny(ClearBuffers set, ClearBuffers bits) noexcept
{
    return (static_cast<std::uint8_t>(set) & static_cast<std::uint8_t>(bits)) != 0;
}

/// A clear of the target framebuffer. GL limits clears by the scissor test and the colour, depth
/// and stencil masks, so they are part of the clear and applied like a draw's state.
struct ClearState {
    ClearBuffers buffers = ClearBuffers::All;
    glm::vec4 color{0.0f, 0.0f, 0.0f, 1.0f};
    double depth = 1.0;
    int stencil = 0;
    ScissorTest scissorTest;
    ColorMask colorMask;
    bool depthMask = true;
    std::uint32_t frontStencilMask = 0xFFFFFFFFu;
    std::uint32_t backStencilMask = 0xFFFFFFFFu;
};

} // namespace orbis::renderer
