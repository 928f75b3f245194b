#include "orbis/scene/Globe.h"

#include "orbis/scene/Effect.h"

#include <orbis/core/BoxTessellator.h>
#include <orbis/core/CubeMapEllipsoidTessellator.h>
#include <orbis/core/GeographicGridEllipsoidTessellator.h>
#include <orbis/core/Error.h>
#include <orbis/core/SubdivisionEllipsoidTessellator.h>
#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>
#include <orbis/world/Diagnostics.h>
#include <orbis/world/TileMapService.h>

#include <glm/geometric.hpp>

#include <cmath>

namespace orbis::scene {

TessellationResult Globe::tessellate(const Ellipsoid& ellipsoid, GlobeTessellation tessellation, int level,
                                     Deviation deviation)
{
    switch (tessellation) {
    case GlobeTessellation::SubdivisionEllipsoid:
        return SubdivisionEllipsoidTessellator::compute(ellipsoid, level, EllipsoidProjection::Geodetic,
                                                        VertexAttributes::Position, deviation);
    case GlobeTessellation::GeographicGrid:
        return GeographicGridEllipsoidTessellator::compute(ellipsoid, 2 * level, level, VertexAttributes::Position,
                                                           deviation);
    case GlobeTessellation::CubeMap:
        break;
    }
    return CubeMapEllipsoidTessellator::compute(ellipsoid, level, CubeMapSpacing::EqualAngle,
                                                EllipsoidProjection::Geodetic, VertexAttributes::Position, deviation);
}

Globe::Globe(const Ellipsoid& ellipsoid, GlobeOptions options)
    : _ellipsoid(ellipsoid)
    , _options(std::move(options))
{
}

Globe::~Globe() = default;

std::optional<BoundingSphere> Globe::boundingSphere() const
{
    return BoundingSphere{glm::dvec3(0.0), _ellipsoid.maximumRadius()};
}

double Globe::gridSpacing(double metersPerPixelOnGround, double radius) noexcept
{
    static constexpr double kSpacingsDegrees[] = {0.1, 0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 15.0, 30.0};
    for (const double spacing : kSpacingsDegrees) {
        if (toRadians(spacing) * radius / std::max(metersPerPixelOnGround, 1e-9) >= 60.0) {
            return toRadians(spacing);
        }
    }
    return toRadians(30.0);
}

renderer::ShaderProgram& Globe::program(FrameState& frameState)
{
    std::shared_ptr<renderer::ShaderProgram>& program = _programs[static_cast<std::size_t>(frameState.depthStrategy)];
    if (program) {
        return *program;
    }
    const bool rayCast = _options.method == GlobeMethod::RayCast;
    renderer::ShaderProgramDescription description;
    description.name = rayCast ? "globe (ray cast)" : "globe (tessellated)";
    description.vertex = renderer::ShaderSource::embedded("scene/globe/globe.vert.glsl");
    description.fragment = renderer::ShaderSource::embedded("scene/globe/globe.frag.glsl");
    if (rayCast) {
        description.defines.push_back({"RAY_CAST"});
        description.fragment.text.insert(0, renderer::ShaderSource::embedded("scene/globe/ray_cast_ellipsoid.glsl").text);
    }
    if (!_options.dayTexture.empty()) {
        description.defines.push_back({"DAY_TEXTURE"});
    }
    if (!_options.nightTexture.empty()) {
        description.defines.push_back({"NIGHT_TEXTURE"});
    }
    if (_options.lighting) {
        description.defines.push_back({"LIGHTING"});
    }
    if (_options.grid) {
        description.defines.push_back({"GRID"});
    }
    for (renderer::ShaderDefine& define : depthStrategyDefines(frameState.depthStrategy, Pass::Opaque)) {
        description.defines.push_back(std::move(define));
    }
    if (frameState.device.info().gpuShader5) {
        // Keeps og_emulatedDoubleSubtract's two-sum (built-in functions.glsl).
        description.defines.push_back({"OG_PRECISE"});
        description.extensions.push_back("GL_ARB_gpu_shader5");
    }
    program = frameState.device.shaderCache().get(description);
    return *program;
}

void Globe::createResources(FrameState& frameState)
{
    const bool rayCast = _options.method == GlobeMethod::RayCast;
    const Mesh mesh = rayCast ? BoxTessellator::compute(_ellipsoid, VertexAttributes::Position, Deviation::Skip).mesh
                              : tessellate(_ellipsoid, _options.tessellation, _options.tessellationLevel).mesh;
    _vertexArray = frameState.context.createVertexArray(mesh, program(frameState));

    // Read here, at the first frame: an error names the file, as the GPU's size limit is known only now.
    auto texture = [&](const std::filesystem::path& path, const char* what) {
        const Image image = world::readGlobeImage(path);
        try {
            return frameState.device.createTexture2D(image, true);
        } catch (const Error& error) {
            throw Error(world::cutForMessage(path.string()) + ": " + what + ": " + error.what());
        }
    };
    if (!_options.dayTexture.empty()) {
        _dayTexture = texture(_options.dayTexture, "globe texture");
    }
    if (!_options.nightTexture.empty()) {
        _nightTexture = texture(_options.nightTexture, "globe night texture");
    }
    SamplerDescription sampler;
    sampler.minificationFilter = TextureMinificationFilter::LinearMipmapLinear;
    sampler.wrapS = TextureWrap::Repeat;
    // No anisotropy: Mesa 22's llvmpipe shows speckles along mip-level boundaries with it.
    _sampler = frameState.device.createSampler(sampler);
}

void Globe::update(FrameState& frameState, CommandList& commands)
{
    if (!_vertexArray) {
        createResources(frameState);
    }
    renderer::ShaderProgram& shaderProgram = program(frameState);
    const bool rayCast = _options.method == GlobeMethod::RayCast;
    SceneCommand command;
    command.draw.debugName = "globe";
    command.tags = static_cast<std::uint32_t>(Effect::Globe);
    command.ground = true;
    if (_options.lighting) {
        command.tags = command.tags | Effect::Lighting;
    }
    if (!_options.nightTexture.empty()) {
        command.tags = command.tags | Effect::NightLights;
    }
    if (_options.grid) {
        command.tags = command.tags | Effect::Grid;
    }
    command.draw.vertexArray = &*_vertexArray;
    command.draw.shaderProgram = &shaderProgram;
    command.boundingSphere = boundingSphere();
    // Nothing on the ellipsoid is nearer than the eye's height above it. Nothing visible is farther
    // than the tangent to the inscribed sphere (radius b: a sight line through it would hit the
    // ellipsoid first) continued to the circumscribed one (radius a). Both are far tighter than
    // the bounding sphere, so a low eye needs fewer frustums.
    const double eyeHeight = _ellipsoid.toGeodetic3D(frameState.camera.eye()).height;
    if (eyeHeight > 0.0) {
        const double a = _ellipsoid.maximumRadius();
        const double b = _ellipsoid.minimumRadius();
        const double eyeDistance = glm::length(frameState.camera.eye());
        command.nearestDistance = eyeHeight;
        command.farthestDistance = std::sqrt(std::max(0.0, eyeDistance * eyeDistance - b * b)) + std::sqrt(a * a - b * b);
    }
    // The box is drawn from inside out so that the globe still shows with the eye inside it.
    command.draw.renderState.facetCulling.face = rayCast ? renderer::CullFace::Front : renderer::CullFace::Back;

    // Each variant uses some of these; the GLSL compiler removes the others.
    auto set = [&](std::string_view name, const renderer::UniformValue& value) {
        if (shaderProgram.hasUniform(name)) {
            command.draw.uniforms.set(name, value);
        }
    };
    set("u_oneOverRadii", glm::vec3(_ellipsoid.oneOverRadii()));
    set("u_oneOverRadiiSquared", glm::vec3(_ellipsoid.oneOverRadiiSquared()));
    set("u_color", _options.color);
    if (rayCast) {
        const glm::dvec3 eyeScaled = frameState.camera.eye() * _ellipsoid.oneOverRadii();
        set("u_cameraScaled", glm::vec3(eyeScaled));
        set("u_cameraScaledLengthSquaredMinusOne", static_cast<float>(glm::dot(eyeScaled, eyeScaled) - 1.0));
    }
    if (_options.grid) {
        const double distance = std::max(1.0, eyeHeight);
        set("u_gridSpacing",
            static_cast<float>(gridSpacing(frameState.metersPerPixel(distance), _ellipsoid.maximumRadius())));
        set("u_gridColor", _options.gridColor);
    }
    if (_dayTexture) {
        command.draw.textures.push_back({0, &*_dayTexture, &*_sampler});
    }
    if (_nightTexture) {
        command.draw.textures.push_back({1, &*_nightTexture, &*_sampler});
    }
    commands.push_back(std::move(command));
}

} // namespace orbis::scene
