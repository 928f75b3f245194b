// Scene depth strategies: which one runs, what each resolves, and the multi-frustum artefacts of
// the SIGGRAPH 2013 course (tears where frustums meet, blended objects drawn twice in the overlap).

#include "PrecisionMeasurement.h"
#include "SceneTestSupport.h"

#include "RendererTestSupport.h"

#include <orbis/core/BoxTessellator.h>
#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>
#include <orbis/scene/BillboardCollection.h>
#include <orbis/scene/Globe.h>
#include <orbis/scene/LabelCollection.h>
#include <orbis/scene/MeshPrimitive.h>
#include <orbis/scene/ModelPrimitive.h>
#include <orbis/scene/PolygonCollection.h>
#include <orbis/scene/PolylineCollection.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <filesystem>

using namespace orbis;
using namespace orbis::renderer;
using namespace orbis::scene;
using namespace orbis::bench;
using namespace orbis::test;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

std::shared_ptr<Globe> blueGlobe()
{
    GlobeOptions options;
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
    // The class named as a reader writes it, not mangled.
    REQUIRE_THROWS_WITH(renderFrame(scene, 16, 16), Catch::Matchers::Contains("supportsLogarithmicDepth") &&
                                                        Catch::Matchers::Contains("::PlainPrimitive does not"));

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
    // measured separation is the smallest from which up no pixel is wrong (8 tries per decade:
    // up to a factor 1.33 above the truth); rasterisation and float rounding add up to about two
    // steps to the analytic one-step separation (Akeley and Su 2006), and llvmpipe orders sloped
    // surfaces a third to a half of a step apart. Hence: within 0.3 to 3 times (llvmpipe measured
    // 0.53 for multi-frustum at 100 m to 2.05 for logarithmic at 100 m). A formula off by a
    // factor of 4, or a strategy not applied, falls outside.
    for (const DepthStrategy strategy : {DepthStrategy::Single, DepthStrategy::MultiFrustum, DepthStrategy::Logarithmic,
                                         DepthStrategy::Complementary}) {
        if (strategy == DepthStrategy::Complementary && !device.info().clipControl) {
            continue; // asserted to throw in "A strategy the frame cannot have throws"
        }
        for (const double distance : {100.0, 1e5}) {
            const double measured = measureMinimumSeparation(context, strategy, distance, {}, 8);
            const double analytic = analyticMinimumSeparation(strategy, distance, 1.0,
                                                              strategy == DepthStrategy::Single ? 1e10 : distance);
            const double spacing = static_cast<double>(std::nextafter(static_cast<float>(distance), 1e30f)) -
                                   static_cast<double>(static_cast<float>(distance));
            INFO(depthStrategyName(strategy) << " at " << distance << " m: measured " << measured << ", analytic "
                                             << analytic);
            CHECK(measured <= 3.0 * std::max(analytic, spacing));
            CHECK(measured >= 0.3 * analytic);
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

// Every primitive under every strategy. Each scene puts a small cube a few metres from the eye, so
// that the frame spans a few metres to hundreds of kilometres: several multi-frustums, and
// logarithmic depth spread over seven decades and more.

namespace {

/// The strategies a frame can be asked for on this device (complementary needs glClipControl and
/// is asserted to throw without it in "A strategy the frame cannot have throws").
std::vector<DepthStrategy> drawableStrategies()
{
    std::vector<DepthStrategy> strategies = {DepthStrategy::Single, DepthStrategy::MultiFrustum,
                                             DepthStrategy::Logarithmic, DepthStrategy::LogarithmicVertex};
    if (sharedDevice().info().clipControl) {
        strategies.push_back(DepthStrategy::Complementary);
    }
    return strategies;
}

/// A grey cube `distance` metres along the view, towards the upper left corner (where the tests
/// look at nothing else), so that the frame's near distance is about `distance`.
std::shared_ptr<MeshPrimitive> cubeNearEye(const Scene& scene, double distance)
{
    const Camera& camera = scene.camera();
    const glm::dvec3 direction = camera.direction();
    const glm::dvec3 right = glm::normalize(glm::cross(direction, camera.up()));
    const glm::dvec3 up = glm::cross(right, direction);
    const glm::dvec3 centre = camera.eye() + distance * (direction - 0.32 * right + 0.32 * up);
    return std::make_shared<MeshPrimitive>(BoxTessellator::cube(centre, 0.02 * distance), glm::vec4(0.5f, 0.5f, 0.5f, 1.0f));
}

/// A geodetic rectangle as one ring of world positions, its edges cut every degree or less.
std::vector<glm::dvec3> geodeticRectangle(double west, double south, double east, double north)
{
    std::vector<glm::dvec3> ring;
    const int columns = static_cast<int>(std::ceil(east - west));
    const int rows = static_cast<int>(std::ceil(north - south));
    for (int i = 0; i < columns; ++i) {
        ring.push_back(kEarth.toCartesian(Geodetic3D::fromDegrees(west + (east - west) * i / columns, south)));
    }
    for (int j = 0; j < rows; ++j) {
        ring.push_back(kEarth.toCartesian(Geodetic3D::fromDegrees(east, south + (north - south) * j / rows)));
    }
    for (int i = columns; i > 0; --i) {
        ring.push_back(kEarth.toCartesian(Geodetic3D::fromDegrees(west + (east - west) * i / columns, north)));
    }
    for (int j = rows; j > 0; --j) {
        ring.push_back(kEarth.toCartesian(Geodetic3D::fromDegrees(west, south + (north - south) * j / rows)));
    }
    return ring;
}

Image solidImage(int width, int height, const glm::ivec4& rgba)
{
    Image image(width, height, 4);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        image.pixels[i] = static_cast<std::uint8_t>(rgba[static_cast<int>(i % 4)]);
    }
    return image;
}

int countNear(const Image& image, const glm::ivec4& color, int tolerance)
{
    int count = 0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            count += pixelNear(image, x, y, color, tolerance) ? 1 : 0;
        }
    }
    return count;
}

} // namespace

