#pragma once

#include "orbis/core/Mesh.h"
#include "orbis/renderer/RenderState.h"
#include "orbis/renderer/UniformValue.h"

#include <glm/mat4x4.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace orbis::renderer {

class Framebuffer;
class Sampler;
class ShaderProgram;
class Texture2D;
class VertexArray;

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
};

} // namespace orbis::renderer
