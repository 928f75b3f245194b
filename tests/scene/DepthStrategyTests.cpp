// Scene depth strategies: which one runs, what each resolves, and the multi-frustum artefacts of
// the SIGGRAPH 2013 course (tears where frustums meet, blended objects drawn twice in the overlap).

#include "SceneTestSupport.h"

#include "RendererTestSupport.h"

#include <orbis/core/BoxTessellator.h>
#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>
#include <orbis/scene/Globe.h>
#include <orbis/scene/MeshPrimitive.h>
#include <orbis/scene/PrecisionMeasurement.h>

#include <catch2/catch.hpp>

#include <cmath>

using namespace orbis;
using namespace orbis::test;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

std::shared_ptr<Globe> blueGlobe()
{
    GlobeOptions options;
    options.lighting = false;
    options.color = {0.0f, 0.0f, 1.0f, 1.0f};
    return std::make_shared<Globe>(kEarth, options);
}

/// A primitive whose shaders know nothing of logarithmic depth.
class PlainPrimitive final : public Primitive {
public:
    explicit PlainPrimitive(const BoundingSphere& sphere) : _sphere(sphere) {}
    std::optional<BoundingSphere> boundingSphere() const override { return _sphere; }
    void update(FrameState&, CommandList&) override {}

private:
    BoundingSphere _sphere;
};

/// A patch following the ellipsoid at a height, ±halfDegrees around a centre, 16 x 16 cells: its
/// chords sag under 0.2 m, where a flat square 50 km across would stand 200 m off the surface at
/// its edges.
Mesh geodeticPatch(const Geodetic3D& centre, double halfDegrees)
{
    Mesh mesh;
    constexpr int cells = 16;
    for (int j = 0; j <= cells; ++j) {
        for (int i = 0; i <= cells; ++i) {
            const double lon = centre.longitude + toRadians(halfDegrees * (2.0 * i / cells - 1.0));
            const double lat = centre.latitude + toRadians(halfDegrees * (2.0 * j / cells - 1.0));
            mesh.positions.push_back(kEarth.toCartesian(Geodetic3D(lon, lat, centre.height)));
        }
    }
    for (int j = 0; j < cells; ++j) {
        for (int i = 0; i < cells; ++i) {
            const auto a = static_cast<std::uint32_t>(j * (cells + 1) + i);
            mesh.indices.insert(mesh.indices.end(), {a, a + 1, a + cells + 2, a, a + cells + 2, a + cells + 1});
        }
    }
    return mesh;
}

/// A flat rectangle y = height below an eye at the origin looking down -z, from zNear to zFar in
/// front of it and halfWidth to each side: ground seen at a slant, spanning every distance between.
Mesh ground(double height, double zNear, double zFar, double halfWidth)
{
    Mesh mesh;
    mesh.positions = {{-halfWidth, height, -zNear}, {halfWidth, height, -zNear}, {halfWidth, height, -zFar},
                      {-halfWidth, height, -zFar}};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    return mesh;
}

/// The image row (from the top) where ground `depth` metres below the eye is `distance` away, for a
/// 45 degree view of `size` pixels looking along -z.
int rowAtDistance(double depth, double distance, int size)
{
    const double ndcY = -depth / distance / std::tan(0.5 * 0.7853981633974483);
    return static_cast<int>(std::floor((1.0 - (ndcY * 0.5 + 0.5)) * size));
}

} // namespace

