#include "SceneTestSupport.h"

#include "RendererTestSupport.h"

#include <orbis/core/BoxTessellator.h>
#include <orbis/core/EllipsoidalOccluder.h>
#include <orbis/core/SunPosition.h>
#include <orbis/renderer/Device.h>
#include <orbis/renderer/ShaderCache.h>
#include <orbis/scene/Globe.h>
#include <orbis/scene/MeshPrimitive.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace orbis;
using namespace orbis::renderer;
using namespace orbis::scene;
using namespace orbis::test;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();
const glm::vec4 kRed(1, 0, 0, 1);
const glm::vec4 kGreen(0, 1, 0, 1);

std::shared_ptr<Globe> plainGlobe(GlobeMethod method = GlobeMethod::RayCast)
{
    GlobeOptions options;
    options.method = method;
    options.color = {0.0f, 0.0f, 1.0f, 1.0f};
    return std::make_shared<Globe>(kEarth, options);
}

/// Counts update() calls; draws nothing.
class CountingPrimitive final : public Primitive {
public:
    explicit CountingPrimitive(const BoundingSphere& sphere) : _sphere(sphere) {}
    std::optional<BoundingSphere> boundingSphere() const override { return _sphere; }
    void update(FrameState&, CommandList&) override { ++updates; }
    int updates = 0;

private:
    BoundingSphere _sphere;
};

} // namespace

TEST_CASE("A globe seen from orbit runs one frustum, no translucent pass, and compiles its program once", "[scene][effects]")
{
    Scene scene(kEarth);
    scene.add(plainGlobe());
    scene.camera().lookAt(kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0, 2e7)), glm::dvec3(0), {0, 0, 1});

    // A device of its own: its shader cache starts empty, so the first frame must compile the
    // globe's one program (the shared device may hold it from an earlier test).
    Device device;
    Context& context = device.context();
    Framebuffer framebuffer = context.createFramebuffer(64, 64);
    context.setFramebuffer(&framebuffer);
    const FrameStatistics first = scene.render(context);
    REQUIRE(first.frustums.size() == 1);
    REQUIRE(first.opaquePasses == 1);
    REQUIRE(first.translucentPasses == 0);
    REQUIRE(first.overlayPasses == 0);
    REQUIRE(first.commandsExecuted == 1);
    REQUIRE(first.programsCompiled == 1);
    REQUIRE(device.shaderCache().size() == 1);

    const FrameStatistics second = scene.render(context);
    REQUIRE(second.programsCompiled == 0);
    REQUIRE(second.frustumsReused);
    REQUIRE(device.shaderCache().size() == 1);
    context.setFramebuffer(nullptr);
}

TEST_CASE("A globe seen from 200 km needs one frustum: its near and far come from the eye's height and horizon", "[scene][effects][multifrustum]")
{
    Scene scene(kEarth);
    scene.add(plainGlobe());
    const glm::dvec3 eye = kEarth.toCartesian(Geodetic3D::fromDegrees(9, 43, 2e5));
    scene.camera().lookAt(eye, kEarth.toCartesian(Geodetic3D::fromDegrees(10, 46, 0)), {0, 0, 1});
    const FrameStatistics statistics = renderFrame(scene, 64, 64).statistics;
    REQUIRE(statistics.frustums.size() == 1); // the bounding sphere alone would reach down to 1 m: 3 frustums
    REQUIRE(statistics.frustums.front().nearDistance > 0.8 * 2e5);
    REQUIRE(statistics.frustums.front().nearDistance <= 2e5);
    REQUIRE(statistics.frustums.front().farDistance < 2.5e6);
}

