#include "BillboardBatch.h"

#include <orbis/renderer/ShaderCache.h>

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
    state.depthTest.enabled = depth.depthTest;
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
    setIfActive(command.draw, "u_inverseAtlasSize",
                glm::vec2(1.0f / static_cast<float>(atlas.width()), 1.0f / static_cast<float>(atlas.height())));
}

} // namespace orbis::scene::detail