TEST_CASE("Auto runs one multi-frustum frustum for a globe from orbit and complementary for a view spanning 1 km to 50,000 km", "[scene][depth]")
{
    const Device& device = sharedDevice();
    Scene scene(kEarth);
    scene.add(blueGlobe());
    scene.camera().lookAt(kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0, 2e7)), glm::dvec3(0), {0, 0, 1});
    const FrameStatistics orbit = renderFrame(scene, 32, 32).statistics;
    CHECK(orbit.depthStrategyAutomatic);
    CHECK(orbit.depthStrategy == DepthStrategy::MultiFrustum);
    CHECK(orbit.frustums.size() == 1);

    // A satellite 1 km from an eye 40,000 km out: far / near about 5e4, two multi-frustum frustums.
    const glm::dvec3 eye = kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0, 4e7 + 1000.0));
    scene.camera().lookAt(eye, glm::dvec3(0), {0, 0, 1});
    const Mesh satellite = BoxTessellator::cube(kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0, 4e7)), 20.0);
    scene.add(std::make_shared<MeshPrimitive>(satellite, glm::vec4(1, 0, 0, 1)));
    const FrameStatistics wide = renderFrame(scene, 32, 32).statistics;
    // Complementary where the driver has glClipControl; logarithmic (every primitive here writes
    // it) where it does not (the ctest run with MESA_EXTENSION_OVERRIDE=-GL_ARB_clip_control).
    CHECK(wide.depthStrategy == (device.info().clipControl ? DepthStrategy::Complementary : DepthStrategy::Logarithmic));
    CHECK(wide.frustums.size() == 1);
    CHECK(wide.commandsExecuted == 2);

    // A primitive that cannot write logarithmic depth: complementary still (it needs nothing of
    // primitives), or else back to multi-frustum.
    scene.add(std::make_shared<PlainPrimitive>(BoundingSphere{eye * 0.9, 1.0}));
    const FrameStatistics mixed = renderFrame(scene, 32, 32).statistics;
    CHECK(mixed.depthStrategy ==
          (device.info().clipControl ? DepthStrategy::Complementary : DepthStrategy::MultiFrustum));
}

TEST_CASE("A strategy the frame cannot have throws, naming what is missing", "[scene][depth]")
{
    const Device& device = sharedDevice();
    Scene scene(kEarth);
    scene.add(std::make_shared<PlainPrimitive>(BoundingSphere{glm::dvec3(0, 0, -100), 1.0}));
    scene.camera().lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0});
    scene.options().depthStrategy = DepthStrategy::Logarithmic;
    REQUIRE_THROWS_WITH(renderFrame(scene, 16, 16), Catch::Matchers::Contains("supportsLogarithmicDepth"));

    scene.options().depthStrategy = DepthStrategy::Complementary;
    if (device.info().clipControl) {
        REQUIRE(renderFrame(scene, 16, 16).statistics.depthStrategy == DepthStrategy::Complementary);
    } else {
        REQUIRE_THROWS_WITH(renderFrame(scene, 16, 16), Catch::Matchers::Contains("GL_ARB_clip_control"));
    }
}

TEST_CASE("Complementary depth orders surfaces 1 m apart at 10,000 km and logarithmic 2 m; a single frustum with near 1 m does not", "[scene][depth]")
{
    const Device& device = sharedDevice();
    Context& context = sharedDevice().context();
    // Two squares squarely facing the eye and nothing else: the frame's near and far are the
    // squares' own (4,700 to 15,000 km) for every strategy but Single, which keeps 1 m and 1e10 m.
    // Each measurement draws the far square larger and smaller, before and after the near one:
    // a tie anywhere counts as wrong.
    ZFightingOptions options;
    options.tilted = false;
    options.nearObjectDistance = 0.0;
    // Single: window depths 1 - 1e-7 apart by 1e-14, far below a 24-bit step: every pixel ties.
    CHECK(measureZFighting(context, DepthStrategy::Single, 1e7, 1.0, options).wrongFraction == 1.0);
    if (device.info().clipControl) {
        // near / w, one division from exact clip coordinates into a float depth buffer.
        CHECK(measureZFighting(context, DepthStrategy::Complementary, 1e7, 1.0, options).wrongFraction == 0.0);
    }
    // Logarithmic depth takes log2(w / near) of a float w / near, whose spacing at 10,000 km is
    // 1 m: 1 m apart the two may round alike (and do for one of the four frames here); 2 m apart
    // they do not, and a step of the buffer (0.7 m here) separates them.
    CHECK(measureZFighting(context, DepthStrategy::Logarithmic, 1e7, 2.0, options).wrongFraction == 0.0);
    CHECK(measureZFighting(context, DepthStrategy::LogarithmicVertex, 1e7, 2.0, options).wrongFraction == 0.0);
    CHECK(measureZFighting(context, DepthStrategy::Single, 1e7, 2.0, options).wrongFraction == 1.0);

    // With a cube 1 m from the eye the frame spans 1 m to 10,000 km. Complementary float depth
    // still orders them; logarithmic depth spreads its 24 bits over log(1e7): one step is
    // z ln(1e7) 2^-24 = 9.6 m there, so 2 m ties and 32 m does not.
    options.nearObjectDistance = 1.0;
    CHECK(measureZFighting(context, DepthStrategy::Logarithmic, 1e7, 2.0, options).wrongFraction == 1.0);
    CHECK(measureZFighting(context, DepthStrategy::Logarithmic, 1e7, 32.0, options).wrongFraction == 0.0);
    if (device.info().clipControl) {
        CHECK(measureZFighting(context, DepthStrategy::Complementary, 1e7, 1.0, options).wrongFraction == 0.0);
    }
}