TEST_CASE("Polygons and polylines on the globe show wherever they lie under every depth strategy, seen at a slant", "[scene][depth][polygon][polyline]")
{
    // 300 km up over (10 E, 40 N) looking 6 degrees north: the ground from about 350 km to the
    // horizon at 2,000 km, its degree-wide triangles and segments seen at a slant (their far
    // corners up to 1.2 times farther than their near ones). A fill east of the view's middle
    // (opaque red) and a line along a meridian west of it (green, 3 pixels), both at the default
    // one-degree granularity: every sampled point of them must show its colour, not the globe's.
    // Per-vertex logarithmic depth would put the middle of those triangles and segments hundreds of
    // metres behind their corners, into the globe, without og_depthPrimitiveVertex.
    constexpr int size = 64;
    for (const DepthStrategy strategy : drawableStrategies()) {
        INFO(depthStrategyName(strategy));
        Scene scene(kEarth);
        scene.options().depthStrategy = strategy;
        scene.camera().lookAt(kEarth.toCartesian(Geodetic3D::fromDegrees(10, 40, 3e5)),
                              kEarth.toCartesian(Geodetic3D::fromDegrees(10, 46, 0)), {0, 0, 1});
        scene.add(blueGlobe());
        auto fills = std::make_shared<PolygonCollection>(kEarth);
        const std::vector<std::vector<glm::dvec3>> rings = {geodeticRectangle(11.0, 43.0, 13.5, 48.0)};
        fills->add(rings, {1, 0, 0, 1});
        scene.add(fills);
        auto lines = std::make_shared<PolylineCollection>(kEarth);
        const Geodetic3D meridian[] = {Geodetic3D::fromDegrees(8.5, 41), Geodetic3D::fromDegrees(8.5, 49)};
        PolylineStyle green;
        green.color = {0, 1, 0, 1};
        green.widthPixels = 3.0f;
        lines->add(meridian, green);
        scene.add(lines);
        scene.add(cubeNearEye(scene, 10.0));
        const RenderedFrame frame = renderFrame(scene, size, size);
        CHECK(frame.statistics.depthStrategy == strategy);
        if (strategy == DepthStrategy::MultiFrustum) {
            CHECK(frame.statistics.frustums.size() >= 2);
        }
        int fillSamples = 0;
        for (double lat = 43.3; lat < 47.8; lat += 0.2) {
            for (double lon = 11.3; lon < 13.3; lon += 0.2) {
                const glm::ivec2 p = projectToPixel(scene, kEarth.toCartesian(Geodetic3D::fromDegrees(lon, lat)), size, size);
                if (p.x < 1 || p.y < 1 || p.x > size - 2 || p.y > size - 2) {
                    continue; // the fill runs out of the view on the right
                }
                INFO("fill at " << lon << " E, " << lat << " N: pixel " << p.x << ", " << p.y << " "
                                << describePixel(frame.image, p.x, p.y));
                REQUIRE(pixelNear(frame.image, p.x, p.y, {255, 0, 0, 255}));
                ++fillSamples;
            }
        }
        CHECK(fillSamples > 100);
        int lineSamples = 0;
        for (double lat = 41.5; lat < 48.6; lat += 0.1) {
            const glm::ivec2 p = projectToPixel(scene, kEarth.toCartesian(Geodetic3D::fromDegrees(8.5, lat)), size, size);
            if (p.x < 1 || p.y < 1 || p.x > size - 2 || p.y > size - 2) {
                continue; // the line enters the view from below
            }
            ++lineSamples;
            // The centre pixel's row can meet the 3-pixel line on its side: green dominates either way.
            const glm::ivec4 pixel = pixelAt(frame.image, p.x, p.y);
            INFO("line at " << lat << " N: pixel " << p.x << ", " << p.y << " " << describePixel(frame.image, p.x, p.y));
            REQUIRE(pixel.g > 200);
            REQUIRE(pixel.b < 60);
        }
        CHECK(lineSamples > 40);
    }
}

