#include "orbis/scene/MeshPrimitive.h"

#include "orbis/scene/Effect.h"

#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>

#include <glm/ext/matrix_transform.hpp>

#include <cassert>

namespace orbis {

MeshPrimitive::MeshPrimitive(Mesh mesh, const glm::vec4& color, Pass pass)
    : _mesh(std::move(mesh))
    , _boundingSphere(BoundingSphere::fromPoints(_mesh.positions))
    , _color(color)
    , _pass(pass)
    , _lit(!_mesh.normals.empty())
{
    assert(!_mesh.positions.empty() && _mesh.primitiveType == PrimitiveType::Triangles);
}

MeshPrimitive::~MeshPrimitive() = default;

void MeshPrimitive::update(FrameState& frameState, CommandList& commands)
{
    if (!_program) {
        ShaderProgramDescription description;
        description.name = "mesh";
        description.vertex = ShaderSource::embedded("scene/mesh/mesh.vert.glsl");
        description.fragment = ShaderSource::embedded("scene/mesh/mesh.frag.glsl");
        if (_lit) {
            description.defines.push_back({"LIGHTING"});
        }
        _program = frameState.device.shaderCache().get(description);
        VertexArrayOptions options;
        options.center = _boundingSphere.centre;
        _vertexArray = frameState.context.createVertexArray(_mesh, *_program, options);
        _mesh = Mesh(); // on the GPU now
    }
    DrawCommand command;
    command.debugName = "mesh";
    command.tags = static_cast<std::uint32_t>(Effect::Meshes);
    command.vertexArray = &*_vertexArray;
    command.shaderProgram = _program.get();
    command.modelMatrix = glm::translate(glm::dmat4(1.0), _boundingSphere.centre);
    command.uniforms.set("u_color", _color);
    command.pass = _pass;
    command.boundingSphere = _boundingSphere;
    command.horizonOcclusionPoint = _occlusionPoint;
    if (_pass == Pass::Translucent) {
        command.renderState.blending = Blending::alphaBlending();
        // "Over" for alpha too, so an opaque background stays opaque.
        command.renderState.blending.sourceAlphaFactor = SourceBlendingFactor::One;
        command.renderState.depthMask = false;
    }
    commands.push_back(std::move(command));
}

} // namespace orbis
