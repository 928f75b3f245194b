// The og_ uniforms: each is computed in double from the SceneState and the model matrix and read
// back from a float framebuffer.
#include "RendererTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/gtc/matrix_inverse.hpp>

#include <catch2/catch.hpp>

#include <cstring>

using namespace orbis;
using namespace orbis::renderer;

namespace {

constexpr double kEarthRadius = 6378137.0;

/// A scene at Earth scale, where single precision alone would fail.
SceneState earthScene()
{
    SceneState scene;
    scene.cameraEye = {kEarthRadius + 1000.25, 10.5, -3.125};
    scene.viewMatrix = glm::lookAt(scene.cameraEye, glm::dvec3(kEarthRadius, 0.0, 0.0), glm::dvec3(0.0, 0.0, 1.0));
    scene.projectionMatrix = glm::perspective(0.8, 4.0 / 3.0, 1.0, 20000.0);
    scene.viewport = {0, 0, 640, 480};
    scene.nearDistance = 1.0;
    scene.farDistance = 20000.0;
    scene.sunDirection = {3.0, 0.0, 4.0};
    scene.timeSeconds = 12.5;
    return scene;
}

glm::dmat4 earthModel()
{
    return glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(kEarthRadius, 0.5, 0.0)), 0.3,
                       glm::dvec3(0.0, 0.0, 1.0));
}

/// Draws a full-screen quad whose fragment shader writes `expression` into a 1 x 1 RGBA32F
/// framebuffer and returns the four floats.
struct Evaluator {
    Device& device = test::sharedDevice();
    Context& context = device.context();
    Framebuffer framebuffer = makeFramebuffer();
    VertexArray array = context.createVertexArray(test::fullScreenQuad());

    Framebuffer makeFramebuffer()
    {
        FramebufferOptions options;
        options.colorFormat = TextureFormat::RGBA32F;
        options.hasDepth = false;
        return context.createFramebuffer(1, 1, options);
    }

    glm::vec4 evaluate(const std::string& declarations, const std::string& expression, const SceneState& scene,
                       const glm::dmat4& model = glm::dmat4(1.0))
    {
        ShaderProgramDescription description;
        description.name = expression;
        description.vertex = ShaderSource::fromText("evaluate.vert.glsl", "in vec4 position;\n"
                                                                          "void main() { gl_Position = position; }\n");
        description.fragment = ShaderSource::fromText(
            "evaluate.frag.glsl",
            declarations + "\nout vec4 fragmentColor;\nvoid main() { fragmentColor = " + expression + "; }\n");
        ShaderProgram program = device.createShaderProgram(description);
        DrawCommand command;
        command.debugName = expression;
        command.vertexArray = &array;
        command.shaderProgram = &program;
        command.framebuffer = &framebuffer;
        command.modelMatrix = model;
        command.renderState.depthTest.enabled = false;
        command.renderState.facetCulling.enabled = false;
        context.draw(command, scene);
        const std::vector<std::byte> bytes = framebuffer.colorAttachment(0)->copyToSystemMemory();
        glm::vec4 value;
        std::memcpy(&value, bytes.data(), sizeof value);
        return value;
    }
};

void checkNear(const glm::vec4& actual, const glm::dvec4& expected, double relative = 1e-6, double absolute = 1e-6)
{
    for (int i = 0; i < 4; ++i) {
        INFO("component " << i);
        CHECK(double(actual[i]) == Approx(expected[i]).epsilon(relative).margin(absolute));
    }
}

} // namespace

TEST_CASE("Matrix uniforms are the double-precision products sent as float", "[renderer][uniforms]")
{
    Evaluator e;
    const SceneState scene = earthScene();
    const glm::dmat4 model = earthModel();
    const glm::dmat4 modelView = scene.viewMatrix * model; // Earth-scale translations cancel here, in double
    const std::pair<const char*, glm::dmat4> matrices[] = {
        {"og_modelMatrix", model},
        {"og_viewMatrix", scene.viewMatrix},
        {"og_projectionMatrix", scene.projectionMatrix},
        {"og_modelViewMatrix", modelView},
        {"og_viewProjectionMatrix", scene.projectionMatrix * scene.viewMatrix},
        {"og_modelViewProjectionMatrix", scene.projectionMatrix * modelView},
    };
    for (const auto& [name, expected] : matrices) {
        for (int column = 0; column < 4; ++column) {
            INFO(name << " column " << column);
            const glm::vec4 value = e.evaluate(std::string("uniform mat4 ") + name + ";",
                                               std::string(name) + "[" + std::to_string(column) + "]", scene, model);
            // Float rounds each column to its own magnitude: a rotation column is held to 1e-6, not to
            // a millionth of the 6,378 km translation beside it.
            checkNear(value, expected[column], 1e-6, 1e-6 * std::max(1.0, glm::length(expected[column])));
        }
    }
    // The model-view of a model near the eye is small and exact, although both are 6378 km out.
    const glm::vec4 translation = e.evaluate("uniform mat4 og_modelViewMatrix;", "og_modelViewMatrix[3]", scene, model);
    checkNear(translation, modelView[3], 1e-6, 1e-4);
    CHECK(glm::length(glm::dvec3(modelView[3])) < 1100.0);
}

