#pragma once

// The fixed-function state of one draw, as in the book's chapter 3: a coarse-grained value passed
// with every DrawCommand, so that no GL state leaks from one draw to the next. The Context
// shadows what GL has and changes only the parts that differ.

#include "orbis/renderer/PixelRectangle.h"

#include <glm/vec4.hpp>

#include <cstdint>

namespace orbis::renderer {

/// Comparison used by the depth and stencil tests.
enum class CompareFunction : std::uint8_t { Never, Less, Equal, LessOrEqual, Greater, NotEqual, GreaterOrEqual, Always };

/// The restart index ends one strip and starts the next (indexed draws only).
struct PrimitiveRestart {
    bool enabled = false;
    std::uint32_t index = 0xFFFFFFFFu;
    friend bool operator==(const PrimitiveRestart&, const PrimitiveRestart&) = default;
};

enum class CullFace : std::uint8_t { Front, Back, FrontAndBack };
enum class WindingOrder : std::uint8_t { Clockwise, Counterclockwise };

/// Which triangles are discarded by their facing.
struct FacetCulling {
    bool enabled = true;
    CullFace face = CullFace::Back;
    WindingOrder frontFaceWindingOrder = WindingOrder::Counterclockwise;
    friend bool operator==(const FacetCulling&, const FacetCulling&) = default;
};

/// How polygons are rasterised (both faces).
enum class RasterizationMode : std::uint8_t { Point, Line, Fill };

/// Fragments outside the rectangle (origin at the bottom left) are discarded; clears are limited to
/// it too.
struct ScissorTest {
    bool enabled = false;
    PixelRectangle rectangle;
    friend bool operator==(const ScissorTest&, const ScissorTest&) = default;
};

enum class StencilOperation : std::uint8_t { Zero, Invert, Keep, Replace, Increment, Decrement, IncrementWrap, DecrementWrap };

/// The stencil test and update of one facing.
struct StencilTestFace {
    StencilOperation stencilFailOperation = StencilOperation::Keep;
    StencilOperation depthFailStencilPassOperation = StencilOperation::Keep;
    StencilOperation depthPassStencilPassOperation = StencilOperation::Keep;
    CompareFunction function = CompareFunction::Always;
    int referenceValue = 0;
    std::uint32_t mask = 0xFFFFFFFFu;      ///< applied to the reference and the stored value before comparing
    std::uint32_t writeMask = 0xFFFFFFFFu; ///< the bits the operations may change
    friend bool operator==(const StencilTestFace&, const StencilTestFace&) = default;
};

/// Needs a framebuffer with a depth-stencil attachment.
struct StencilTest {
    bool enabled = false;
    StencilTestFace frontFace;
    StencilTestFace backFace;
    friend bool operator==(const StencilTest&, const StencilTest&) = default;
};

/// Depth comparison; when disabled, depth is neither tested nor written.
struct DepthTest {
    bool enabled = true;
    CompareFunction function = CompareFunction::Less;
    friend bool operator==(const DepthTest&, const DepthTest&) = default;
};

/// Maps normalised device depth -1..1 to window depth nearValue..farValue.
struct DepthRange {
    double nearValue = 0.0;
    double farValue = 1.0;
    friend bool operator==(const DepthRange&, const DepthRange&) = default;
};

enum class SourceBlendingFactor : std::uint8_t {
    Zero, One, SourceAlpha, OneMinusSourceAlpha, DestinationAlpha, OneMinusDestinationAlpha,
    DestinationColor, OneMinusDestinationColor, SourceAlphaSaturate, ConstantColor,
    OneMinusConstantColor, ConstantAlpha, OneMinusConstantAlpha
};
enum class DestinationBlendingFactor : std::uint8_t {
    Zero, One, SourceColor, OneMinusSourceColor, SourceAlpha, OneMinusSourceAlpha, DestinationAlpha,
    OneMinusDestinationAlpha, DestinationColor, OneMinusDestinationColor, ConstantColor,
    OneMinusConstantColor, ConstantAlpha, OneMinusConstantAlpha
};
enum class BlendEquation : std::uint8_t { Add, Minimum, Maximum, Subtract, ReverseSubtract };

/// result = source * sourceFactor (equation) destination * destinationFactor, per RGB and alpha.
struct Blending {
    bool enabled = false;
    SourceBlendingFactor sourceRgbFactor = SourceBlendingFactor::One;
    SourceBlendingFactor sourceAlphaFactor = SourceBlendingFactor::One;
    DestinationBlendingFactor destinationRgbFactor = DestinationBlendingFactor::Zero;
    DestinationBlendingFactor destinationAlphaFactor = DestinationBlendingFactor::Zero;
    BlendEquation rgbEquation = BlendEquation::Add;
    BlendEquation alphaEquation = BlendEquation::Add;
    glm::vec4 color{0.0f}; ///< the constant colour of the Constant* factors

    /// Straight-alpha "over": source alpha, one minus source alpha.
    static Blending alphaBlending() noexcept
    {
        Blending b;
        b.enabled = true;
        b.sourceRgbFactor = SourceBlendingFactor::SourceAlpha;
        b.sourceAlphaFactor = SourceBlendingFactor::SourceAlpha;
        b.destinationRgbFactor = DestinationBlendingFactor::OneMinusSourceAlpha;
        b.destinationAlphaFactor = DestinationBlendingFactor::OneMinusSourceAlpha;
        return b;
    }
    friend bool operator==(const Blending&, const Blending&) = default;
};

/// Which colour channels a draw or clear may write.
struct ColorMask {
    bool red = true;
    bool green = true;
    bool blue = true;
    bool alpha = true;
    friend bool operator==(const ColorMask&, const ColorMask&) = default;
};

/// Offsets filled polygons' depth by factor * slope + units * the smallest resolvable step.
struct PolygonOffset {
    bool enabled = false;
    float factor = 0.0f;
    float units = 0.0f;
    friend bool operator==(const PolygonOffset&, const PolygonOffset&) = default;
};

/// Everything fixed-function about one draw. The defaults are the book's: back faces culled,
/// depth test Less, no blending, every mask on.
struct RenderState {
    PrimitiveRestart primitiveRestart;
    FacetCulling facetCulling;
    RasterizationMode rasterizationMode = RasterizationMode::Fill;
    ScissorTest scissorTest;
    StencilTest stencilTest;
    DepthTest depthTest;
    DepthRange depthRange;
    /// GL_DEPTH_CLAMP: nothing is clipped by the near and far planes; depth beyond them is clamped
    /// to the range (shadow volumes: a face beyond the far plane still counts, as lying behind).
    bool depthClamp = false;
    Blending blending;
    ColorMask colorMask;
    bool depthMask = true;
    PolygonOffset polygonOffset;
    bool programPointSize = false; ///< gl_PointSize from the vertex shader when true, 1 pixel otherwise
    friend bool operator==(const RenderState&, const RenderState&) = default;
};

} // namespace orbis::renderer