TEST_CASE("Each strategy's measured minimum separation is within a few depth steps of the analytic one", "[scene][depth]")
{
    Device& device = sharedDevice();
    Context& context = device.context();
    // Something 1 m from the eye, surfaces tilted so that every pixel has its own depth. The
    // measured separation is the smallest from which up no pixel is wrong (2 tries per decade:
    // up to a factor 3.2 above the truth); rasterisation and float rounding add one to three steps
    // to the analytic one-step separation (Akeley and Su 2006), and llvmpipe was seen to order
    // sloped surfaces a third of a step apart. Hence: within 1/4 to 12 times.
    for (const DepthStrategy strategy : {DepthStrategy::Single, DepthStrategy::MultiFrustum, DepthStrategy::Logarithmic,
                                         DepthStrategy::Complementary}) {
        if (strategy == DepthStrategy::Complementary && !device.info().clipControl) {
            continue; // asserted to throw in "A strategy the frame cannot have throws"
        }
        for (const double distance : {100.0, 1e5}) {
            const double measured = measureMinimumSeparation(context, strategy, distance, {}, 2);
            const double analytic = analyticMinimumSeparation(strategy, distance, 1.0,
                                                              strategy == DepthStrategy::Single ? 1e10 : distance);
            const double spacing = static_cast<double>(std::nextafter(static_cast<float>(distance), 1e30f)) -
                                   static_cast<double>(static_cast<float>(distance));
            INFO(depthStrategyName(strategy) << " at " << distance << " m: measured " << measured << ", analytic "
                                             << analytic);
            CHECK(measured <= 12.0 * std::max(analytic, spacing));
            CHECK(measured >= 0.25 * analytic);
        }
    }
}

TEST_CASE("No tears where multi-frustums meet: ground crossing the boundary shows no background", "[scene][depth][multifrustum]")
{
    Scene scene(kEarth);
    scene.options().depthStrategy = DepthStrategy::MultiFrustum;
    scene.options().background = {1.0f, 0.0f, 1.0f, 1.0f};
    scene.camera().lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0});
    // Ground 200 m below, from 2 m to 20 km: it spans the boundary near 1,000 m (the cube 1 m ahead
    // makes the first frustum start there).
    scene.add(std::make_shared<MeshPrimitive>(ground(-200.0, 2.0, 20e3, 20e3), glm::vec4(0, 1, 0, 1)));
    scene.add(std::make_shared<MeshPrimitive>(BoxTessellator::cube({0.5, 0.5, -1.2}, 0.05), glm::vec4(1, 1, 1, 1)));
    constexpr int size = 128;
    const RenderedFrame frame = renderFrame(scene, size, size);
    REQUIRE(frame.statistics.frustums.size() == 2);
    const double boundary = frame.statistics.frustums[0].farDistance;
    const int seam = rowAtDistance(200.0, boundary, size);
    INFO("boundary " << boundary << " m at row " << seam);
    REQUIRE(seam > size / 2);
    REQUIRE(seam < size - 2);
    for (int y = seam - 2; y <= seam + 2; ++y) {
        for (int x = 0; x < size; ++x) {
            INFO("pixel " << x << ", " << y << ": " << describePixel(frame.image, x, y));
            REQUIRE(pixelNear(frame.image, x, y, {0, 255, 0, 255}));
        }
    }
}

