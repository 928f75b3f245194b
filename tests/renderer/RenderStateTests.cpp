// One pixel test per RenderState part: each fails if the state is not applied (each draws the
// state and its opposite, so the shadow must switch both ways).
#include "RendererTestSupport.h"

#include <orbis/renderer/Device.h>

#include <catch2/catch.hpp>

using namespace orbis;
using namespace orbis::renderer;

namespace {

constexpr int kSize = 16;
const glm::ivec4 kBlack{0, 0, 0, 255};
const glm::ivec4 kRed{255, 0, 0, 255};
const glm::ivec4 kBlue{0, 0, 255, 255};

/// A 16 x 16 framebuffer with a depth-stencil attachment and a solid-colour program.
struct StateFixture {
    explicit StateFixture(TextureFormat depthFormat = TextureFormat::Depth24Stencil8)
        : framebuffer(context.createFramebuffer(kSize, kSize, {TextureFormat::RGBA8, depthFormat}))
    {
    }
    Device& device = test::sharedDevice();
    Context& context = device.context();
    Framebuffer framebuffer;
    ShaderProgram program = device.createShaderProgram(test::solidColorDescription());

    void clear(const glm::vec4& color = {0.0f, 0.0f, 0.0f, 1.0f}, double depth = 1.0, int stencil = 0)
    {
        ClearState clear;
        clear.color = color;
        clear.depth = depth;
        clear.stencil = stencil;
        context.clear(clear, &framebuffer);
    }
    void draw(const VertexArray& array, const RenderState& state, const glm::vec4& color,
              PrimitiveType primitive = PrimitiveType::Triangles, ShaderProgram* withProgram = nullptr)
    {
        DrawCommand command = test::makeCommand(array, withProgram ? *withProgram : program, framebuffer, color);
        command.renderState = state;
        command.primitiveType = primitive;
        context.draw(command);
    }
    VertexArray array(const Mesh& mesh) { return context.createVertexArray(mesh, program); }
    Image read() { return context.readPixels(&framebuffer); }
};

/// The image pixel (x right, y down) at normalised device coordinates.
glm::ivec2 pixelOf(double x, double y)
{
    return {static_cast<int>((x + 1.0) * 0.5 * kSize), kSize - 1 - static_cast<int>((y + 1.0) * 0.5 * kSize)};
}

bool at(const Image& image, double x, double y, const glm::ivec4& expected, int tolerance = 1)
{
    const glm::ivec2 p = pixelOf(x, y);
    return test::pixelNear(image, p.x, p.y, expected, tolerance);
}

int litPixels(const Image& image)
{
    int count = 0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            count += test::pixelAt(image, x, y).r > 0 ? 1 : 0;
        }
    }
    return count;
}

RenderState noCulling()
{
    RenderState state;
    state.facetCulling.enabled = false;
    return state;
}

} // namespace

TEST_CASE("Primitive restart splits a strip at the restart index", "[renderer][renderstate]")
{
    StateFixture f;
    Mesh mesh;
    mesh.primitiveType = PrimitiveType::TriangleStrip;
    mesh.positions = {{-1, -1, 0}, {-0.2, -1, 0}, {-1, 1, 0}, {-0.2, 1, 0},  // left strip
                      {0.2, -1, 0}, {1, -1, 0},   {0.2, 1, 0}, {1, 1, 0},    // right strip
                      {0.2, 1, 0}};                                           // index 8
    mesh.indices = {0, 1, 2, 3, 8, 4, 5, 6, 7};
    const VertexArray array = f.array(mesh);
    RenderState state = noCulling();
    state.primitiveRestart = {true, 8};

    f.clear();
    f.draw(array, state, {1, 0, 0, 1}, PrimitiveType::TriangleStrip);
    Image image = f.read();
    CHECK(at(image, -0.6, 0.0, kRed));
    CHECK(at(image, 0.6, 0.0, kRed));
    CHECK(at(image, 0.05, 0.5, kBlack)); // the gap: index 8 restarted the strip

    state.primitiveRestart.enabled = false; // index 8 is a vertex: the strip bridges the gap
    f.clear();
    f.draw(array, state, {1, 0, 0, 1}, PrimitiveType::TriangleStrip);
    image = f.read();
    CHECK(at(image, 0.05, 0.5, kRed));
}