TEST_CASE("A line running behind the eye is clipped at the near plane under every depth strategy", "[scene][depth][polyline][clipping]")
{
    // The eye 1 km over the ground looks north at a slant; a line runs across the view from 50 km
    // south-west (behind the eye) to 50 km north-east, in one segment. Only its part ahead may show,
    // 3 pixels wide along where that part projects: a part behind the eye projected through w < 0
    // lands mirrored, and a quad widened from a mirrored end points the wrong way. Complementary
    // depth clips at z = w, not z = -w (the geometry shader clips before the division by w).
    constexpr int size = 64;
    const Geodetic3D ends[] = {Geodetic3D::fromDegrees(-0.05, -0.45), Geodetic3D::fromDegrees(0.05, 0.45)};
    for (const DepthStrategy strategy : drawableStrategies()) {
        INFO(depthStrategyName(strategy));
        Scene scene(kEarth);
        scene.options().depthStrategy = strategy;
        const glm::dvec3 eye = kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0, 1000));
        scene.camera().lookAt(eye, kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0.012, 0)), {0, 0, 1});
        auto lines = std::make_shared<PolylineCollection>(kEarth);
        PolylineStyle red;
        red.color = {1, 0, 0, 1};
        red.widthPixels = 3.0f;
        lines->add(ends, red);
        scene.add(lines);
        const RenderedFrame frame = renderFrame(scene, size, size);
        CHECK(frame.statistics.depthStrategy == strategy);
        INFO("near plane " << frame.statistics.frustums.front().nearDistance << " m");
        // Where the part from the near plane on projects, row by row (less 2 % for rounding).
        const double nearDistance = frame.statistics.frustums.front().nearDistance;
        std::vector<double> lineX(size, -1.0);
        const std::span<const glm::dvec3> drawn = lines->positions(0);
        REQUIRE(drawn.size() == 2);
        for (int k = 0; k <= 100000; ++k) {
            const glm::dvec3 p = glm::mix(drawn.front(), drawn.back(), k / 100000.0);
            const glm::ivec2 pixel = projectToPixel(scene, p, size, size);
            if (glm::dot(p - eye, scene.camera().direction()) >= 0.98 * nearDistance && pixel.y >= 0 && pixel.y < size) {
                lineX[static_cast<std::size_t>(pixel.y)] = pixel.x;
            }
        }
        // Red only there; and in every row from below the far end down to the lowest red row (where
        // the near plane cuts it, moved by the depth offset), a run from there up.
        int lowestRed = -1;
        for (int y = 0; y < size; ++y) {
            for (int x = 0; x < size; ++x) {
                const glm::ivec4 p = pixelAt(frame.image, x, y);
                if (p.r > 100 && p.g < 100) {
                    const double expected = lineX[static_cast<std::size_t>(y)];
                    INFO("red at " << x << ", " << y << "; the line there at x = " << expected);
                    REQUIRE(expected >= 0.0);
                    REQUIRE(std::abs(x - expected) <= 3.0);
                    lowestRed = y;
                }
            }
        }
        const int farRow = projectToPixel(scene, drawn.back(), size, size).y;
        int rowsWithLine = 0;
        for (int y = std::max(farRow + 2, 0); y <= lowestRed; ++y) {
            const auto at = static_cast<int>(lineX[static_cast<std::size_t>(y)]);
            INFO("row " << y << " at x = " << at << ": " << describePixel(frame.image, at, y));
            CHECK((pixelAt(frame.image, at, y).r > 100 || pixelAt(frame.image, at + 1, y).r > 100 ||
                   pixelAt(frame.image, at - 1, y).r > 100));
            ++rowsWithLine;
        }
        CHECK(rowsWithLine > 15);
    }
}