TEST_CASE("A satellite near the camera 40,000 km out adds frustums as the formula says, and removing it restores one", "[scene][effects][multifrustum]")
{
    Scene scene(kEarth);
    scene.options().depthStrategy = DepthStrategy::MultiFrustum; // Automatic would pick one complementary frustum
    scene.add(plainGlobe());
    const glm::dvec3 satellitePosition = kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0, 4e7));
    const glm::dvec3 eye = kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0, 4e7 + 1000.0));
    scene.camera().lookAt(eye, glm::dvec3(0), {0, 0, 1});

    const FrameStatistics globeOnly = renderFrame(scene, 64, 64).statistics;
    REQUIRE(globeOnly.frustums.size() == 1);

    auto satellite = std::make_shared<MeshPrimitive>(BoxTessellator::cube(satellitePosition, 20.0), kRed);
    scene.add(satellite);
    const FrameStatistics withSatellite = renderFrame(scene, 64, 64).statistics;
    const double nearest = withSatellite.frustums.front().nearDistance;
    const double farthest = withSatellite.frustums.back().farDistance;
    REQUIRE(nearest < 1000.0);
    REQUIRE(withSatellite.frustums.size() ==
            MultiFrustum::frustumCount(nearest, farthest, scene.options().multiFrustum.farToNearRatio));
    REQUIRE(withSatellite.frustums.size() == 2); // 980 m .. 52,700 km: log(5.4e4) / log(1000) = 1.58
    REQUIRE(withSatellite.commandsExecuted == 2);

    scene.remove(satellite.get());
    const FrameStatistics removed = renderFrame(scene, 64, 64).statistics;
    REQUIRE(removed.frustums.size() == 1);
}

TEST_CASE("The ray-cast globe writes true depth: a marker 1 m above the surface shows, 1 m below or behind the limb hides", "[scene][globe]")
{
    // The tessellated globe sags up to its deviation (about 1 km here) below the true surface, so
    // it cannot hide the marker 1 m below: only ray casting is held to that.
    for (const GlobeMethod method : {GlobeMethod::RayCast, GlobeMethod::Tessellated}) {
        // The eye 1,000 km over (45 E, 35 N): inside the ray-cast box, so its back faces are drawn.
        const Geodetic3D below = Geodetic3D::fromDegrees(45.0, 35.0, 0.0);
        const glm::dvec3 eye = kEarth.toCartesian(Geodetic3D(below.longitude, below.latitude, 1e6));
        Scene scene(kEarth);
        scene.add(plainGlobe(method));
        scene.camera().lookAt(eye, kEarth.toCartesian(below), {0, 0, 1});
        REQUIRE(glm::all(glm::lessThan(glm::abs(eye), kEarth.radii())));

        const Geodetic3D above = Geodetic3D::fromDegrees(47.0, 35.0, 1.0);
        const Geodetic3D under = Geodetic3D::fromDegrees(43.0, 35.0, -1.0);
        const Geodetic3D antipode = Geodetic3D::fromDegrees(45.0 - 180.0, -35.0, 1.0);
        scene.add(std::make_shared<MeshPrimitive>(horizontalSquare(kEarth, above, 50e3), kRed));
        scene.add(std::make_shared<MeshPrimitive>(horizontalSquare(kEarth, under, 50e3), kGreen));
        scene.add(std::make_shared<MeshPrimitive>(horizontalSquare(kEarth, antipode, 500e3), kGreen));

        const int size = 128;
        const RenderedFrame frame = renderFrame(scene, size, size);
        const glm::ivec2 abovePixel = projectToPixel(scene, kEarth.toCartesian(above), size, size);
        const glm::ivec2 underPixel = projectToPixel(scene, kEarth.toCartesian(under), size, size);
        const glm::ivec2 antipodePixel = projectToPixel(scene, kEarth.toCartesian(antipode), size, size);
        INFO("method " << (method == GlobeMethod::RayCast ? "ray cast" : "tessellated"));
        INFO("above " << describePixel(frame.image, abovePixel.x, abovePixel.y) << ", under "
                      << describePixel(frame.image, underPixel.x, underPixel.y) << ", antipode "
                      << describePixel(frame.image, antipodePixel.x, antipodePixel.y));
        REQUIRE(pixelNear(frame.image, abovePixel.x, abovePixel.y, {255, 0, 0, 255}));
        if (method == GlobeMethod::RayCast) {
            REQUIRE(pixelNear(frame.image, underPixel.x, underPixel.y, {0, 0, 255, 255}));
        }
        REQUIRE(pixelNear(frame.image, antipodePixel.x, antipodePixel.y, {0, 0, 255, 255}));
        // The view is filled by the globe: no pixel shows the black background.
        REQUIRE(pixelNear(frame.image, 0, 0, {0, 0, 255, 255}));
        REQUIRE(pixelNear(frame.image, size - 1, size - 1, {0, 0, 255, 255}));
    }
}