TEST_CASE("Facet culling discards triangles by facing and winding", "[renderer][renderstate]")
{
    StateFixture f;
    Mesh mesh = test::quad(-0.5, -0.5, 0.5, 0.5);
    mesh.indices = {0, 2, 1, 0, 3, 2}; // clockwise
    const VertexArray array = f.array(mesh);
    struct Case {
        bool enabled;
        CullFace face;
        WindingOrder front;
        bool drawn;
    };
    const Case cases[] = {
        {true, CullFace::Back, WindingOrder::Counterclockwise, false}, // clockwise = back: culled
        {true, CullFace::Back, WindingOrder::Clockwise, true},
        {true, CullFace::Front, WindingOrder::Counterclockwise, true},
        {true, CullFace::Front, WindingOrder::Clockwise, false},
        {true, CullFace::FrontAndBack, WindingOrder::Clockwise, false},
        {false, CullFace::Back, WindingOrder::Counterclockwise, true},
    };
    for (const Case& c : cases) {
        RenderState state;
        state.facetCulling = {c.enabled, c.face, c.front};
        f.clear();
        f.draw(array, state, {1, 0, 0, 1});
        INFO("enabled " << c.enabled << " face " << int(c.face) << " front " << int(c.front));
        CHECK(at(f.read(), 0.0, 0.0, c.drawn ? kRed : kBlack));
    }
}

TEST_CASE("Rasterization mode fills, outlines or dots polygons", "[renderer][renderstate]")
{
    StateFixture f;
    const VertexArray array = f.array(test::quad(-0.55, -0.55, 0.55, 0.55));
    RenderState state = noCulling();

    // (0.25, -0.25) is inside the quad, away from its edges and its diagonal.
    state.rasterizationMode = RasterizationMode::Fill;
    f.clear();
    f.draw(array, state, {1, 0, 0, 1});
    Image image = f.read();
    CHECK(at(image, 0.25, -0.25, kRed));
    const int filled = litPixels(image);

    state.rasterizationMode = RasterizationMode::Line;
    f.clear();
    f.draw(array, state, {1, 0, 0, 1});
    image = f.read();
    CHECK(at(image, 0.25, -0.25, kBlack));
    const int outlined = litPixels(image);
    CHECK(outlined > 0);
    CHECK(outlined < filled);

    state.rasterizationMode = RasterizationMode::Point;
    f.clear();
    f.draw(array, state, {1, 0, 0, 1});
    image = f.read();
    CHECK(at(image, 0.25, -0.25, kBlack));
    CHECK(litPixels(image) > 0);
    CHECK(litPixels(image) <= 4); // the four corners, one pixel each
}

TEST_CASE("The scissor test keeps fragments inside its rectangle", "[renderer][renderstate]")
{
    StateFixture f;
    const VertexArray array = f.array(test::fullScreenQuad());
    RenderState state;
    state.scissorTest = {true, {0, 0, kSize / 2, kSize}}; // the left half
    f.clear();
    f.draw(array, state, {1, 0, 0, 1});
    Image image = f.read();
    CHECK(at(image, -0.5, 0.0, kRed));
    CHECK(at(image, 0.5, 0.0, kBlack));

    state.scissorTest.rectangle = {kSize / 2, 0, kSize / 2, kSize}; // the right half
    f.clear();
    f.draw(array, state, {1, 0, 0, 1});
    image = f.read();
    CHECK(at(image, -0.5, 0.0, kBlack));
    CHECK(at(image, 0.5, 0.0, kRed));

    state.scissorTest.enabled = false;
    f.clear();
    f.draw(array, state, {1, 0, 0, 1});
    image = f.read();
    CHECK(at(image, -0.5, 0.0, kRed));
    CHECK(at(image, 0.5, 0.0, kRed));
}

