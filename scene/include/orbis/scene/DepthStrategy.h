#pragma once

#include <cstdint>
#include <vector>

namespace orbis {

// Kept free of renderer headers: the scene-file description includes this file.
enum class Pass : std::uint8_t; // orbis/renderer/DrawCommand.h
struct ShaderDefine;            // orbis/renderer/ShaderProgram.h

/// How a Scene resolves depth across its view distance (book chapter 6, SIGGRAPH 2013 course
/// chapter 2). docs/precision.md measures each; FrameStatistics::depthStrategy says which ran.
enum class DepthStrategy : std::uint8_t {
    /// The cheapest that resolves the frame, decided from its commands' depth range: MultiFrustum
    /// when its frustums come to one (far/near within the ratio: plain depth, nothing extra);
    /// otherwise Complementary where the device has glClipControl and the target has texture
    /// attachments; otherwise Logarithmic when every primitive supports it; MultiFrustum otherwise.
    /// A frame starts with last frame's choice and updates its primitives again only when the
    /// commands call for another (docs/precision.md, "How Automatic chooses").
    Automatic,
    /// Dynamic multiple frustums: far/near at most the ratio in each, overlapping slightly, a depth
    /// clear each, back to front; commands drawn once per frustum they span. Blended draws keep
    /// only the fragments their frustum owns, so none is blended twice where frustums overlap.
    MultiFrustum,
    /// One frustum over the frame's near and far; window depth log2(w / near) / log2(far / near)
    /// written per fragment (exact, the depth test after the fragment shader). Every primitive
    /// must write it (Primitive::supportsLogarithmicDepth).
    Logarithmic,
    /// The same written per vertex: no fragment-shader cost, but linear across each triangle, so
    /// large triangles are drawn too far between their vertices, and clipping at the near plane
    /// is approximate.
    LogarithmicVertex,
    /// One frustum, complementary (reversed) depth: window depth near / w in a Depth32F buffer with
    /// a 0..1 clip range (glClipControl: OpenGL 4.5 or GL_ARB_clip_control, else orbis::Error).
    /// About 2^-23 of the distance everywhere. The scene renders into the target's colour textures
    /// with a float depth texture of its own when the target's depth is not Depth32F.
    Complementary,
    /// One frustum with the fixed near and far limits and ordinary 24-bit depth: the naive baseline.
    Single,
};

/// The six strategies, Automatic first.
inline constexpr DepthStrategy kAllDepthStrategies[] = {DepthStrategy::Automatic,     DepthStrategy::MultiFrustum,
                                                        DepthStrategy::Logarithmic,   DepthStrategy::LogarithmicVertex,
                                                        DepthStrategy::Complementary, DepthStrategy::Single};

/// "auto", "multi-frustum", "logarithmic", "logarithmic (vertex)", "complementary", "single".
const char* depthStrategyName(DepthStrategy strategy) noexcept;

/// The defines a program drawn under a (resolved) strategy needs from the built-in depth.glsl:
/// OG_DEPTH_LOGARITHMIC, OG_DEPTH_LOGARITHMIC_VERTEX or OG_DEPTH_COMPLEMENTARY, and for blended
/// (Translucent) draws under MultiFrustum OG_DEPTH_OWNED_RANGE.
std::vector<ShaderDefine> depthStrategyDefines(DepthStrategy strategy, Pass pass);

/// The analytic minimum separation, metres, between two surfaces at `distance` that the strategy
/// still orders: the separation that moves the window depth by one step of the buffer, for a frame
/// whose nearest geometry is `nearDistance` away and farthest `farDistance` (Single: its fixed
/// limits). Single and MultiFrustum: Baker's s = z^2 / (2^24 n - z) of the course notes, with n the
/// near plane of the frustum holding z; Logarithmic: z ln(far / near) 2^-24; Complementary:
/// z 2^-23, the float's spacing of near / z at its coarsest. Infinity where the strategy cannot
/// resolve at all (z at or beyond 2^24 n). Rasterisation and float arithmetic add to these (Akeley
/// and Su 2006): measured separations run one to three times larger.
double analyticMinimumSeparation(DepthStrategy strategy, double distance, double nearDistance, double farDistance,
                                 double farToNearRatio = 1000.0) noexcept;

} // namespace orbis
