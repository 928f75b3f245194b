#include "BillboardBatch.h"

#include <orbis/renderer/ShaderCache.h>

#include <limits>

namespace orbis::scene::detail {

namespace {

void setIfActive(renderer::DrawCommand& command, const char* name, const renderer::UniformValue& value)
{
    if (command.shaderProgram->hasUniform(name)) {
        command.uniforms.set(name, value);
    }
}

} // namespace

std::unique_ptr<DepthPrograms> billboardPrograms(bool label)
{
    return std::make_unique<DepthPrograms>([label](DepthStrategy, Pass) {
        renderer::ShaderProgramDescription description;
        description.name = label ? "label" : "billboard";
        description.vertex = renderer::ShaderSource::embedded("scene/billboard/billboard.vert.glsl");
        description.geometry = renderer::ShaderSource::embedded("scene/billboard/billboard.geom.glsl");
        description.fragment = renderer::ShaderSource::embedded("scene/billboard/billboard.frag.glsl");
        if (label) {
            description.defines.push_back({"LABEL"});
        }
        return description;
    });
}

void prepareBillboardCommand(SceneCommand& command, const FrameState& frameState, const BillboardDepthOptions& depth,
                             const renderer::TextureAtlas& atlas)
{
    assert(command.draw.shaderProgram);
    command.draw.primitiveType = PrimitiveType::Points;
    command.pass = Pass::Translucent;
    renderer::RenderState& state = command.draw.renderState;
    state.facetCulling.enabled = false;
    state.depthTest.enabled = false; // the geometry shader tests each anchor (never a quad's fragments)
    state.depthTest.function = renderer::CompareFunction::LessOrEqual;
    state.depthMask = false;
    // The shader writes premultiplied colour (the atlas is premultiplied, so linear filtering
    // of a scaled image does not darken its edges with the transparent padding): "over".
    state.blending = renderer::Blending::alphaBlending();
    state.blending.sourceRgbFactor = renderer::SourceBlendingFactor::One;
    state.blending.sourceAlphaFactor = renderer::SourceBlendingFactor::One;
    if (!depth.horizonCulling) {
        command.horizonOcclusionPoint.reset(); // the scene would cull the command by it
    }

    const glm::dvec3 oneOverRadii = frameState.ellipsoid.oneOverRadii();
    const glm::dvec3 eyeScaled = frameState.camera.eye() * oneOverRadii;
    const double horizon = glm::dot(eyeScaled, eyeScaled) - 1.0;
    // A camera on or under the surface hides nothing behind the ellipsoid (EllipsoidalOccluder).
    const bool cull = depth.horizonCulling && horizon > 0.0;
    setIfActive(command.draw, "u_oneOverRadii", glm::vec3(oneOverRadii));
    setIfActive(command.draw, "u_eyeScaled", glm::vec3(eyeScaled));
    setIfActive(command.draw, "u_horizonDistanceSquared", cull ? static_cast<float>(horizon) : -1.0f);
    const float depthOffset = std::clamp(depth.depthOffsetFraction, 0.0f, 1.0f);
    setIfActive(command.draw, "u_depthScale", 1.0f - depthOffset);
    // The depth is taken up to depthOffsetFraction of the distance nearer the eye than the
    // anchors: the sphere the scene bins by must reach there, or the near plane clips the quads
    // (twice that, so float rounding of the depth cannot put a quad on the plane).
    if (command.boundingSphere) {
        const double distance = glm::length(command.boundingSphere->centre - frameState.camera.eye());
        command.boundingSphere->radius += 2.0 * static_cast<double>(depthOffset) *
                                          (distance + command.boundingSphere->radius);
    }
    // The anchors are tested against a copy of the depth the frustum's opaque commands wrote, in the
    // geometry shader; without one (a window's depth) they are not tested. The sampler reads a
    // texture either way: the atlas stands in, unread.
    const double disableDistance = std::clamp(depth.disableDepthTestDistance, 0.0,
                                              static_cast<double>(std::numeric_limits<float>::max()));
    setIfActive(command.draw, "u_disableDepthTestDistance", static_cast<float>(disableDistance));
    setIfActive(command.draw, "u_anchorDepthTest", frameState.sceneDepth ? 1.0f : 0.0f);
    command.readsSceneDepth = frameState.sceneDepth != nullptr;
    assert(!command.draw.textures.empty()); // the atlas, on unit 0
    command.draw.textures.push_back(
        {1, frameState.sceneDepth ? frameState.sceneDepth : command.draw.textures.front().texture, nullptr});
    setIfActive(command.draw, "u_inverseAtlasSize",
                glm::vec2(1.0f / static_cast<float>(atlas.width()), 1.0f / static_cast<float>(atlas.height())));
}

} // namespace orbis::scene::detail