TEST_CASE("The stencil test masks a draw with what an earlier draw wrote", "[renderer][renderstate]")
{
    // Both depth-stencil formats: the float one is what complementary depth draws draped polygons in.
    const TextureFormat format = GENERATE(TextureFormat::Depth24Stencil8, TextureFormat::Depth32FStencil8);
    INFO(textureFormatName(format));
    StateFixture f(format);
    const VertexArray left = f.array(test::quad(-1.0, -1.0, 0.0, 1.0));
    const VertexArray all = f.array(test::fullScreenQuad());

    // Write 1 into the stencil of the left half, no colour. No depth test: the draws are coplanar.
    RenderState mark;
    mark.depthTest.enabled = false;
    mark.stencilTest.enabled = true;
    mark.stencilTest.frontFace.function = CompareFunction::Always;
    mark.stencilTest.frontFace.referenceValue = 1;
    mark.stencilTest.frontFace.depthPassStencilPassOperation = StencilOperation::Replace;
    mark.colorMask = {false, false, false, false};
    RenderState masked;
    masked.depthTest.enabled = false;
    masked.stencilTest.enabled = true;
    masked.stencilTest.frontFace.function = CompareFunction::Equal;
    masked.stencilTest.frontFace.referenceValue = 1;

    f.clear();
    f.draw(left, mark, {0, 1, 0, 1});
    f.draw(all, masked, {1, 0, 0, 1});
    Image image = f.read();
    CHECK(at(image, -0.5, 0.0, kRed));
    CHECK(at(image, 0.5, 0.0, kBlack));

    masked.stencilTest.frontFace.function = CompareFunction::NotEqual;
    f.draw(all, masked, {0, 0, 1, 1});
    image = f.read();
    CHECK(at(image, -0.5, 0.0, kRed));
    CHECK(at(image, 0.5, 0.0, kBlue));

    masked.stencilTest.enabled = false;
    f.draw(all, masked, {0, 0, 1, 1});
    CHECK(at(f.read(), -0.5, 0.0, kBlue));
}

TEST_CASE("The depth test compares with the depth already drawn", "[renderer][renderstate]")
{
    StateFixture f;
    const VertexArray nearQuad = f.array(test::fullScreenQuad(-0.5)); // window depth 0.25
    const VertexArray farQuad = f.array(test::fullScreenQuad(0.5));   // window depth 0.75
    RenderState state;

    f.clear();
    f.draw(nearQuad, state, {1, 0, 0, 1});
    f.draw(farQuad, state, {0, 0, 1, 1}); // Less: behind, hidden
    CHECK(at(f.read(), 0.0, 0.0, kRed));

    state.depthTest.function = CompareFunction::Greater;
    f.draw(farQuad, state, {0, 0, 1, 1});
    CHECK(at(f.read(), 0.0, 0.0, kBlue));

    f.clear();
    state.depthTest = {true, CompareFunction::Less};
    f.draw(nearQuad, state, {1, 0, 0, 1});
    state.depthTest.enabled = false;
    f.draw(farQuad, state, {0, 0, 1, 1}); // no test: drawn over
    CHECK(at(f.read(), 0.0, 0.0, kBlue));
}

TEST_CASE("The depth range maps depth into the range it gives", "[renderer][renderstate]")
{
    StateFixture f;
    const VertexArray front = f.array(test::fullScreenQuad(-0.99)); // window depth 0.005 in [0, 1]
    RenderState state;
    f.clear({0, 0, 0, 1}, 0.4);
    state.depthRange = {0.5, 1.0}; // depth 0.5025: behind the cleared 0.4
    f.draw(front, state, {1, 0, 0, 1});
    CHECK(at(f.read(), 0.0, 0.0, kBlack));
    state.depthRange = {0.0, 1.0};
    f.draw(front, state, {1, 0, 0, 1});
    CHECK(at(f.read(), 0.0, 0.0, kRed));
}

TEST_CASE("Depth clamping draws what lies beyond the far plane, at the far depth", "[renderer][renderstate]")
{
    StateFixture f;
    const VertexArray beyond = f.array(test::fullScreenQuad(1.5)); // clipped by the far plane
    RenderState state;
    state.depthTest.function = CompareFunction::LessOrEqual;
    f.clear();
    f.draw(beyond, state, {1, 0, 0, 1});
    CHECK(at(f.read(), 0.0, 0.0, kBlack));
    state.depthClamp = true; // depth 1: on the cleared depth, not in front of it
    f.draw(beyond, state, {1, 0, 0, 1});
    CHECK(at(f.read(), 0.0, 0.0, kRed));
    f.clear({0, 0, 0, 1}, 0.9);
    f.draw(beyond, state, {1, 0, 0, 1});
    CHECK(at(f.read(), 0.0, 0.0, kBlack));
    f.clear();
    state.depthClamp = false;
    f.draw(beyond, state, {1, 0, 0, 1});
    CHECK(at(f.read(), 0.0, 0.0, kBlack));
}