TEST_CASE("A translucent surface spanning two overlapping frustums is blended once where they overlap", "[scene][depth][multifrustum]")
{
    Scene scene(kEarth);
    scene.options().depthStrategy = DepthStrategy::MultiFrustum;
    // A wide overlap, so that the doubly drawn band covers many rows: 30 % of 1,000 m.
    scene.options().multiFrustum.overlap = 0.3;
    scene.camera().lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0});
    scene.add(std::make_shared<MeshPrimitive>(ground(-200.0, 2.0, 20e3, 20e3), glm::vec4(1, 0, 0, 0.5),
                                              Pass::Translucent));
    scene.add(std::make_shared<MeshPrimitive>(BoxTessellator::cube({0.5, 0.5, -1.2}, 0.05), glm::vec4(1, 1, 1, 1)));
    constexpr int size = 128;
    const RenderedFrame frame = renderFrame(scene, size, size);
    REQUIRE(frame.statistics.frustums.size() == 2);
    REQUIRE(frame.statistics.commandsExecutedMoreThanOnce == 1); // the ground, in both frustums
    const double overlapNear = frame.statistics.frustums[1].nearDistance;
    const double overlapFar = frame.statistics.frustums[0].farDistance;
    const int top = rowAtDistance(200.0, overlapFar, size) + 1;
    const int bottom = rowAtDistance(200.0, overlapNear, size) - 1;
    INFO("overlap " << overlapNear << " m to " << overlapFar << " m: rows " << top << " to " << bottom);
    REQUIRE(bottom - top >= 4);
    // Half red over black once: 128 (blended twice it would be 191). Rows around the band too.
    for (int y = top - 3; y <= bottom + 3; ++y) {
        for (int x = 0; x < size; x += 7) {
            INFO("pixel " << x << ", " << y << ": " << describePixel(frame.image, x, y));
            REQUIRE(pixelNear(frame.image, x, y, {128, 0, 0, 255}, 1));
        }
    }
}

