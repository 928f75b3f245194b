#include "orbis/scene/MeshPrimitive.h"

#include "orbis/scene/Effect.h"

#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>

#include <cassert>

namespace orbis::scene {

MeshPrimitive::MeshPrimitive(Mesh mesh, const glm::vec4& color, Pass pass, VertexTransform transform)
    : _boundingSphere(BoundingSphere::fromPoints(mesh.positions))
    , _color(color)
    , _pass(pass)
    , _lit(!mesh.normals.empty())
    , _primitiveType(mesh.primitiveType)
    , _transform(transform)
    , _lastTransform(transform == VertexTransform::Automatic ? VertexTransform::RelativeToCenter : transform)
{
    assert(!mesh.positions.empty() &&
           (mesh.primitiveType == PrimitiveType::Triangles || mesh.primitiveType == PrimitiveType::Points));
    _arrays = std::make_unique<VertexTransformArrays>(std::move(mesh), _boundingSphere.centre, transform);
}

MeshPrimitive::~MeshPrimitive() = default;

renderer::ShaderProgramDescription MeshPrimitive::programDescription(VertexTransform transform, DepthStrategy depth, Pass pass,
                                                           bool lit, const renderer::DeviceInfo& device)
{
    renderer::ShaderProgramDescription description;
    description.name = std::string("mesh (") + vertexTransformName(transform) + ", " + depthStrategyName(depth) + ")";
    description.vertex = renderer::ShaderSource::embedded("scene/mesh/mesh.vert.glsl");
    description.fragment = renderer::ShaderSource::embedded("scene/mesh/mesh.frag.glsl");
    if (lit) {
        description.defines.push_back({"LIGHTING"});
    }
    addVertexTransformDefines(transform, device, description);
    for (renderer::ShaderDefine& define : depthStrategyDefines(depth, pass)) {
        description.defines.push_back(std::move(define));
    }
    return description;
}

void MeshPrimitive::update(FrameState& frameState, CommandList& commands)
{
    const VertexTransform transform = resolveVertexTransform(_transform, _boundingSphere, frameState);
    _lastTransform = transform;
    std::shared_ptr<renderer::ShaderProgram>& program =
        _programs[static_cast<std::size_t>(transform)][static_cast<std::size_t>(frameState.depthStrategy)];
    if (!program) {
        program = frameState.device.shaderCache().get(
            programDescription(transform, frameState.depthStrategy, _pass, _lit, frameState.device.info()));
    }
    SceneCommand command;
    command.draw.debugName = "mesh";
    command.tags = static_cast<std::uint32_t>(Effect::Meshes);
    command.draw.vertexArray = &_arrays->get(frameState.context, transform, frameState.camera.eye());
    command.draw.primitiveType = _primitiveType;
    command.draw.shaderProgram = program.get();
    command.draw.modelMatrix = _arrays->modelMatrix(transform);
    command.draw.uniforms.set("u_color", _color);
    command.pass = _pass;
    command.boundingSphere = _boundingSphere;
    command.horizonOcclusionPoint = _occlusionPoint;
    if (_pass == Pass::Translucent) {
        command.draw.renderState.blending = renderer::Blending::alphaBlending();
        // "Over" for alpha too, so an opaque background stays opaque.
        command.draw.renderState.blending.sourceAlphaFactor = renderer::SourceBlendingFactor::One;
        command.draw.renderState.depthMask = false;
    }
    commands.push_back(std::move(command));
}

} // namespace orbis::scene