TEST_CASE("Blending mixes the fragment with the framebuffer", "[renderer][renderstate]")
{
    StateFixture f;
    const VertexArray array = f.array(test::fullScreenQuad());
    RenderState state;
    state.blending = Blending::alphaBlending();
    f.clear({0, 0, 1, 1});
    f.draw(array, state, {1, 0, 0, 0.5f});
    // 0.5 red + 0.5 blue; alpha 0.5 * 0.5 + 1 * 0.5.
    CHECK(at(f.read(), 0.0, 0.0, {128, 0, 128, 191}, 1));

    state.blending.sourceRgbFactor = SourceBlendingFactor::ConstantColor;
    state.blending.destinationRgbFactor = DestinationBlendingFactor::Zero;
    state.blending.color = {0.25f, 0.25f, 0.25f, 0.25f};
    f.clear({0, 0, 1, 1});
    f.draw(array, state, {1, 1, 1, 1});
    CHECK(at(f.read(), 0.0, 0.0, {64, 64, 64, 255}, 1));

    state.blending.enabled = false;
    f.clear({0, 0, 1, 1});
    f.draw(array, state, {1, 0, 0, 0.5f});
    CHECK(at(f.read(), 0.0, 0.0, {255, 0, 0, 128}, 1));
}

TEST_CASE("The colour mask keeps channels from being written", "[renderer][renderstate]")
{
    StateFixture f;
    const VertexArray array = f.array(test::fullScreenQuad());
    RenderState state;
    state.colorMask = {true, false, false, false};
    f.clear({0, 0, 0, 1});
    f.draw(array, state, {1, 1, 1, 0});
    CHECK(at(f.read(), 0.0, 0.0, {255, 0, 0, 255}));
    state.colorMask = {false, true, false, true};
    f.clear({0, 0, 0, 1});
    f.draw(array, state, {1, 1, 1, 0});
    CHECK(at(f.read(), 0.0, 0.0, {0, 255, 0, 0}));
}

TEST_CASE("The depth mask keeps depth from being written", "[renderer][renderstate]")
{
    StateFixture f;
    const VertexArray nearQuad = f.array(test::fullScreenQuad(-0.5));
    const VertexArray farQuad = f.array(test::fullScreenQuad(0.5));
    RenderState state;
    state.depthMask = false;
    f.clear();
    f.draw(nearQuad, state, {1, 0, 0, 1});
    f.draw(farQuad, RenderState{}, {0, 0, 1, 1}); // the near quad left no depth: drawn
    CHECK(at(f.read(), 0.0, 0.0, kBlue));

    state.depthMask = true;
    f.clear();
    f.draw(nearQuad, state, {1, 0, 0, 1});
    f.draw(farQuad, RenderState{}, {0, 0, 1, 1});
    CHECK(at(f.read(), 0.0, 0.0, kRed));
}

TEST_CASE("Polygon offset moves a coplanar draw in front", "[renderer][renderstate]")
{
    StateFixture f;
    const VertexArray array = f.array(test::fullScreenQuad(0.2));
    RenderState state;
    f.clear();
    f.draw(array, state, {1, 0, 0, 1});
    f.draw(array, state, {0, 0, 1, 1}); // equal depth fails Less
    CHECK(at(f.read(), 0.0, 0.0, kRed));
    state.polygonOffset = {true, -1.0f, -4.0f};
    f.draw(array, state, {0, 0, 1, 1});
    CHECK(at(f.read(), 0.0, 0.0, kBlue));
}

TEST_CASE("Program point size lets the vertex shader size points", "[renderer][renderstate]")
{
    StateFixture f;
    ShaderProgramDescription description = test::solidColorDescription();
    description.vertex = ShaderSource::fromText("points.vert.glsl", R"(
in vec4 position;
void main() { gl_Position = position; gl_PointSize = 8.0; }
)");
    ShaderProgram points = f.device.createShaderProgram(description);
    Mesh mesh;
    mesh.primitiveType = PrimitiveType::Points;
    mesh.positions = {{0.0, 0.0, 0.0}};
    const VertexArray array = f.context.createVertexArray(mesh, points);
    RenderState state;
    state.programPointSize = true;
    f.clear();
    f.draw(array, state, {1, 0, 0, 1}, PrimitiveType::Points, &points);
    Image image = f.read();
    CHECK(test::pixelNear(image, 5, 5, kRed)); // 3 pixels from the centre: inside an 8-pixel point
    CHECK(litPixels(image) == 64);

    state.programPointSize = false; // the fixed size, 1 pixel
    f.clear();
    f.draw(array, state, {1, 0, 0, 1}, PrimitiveType::Points, &points);
    image = f.read();
    CHECK(test::pixelNear(image, 5, 5, kBlack));
    CHECK(litPixels(image) == 1);
}