TEST_CASE("A primitive outside the view is culled whole and never updated", "[scene][culling]")
{
    Scene scene(kEarth);
    const glm::dvec3 eye = kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0, 2e7));
    scene.camera().lookAt(eye, glm::dvec3(0), {0, 0, 1});
    auto behind = std::make_shared<CountingPrimitive>(BoundingSphere{eye * 1.5, 1000.0});
    auto inFront = std::make_shared<CountingPrimitive>(BoundingSphere{eye * 0.5, 1000.0});
    scene.add(behind);
    scene.add(inFront);
    const FrameStatistics statistics = renderFrame(scene, 32, 32).statistics;
    REQUIRE(behind->updates == 0);
    REQUIRE(inFront->updates == 1);
    REQUIRE(statistics.primitivesCulled == 1);
    REQUIRE(statistics.primitivesUpdated == 1);
    REQUIRE(statistics.frustums.empty()); // no commands: nothing to bin, nothing drawn
    REQUIRE(statistics.commandsExecuted == 0);
}

TEST_CASE("Commands below the horizon are culled by their occlusion point and counted", "[scene][culling]")
{
    Scene scene(kEarth);
    scene.add(plainGlobe());
    const glm::dvec3 eye = kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0, 1e6));
    scene.camera().lookAt(eye, glm::dvec3(0), {0, 0, 1});
    const EllipsoidalOccluder occluder(kEarth, eye);

    auto makeMarker = [&](const Geodetic3D& where) {
        const Mesh mesh = horizontalSquare(kEarth, where, 10e3);
        auto marker = std::make_shared<MeshPrimitive>(mesh, kRed);
        const glm::dvec3 direction = glm::normalize(kEarth.toCartesian(where));
        marker->setHorizonOcclusionPoint(occluder.horizonOcclusionPoint(direction, mesh.positions));
        return marker;
    };
    scene.add(makeMarker(Geodetic3D::fromDegrees(1, 0, 0)));   // visible
    scene.add(makeMarker(Geodetic3D::fromDegrees(150, 0, 0))); // far below the horizon, in the view cone
    const FrameStatistics statistics = renderFrame(scene, 32, 32).statistics;
    REQUIRE(statistics.commandsSubmitted == 3);
    REQUIRE(statistics.commandsCulledByHorizon == 1);
    REQUIRE(statistics.commandsExecuted == 2);
}

TEST_CASE("A command straddling two frustums is drawn in each and counted once as redundant", "[scene][multifrustum]")
{
    Scene scene(kEarth);
    scene.options().depthStrategy = DepthStrategy::MultiFrustum;
    scene.camera().lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0});
    // Bounding spheres of cubes reach sqrt(3) half-sizes: the nearest starts at 15 - 5 sqrt(3) m,
    // so the frustums meet 1000 times farther out; the third cube sits on that boundary.
    const double nearest = 15.0 - 5.0 * std::sqrt(3.0);
    scene.add(std::make_shared<MeshPrimitive>(BoxTessellator::cube({0, 0, -15.0}, 5.0), kRed));
    scene.add(std::make_shared<MeshPrimitive>(BoxTessellator::cube({0, 0, -100e3}, 1e3), kGreen));
    scene.add(std::make_shared<MeshPrimitive>(BoxTessellator::cube({0, 0, -1000.0 * nearest}, 100.0), kRed));
    const FrameStatistics statistics = renderFrame(scene, 32, 32).statistics;
    REQUIRE(statistics.frustums.size() == 2);
    REQUIRE_THAT(statistics.frustums[0].nearDistance, Catch::Matchers::WithinRel(nearest, 1e-12));
    REQUIRE(statistics.commandsExecutedMoreThanOnce == 1);
    REQUIRE(statistics.commandsExecuted == 4);
    REQUIRE(statistics.drawCallsPerFrustum[0] + statistics.drawCallsPerFrustum[1] == 4);
}

