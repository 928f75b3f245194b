#pragma once

#include <orbis/core/BoundingSphere.h>
#include <orbis/renderer/DrawCommand.h>

#include <glm/vec3.hpp>

#include <cstdint>
#include <limits>
#include <optional>

namespace orbis::scene {

/// When a command is drawn within a frame: opaque first, then translucent (blended, in the order
/// submitted), then overlay (screen-space, after every frustum). Draped commands (shadow volumes
/// that colour the ground inside them) are drawn in each frustum's opaque pass, right after its
/// ground commands (SceneCommand::ground) and before its other opaque commands.
enum class Pass : std::uint8_t { Opaque, Translucent, Overlay, Draped };

/// What a primitive hands the Scene for one draw: the renderer's DrawCommand, which the Context
/// executes, and what the scene reads to cull it and bin it into frustums and passes, which the
/// renderer never sees.
///
/// ```
/// SceneCommand command;
/// command.draw.vertexArray = &vertexArray;
/// command.draw.shaderProgram = &program;
/// command.boundingSphere = sphere;
/// commands.push_back(std::move(command)); // in Primitive::update
/// ```
struct SceneCommand {
    renderer::DrawCommand draw;
    Pass pass = Pass::Opaque;
    std::optional<BoundingSphere> boundingSphere; ///< world; none: never culled, spans every frustum
    /// Horizon occlusion point in ellipsoid-scaled space (EllipsoidalOccluder); none: the command is
    /// not horizon-culled.
    std::optional<glm::dvec3> horizonOcclusionPoint;
    /// Bounds on the distance (metres) from the eye to anything the command draws, where the
    /// primitive knows better than its sphere (a globe: its height above the ellipsoid, and the
    /// distance to its horizon). They narrow the frustums; the defaults leave the sphere to decide.
    double nearestDistance = 0.0;
    double farthestDistance = std::numeric_limits<double>::infinity();
    /// The Effect bits of what the command draws (Effect.h), gathered into FrameStatistics::effects.
    std::uint32_t tags = 0;
    /// A translucent command that samples FrameState::sceneDepth: the scene copies the depth its
    /// frustum's opaque commands wrote into that texture before the translucent pass.
    bool readsSceneDepth = false;
    /// An opaque command that draws the globe's surface: draped commands colour it and follow it.
    bool ground = false;
};

} // namespace orbis::scene
