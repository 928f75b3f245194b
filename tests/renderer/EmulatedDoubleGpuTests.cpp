// The GPU's relative-to-eye differences against their CPU mirrors (core/EmulatedDouble.h), read back
// with transform feedback: does the shader compiler keep DSFUN90's two-sum?

#include "RendererTestSupport.h"

#include <orbis/core/EmulatedDouble.h>
#include <orbis/renderer/Device.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <random>

using namespace orbis;
using namespace orbis::renderer;

namespace {

struct Sample {
    EmulatedDVec3 position;
    EmulatedDVec3 eye;
};

/// Points at Earth radius and GEO, eyes 1 m to 10,000 km away: many of the highs' differences are
/// inexact there (the two coordinates more than a factor 2 apart), which is where the two-sum's
/// error term is not zero.
std::vector<Sample> makeSamples(std::uint64_t seed, std::size_t count, bool split65536)
{
    std::mt19937_64 random(seed);
    std::normal_distribution<double> normal;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<Sample> samples;
    for (std::size_t i = 0; i < count; ++i) {
        auto direction = [&] {
            const glm::dvec3 v(normal(random), normal(random), normal(random));
            return v / std::sqrt(glm::dot(v, v));
        };
        const glm::dvec3 position = (i % 2 ? 6378137.0 : 42164000.0) * direction();
        const glm::dvec3 eye = position + std::pow(10.0, 7.0 * unit(random)) * direction();
        samples.push_back(split65536 ? Sample{splitAt65536(position), splitAt65536(eye)}
                                     : Sample{EmulatedDVec3::fromDVec3(position), EmulatedDVec3::fromDVec3(eye)});
    }
    return samples;
}

enum class Protection { Precise, OpaqueOne };

/// What the GPU computes for each sample with the given built-in function, read back.
std::vector<glm::vec3> gpuDifferences(const std::vector<Sample>& samples, const char* function, Protection protection)
{
    const bool precise = protection == Protection::Precise;
    Device& device = test::sharedDevice();
    Context& context = device.context();
    ShaderProgramDescription description;
    description.name = std::string(function) + (precise ? " (precise)" : "");
    description.vertex = ShaderSource::fromText("difference.vert.glsl", std::string(R"(
in vec3 positionHigh;
in vec3 positionLow;
in vec3 normal;            // the eye's high part, per vertex so that one draw covers every sample
in vec2 textureCoordinate; // the eye's low x, y
in vec4 color;             // the eye's low z in x
out vec3 v_difference;
void main()
{
    vec3 eyeLow = vec3(textureCoordinate, color.x);
    v_difference = )") + function + R"((positionHigh, positionLow, normal, eyeLow);
    gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
}
)");
    description.fragment = ShaderSource::fromText("difference.frag.glsl", "out vec4 c;\nvoid main() { c = vec4(1.0); }\n");
    description.transformFeedbackVaryings = {"v_difference"};
    if (precise) {
        description.defines.push_back({"OG_PRECISE"});
        description.extensions.push_back("GL_ARB_gpu_shader5");
    }
    ShaderProgram program = device.createShaderProgram(description);

    std::vector<float> high, low, eyeHigh, eyeLowXy, eyeLowZ;
    for (const Sample& s : samples) {
        for (int i = 0; i < 3; ++i) {
            high.push_back(s.position.high[i]);
            low.push_back(s.position.low[i]);
            eyeHigh.push_back(s.eye.high[i]);
        }
        eyeLowXy.insert(eyeLowXy.end(), {s.eye.low.x, s.eye.low.y});
        eyeLowZ.insert(eyeLowZ.end(), {s.eye.low.z, 0.0f, 0.0f, 0.0f});
    }
    auto upload = [&](const std::vector<float>& data) {
        return device.createVertexBuffer(std::as_bytes(std::span(data)));
    };
    const VertexBuffer buffers[] = {upload(high), upload(low), upload(eyeHigh), upload(eyeLowXy), upload(eyeLowZ)};
    VertexArray array = context.createVertexArray();
    array.setAttribute("positionHigh", buffers[0], {ComponentType::Float, 3});
    array.setAttribute("positionLow", buffers[1], {ComponentType::Float, 3});
    array.setAttribute("normal", buffers[2], {ComponentType::Float, 3});
    array.setAttribute("textureCoordinate", buffers[3], {ComponentType::Float, 2});
    array.setAttribute("color", buffers[4], {ComponentType::Float, 4});
    Framebuffer framebuffer = context.createFramebuffer(1, 1);
    DrawCommand command;
    command.vertexArray = &array;
    command.shaderProgram = &program;
    command.primitiveType = PrimitiveType::Points;
    command.framebuffer = &framebuffer;
    const std::vector<float> captured = context.captureVertexOutputs(command, SceneState{});
    std::vector<glm::vec3> result(samples.size());
    std::memcpy(result.data(), captured.data(), captured.size() * sizeof(float));
    return result;
}

bool sameBits(const glm::vec3& a, const glm::vec3& b)
{
    return std::memcmp(&a, &b, sizeof a) == 0;
}

} // namespace

TEST_CASE("DSFUN90's two-sum on the GPU, kept by precise or by og_opaqueOne, matches its CPU mirror bit for bit", "[renderer][emulated]")
{
    Device& device = test::sharedDevice();
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    const Protection protection = GENERATE(Protection::Precise, Protection::OpaqueOne);
    INFO("seed " << seed << (protection == Protection::Precise ? ", precise" : ", og_opaqueOne"));
    const std::vector<Sample> samples = makeSamples(seed, 4096, false);
    if (protection == Protection::Precise && !device.info().gpuShader5) {
        // Without ARB_gpu_shader5 there is no `precise`: asking for it must fail to compile, loudly.
        REQUIRE_THROWS_WITH(gpuDifferences(samples, "og_emulatedDoubleSubtract", protection),
                            Catch::Matchers::Contains("GL_ARB_gpu_shader5"));
        return;
    }
    const std::vector<glm::vec3> gpu = gpuDifferences(samples, "og_emulatedDoubleSubtract", protection);
    std::size_t twoSumMatters = 0;
    for (std::size_t i = 0; i < samples.size(); ++i) {
        const glm::vec3 expected = relativeToEye(samples[i].position, samples[i].eye);
        const glm::vec3 collapsed = (samples[i].position.high - samples[i].eye.high) +
                                    (samples[i].position.low - samples[i].eye.low);
        INFO("sample " << i);
        REQUIRE(sameBits(gpu[i], expected));
        twoSumMatters += sameBits(expected, collapsed) ? 0 : 1;
    }
    // The samples exercise the error term: without it some of them would differ.
    INFO("samples where the two-sum's error term changes the result: " << twoSumMatters);
    CHECK(twoSumMatters > samples.size() / 100); // about 2 % of these samples
}

TEST_CASE("The book's split at 65536 m: the GPU's difference matches its CPU mirror bit for bit", "[renderer][emulated]")
{
    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    const std::vector<Sample> samples = makeSamples(seed, 4096, true);
    const std::vector<glm::vec3> gpu = gpuDifferences(samples, "og_subtractSplitAt65536", Protection::OpaqueOne);
    for (std::size_t i = 0; i < samples.size(); ++i) {
        INFO("sample " << i);
        REQUIRE(sameBits(gpu[i], relativeToEyeSplitAt65536(samples[i].position, samples[i].eye)));
    }
}

