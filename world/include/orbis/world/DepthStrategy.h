#pragma once

#include <cstdint>

namespace orbis::world {

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

} // namespace orbis::world
