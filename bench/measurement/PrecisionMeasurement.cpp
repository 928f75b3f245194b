#include "PrecisionMeasurement.h"

#include <orbis/core/BoxTessellator.h>
#include <orbis/core/EmulatedDouble.h>
#include <orbis/core/Error.h>
#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>
#include <orbis/renderer/Framebuffer.h>
#include <orbis/renderer/SceneState.h>
#include <orbis/core/Transforms.h>
#include <orbis/scene/MeshPrimitive.h>
#include <orbis/scene/Scene.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

using namespace orbis::scene;

namespace orbis::bench {

namespace {

/// The next float above x's float, as a double.
double floatAbove(double x) noexcept
{
    return static_cast<double>(std::nextafter(static_cast<float>(x), std::numeric_limits<float>::infinity()));
}

/// A square facing an eye that looks along +z with +y up (screen right is world -x),
/// counter-clockwise on screen, tilted so that its distance grows by `tilt` per `half` upwards.
/// Offsets from the eye are rounded to float, as the vertex stage sees them.
Mesh facingSquare(const glm::dvec3& eye, double distance, double half, double tilt)
{
    auto at = [&](double x, double y) {
        const double z = static_cast<double>(static_cast<float>(distance + tilt * y / half));
        return eye + glm::dvec3(x, y, z);
    };
    Mesh mesh;
    mesh.positions = {at(half, -half), at(-half, -half), at(-half, half), at(half, half)};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    return mesh;
}

} // namespace

ClipmapJitterResult measureClipmapJitter(renderer::Context& context, const scene::ClipmapTerrainOptions& clipmap,
                                         const Geodetic2D& place, double eyeAboveGround, const JitterOptions& options)
{
    const Ellipsoid& earth = Ellipsoid::wgs84();
    Scene scene(earth);
    auto terrain = std::make_shared<ClipmapTerrain>(earth, clipmap);
    scene.add(terrain);
    // A frame of the view's aspect, small: what is drawn depends on the view, not on its pixels.
    renderer::Framebuffer* previous = context.framebuffer();
    renderer::Framebuffer framebuffer = context.createFramebuffer(64, std::max(1, 64 * options.height / options.width));
    context.setFramebuffer(&framebuffer);
    auto converge = [&](double height) {
        scene.camera().setView(earth, Geodetic3D(place.longitude, place.latitude, height),
                               HeadingPitchRoll{0.0, toRadians(-20.0), 0.0});
        for (int frame = 0; frame < 200 && !(frame > 0 && terrain->converged()); ++frame) {
            scene.render(context);
        }
    };
    ClipmapJitterResult result;
    try {
        converge(9000.0);
        const std::optional<double> ground = terrain->groundHeight(place);
        if (ground) {
            converge(*ground + eyeAboveGround);
        }
    } catch (...) {
        context.setFramebuffer(previous);
        throw;
    }
    context.setFramebuffer(previous);
    const std::optional<double> ground = terrain->groundHeight(place);
    if (!ground) {
        return result;
    }
    const Camera& camera = scene.camera();
    result.groundHeight = *ground;
    result.eyeAboveGround = earth.toGeodetic3D(camera.eye()).height - *ground;
    result.finestLevelDrawn = terrain->clipmapStatistics()->finestLevelDrawn;
    result.converged = terrain->converged();

    renderer::SceneState state;
    state.viewMatrix = camera.viewMatrix();
    state.projectionMatrix = camera.projectionMatrix(static_cast<double>(options.width) / options.height,
                                                     0.1 * eyeAboveGround, 1e7);
    state.cameraEye = camera.eye();
    state.viewport = {0, 0, options.width, options.height};
    const std::vector<glm::vec4> clip = terrain->captureDrawnClipPositions(context, state);
    const std::vector<glm::dvec3> reference = terrain->drawnTriangles(true);
    if (clip.size() != reference.size()) {
        throw Error("clipmap jitter: " + std::to_string(clip.size()) + " vertices captured for " +
                    std::to_string(reference.size()) + " drawn");
    }
    const glm::dmat4 viewProjection = state.projectionMatrix * state.viewMatrix;
    auto window = [&](const glm::dvec4& c) {
        return glm::dvec2((c.x / c.w * 0.5 + 0.5) * options.width, (c.y / c.w * 0.5 + 0.5) * options.height);
    };
    const double pixelAngle = 2.0 * std::tan(0.5 * camera.fieldOfViewY()) / options.height;
    for (std::size_t i = 0; i < clip.size(); ++i) {
        const glm::dvec4 exact = viewProjection * glm::dvec4(reference[i], 1.0);
        if (exact.w < 0.1 * eyeAboveGround || std::abs(exact.x) > exact.w || std::abs(exact.y) > exact.w) {
            continue; // behind the eye, or outside the view
        }
        const glm::dvec4 gpu(clip[i]);
        const double pixels = gpu.w > 0.0 && std::isfinite(gpu.x) && std::isfinite(gpu.y)
                                  ? glm::length(window(gpu) - window(exact))
                                  : std::numeric_limits<double>::infinity();
        if (pixels > result.error.maxPixels) {
            result.error.maxPixels = pixels;
            result.error.maxMeters = pixels * pixelAngle * exact.w;
        }
        ++result.vertices;
        result.within10m += glm::distance(reference[i], camera.eye()) < 10.0 ? 1 : 0;
    }
    return result;
}

glm::dvec3 jitterTarget(double heightMeters)
{
    return Ellipsoid::wgs84().toCartesian(Geodetic3D::fromDegrees(10.0, 45.0, heightMeters));
}

JitterResult measureVertexJitter(renderer::Context& context, VertexTransform transform, const glm::dvec3& target,
                                 double eyeDistance, const JitterOptions& options)
{
    renderer::Device& device = context.device();
    const Ellipsoid& earth = Ellipsoid::wgs84();
    const glm::dvec3 eye = target + eyeDistance * earth.geodeticSurfaceNormal(target);
    Camera camera;
    camera.setFieldOfViewY(options.fieldOfViewYRadians);
    camera.lookAt(eye, target, glm::dvec3(0.0, 0.0, 1.0));
    const double aspect = static_cast<double>(options.width) / options.height;
    const glm::dvec3 right = camera.right();
    const glm::dvec3 up = glm::cross(right, camera.direction());

    // The measured points over the middle 60 % of the view, then one vertex that stretches the
    // object's bounding sphere to objectRadiusMeters, its centre off to one side.
    const double halfHeight = eyeDistance * std::tan(0.5 * options.fieldOfViewYRadians);
    Mesh mesh;
    mesh.primitiveType = PrimitiveType::Points;
    const int g = std::max(options.gridSize, 2);
    for (int i = 0; i < g; ++i) {
        for (int j = 0; j < g; ++j) {
            const double u = 0.6 * (2.0 * i / (g - 1) - 1.0);
            const double v = 0.6 * (2.0 * j / (g - 1) - 1.0);
            mesh.positions.push_back(target + u * halfHeight * aspect * right + v * halfHeight * up);
        }
    }
    const std::size_t measured = mesh.positions.size();
    mesh.positions.push_back(target + 2.0 * options.objectRadiusMeters * right);
    const std::vector<glm::dvec3> positions = mesh.positions;
    const BoundingSphere sphere = BoundingSphere::fromPoints(positions);

    renderer::SceneState scene;
    scene.viewMatrix = camera.viewMatrix();
    scene.projectionMatrix = camera.projectionMatrix(aspect, 0.01 * eyeDistance, 100.0 * eyeDistance);
    scene.cameraEye = eye;
    scene.viewport = {0, 0, options.width, options.height};

    renderer::Framebuffer unused = context.createFramebuffer(1, 1);
    FrameState frameState{context, device, camera, earth, options.width, options.height, glm::dvec3(1.0, 0.0, 0.0),
                          0.0, 0, Frustum::fromViewProjection(scene.projectionMatrix * scene.viewMatrix),
                          EllipsoidalOccluder(earth, eye), DepthStrategy::MultiFrustum};
    const VertexTransform concrete = resolveVertexTransform(transform, sphere, frameState);
    VertexTransformArrays arrays(std::move(mesh), sphere.centre, concrete);
    renderer::ShaderProgramDescription description =
        MeshPrimitive::programDescription(concrete, DepthStrategy::MultiFrustum, Pass::Opaque, false, device.info());
    description.transformFeedbackVaryings = {"gl_Position"};
    const std::shared_ptr<renderer::ShaderProgram> program = device.shaderCache().get(description);

    renderer::DrawCommand command;
    command.debugName = "jitter measurement";
    command.vertexArray = &arrays.get(context, concrete, eye);
    command.shaderProgram = program.get();
    command.primitiveType = PrimitiveType::Points;
    command.modelMatrix = arrays.modelMatrix(concrete);
    command.framebuffer = &unused;
    command.uniforms.set("u_color", glm::vec4(1.0f));
    const std::vector<float> clip = context.captureVertexOutputs(command, scene);

    JitterResult result;
    const glm::dmat4 viewProjection = scene.projectionMatrix * scene.viewMatrix;
    for (std::size_t i = 0; i < measured; ++i) {
        const glm::dvec4 gpu(clip[4 * i], clip[4 * i + 1], clip[4 * i + 2], clip[4 * i + 3]);
        const glm::dvec4 reference = viewProjection * glm::dvec4(positions[i], 1.0);
        // A vertex the GPU put at or behind the eye has no window position: unbounded error.
        const double pixels = gpu.w > 0.0 ? glm::length(clipToWindow(gpu, options.width, options.height) -
                                                         clipToWindow(reference, options.width, options.height))
                                          : std::numeric_limits<double>::infinity();
        const double depth = glm::dot(positions[i] - eye, camera.direction());
        const double metersPerPixel = 2.0 * depth * std::tan(0.5 * options.fieldOfViewYRadians) / options.height;
        result.maxPixels = std::max(result.maxPixels, pixels);
        result.maxMeters = std::max(result.maxMeters, pixels * metersPerPixel);
    }
    return result;
}

ZFightingResult measureZFighting(renderer::Context& context, DepthStrategy strategy, double distance, double separation,
                                 const ZFightingOptions& options)
{
    const Ellipsoid& earth = Ellipsoid::wgs84();
    // An integer eye over the pole looking straight up: the view matrix is exact, and offsets that
    // are floats reach the vertex stage exactly (DSFUN90 below).
    const glm::dvec3 eye(0.0, 0.0, std::round(earth.radii().z) + 10.0);
    const double nearDistance = static_cast<double>(static_cast<float>(distance));
    const double farDistance = std::max(static_cast<double>(static_cast<float>(distance + separation)),
                                        floatAbove(nearDistance));
    const double fieldOfView = 0.7853981633974483;
    const double halfView = nearDistance * std::tan(0.5 * fieldOfView);
    // The near square reaches 0.6 of the view each way; sizes are floats, and not powers of two:
    // round numbers were seen to round the depths of two parallel squares alike (a single frustum
    // then "resolved" a hundredth of a depth step at 100 m).
    const double half = static_cast<double>(static_cast<float>(0.6 * halfView));
    // Tilted by about 1.4 % of the distance across the square, so that the counted pixels sample
    // depths across many of the buffer's steps rather than one.
    const double tilt = options.tilted ? static_cast<double>(static_cast<float>(0.0137 * distance)) : 0.0;

    // Four frames: the far square half as large again as the near one and smaller (in the same
    // plane), each submitted before and after the near one. Triangles of different sizes round
    // their interpolated depths differently, which may favour either square; and llvmpipe lets
    // the second of two sloped surfaces at one depth pass a Less test (measured: bit-identical
    // tilted quads drawn twice show the second), so a tie favours whichever comes second. A pixel
    // is wrong when it is wrong in any of the four.
    auto render = [&](double farScale, bool farFirst, FrameStatistics& statistics) {
        SceneOptions sceneOptions;
        sceneOptions.depthStrategy = strategy;
        sceneOptions.multiFrustum.nearLimit = options.nearLimit;
        Scene scene(earth, sceneOptions);
        scene.camera().setFieldOfViewY(fieldOfView);
        scene.camera().lookAt(eye, eye + glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(0.0, 1.0, 0.0));
        scene.options().background = {0.0f, 0.0f, 0.0f, 1.0f};
        constexpr VertexTransform exact = VertexTransform::RelativeToEyeDsfun90;
        auto far = std::make_shared<MeshPrimitive>(facingSquare(eye, farDistance, farScale * half, farScale * tilt),
                                                   glm::vec4(1, 0, 0, 1), Pass::Opaque, exact);
        auto near = std::make_shared<MeshPrimitive>(facingSquare(eye, nearDistance, half, tilt), glm::vec4(0, 1, 0, 1),
                                                    Pass::Opaque, exact);
        scene.add(farFirst ? far : near);
        scene.add(farFirst ? near : far);
        if (options.nearObjectDistance > 0.0) {
            // Up and to the right on screen (screen right is world -x), clear of the counted pixels.
            const double d = options.nearObjectDistance;
            const double e = d * std::tan(0.5 * fieldOfView);
            const Mesh cube = BoxTessellator::cube(eye + glm::dvec3(-0.75 * e, 0.75 * e, d), 0.04 * d);
            scene.add(std::make_shared<MeshPrimitive>(cube, glm::vec4(1, 1, 1, 1), Pass::Opaque, exact));
        }
        renderer::Framebuffer* previous = context.framebuffer();
        renderer::Framebuffer framebuffer = context.createFramebuffer(options.size, options.size);
        context.setFramebuffer(&framebuffer);
        try {
            statistics = scene.render(context);
        } catch (...) {
            context.setFramebuffer(previous);
            throw;
        }
        Image image = context.readPixels();
        context.setFramebuffer(previous);
        return image;
    };
    ZFightingResult result;
    FrameStatistics other;
    const Image images[] = {render(1.5, true, result.statistics), render(1.5, false, other),
                            render(0.8, true, other), render(0.8, false, other)};

    // The middle 36 % of the view each way: inside the near square (0.6 of the view) and the
    // smaller far square (0.48 of it).
    const int lo = static_cast<int>(std::ceil(options.size * 0.32));
    const int hi = static_cast<int>(std::floor(options.size * 0.68));
    int wrong = 0;
    for (int y = lo; y < hi; ++y) {
        for (int x = lo; x < hi; ++x) {
            bool right = true;
            for (const Image& image : images) {
                const std::uint8_t* p = image.pixel(x, y);
                right = right && p[1] > 127 && p[0] < 128;
            }
            wrong += right ? 0 : 1;
            ++result.pixels;
        }
    }
    result.wrongFraction = result.pixels ? static_cast<double>(wrong) / result.pixels : 0.0;
    return result;
}

double measureMinimumSeparation(renderer::Context& context, DepthStrategy strategy, double distance,
                                const ZFightingOptions& options, int stepsPerDecade)
{
    // From the distance down: wrongly ordered pixels come and go with where the depth steps fall,
    // so the answer is the smallest separation above which every one tried is resolved.
    const double spacing = floatAbove(distance) - static_cast<double>(static_cast<float>(distance));
    const double ratio = std::pow(10.0, 1.0 / std::max(stepsPerDecade, 1));
    double resolved = std::numeric_limits<double>::infinity();
    for (double separation = distance; separation >= spacing; separation /= ratio) {
        if (measureZFighting(context, strategy, distance, separation, options).wrongFraction > 0.0) {
            return resolved;
        }
        resolved = separation;
    }
    return measureZFighting(context, strategy, distance, spacing, options).wrongFraction > 0.0 ? resolved : spacing;
}

TwoSumSurvival measureTwoSumSurvival(renderer::Context& context, TwoSumProtection protection, std::size_t samples,
                                     std::uint64_t seed)
{
    renderer::Device& device = context.device();
    std::mt19937_64 random(seed);
    std::normal_distribution<double> normal;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<EmulatedDVec3> positions;
    std::vector<EmulatedDVec3> eyes;
    auto direction = [&] {
        const glm::dvec3 v(normal(random), normal(random), normal(random));
        return v / glm::length(v);
    };
    for (std::size_t i = 0; i < samples; ++i) {
        const glm::dvec3 position = (i % 2 ? 6378137.0 : 42164000.0) * direction();
        const glm::dvec3 eye = position + std::pow(10.0, 7.0 * unit(random)) * direction();
        positions.push_back(EmulatedDVec3::fromDVec3(position));
        eyes.push_back(EmulatedDVec3::fromDVec3(eye));
    }

    renderer::ShaderProgramDescription description;
    description.name = "two-sum survival";
    description.vertex = renderer::ShaderSource::fromText("two-sum.vert.glsl", R"(
in vec3 positionHigh;
in vec3 positionLow;
in vec3 normal;            // the eye's high part, per vertex so that one draw covers every sample
in vec3 color;             // the eye's low part
out vec3 v_difference;
void main()
{
    v_difference = og_emulatedDoubleSubtract(positionHigh, positionLow, normal, color);
    gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
}
)");
    description.fragment = renderer::ShaderSource::fromText("two-sum.frag.glsl", "out vec4 c;\nvoid main() { c = vec4(1.0); }\n");
    description.transformFeedbackVaryings = {"v_difference"};
    if (protection == TwoSumProtection::Precise) {
        description.defines.push_back({"OG_PRECISE"});
        description.extensions.push_back("GL_ARB_gpu_shader5");
    } else if (protection == TwoSumProtection::Unprotected) {
        description.defines.push_back({"OG_UNPROTECTED_TWO_SUM"});
    }
    renderer::ShaderProgram program = device.createShaderProgram(description);

    std::vector<float> data[4];
    for (std::size_t i = 0; i < samples; ++i) {
        for (int k = 0; k < 3; ++k) {
            data[0].push_back(positions[i].high[k]);
            data[1].push_back(positions[i].low[k]);
            data[2].push_back(eyes[i].high[k]);
            data[3].push_back(eyes[i].low[k]);
        }
    }
    const renderer::VertexBuffer buffers[] = {device.createVertexBuffer(std::as_bytes(std::span(data[0]))),
                                    device.createVertexBuffer(std::as_bytes(std::span(data[1]))),
                                    device.createVertexBuffer(std::as_bytes(std::span(data[2]))),
                                    device.createVertexBuffer(std::as_bytes(std::span(data[3])))};
    renderer::VertexArray array = context.createVertexArray();
    const renderer::VertexAttributeFormat vec3{renderer::ComponentType::Float, 3};
    array.setAttribute("positionHigh", buffers[0], vec3);
    array.setAttribute("positionLow", buffers[1], vec3);
    array.setAttribute("normal", buffers[2], vec3);
    array.setAttribute("color", buffers[3], vec3);
    renderer::Framebuffer unused = context.createFramebuffer(1, 1);
    renderer::DrawCommand command;
    command.debugName = "two-sum survival";
    command.vertexArray = &array;
    command.shaderProgram = &program;
    command.primitiveType = PrimitiveType::Points;
    command.framebuffer = &unused;
    const std::vector<float> captured = context.captureVertexOutputs(command, renderer::SceneState{});

    TwoSumSurvival result;
    result.samples = samples;
    for (std::size_t i = 0; i < samples; ++i) {
        glm::vec3 gpu;
        std::memcpy(&gpu, captured.data() + 3 * i, sizeof gpu);
        const glm::vec3 twoSum = relativeToEye(positions[i], eyes[i]);
        const glm::vec3 collapsed = (positions[i].high - eyes[i].high) + (positions[i].low - eyes[i].low);
        result.errorTermMatters += std::memcmp(&twoSum, &collapsed, sizeof twoSum) != 0 ? 1 : 0;
        result.matchesTwoSum += std::memcmp(&gpu, &twoSum, sizeof gpu) == 0 ? 1 : 0;
        result.matchesCollapsed += std::memcmp(&gpu, &collapsed, sizeof gpu) == 0 ? 1 : 0;
    }
    return result;
}

} // namespace orbis::bench