TEST_CASE("Relative-to-eye matrices drop the translation and the eye splits into high and low floats",
          "[renderer][uniforms]")
{
    Evaluator e;
    const SceneState scene = earthScene();
    const glm::dmat4 modelView = scene.viewMatrix;
    for (int column = 0; column < 4; ++column) {
        INFO("column " << column);
        const glm::dvec4 expected = column == 3 ? glm::dvec4(0.0, 0.0, 0.0, 1.0) : modelView[column];
        checkNear(e.evaluate("uniform mat4 og_modelViewMatrixRelativeToEye;",
                             "og_modelViewMatrixRelativeToEye[" + std::to_string(column) + "]", scene),
                  expected);
        glm::dmat4 rte = modelView;
        rte[3] = glm::dvec4(0.0, 0.0, 0.0, 1.0);
        checkNear(e.evaluate("uniform mat4 og_modelViewProjectionMatrixRelativeToEye;",
                             "og_modelViewProjectionMatrixRelativeToEye[" + std::to_string(column) + "]", scene),
                  (scene.projectionMatrix * rte)[column]);
    }
    const glm::vec4 high = e.evaluate("uniform vec3 og_cameraEyeHigh;", "vec4(og_cameraEyeHigh, 0.0)", scene);
    const glm::vec4 low = e.evaluate("uniform vec3 og_cameraEyeLow;", "vec4(og_cameraEyeLow, 0.0)", scene);
    for (int i = 0; i < 3; ++i) {
        INFO("axis " << i);
        CHECK(high[i] == static_cast<float>(scene.cameraEye[i]));
        // high + low holds the eye to about 1e-7 of the low part: far below a millimetre.
        CHECK(std::abs(double(high[i]) + double(low[i]) - scene.cameraEye[i]) < 1e-6);
    }
    CHECK(low[0] != 0.0f); // 6379137.25 is not a float: the low part carries the rest
}

TEST_CASE("Viewport, distances, sun, time and normal matrix uniforms", "[renderer][uniforms]")
{
    Evaluator e;
    const SceneState scene = earthScene();
    checkNear(e.evaluate("uniform vec4 og_viewport;", "og_viewport", scene), {0.0, 0.0, 640.0, 480.0});
    checkNear(e.evaluate("uniform vec2 og_inverseViewportDimensions;", "vec4(og_inverseViewportDimensions, 0, 0)", scene),
              {1.0 / 640.0, 1.0 / 480.0, 0.0, 0.0});
    checkNear(e.evaluate("uniform float og_nearDistance; uniform float og_farDistance; uniform float og_time;",
                         "vec4(og_nearDistance, og_farDistance, og_time, 0.0)", scene),
              {1.0, 20000.0, 12.5, 0.0});
    checkNear(e.evaluate("uniform vec3 og_sunDirection;", "vec4(og_sunDirection, 0.0)", scene), {0.6, 0.0, 0.8, 0.0});
    const glm::dvec3 sunEye = glm::normalize(glm::dmat3(scene.viewMatrix) * scene.sunDirection);
    checkNear(e.evaluate("uniform vec3 og_sunDirectionEye;", "vec4(og_sunDirectionEye, 0.0)", scene),
              glm::dvec4(sunEye, 0.0));
    // A window position through the built-in og_transformToWindowCoordinates: NDC (0.5, -0.5, 0)
    // in a 640 x 480 viewport at depth range 0..1.
    checkNear(e.evaluate("uniform mat4 og_viewportTransformationMatrix;",
                         "og_transformToWindowCoordinates(mat4(1.0), og_viewportTransformationMatrix, "
                         "vec4(0.5, -0.5, 0.0, 1.0))",
                         scene),
              {480.0, 120.0, 0.5, 1.0});
    const glm::dmat4 model = earthModel();
    const glm::dmat3 normal = glm::inverseTranspose(glm::dmat3(scene.viewMatrix * model));
    for (int column = 0; column < 3; ++column) {
        checkNear(e.evaluate("uniform mat3 og_normalMatrix;",
                             "vec4(og_normalMatrix[" + std::to_string(column) + "], 0.0)", scene, model),
                  glm::dvec4(normal[column], 0.0));
    }
}

