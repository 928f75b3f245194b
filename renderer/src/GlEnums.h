#pragma once

// orbis enums to GL enums. Private.

#include <GL/glcorearb.h>

#include "orbis/core/Mesh.h"
#include "orbis/renderer/IndexBuffer.h"
#include "orbis/renderer/RenderState.h"
#include "orbis/renderer/Sampler.h"
#include "orbis/renderer/VertexArray.h"
#include "orbis/renderer/VertexBuffer.h"

namespace orbis::renderer::detail {

inline GLenum toGl(CompareFunction f) noexcept
{
    constexpr GLenum table[] = {GL_NEVER, GL_LESS, GL_EQUAL, GL_LEQUAL, GL_GREATER, GL_NOTEQUAL, GL_GEQUAL, GL_ALWAYS};
    return table[static_cast<int>(f)];
}

inline GLenum toGl(CullFace f) noexcept
{
    constexpr GLenum table[] = {GL_FRONT, GL_BACK, GL_FRONT_AND_BACK};
    return table[static_cast<int>(f)];
}

inline GLenum toGl(WindingOrder w) noexcept { return w == WindingOrder::Clockwise ? GL_CW : GL_CCW; }

inline GLenum toGl(RasterizationMode m) noexcept
{
    constexpr GLenum table[] = {GL_POINT, GL_LINE, GL_FILL};
    return table[static_cast<int>(m)];
}

inline GLenum toGl(StencilOperation o) noexcept
{
    constexpr GLenum table[] = {GL_ZERO, GL_INVERT, GL_KEEP, GL_REPLACE, GL_INCR, GL_DECR, GL_INCR_WRAP, GL_DECR_WRAP};
    return table[static_cast<int>(o)];
}

inline GLenum toGl(SourceBlendingFactor f) noexcept
{
    constexpr GLenum table[] = {GL_ZERO, GL_ONE, GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_DST_ALPHA,
                                GL_ONE_MINUS_DST_ALPHA, GL_DST_COLOR, GL_ONE_MINUS_DST_COLOR, GL_SRC_ALPHA_SATURATE,
                                GL_CONSTANT_COLOR, GL_ONE_MINUS_CONSTANT_COLOR, GL_CONSTANT_ALPHA,
                                GL_ONE_MINUS_CONSTANT_ALPHA};
    return table[static_cast<int>(f)];
}

inline GLenum toGl(DestinationBlendingFactor f) noexcept
{
    constexpr GLenum table[] = {GL_ZERO, GL_ONE, GL_SRC_COLOR, GL_ONE_MINUS_SRC_COLOR, GL_SRC_ALPHA,
                                GL_ONE_MINUS_SRC_ALPHA, GL_DST_ALPHA, GL_ONE_MINUS_DST_ALPHA, GL_DST_COLOR,
                                GL_ONE_MINUS_DST_COLOR, GL_CONSTANT_COLOR, GL_ONE_MINUS_CONSTANT_COLOR,
                                GL_CONSTANT_ALPHA, GL_ONE_MINUS_CONSTANT_ALPHA};
    return table[static_cast<int>(f)];
}

inline GLenum toGl(BlendEquation e) noexcept
{
    constexpr GLenum table[] = {GL_FUNC_ADD, GL_MIN, GL_MAX, GL_FUNC_SUBTRACT, GL_FUNC_REVERSE_SUBTRACT};
    return table[static_cast<int>(e)];
}

inline GLenum toGl(PrimitiveType p) noexcept
{
    switch (p) {
    case PrimitiveType::Points: return GL_POINTS;
    case PrimitiveType::Lines: return GL_LINES;
    case PrimitiveType::LineStrip: return GL_LINE_STRIP;
    case PrimitiveType::Triangles: return GL_TRIANGLES;
    case PrimitiveType::TriangleStrip: return GL_TRIANGLE_STRIP;
    case PrimitiveType::LinesAdjacency: return GL_LINES_ADJACENCY;
    case PrimitiveType::LineStripAdjacency: return GL_LINE_STRIP_ADJACENCY;
    }
    return GL_TRIANGLES;
}

inline GLenum toGl(BufferUsage u) noexcept
{
    constexpr GLenum table[] = {GL_STREAM_DRAW, GL_STREAM_READ, GL_STREAM_COPY, GL_STATIC_DRAW, GL_STATIC_READ,
                                GL_STATIC_COPY, GL_DYNAMIC_DRAW, GL_DYNAMIC_READ, GL_DYNAMIC_COPY};
    return table[static_cast<int>(u)];
}

inline GLenum toGl(IndexType t) noexcept { return t == IndexType::UnsignedShort ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT; }

inline GLenum toGl(ComponentType t) noexcept
{
    constexpr GLenum table[] = {GL_BYTE, GL_UNSIGNED_BYTE, GL_SHORT, GL_UNSIGNED_SHORT, GL_INT, GL_UNSIGNED_INT, GL_FLOAT};
    return table[static_cast<int>(t)];
}

inline std::size_t componentSize(ComponentType t) noexcept
{
    constexpr std::size_t table[] = {1, 1, 2, 2, 4, 4, 4};
    return table[static_cast<int>(t)];
}

inline GLint toGl(TextureWrap w) noexcept
{
    constexpr GLint table[] = {GL_CLAMP_TO_EDGE, GL_REPEAT, GL_MIRRORED_REPEAT};
    return table[static_cast<int>(w)];
}

inline GLint toGl(TextureMinificationFilter f) noexcept
{
    constexpr GLint table[] = {GL_NEAREST, GL_LINEAR, GL_NEAREST_MIPMAP_NEAREST, GL_LINEAR_MIPMAP_NEAREST,
                               GL_NEAREST_MIPMAP_LINEAR, GL_LINEAR_MIPMAP_LINEAR};
    return table[static_cast<int>(f)];
}

inline GLint toGl(TextureMagnificationFilter f) noexcept
{
    return f == TextureMagnificationFilter::Nearest ? GL_NEAREST : GL_LINEAR;
}

/// Primitives drawn by `count` vertices of type p (restarts not subtracted).
inline std::uint64_t primitiveCount(PrimitiveType p, std::size_t count) noexcept
{
    switch (p) {
    case PrimitiveType::Points: return count;
    case PrimitiveType::Lines: return count / 2;
    case PrimitiveType::LineStrip: return count >= 2 ? count - 1 : 0;
    case PrimitiveType::Triangles: return count / 3;
    case PrimitiveType::TriangleStrip: return count >= 3 ? count - 2 : 0;
    case PrimitiveType::LinesAdjacency: return count / 4;
    case PrimitiveType::LineStripAdjacency: return count >= 4 ? count - 3 : 0;
    }
    return 0;
}

} // namespace orbis::renderer::detail