TEST_CASE("Billboards and labels keep their pixels under every depth strategy, depth-tested or not", "[scene][depth][billboard][label]")
{
    // Straight down from 1,000 km: a 7 x 5 red billboard and a label above it. Depth-tested (the
    // default) they show whole over the globe (their depth taken nearer than the anchor by their
    // reach on the screen, tens of kilometres here) and a 200 km cube halfway to them hides them;
    // with the depth test off every strategy draws them alike, whatever stands in front. Single is
    // spared the first: its 24 bits from 1 m to 1e10 m resolve 60 km at 1,000 km, a tie the globe
    // may win.
    constexpr int size = 64;
    const glm::dvec3 anchor = kEarth.toCartesian(Geodetic3D::fromDegrees(10, 30, 0));
    auto whitePixels = [](const Image& image) {
        int count = 0;
        for (int y = 0; y < image.height; ++y) {
            for (int x = 0; x < image.width; ++x) {
                const glm::ivec4 p = pixelAt(image, x, y);
                count += p.r > 200 && p.g > 200 && p.b > 200 ? 1 : 0;
            }
        }
        return count;
    };
    const BillboardDepthOptions untested{.disableDepthTestDistance = std::numeric_limits<double>::infinity()};
    int referenceLabelPixels = -1;
    for (const DepthStrategy strategy : drawableStrategies()) {
        INFO(depthStrategyName(strategy));
        Scene scene(kEarth);
        scene.options().depthStrategy = strategy;
        scene.camera().lookAt(kEarth.toCartesian(Geodetic3D::fromDegrees(10, 30, 1e6)), anchor, {0, 0, 1});
        scene.add(blueGlobe());
        auto billboards = std::make_shared<BillboardCollection>();
        Billboard billboard;
        billboard.position = anchor;
        billboard.image = billboards->addImage(solidImage(7, 5, {255, 0, 0, 255}));
        billboards->add(billboard);
        scene.add(billboards);
        auto labels = std::make_shared<LabelCollection>();
        Label label;
        label.position = anchor;
        label.text = "ab";
        label.fontSizePixels = 12.0f;
        label.pixelOffset = {0, -4}; // clear of the billboard
        labels->add(label);
        scene.add(labels);
        scene.add(cubeNearEye(scene, 10.0));

        billboards->setDepthOptions(untested);
        labels->setDepthOptions(untested);
        const RenderedFrame frame = renderFrame(scene, size, size);
        CHECK(frame.statistics.depthStrategy == strategy);
        const int white = whitePixels(frame.image); // the label's fill
        CHECK(countNear(frame.image, {255, 0, 0, 255}, 0) == 35);
        CHECK(white > 10);
        if (referenceLabelPixels < 0) {
            referenceLabelPixels = white;
        }
        CHECK(white == referenceLabelPixels); // screen-space text: the same pixels whatever the depth

        billboards->setDepthOptions({});
        labels->setDepthOptions({});
        if (strategy != DepthStrategy::Single) {
            const RenderedFrame tested = renderFrame(scene, size, size);
            CHECK(countNear(tested.image, {255, 0, 0, 255}, 0) == 35);
            CHECK(whitePixels(tested.image) == white);
        }
        const glm::dvec3 halfway = 0.5 * (scene.camera().eye() + anchor);
        scene.add(std::make_shared<MeshPrimitive>(BoxTessellator::cube(halfway, 1e5), glm::vec4(0, 1, 0, 1)));
        const RenderedFrame hidden = renderFrame(scene, size, size);
        CHECK(countNear(hidden.image, {255, 0, 0, 255}, 0) == 0);
        CHECK(whitePixels(hidden.image) == 0);
        billboards->setDepthOptions(untested);
        labels->setDepthOptions(untested);
        const RenderedFrame shown = renderFrame(scene, size, size);
        CHECK(countNear(shown.image, {255, 0, 0, 255}, 0) == 35);
        CHECK(whitePixels(shown.image) == white);
    }
}

