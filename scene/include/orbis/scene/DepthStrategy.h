#pragma once

#include <orbis/world/DepthStrategy.h>

#include <cstdint>
#include <vector>

namespace orbis::renderer {
struct ShaderDefine; // orbis/renderer/ShaderProgram.h
} // namespace orbis::renderer

namespace orbis::scene {

// The depth strategy is named in scene files, so the enumeration is the world layer's; the scene
// layer names it as its own (scene::DepthStrategy is world::DepthStrategy) and adds what drawing
// with one takes. Kept free of renderer headers.
using world::DepthStrategy;
using world::depthStrategyName;
using world::kAllDepthStrategies;

enum class Pass : std::uint8_t; // orbis/scene/SceneCommand.h

/// The defines a program drawn under a (resolved) strategy needs from the built-in depth.glsl:
/// OG_DEPTH_LOGARITHMIC, OG_DEPTH_LOGARITHMIC_VERTEX or OG_DEPTH_COMPLEMENTARY, and for blended
/// (Translucent) draws under MultiFrustum OG_DEPTH_OWNED_RANGE.
std::vector<renderer::ShaderDefine> depthStrategyDefines(DepthStrategy strategy, Pass pass);

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

} // namespace orbis::scene