TEST_CASE("The ray-cast globe writes its depth under every strategy: a patch 20 m above shows, 20 m below hides", "[scene][depth][globe]")
{
    const Device& device = sharedDevice();
    // Something 10 m from the eye makes the frame span 10 m to 7,400 km. The separations each
    // strategy resolves at 1,000 km are then 6 m (multi-frustum: its second frustum starts near
    // 10 km), 0.8 m (logarithmic) and 0.12 m (complementary): 20 m is clear of them all, and a globe
    // writing another strategy's depth would be off by kilometres. Single (near 1 m, far 1e10 m)
    // resolves only 60 km there.
    for (const DepthStrategy strategy : {DepthStrategy::MultiFrustum, DepthStrategy::Logarithmic,
                                         DepthStrategy::LogarithmicVertex, DepthStrategy::Complementary}) {
        if (strategy == DepthStrategy::Complementary && !device.info().clipControl) {
            continue; // asserted to throw in "A strategy the frame cannot have throws"
        }
        INFO(depthStrategyName(strategy));
        const Geodetic3D below = Geodetic3D::fromDegrees(45.0, 35.0, 0.0);
        const glm::dvec3 eye = kEarth.toCartesian(Geodetic3D(below.longitude, below.latitude, 1e6));
        Scene scene(kEarth);
        scene.options().depthStrategy = strategy;
        scene.add(blueGlobe());
        scene.camera().lookAt(eye, kEarth.toCartesian(below), {0, 0, 1});
        const Geodetic3D above = Geodetic3D::fromDegrees(47.0, 35.0, 20.0);
        const Geodetic3D under = Geodetic3D::fromDegrees(43.0, 35.0, -20.0);
        scene.add(std::make_shared<MeshPrimitive>(geodeticPatch(above, 0.4), glm::vec4(1, 0, 0, 1)));
        scene.add(std::make_shared<MeshPrimitive>(geodeticPatch(under, 0.4), glm::vec4(0, 1, 0, 1)));
        // Something 10 m from the eye: the frame spans 10 m to 1,000 km, three decades and more.
        const glm::dvec3 down = glm::normalize(kEarth.toCartesian(below) - eye);
        const glm::dvec3 side = glm::normalize(glm::cross(down, glm::dvec3(0, 0, 1)));
        scene.add(std::make_shared<MeshPrimitive>(BoxTessellator::cube(eye + 10.0 * down + 3.5 * side, 0.2),
                                                  glm::vec4(1, 1, 1, 1)));
        constexpr int size = 96;
        const RenderedFrame frame = renderFrame(scene, size, size);
        CHECK(frame.statistics.depthStrategy == strategy);
        int red = 0;
        int green = 0;
        for (std::size_t i = 0; i < frame.image.pixels.size(); i += 4) {
            red += frame.image.pixels[i] > 128 && frame.image.pixels[i + 1] < 128 ? 1 : 0;
            green += frame.image.pixels[i + 1] > 128 && frame.image.pixels[i] < 128 ? 1 : 0;
        }
        INFO(red << " red pixels, " << green << " green");
        CHECK(red > 60);    // the patch above: 80 pixels, less its edges
        CHECK(green == 0);  // the patch below: none
        const glm::ivec2 abovePixel = projectToPixel(scene, kEarth.toCartesian(above), size, size);
        CHECK(pixelNear(frame.image, abovePixel.x, abovePixel.y, {255, 0, 0, 255}));
    }
}

TEST_CASE("Logarithmic depth per vertex puts a large triangle too far between its vertices; per fragment does not", "[scene][depth]")
{
    // Ground from 2 m to 20 km in two triangles, and a small square 1 m under it 100 m away: hidden
    // in truth. Per vertex, the ground's depth is interpolated linearly from the logarithms at its
    // corners, which lies beyond the logarithm in between (it is concave): the square shows through.
    const Device& device = sharedDevice();
    (void)device;
    auto render = [](DepthStrategy strategy) {
        Scene scene(kEarth);
        scene.options().depthStrategy = strategy;
        scene.camera().lookAt({0, 0, 0}, {0, -0.2, -1}, {0, 1, 0});
        scene.add(std::make_shared<MeshPrimitive>(ground(-20.0, 2.0, 20e3, 20e3), glm::vec4(0, 1, 0, 1)));
        Mesh marker = ground(-21.0, 95.0, 105.0, 5.0);
        scene.add(std::make_shared<MeshPrimitive>(marker, glm::vec4(1, 0, 0, 1)));
        scene.add(std::make_shared<MeshPrimitive>(BoxTessellator::cube({0.3, 0.3, -1.0}, 0.02), glm::vec4(1, 1, 1, 1)));
        return renderFrame(scene, 64, 64);
    };
    const glm::dvec3 markerCentre(0.0, -21.0, -100.0);
    Scene probe(kEarth);
    probe.camera().lookAt({0, 0, 0}, {0, -0.2, -1}, {0, 1, 0});
    const glm::ivec2 pixel = projectToPixel(probe, markerCentre, 64, 64);
    const RenderedFrame vertex = render(DepthStrategy::LogarithmicVertex);
    const RenderedFrame fragment = render(DepthStrategy::Logarithmic);
    INFO("per vertex " << describePixel(vertex.image, pixel.x, pixel.y) << ", per fragment "
                       << describePixel(fragment.image, pixel.x, pixel.y));
    CHECK(pixelNear(vertex.image, pixel.x, pixel.y, {255, 0, 0, 255}));
    CHECK(pixelNear(fragment.image, pixel.x, pixel.y, {0, 255, 0, 255}));
}