TEST_CASE("A model above the globe shows and one below it hides under every depth strategy", "[scene][depth][model]")
{
    // As "A model 500 m above the ray-cast globe shows", with something 5 m from the eye: the frame
    // spans 5 m to 200 km. Scale 40: a 450 m aircraft.
    constexpr int size = 64;
    const Geodetic2D place = Geodetic2D::fromDegrees(-100.0, 40.0);
    const std::filesystem::path aircraft = std::filesystem::path(ORBIS_SOURCE_DIR) / "data" / "models" / "aircraft.glb";
    for (const DepthStrategy strategy : drawableStrategies()) {
        INFO(depthStrategyName(strategy));
        for (const double height : {500.0, -500.0}) {
            INFO("model " << height << " m above the ellipsoid");
            Scene scene(kEarth);
            scene.options().depthStrategy = strategy;
            scene.add(blueGlobe());
            const Geodetic3D position{place.longitude, place.latitude, height};
            scene.add(ModelPrimitive::fromFile(aircraft, kEarth, ModelPlacement{position, {}, 40.0}));
            const glm::dvec3 ground = kEarth.toCartesian(Geodetic3D{place.longitude, place.latitude, 0.0});
            scene.camera().lookAt(kEarth.toCartesian(Geodetic3D{place.longitude, place.latitude, 3000.0}), ground,
                                  {0, 0, 1});
            scene.setSunDirection(kEarth.geodeticSurfaceNormal(ground)); // overhead: the fuselage white
            scene.add(cubeNearEye(scene, 5.0));
            const RenderedFrame frame = renderFrame(scene, size, size);
            CHECK(frame.statistics.depthStrategy == strategy);
            const glm::ivec2 p = projectToPixel(scene, kEarth.toCartesian(position), size, size);
            const glm::ivec4 pixel = pixelAt(frame.image, p.x, p.y);
            INFO(describePixel(frame.image, p.x, p.y));
            if (height > 0.0) {
                CHECK(pixel.r > 150); // the white fuselage, not the blue globe
            } else {
                CHECK(pixel == glm::ivec4(0, 0, 255, 255));
            }
        }
    }
}