TEST_CASE("Translucent commands draw after opaque ones and blend over them", "[scene][passes]")
{
    Scene scene(kEarth);
    scene.camera().lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0});
    // Submitted first but translucent: must still be blended over the opaque square behind it.
    scene.add(std::make_shared<MeshPrimitive>(BoxTessellator::cube({0, 0, -10.0}, 1.0), glm::vec4(1, 0, 0, 0.5),
                                              Pass::Translucent));
    scene.add(std::make_shared<MeshPrimitive>(BoxTessellator::cube({0, 0, -20.0}, 10.0), glm::vec4(0, 0, 1, 1)));
    const RenderedFrame frame = renderFrame(scene, 32, 32);
    REQUIRE(frame.statistics.translucentPasses == 1);
    REQUIRE(frame.statistics.opaquePasses == 1);
    INFO(describePixel(frame.image, 16, 16));
    REQUIRE(pixelNear(frame.image, 16, 16, {128, 0, 127, 255}, 1)); // half red over blue; alpha stays 1
}

TEST_CASE("Scene::setTime places the Sun as a scene file's time does; the shaders' clock moves nothing in the sky", "[scene][sun]")
{
    Scene scene(kEarth);
    const std::chrono::sys_seconds solstice = *parseUtcTime("2026-06-21T12:00:00Z");
    scene.setTime(solstice);
    REQUIRE(glm::distance(scene.sunDirection(), sunDirectionEarthFixed(solstice)) < 1e-15);
    // Noon UTC at the June solstice: overhead near 23.4 N on the meridian of Greenwich.
    REQUIRE(scene.sunDirection().z > std::sin(toRadians(23.0)));
    REQUIRE(scene.sunDirection().x > 0.9);
    scene.setClockSeconds(12.5);
    REQUIRE(scene.clockSeconds() == 12.5);
    REQUIRE(glm::distance(scene.sunDirection(), sunDirectionEarthFixed(solstice)) < 1e-15);
}

TEST_CASE("A scene drawn with 4 samples a pixel has pixels between the globe and the sky at the limb; with 1, none", "[scene][msaa]")
{
    // The tessellated globe: its triangles' edges are what multisampling smooths. (The ray-cast
    // globe decides coverage per pixel in its fragment shader, so its limb stays hard.)
    Scene scene(kEarth);
    scene.add(plainGlobe(GlobeMethod::Tessellated));
    scene.camera().lookAt(kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0, 2e7)), glm::dvec3(0), {0, 0, 1});
    auto limbPixels = [&](int samples) {
        scene.options().samples = samples;
        const RenderedFrame frame = renderFrame(scene, 64, 64);
        CHECK(frame.statistics.samples == samples);
        int between = 0;
        int blue = 0;
        for (int y = 0; y < 64; ++y) {
            for (int x = 0; x < 64; ++x) {
                const int b = pixelAt(frame.image, x, y).b;
                between += b > 0 && b < 255 ? 1 : 0;
                blue += b == 255 ? 1 : 0;
            }
        }
        CHECK(blue > 400); // the disc, about 17 pixels across the radius
        const std::vector<std::string> effects = frame.statistics.effectsRun();
        CHECK((std::find(effects.begin(), effects.end(), "multisampling") != effects.end()) == (samples > 1));
        return between;
    };
    CHECK(limbPixels(1) == 0); // the ray-cast globe covers a pixel or not
    CHECK(limbPixels(4) > 40); // most of the limb's 100-odd pixels
    CHECK(limbPixels(1) == 0);
}