TEST_CASE("Under logarithmic depth a triangle reaching behind the eye is clipped, not dropped", "[scene][depth]")
{
    // Ground from 50 m behind the eye to 20 km ahead, in two triangles: log2 of the vertices
    // behind the eye is undefined; they must not take their triangles with them.
    for (const DepthStrategy strategy : {DepthStrategy::LogarithmicVertex, DepthStrategy::Logarithmic}) {
        Scene scene(kEarth);
        scene.options().depthStrategy = strategy;
        scene.camera().lookAt({0, 0, 0}, {0, -0.2, -1}, {0, 1, 0});
        scene.add(std::make_shared<MeshPrimitive>(ground(-20.0, -50.0, 20e3, 20e3), glm::vec4(0, 1, 0, 1)));
        scene.add(std::make_shared<MeshPrimitive>(BoxTessellator::cube({0.3, 0.3, -1.0}, 0.02), glm::vec4(1, 1, 1, 1)));
        const RenderedFrame frame = renderFrame(scene, 64, 64);
        INFO(depthStrategyName(strategy) << ": " << describePixel(frame.image, 32, 60) << " at the bottom, "
                                         << describePixel(frame.image, 5, 40) << " at the left");
        CHECK(frame.statistics.depthStrategy == strategy);
        CHECK(pixelNear(frame.image, 32, 60, {0, 255, 0, 255}));
        CHECK(pixelNear(frame.image, 5, 40, {0, 255, 0, 255}));
    }
}

namespace {

/// Counts update() calls; draws nothing, writes any depth.
class CountingPrimitive final : public Primitive {
public:
    std::optional<BoundingSphere> boundingSphere() const override { return std::nullopt; }
    void update(FrameState& frameState, CommandList&) override
    {
        ++updates;
        lastStrategy = frameState.depthStrategy;
    }
    bool supportsLogarithmicDepth() const override { return true; }
    int updates = 0;
    DepthStrategy lastStrategy = DepthStrategy::Automatic;
};

} // namespace

TEST_CASE("Automatic decides by the commands' depth bounds, updating again only in a frame where the choice changes", "[scene][depth]")
{
    // 3 km over the ground looking along it: the globe's sphere spans 1 m to 13,000 km, but its
    // command bounds its depth by the eye's height and the horizon (2.6 to 940 km): one frustum.
    Scene scene(kEarth);
    scene.add(blueGlobe());
    auto counter = std::make_shared<CountingPrimitive>();
    scene.add(counter);
    const glm::dvec3 eye = kEarth.toCartesian(Geodetic3D::fromDegrees(20, 45, 3000));
    scene.camera().lookAt(eye, kEarth.toCartesian(Geodetic3D::fromDegrees(20, 45.5, 0)), kEarth.geodeticSurfaceNormal(eye));
    const FrameStatistics first = renderFrame(scene, 32, 32).statistics;
    CHECK(first.depthStrategy == DepthStrategy::MultiFrustum);
    CHECK(first.frustums.size() == 1);
    CHECK(first.primitivesUpdated == 2);
    // The spheres asked for more (complementary, or logarithmic without glClipControl): the first
    // frame updated once with that, once more with the commands' choice.
    CHECK(counter->updates == 2);
    CHECK(counter->lastStrategy == DepthStrategy::MultiFrustum);
    renderFrame(scene, 32, 32);
    CHECK(counter->updates == 3); // a steady view: one update a frame
}