TEST_CASE("A translucent polygon spanning two overlapping frustums is blended once where they overlap", "[scene][depth][multifrustum][polygon]")
{
    // As the mesh test above, with a translucent fill on the ellipsoid seen 45 degrees down: a
    // cube 1.2 m from the eye starts the first frustum there, the fill crosses into the second,
    // which starts 30 % short of the first one's far end. Every sample of the fill is half red over
    // black once: 128 (blended twice 191). Two frustum ratios: 1,000 (the default), and 100,000,
    // where the fill's depth offset in the first frustum (four steps of its depth buffer: 2.4 % of
    // the distance at its far end) is far larger than in the second (1e-5 of the distance), so that
    // deciding ownership by the moved depth would blend a band beyond the boundary twice.
    constexpr int size = 128;
    for (const double ratio : {1e3, 1e5}) {
        INFO("far / near " << ratio);
        Scene scene(kEarth);
        scene.options().depthStrategy = DepthStrategy::MultiFrustum;
        scene.options().multiFrustum.farToNearRatio = ratio;
        scene.options().multiFrustum.overlap = 0.3;
        // The view's middle 1.2 ratio away, where the first frustum ends.
        const double height = 0.85 * ratio;
        const double north = toDegrees(height / 6.378e6);
        const glm::dvec3 eye = kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0, height));
        scene.camera().lookAt(eye, kEarth.toCartesian(Geodetic3D::fromDegrees(0, north, 0)), {0, 0, 1});
        PolygonCollectionOptions options;
        options.granularityRadians = toRadians(north / 20.0);
        auto fills = std::make_shared<PolygonCollection>(kEarth, options);
        const double side = 4.0 * north;
        const std::vector<std::vector<glm::dvec3>> rings = {
            {kEarth.toCartesian(Geodetic3D::fromDegrees(-side, 0.02 * north)),
             kEarth.toCartesian(Geodetic3D::fromDegrees(side, 0.02 * north)),
             kEarth.toCartesian(Geodetic3D::fromDegrees(side, 5.0 * north)),
             kEarth.toCartesian(Geodetic3D::fromDegrees(-side, 5.0 * north))}};
        fills->add(rings, {1, 0, 0, 0.5});
        scene.add(fills);
        scene.add(cubeNearEye(scene, 1.2));
        const RenderedFrame frame = renderFrame(scene, size, size);
        REQUIRE(frame.statistics.frustums.size() == 2);
        REQUIRE(frame.statistics.commandsExecutedMoreThanOnce == 1); // the fill, in both frustums
        const double overlapNear = frame.statistics.frustums[1].nearDistance;
        const double overlapFar = frame.statistics.frustums[0].farDistance;
        int inOverlap = 0;
        int samples = 0;
        for (double lat = 0.1 * north; lat < 4.9 * north; lat += 0.01 * north) {
            for (double lon = -0.5 * north; lon <= 0.5 * north; lon += 0.1 * north) {
                const glm::dvec3 ground = kEarth.toCartesian(Geodetic3D::fromDegrees(lon, lat));
                const glm::ivec2 p = projectToPixel(scene, ground, size, size);
                if (p.x < 1 || p.y < 1 || p.x > size - 2 || p.y > size - 2 || (p.x < size / 3 && p.y < size / 3)) {
                    continue; // outside the view, or at the cube
                }
                const double depth = glm::dot(ground - eye, scene.camera().direction());
                inOverlap += depth > overlapNear && depth < overlapFar ? 1 : 0;
                ++samples;
                INFO("pixel " << p.x << ", " << p.y << " at depth " << depth << " m (overlap " << overlapNear
                              << " to " << overlapFar << " m): " << describePixel(frame.image, p.x, p.y));
                REQUIRE(pixelNear(frame.image, p.x, p.y, {128, 0, 0, 255}, 1));
            }
        }
        INFO(samples << " samples, " << inOverlap << " in the overlap");
        CHECK(inOverlap > 50);
    }
}