TEST_CASE("Only the automatic uniforms a program uses are computed and sent", "[renderer][uniforms]")
{
    Evaluator e;
    ShaderProgramDescription description;
    description.name = "time only";
    description.vertex = ShaderSource::fromText("t.vert.glsl", "in vec4 position;\nvoid main() { gl_Position = position; }\n");
    description.fragment = ShaderSource::fromText("t.frag.glsl", "out vec4 fragmentColor;\nuniform float og_time;\n"
                                                                 "uniform mat4 og_viewMatrix; // unused: not active\n"
                                                                 "void main() { fragmentColor = vec4(og_time); }\n");
    ShaderProgram program = e.device.createShaderProgram(description);
    REQUIRE(program.uniforms().size() == 1);
    CHECK(program.uniforms()[0].name == "og_time");

    DrawCommand command;
    command.vertexArray = &e.array;
    command.shaderProgram = &program;
    command.framebuffer = &e.framebuffer;
    SceneState scene = earthScene();
    e.context.draw(command, scene);
    e.context.resetStatistics();
    scene.viewMatrix = glm::dmat4(2.0); // not used by the program: nothing to send
    scene.cameraEye = {1.0, 2.0, 3.0};
    e.context.draw(command, scene);
    CHECK(e.context.statistics().uniformUploads == 0);
    CHECK(e.context.statistics().uniformUploadsAvoided == 1); // og_time, unchanged
    scene.timeSeconds = 99.0;
    e.context.resetStatistics();
    e.context.draw(command, scene);
    CHECK(e.context.statistics().uniformUploads == 1);
}

TEST_CASE("GPU relative-to-eye draws Earth-scale geometry where plain floats fail", "[renderer][uniforms][rte]")
{
    Device& device = test::sharedDevice();
    Context& context = device.context();
    Framebuffer framebuffer = context.createFramebuffer(32, 32);

    // A 1 m square facing a camera 10 m away, with a field of view twice its size.
    auto render = [&](const glm::dvec3& centre, ShaderProgram& program) {
        Mesh mesh = test::quad(-0.5, -0.5, 0.5, 0.5);
        for (glm::dvec3& p : mesh.positions) {
            p += centre;
        }
        const VertexArray array = context.createVertexArray(mesh, program);
        SceneState scene;
        scene.cameraEye = centre + glm::dvec3(0.0, 0.0, 10.0);
        scene.viewMatrix = glm::lookAt(scene.cameraEye, centre, glm::dvec3(0.0, 1.0, 0.0));
        scene.projectionMatrix = glm::perspective(2.0 * std::atan(0.1), 1.0, 1.0, 100.0);
        context.clear(ClearState{}, &framebuffer);
        context.draw(test::makeCommand(array, program, framebuffer, {1, 1, 1, 1}, "square"), scene);
        return context.readPixels(&framebuffer);
    };
    ShaderProgramDescription rte = test::solidColorDescription();
    rte.name = "relative to eye";
    rte.vertex = ShaderSource::fromText("rte.vert.glsl", R"(
in vec3 positionHigh;
in vec3 positionLow;
uniform vec3 og_cameraEyeHigh;
uniform vec3 og_cameraEyeLow;
uniform mat4 og_modelViewProjectionMatrixRelativeToEye;
void main()
{
    vec3 relative = og_emulatedDoubleSubtract(positionHigh, positionLow, og_cameraEyeHigh, og_cameraEyeLow);
    gl_Position = og_modelViewProjectionMatrixRelativeToEye * vec4(relative, 1.0);
}
)");
    ShaderProgram rteProgram = device.createShaderProgram(rte);
    ShaderProgram plainProgram = device.createShaderProgram(test::solidColorDescription());

    const glm::dvec3 nearOrigin{0.3, 0.7, 0.1};
    const glm::dvec3 onEarth{kEarthRadius + 0.3, 1000.7, 20.1};
    const Image reference = render(nearOrigin, plainProgram);
    const Image relativeToEye = render(onEarth, rteProgram);
    const Image plain = render(onEarth, plainProgram); // float(position) on the GPU: 0.5 m steps

    auto differing = [](const Image& a, const Image& b) {
        int count = 0;
        for (std::size_t i = 0; i < a.pixels.size(); i += 4) {
            count += a.pixels[i] != b.pixels[i] ? 1 : 0;
        }
        return count;
    };
    CHECK(test::pixelNear(reference, 16, 16, {255, 255, 255, 255}));
    CHECK(test::pixelNear(reference, 2, 2, {0, 0, 0, 255}));
    CHECK(differing(relativeToEye, reference) <= 2); // edge pixels at most
    CHECK(differing(plain, reference) > 20);          // the plain-float square is visibly off
}
