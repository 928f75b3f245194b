#pragma once

#include "orbis/core/BoundingSphere.h"
#include "orbis/core/Mesh.h"
#include "orbis/renderer/RenderState.h"
#include "orbis/renderer/UniformValue.h"

#include <glm/mat4x4.hpp>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace orbis::renderer {

class Framebuffer;
class Sampler;
class ShaderProgram;
class Texture2D;
class VertexArray;

/// When a command is drawn within a frame: opaque first, then translucent (blended, in the order
/// submitted), then overlay (screen-space, after every frustum).
enum class Pass : std::uint8_t { Opaque, Translucent, Overlay };

/// A texture and the sampler that reads it, on one texture unit.
struct TextureBinding {
    int unit = 0;
    const Texture2D* texture = nullptr;
    const Sampler* sampler = nullptr; ///< null: the texture's own parameters (linear, clamp to edge)
};

/// Everything needed to draw once, as plain data: building one touches no GL; Context::draw
/// executes it. Pointers do not own: the resources must outlive the draw.
///
/// ```
/// DrawCommand command;
/// command.vertexArray = &vertexArray;
/// command.shaderProgram = &program;
/// command.uniforms.set("u_color", glm::vec4(1, 0, 0, 1));
/// command.renderState.depthTest.enabled = false;
/// context.draw(command, sceneState);
/// ```
struct DrawCommand {
    const VertexArray* vertexArray = nullptr;
    PrimitiveType primitiveType = PrimitiveType::Triangles;
    std::size_t first = 0;            ///< first index (indexed arrays) or vertex
    std::optional<std::size_t> count; ///< indices or vertices; empty: all from first to the end
    ShaderProgram* shaderProgram = nullptr;
    UniformValues uniforms;
    RenderState renderState;
    std::vector<TextureBinding> textures;
    Framebuffer* framebuffer = nullptr; ///< null: the Context's current framebuffer
    glm::dmat4 modelMatrix{1.0};        ///< model to world, for the og_ matrices
    std::string debugName;              ///< named in error messages

    // Read by the scene to cull and bin the command; Context::draw ignores them.
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
    /// A bit set the layer above defines (the scene's Effect); reported, never interpreted here.
    std::uint32_t tags = 0;
};

} // namespace orbis::renderer