TEST_CASE("Automatic picks complementary depth, or logarithmic without glClipControl, for a scene with vector layers, billboards, labels and a model", "[scene][depth]")
{
    // Every primitive now writes every strategy's depth: the rule's third branch applies to a frame
    // holding them all. 3 km over the ground with a cube 2 m from the eye: 2 m to 200 km.
    const Device& device = sharedDevice();
    Scene scene(kEarth);
    const Geodetic3D place = Geodetic3D::fromDegrees(-100.0, 40.0, 0.0);
    scene.camera().lookAt(kEarth.toCartesian(Geodetic3D(place.longitude, place.latitude, 3000.0)),
                          kEarth.toCartesian(Geodetic3D::fromDegrees(-100.0, 40.05, 0.0)), {0, 0, 1});
    scene.add(blueGlobe());
    auto fills = std::make_shared<PolygonCollection>(kEarth);
    const std::vector<std::vector<glm::dvec3>> rings = {geodeticRectangle(-100.1, 40.01, -99.9, 40.2)};
    fills->add(rings, {1, 0.5f, 0, 0.6f});
    scene.add(fills);
    auto lines = std::make_shared<PolylineCollection>(kEarth);
    const Geodetic3D border[] = {Geodetic3D::fromDegrees(-100.1, 40.1), Geodetic3D::fromDegrees(-99.9, 40.1)};
    lines->add(border);
    scene.add(lines);
    auto billboards = std::make_shared<BillboardCollection>();
    Billboard billboard;
    billboard.position = kEarth.toCartesian(Geodetic3D::fromDegrees(-100.0, 40.08, 0.0));
    billboard.image = billboards->addImage(solidImage(3, 3, {255, 255, 0, 255}));
    billboards->add(billboard);
    scene.add(billboards);
    auto labels = std::make_shared<LabelCollection>();
    Label label;
    label.position = billboard.position;
    label.text = "here";
    labels->add(label);
    scene.add(labels);
    const std::filesystem::path aircraft = std::filesystem::path(ORBIS_SOURCE_DIR) / "data" / "models" / "aircraft.glb";
    scene.add(ModelPrimitive::fromFile(aircraft, kEarth, ModelPlacement{Geodetic3D::fromDegrees(-100.0, 40.06, 500.0), {}, 1.0}));
    scene.add(cubeNearEye(scene, 2.0));
    for (const std::shared_ptr<Primitive>& primitive : scene.primitives()) {
        CHECK(primitive->supportsLogarithmicDepth());
    }

    const DepthStrategy expected = device.info().clipControl ? DepthStrategy::Complementary : DepthStrategy::Logarithmic;
    const FrameStatistics first = renderFrame(scene, 64, 64).statistics;
    CHECK(first.depthStrategyAutomatic);
    CHECK(first.depthStrategy == expected);
    CHECK(first.frustums.size() == 1);
    // The variants are kept: a steady view compiles nothing, nor does a strategy seen before.
    const FrameStatistics second = renderFrame(scene, 64, 64).statistics;
    CHECK(second.depthStrategy == expected);
    CHECK(second.programsCompiled == 0);
    scene.options().depthStrategy = DepthStrategy::MultiFrustum;
    CHECK(renderFrame(scene, 64, 64).statistics.frustums.size() == 2);
    scene.options().depthStrategy = DepthStrategy::Automatic;
    const FrameStatistics back = renderFrame(scene, 64, 64).statistics;
    CHECK(back.depthStrategy == expected);
    CHECK(back.programsCompiled == 0);
}
