#include "GoldenImage.h"
#include "PrecisionMeasurement.h"
#include "ProceduralTileSource.h"
#include "RendererTestSupport.h"
#include "SceneTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/core/Transforms.h>
#include <orbis/renderer/Device.h>
#include <orbis/renderer/ShaderCache.h>
#include <orbis/scene/ClipmapTerrain.h>
#include <orbis/scene/Globe.h>
#include <orbis/world/FunctionTerrainSource.h>
#include <orbis/world/TerrainHeight.h>
#include <orbis/world/TerrainSource.h>
#include <orbis/world/TileSource.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>

using namespace orbis;
using namespace orbis::scene;
using namespace orbis::test;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

std::string dataPath(const std::string& relative)
{
    return std::string(ORBIS_SOURCE_DIR) + "/data/" + relative;
}

/// Loads on the render thread, arriving `latencyFrames` after they start, as many as a view needs.
world::TileLoaderOptions deterministicLoader(int latencyFrames)
{
    world::TileLoaderOptions loader;
    loader.workerThreads = 0;
    loader.latencyFrames = latencyFrames;
    loader.maximumStartsPerFrame = 256;
    loader.maximumInFlight = 512;
    return loader;
}

ClipmapTerrainOptions etopo5Options()
{
    ClipmapTerrainOptions options;
    options.terrain = world::openTerrainSource(dataPath("terrain/etopo5"));
    options.imagery.push_back({world::openTileSource(dataPath("imagery/BlueMarble")), {}});
    options.lighting = true;
    options.posts = 63;
    options.exaggeration = 20.0;
    options.loader = deterministicLoader(1);
    return options;
}

RenderedFrame renderConverged(Scene& scene, const ClipmapTerrain& terrain, int width, int height, int maxFrames = 60)
{
    RenderedFrame frame;
    for (int i = 0; i < maxFrames; ++i) {
        frame = renderFrame(scene, width, height);
        if (terrain.converged()) {
            break;
        }
    }
    return frame;
}

std::size_t backgroundPixels(const Image& image, int firstRow)
{
    std::size_t count = 0;
    for (int y = firstRow; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const std::uint8_t* p = &image.pixels[(static_cast<std::size_t>(y) * image.width + x) * 4];
            count += (p[0] == 0 && p[1] == 0 && p[2] == 0) ? 1 : 0;
        }
    }
    return count;
}

/// Every drawn triangle whose centre faces the eye (above the horizon) and lies in the view has a
/// positive area in window space (counter-clockwise with y up) and finite corners; returns how
/// many were checked.
std::size_t checkWindowAreas(const Scene& scene, const ClipmapTerrain& terrain, int width, int height)
{
    const std::vector<glm::dvec3> triangles = terrain.drawnTriangles();
    const Camera& camera = scene.camera();
    std::size_t checked = 0;
    for (std::size_t i = 0; i < triangles.size(); i += 3) {
        for (std::size_t k = 0; k < 3; ++k) {
            REQUIRE(std::isfinite(triangles[i + k].x));
            REQUIRE(std::isfinite(triangles[i + k].y));
            REQUIRE(std::isfinite(triangles[i + k].z));
        }
        const glm::dvec3 centre = (triangles[i] + triangles[i + 1] + triangles[i + 2]) / 3.0;
        // Beyond the horizon, or so near it that a triangle on the curved surface may be seen
        // from behind (3 degrees above it at least).
        if (glm::dot(kEarth.geodeticSurfaceNormal(centre), glm::normalize(camera.eye() - centre)) <= 0.05) {
            continue;
        }
        std::array<glm::dvec2, 3> window;
        bool inView = true;
        for (std::size_t k = 0; k < 3; ++k) {
            const std::optional<glm::dvec2> w = camera.worldToWindow(triangles[i + k], width, height);
            if (!w || w->x < 0 || w->x > width || w->y < 0 || w->y > height ||
                glm::dot(triangles[i + k] - camera.eye(), camera.direction()) <= 0.0) {
                inView = false;
                break;
            }
            window[k] = {w->x, height - w->y};
        }
        if (!inView) {
            continue;
        }
        const glm::dvec2 e1 = window[1] - window[0], e2 = window[2] - window[0];
        INFO("triangle " << i / 3);
        REQUIRE(e1.x * e2.y - e1.y * e2.x > 0.0);
        ++checked;
    }
    return checked;
}

} // namespace

TEST_CASE("Clipmap terrain rejects posts that are not 2^k - 1 and bad numbers", "[scene][clipmap]")
{
    for (const int posts : {0, 7, 100, 256, 2047}) {
        ClipmapTerrainOptions options;
        options.posts = posts;
        CHECK_THROWS_AS(ClipmapTerrain(kEarth, options), Error);
    }
    ClipmapTerrainOptions options;
    options.exaggeration = -1.0;
    CHECK_THROWS_AS(ClipmapTerrain(kEarth, options), Error);
    options.exaggeration = 1.0;
    options.levels = 25;
    CHECK_THROWS_AS(ClipmapTerrain(kEarth, options), Error);
    options.levels = 0;
    const ClipmapTerrain terrain(kEarth, options);
    // Without terrain: 1/64 degree, up to the coarsest level that stays 48 degrees wide.
    CHECK(terrain.finestSpacing() == Approx(toRadians(1.0 / 64.0)));
    CHECK(terrain.finestSpacing() * std::ldexp(1.0, terrain.levels() - 1) * 127.0 <= toRadians(48.0));
    CHECK(terrain.finestSpacing() * std::ldexp(1.0, terrain.levels()) * 127.0 > toRadians(48.0));
}

TEST_CASE("Clipmap terrain over ETOPO5 converges, draws at most 2L + 1 commands and leaves no hole", "[scene][clipmap][gl]")
{
    Scene scene(kEarth);
    auto terrain = std::make_shared<ClipmapTerrain>(kEarth, etopo5Options());
    scene.add(terrain);
    placeCamera(scene, Geodetic3D::fromDegrees(8.0, 44.0, 150000.0), 0.0, -30.0);
    const RenderedFrame frame = renderConverged(scene, *terrain, 160, 90);
    REQUIRE(frame.statistics.clipmap);
    INFO(frame.statistics.toText());
    const ClipmapStatistics& clipmap = *frame.statistics.clipmap;
    CHECK(terrain->converged());
    CHECK(clipmap.drawCalls <= static_cast<std::size_t>(2 * clipmap.levels + 1));
    CHECK(clipmap.drawCalls > 0);
    CHECK(clipmap.piecesCulled > 0); // looking north: the pieces behind are left out
    // 44 degrees north is past 40: the grid whose pole is on the y axis.
    CHECK(clipmap.parameterization == 2);
    const std::vector<std::string> effects = frame.statistics.effectsRun();
    CHECK(std::vector<std::string>(effects.begin(), effects.begin() + 4) ==
          std::vector<std::string>{"globe", "lighting", "terrain", "clipmap terrain"});
    // Below the horizon (the lower two thirds), every pixel is terrain.
    CHECK(backgroundPixels(frame.image, 30) == 0);
    // The next frame with nothing new writes nothing.
    const RenderedFrame again = renderFrame(scene, 160, 90);
    CHECK(again.statistics.clipmap->postsUpdated == 0);
    CHECK(again.statistics.clipmap->bytesUploaded == 0);
}

TEST_CASE("Clipmap terrain answers the ground's height and picks: the drawn posts' own, on both parameterisations, none off the levels",
          "[scene][clipmap][gl]")
{
    // The Himalaya on the geodetic grid, the Alps on the one whose pole is on the y axis.
    for (const Geodetic3D& eye : {Geodetic3D::fromDegrees(86.9, 27.0, 150000.0), Geodetic3D::fromDegrees(8.0, 44.0, 150000.0)}) {
        Scene scene(kEarth);
        auto terrain = std::make_shared<ClipmapTerrain>(kEarth, etopo5Options());
        scene.add(terrain);
        CHECK_FALSE(terrain->groundHeight(Geodetic2D(eye.longitude, eye.latitude))); // nothing drawn yet
        placeCamera(scene, eye, 0.0, -30.0);
        renderConverged(scene, *terrain, 160, 90);
        REQUIRE(terrain->converged());
        // Every drawn vertex (one in 17) is where the ground's height says, blended levels included.
        const std::vector<glm::dvec3> points = terrain->drawnTriangles();
        REQUIRE(points.size() > 10000);
        std::size_t checked = 0;
        double lowest = 1e9, highest = -1e9;
        for (std::size_t i = 0; i < points.size(); i += 17) {
            const Geodetic3D vertex = kEarth.toGeodetic3D(points[i]);
            const std::optional<double> height = terrain->groundHeight(Geodetic2D(vertex.longitude, vertex.latitude));
            INFO("vertex " << i << " at " << toDegrees(vertex.longitude) << ", " << toDegrees(vertex.latitude));
            REQUIRE(height);
            REQUIRE(std::abs(*height - vertex.height) < 0.01);
            lowest = std::min(lowest, vertex.height);
            highest = std::max(highest, vertex.height);
            ++checked;
        }
        CHECK(checked > 600);
        CHECK(highest - lowest > 20000.0); // mountains (exaggerated 20 times), not a flat answer
        // The scene asks it: the camera is kept above it.
        CHECK(std::abs(scene.groundHeight(Geodetic2D(eye.longitude, eye.latitude)) -
                       *terrain->groundHeight(Geodetic2D(eye.longitude, eye.latitude))) < 1e-9);
        // The far side of the globe is outside every level.
        CHECK_FALSE(terrain->groundHeight(Geodetic2D(eye.longitude + kPi, -eye.latitude)));
        // A pick straight down onto a drawn triangle's centre meets it there, 10 km down.
        for (std::size_t t = 0; t + 2 < points.size(); t += 3 * 4999) {
            const glm::dvec3 centre = (points[t] + points[t + 1] + points[t + 2]) / 3.0;
            const glm::dvec3 up = kEarth.geodeticSurfaceNormal(centre);
            const std::optional<double> hit = terrain->pickGround(Ray{centre + 10000.0 * up, -up});
            REQUIRE(hit);
            CHECK(std::abs(*hit - 10000.0) < 1e-3);
        }
        // And the scene's pick from the view's centre lands on the ground the clipmap answers.
        const std::optional<glm::dvec3> picked = scene.pickGround({80.0, 45.0}, 160, 90);
        REQUIRE(picked);
        const Geodetic3D ground = kEarth.toGeodetic3D(*picked);
        CHECK(ground.height > lowest - 1.0);
        CHECK(ground.height < highest + 1.0);
        // (The flat triangle sags below the grid's interpolation: 5 m here, for cells of about 16 km.)
        CHECK(std::abs(ground.height - *terrain->groundHeight(Geodetic2D(ground.longitude, ground.latitude))) < 10.0);
    }
}

TEST_CASE("From orbit the clipmap's globe is whole: a backdrop beyond the coarsest level, none when the levels cover the view",
          "[scene][clipmap][gl]")
{
    constexpr int kWidth = 160, kHeight = 90;
    // The coarsest level reaches 48 degrees from the viewer; from 8,000 km the limb is 64 degrees away.
    for (const Geodetic2D& below : {Geodetic2D::fromDegrees(8.0, 43.0), Geodetic2D::fromDegrees(100.0, 0.0)}) {
        ClipmapTerrainOptions options = etopo5Options();
        options.exaggeration = 1.0;
        Scene scene(kEarth);
        scene.options().background = {1.0f, 0.0f, 1.0f, 1.0f};
        auto terrain = std::make_shared<ClipmapTerrain>(kEarth, options);
        scene.add(terrain);
        placeCamera(scene, Geodetic3D(below.longitude, below.latitude, 8e6), 0.0, -90.0);
        const RenderedFrame frame = renderConverged(scene, *terrain, kWidth, kHeight);
        REQUIRE(terrain->converged());
        // Every pixel whose ray meets the globe 30 km inside its surface (clear of the limb, where
        // heights decide) shows ground, not the background.
        const Ellipsoid inner(kEarth.radii() - glm::dvec3(30000.0));
        std::size_t onGlobe = 0, holes = 0;
        for (int y = 0; y < kHeight; ++y) {
            for (int x = 0; x < kWidth; ++x) {
                if (!scene.camera().pickEllipsoid({x + 0.5, y + 0.5}, kWidth, kHeight, inner)) {
                    continue;
                }
                ++onGlobe;
                const std::uint8_t* p = &frame.image.pixels[(static_cast<std::size_t>(y) * kWidth + static_cast<std::size_t>(x)) * 4];
                holes += (p[0] == 255 && p[1] == 0 && p[2] == 255) ? 1 : 0;
            }
        }
        INFO("below " << toDegrees(below.longitude) << ", " << toDegrees(below.latitude) << ": " << holes << " of " << onGlobe);
        CHECK(onGlobe > 3000);
        CHECK(holes == 0);
        CHECK(frame.statistics.clipmap->backdropDrawn);
        CHECK(frame.statistics.clipmap->drawCalls <= static_cast<std::size_t>(2 * frame.statistics.clipmap->levels + 2));
    }
    // From 150 km the levels cover all the eye sees: no backdrop drawn.
    Scene low(kEarth);
    auto terrain = std::make_shared<ClipmapTerrain>(kEarth, etopo5Options());
    low.add(terrain);
    placeCamera(low, Geodetic3D::fromDegrees(8.0, 43.0, 150000.0), 0.0, -30.0);
    const RenderedFrame frame = renderConverged(low, *terrain, 64, 36);
    REQUIRE(terrain->converged());
    CHECK_FALSE(frame.statistics.clipmap->backdropDrawn);
}

TEST_CASE("Clipmap vertices do not jitter at 1 m: the GPU's window positions within 0.1 px of double precision's",
          "[scene][clipmap][gl]")
{
    // Posts 1.1 m apart near the eye (as a 1 m DEM would give), the eye 1 m above the drawn ground,
    // on the geodetic grid (Himalaya, ground 5 km above the ellipsoid) and a rotated one (Norway).
    // Measured as docs/precision.md measures vertex transforms, at 1920 x 1080 and 45 degrees.
    for (const Geodetic2D& place : {Geodetic2D::fromDegrees(86.9, 27.9), Geodetic2D::fromDegrees(8.0, 61.0)}) {
        ClipmapTerrainOptions options = etopo5Options();
        options.exaggeration = 1.0;
        options.finestSpacingDegrees = 1e-5;
        const bench::ClipmapJitterResult measured = bench::measureClipmapJitter(sharedDevice().context(), options, place, 1.0);
        INFO("at " << toDegrees(place.longitude) << ", " << toDegrees(place.latitude) << ": " << measured.vertices
                   << " vertices in view, " << measured.within10m << " within 10 m, worst " << measured.error.maxPixels << " px");
        REQUIRE(measured.converged);
        REQUIRE(measured.finestLevelDrawn == 0);
        CHECK(std::abs(measured.eyeAboveGround - 1.0) < 0.05);
        CHECK(measured.within10m > 20);
        CHECK(measured.vertices > 1000);
        // Heights drawn as differences from the eye's: 0.013 and 0.004 px; 0.44 px (Himalaya) before.
        CHECK(measured.error.maxPixels < 0.1);
    }
}

TEST_CASE("Clipmap levels take the finest tile loaded at every post, also beside posts only a coarser tile covers",
          "[scene][clipmap][gl]")
{
    // The Cumberland DEM is 27 x 32 km: a level's window of 255 posts reaches beyond it, where
    // only coarser tiles exist. Writing a row, a post there once made the coarser tile serve the
    // posts after it over its whole extent, DEM included: the ground 4-6 km from the eye was
    // 200-330 m below the data.
    const std::string dem = orbis::test::dataPath("terrain/cumberland/jacksboro_fault.vrt");
    ClipmapTerrainOptions options;
    options.terrain = world::openTerrainSource(dem);
    options.posts = 255;
    options.loader = deterministicLoader(0);
    auto terrain = std::make_shared<ClipmapTerrain>(kEarth, options);
    Scene scene(kEarth);
    scene.add(terrain);
    placeCamera(scene, Geodetic3D::fromDegrees(-84.40, 36.46, 2000.0), 45.0, -3.0);
    renderConverged(scene, *terrain, 160, 90, 100);
    REQUIRE(terrain->converged());
    const auto source = world::openTerrainSource(dem);
    world::TerrainHeightQuery query(*source);
    double largest = 0.0;
    for (double latitude = 36.46; latitude <= 36.55; latitude += 0.005) {
        for (double longitude = -84.42; longitude <= -84.34; longitude += 0.005) {
            const Geodetic2D point = Geodetic2D::fromDegrees(longitude, latitude);
            const std::optional<double> drawn = terrain->groundHeight(point);
            const std::optional<world::TerrainHeight> data = query.at(point);
            REQUIRE((drawn && data));
            largest = std::max(largest, std::abs(*drawn - data->height));
        }
    }
    // The finest levels interpolate the DEM's 80 m grids, bilinearly on 129 x 129 lattices.
    CHECK(largest < 10.0);
}

TEST_CASE("Clipmap colours blend across imagery tiles' edges: no line where the imagery is magnified", "[scene][clipmap][gl]")
{
    // Tiles of 2 x 2 texels, a texel 5.6 degrees across: from 400 km over the corner of four
    // tiles (11.25 E, 11.25 N) about one texel fills the view. The pattern is continuous across
    // tiles and its red and green rise steadily there (11 levels a degree, a third of a level a
    // pixel), so bilinear colours change by a few levels over 12 pixels; a post within half a
    // texel of a tile's edge held to that tile's edge texels instead makes a step of a texel's
    // difference (64 levels) along the boundaries, spread over a post or two (63 levels over 12
    // pixels when it was so).
    test::ProceduralTileSourceOptions tiles;
    tiles.tileSize = 2;
    tiles.maximumLevel = 4;
    ClipmapTerrainOptions options;
    options.imagery.push_back({std::make_shared<test::ProceduralTileSource>(tiles), {}});
    options.posts = 63;
    options.loader = deterministicLoader(1);
    auto terrain = std::make_shared<ClipmapTerrain>(kEarth, options);
    Scene scene(kEarth);
    scene.add(terrain);
    placeCamera(scene, Geodetic3D::fromDegrees(11.55, 11.45, 400000.0), 0.0, -90.0);
    const RenderedFrame frame = renderConverged(scene, *terrain, 160, 120);
    REQUIRE(terrain->converged());
    const Image& image = frame.image;
    // The boundaries cross the view.
    const glm::ivec2 corner = projectToPixel(scene, kEarth.toCartesian(Geodetic3D::fromDegrees(11.25, 11.25, 0.0)), 160, 120);
    REQUIRE((corner.x > 10 && corner.x < 150 && corner.y > 10 && corner.y < 110));
    constexpr int kApart = 12;
    int largest = 0;
    for (int y = 0; y + kApart < image.height; ++y) {
        for (int x = 0; x + kApart < image.width; ++x) {
            const std::uint8_t* p = image.pixel(x, y);
            for (const std::uint8_t* q : {image.pixel(x + kApart, y), image.pixel(x, y + kApart)}) {
                for (int c = 0; c < 3; ++c) {
                    largest = std::max(largest, std::abs(static_cast<int>(p[c]) - static_cast<int>(q[c])));
                }
            }
        }
    }
    CHECK(largest <= 10); // 4 as written
}

TEST_CASE("In a rotated grid the posts are written at their own geodetic positions, stepped from post to post",
          "[scene][clipmap][gl]")
{
    // Ground rising 20 km a radian eastwards and 10 km northwards: linear in longitude and
    // latitude, so a post's height says where the post was sampled (a post a step off would be
    // 0.1-0.3 m off here), whatever level and lattice it was read from.
    const auto plane = [](const Geodetic2D& g) { return 2.0e4 * g.longitude + 1.0e4 * g.latitude; };
    ClipmapTerrainOptions options;
    options.terrain = std::make_shared<world::FunctionTerrainSource>(plane, 12);
    options.posts = 127;
    options.loader = deterministicLoader(0);
    auto terrain = std::make_shared<ClipmapTerrain>(kEarth, options);
    Scene scene(kEarth);
    scene.add(terrain);
    const Geodetic3D eye = Geodetic3D::fromDegrees(10.0, 62.0, 2000.0 + plane(Geodetic2D::fromDegrees(10.0, 62.0)));
    placeCamera(scene, eye, 30.0, -20.0);
    const RenderedFrame frame = renderConverged(scene, *terrain, 96, 54, 200);
    REQUIRE(terrain->converged());
    REQUIRE(frame.statistics.clipmap->parameterization != 0);
    double largest = 0.0;
    int points = 0;
    for (double north = -0.02; north <= 0.02; north += 0.002) {
        for (double east = -0.04; east <= 0.04; east += 0.004) {
            const Geodetic2D point = Geodetic2D::fromDegrees(10.0 + east, 62.0 + north);
            const std::optional<double> drawn = terrain->groundHeight(point);
            REQUIRE(drawn);
            largest = std::max(largest, std::abs(*drawn - plane(point)));
            ++points;
        }
    }
    CHECK(points >= 400);
    CHECK(largest < 0.02);
}

TEST_CASE("A moving viewer's clipmap updates stay within the budget, coarse levels first, and end where a fresh one starts", "[scene][clipmap][gl]")
{
    ClipmapTerrainOptions options = etopo5Options();
    options.postsPerFrame = 64 * 20; // twenty rows of a level each frame
    Scene moving(kEarth);
    auto terrain = std::make_shared<ClipmapTerrain>(kEarth, options);
    moving.add(terrain);
    placeCamera(moving, Geodetic3D::fromDegrees(5.0, 45.0, 60000.0), 90.0, -40.0);
    renderConverged(moving, *terrain, 128, 72, 400);
    REQUIRE(terrain->converged());
    bool waited = false;
    for (int step = 1; step <= 24; ++step) {
        placeCamera(moving, Geodetic3D::fromDegrees(5.0 + 0.3 * step, 45.0 + 0.1 * step, 60000.0), 90.0, -40.0);
        const RenderedFrame frame = renderFrame(moving, 128, 72);
        const ClipmapStatistics& clipmap = *frame.statistics.clipmap;
        // At most the budget, rounded up to whole rows of one region.
        CHECK(clipmap.postsUpdated <= options.postsPerFrame + 64);
        waited = waited || clipmap.finestLevelDrawn > 0;
        CHECK(backgroundPixels(frame.image, 30) == 0);
    }
    CHECK(waited); // finer levels waited for their strips rather than show unwritten posts
    const RenderedFrame movedFrame = renderConverged(moving, *terrain, 128, 72, 400);
    REQUIRE(terrain->converged());

    Scene fresh(kEarth);
    auto freshTerrain = std::make_shared<ClipmapTerrain>(kEarth, options);
    fresh.add(freshTerrain);
    placeCamera(fresh, Geodetic3D::fromDegrees(5.0 + 0.3 * 24, 45.0 + 0.1 * 24, 60000.0), 90.0, -40.0);
    const RenderedFrame freshFrame = renderConverged(fresh, *freshTerrain, 128, 72, 400);
    REQUIRE(freshTerrain->converged());
    CHECK(movedFrame.image.pixels == freshFrame.image.pixels);
}

TEST_CASE("Clipmap terrain at the poles and across the antimeridian draws no collapsed or inverted triangle", "[scene][clipmap][gl]")
{
    struct View {
        const char* name;
        Geodetic3D position;
        double heading, pitch;
        bool geodetic; ///< the grid is the geodetic one (else one whose pole is on the equator)
    };
    const View views[] = {
        {"North Pole, looking down", Geodetic3D::fromDegrees(0.0, 90.0, 30000.0), 0.0, -90.0, false},
        {"near the South Pole, oblique", Geodetic3D::fromDegrees(135.0, -89.5, 30000.0), 30.0, -20.0, false},
        {"antimeridian", Geodetic3D::fromDegrees(180.0, -17.0, 50000.0), 90.0, -30.0, true},
    };
    for (const View& view : views) {
        INFO(view.name);
        ClipmapTerrainOptions options;
        options.posts = 63;
        options.colorByLevel = true;
        Scene scene(kEarth);
        auto terrain = std::make_shared<ClipmapTerrain>(kEarth, options);
        scene.add(terrain);
        placeCamera(scene, view.position, view.heading, view.pitch);
        const RenderedFrame frame = renderConverged(scene, *terrain, 128, 96);
        REQUIRE(terrain->converged());
        CHECK((frame.statistics.clipmap->parameterization == 0) == view.geodetic);
        CHECK(checkWindowAreas(scene, *terrain, 128, 96) > 300);
        CHECK(backgroundPixels(frame.image, view.pitch < -60.0 ? 0 : 48) == 0);
    }
}

TEST_CASE("A scene without clipmap terrain compiles none of its programs", "[scene][clipmap][gl]")
{
    renderer::Device& device = sharedDevice();
    device.shaderCache().clear(); // as in a process of its own: tests before may have made the program
    Scene plain(kEarth);
    plain.add(std::make_shared<Globe>(kEarth));
    placeCamera(plain, Geodetic3D::fromDegrees(8.0, 44.0, 3000000.0), 0.0, -90.0);
    const RenderedFrame first = renderFrame(plain, 64, 64);
    CHECK_FALSE(first.statistics.clipmap);
    renderFrame(plain, 64, 64);
    const std::uint64_t compiles = device.shaderCache().compiles();
    const std::uint64_t hits = device.shaderCache().hits();

    ClipmapTerrainOptions options;
    options.posts = 31;
    options.baseColor = {0.5f, 0.25f, 0.125f, 1.0f};
    Scene clipmapScene(kEarth);
    clipmapScene.add(std::make_shared<ClipmapTerrain>(kEarth, options));
    placeCamera(clipmapScene, Geodetic3D::fromDegrees(8.0, 44.0, 3000.0), 0.0, -90.0);
    const RenderedFrame frame = renderFrame(clipmapScene, 64, 64);
    REQUIRE(frame.statistics.clipmap);
    // Its program was compiled now, not found in the cache: the plain scene had not made it.
    CHECK(device.shaderCache().compiles() == compiles + 1);
    CHECK(device.shaderCache().hits() == hits);
    const std::uint8_t* centre = &frame.image.pixels[(32 * 64 + 32) * 4];
    CHECK(static_cast<int>(centre[0]) == Approx(128).margin(2));
    CHECK(static_cast<int>(centre[1]) == Approx(64).margin(2));
}

TEST_CASE("Clipmap terrain golden images: the Alps shaded, the North Pole, the antimeridian and the globe from orbit", "[scene][clipmap][gl][golden]")
{
    struct View {
        const char* name;
        Geodetic3D position;
        double heading, pitch;
        bool levels;
    };
    const View views[] = {
        {"clipmap-alps", Geodetic3D::fromDegrees(8.0, 44.0, 40000.0), 0.0, -25.0, false},
        {"clipmap-alps-levels", Geodetic3D::fromDegrees(8.0, 44.0, 40000.0), 0.0, -25.0, true},
        {"clipmap-north-pole", Geodetic3D::fromDegrees(-40.0, 86.0, 150000.0), 180.0, -35.0, false},
        {"clipmap-antimeridian", Geodetic3D::fromDegrees(178.0, -17.5, 60000.0), 90.0, -30.0, false},
        // The backdrop beyond the coarsest level, from Japan and Arabia to the limb.
        {"clipmap-orbit", Geodetic3D::fromDegrees(100.0, 0.0, 8e6), 0.0, -90.0, false},
    };
    for (const View& view : views) {
        ClipmapTerrainOptions options = etopo5Options();
        options.colorByLevel = view.levels;
        Scene scene(kEarth);
        auto terrain = std::make_shared<ClipmapTerrain>(kEarth, options);
        scene.add(terrain);
        placeCamera(scene, view.position, view.heading, view.pitch);
        // The Sun 50 degrees up behind the viewer's left shoulder: slopes facing it light up.
        const glm::dvec3 up = kEarth.geodeticSurfaceNormal(scene.camera().eye());
        const glm::dvec3 back = glm::normalize(glm::cross(scene.camera().right(), up));
        scene.setSunDirection(view.position.height > 1e6 ? up // from orbit: overhead, the whole disc lit
                                                         : glm::normalize(1.2 * up + back - 0.5 * scene.camera().right()));
        const RenderedFrame frame = renderConverged(scene, *terrain, 256, 144);
        INFO(view.name << "\n" << frame.statistics.toText());
        REQUIRE(terrain->converged());
        // llvmpipe draws these exactly; the tolerance allows another rasteriser's edges, not a
        // level missing or misplaced (thousands of pixels).
        ORBIS_REQUIRE_GOLDEN(frame.image, view.name, GoldenTolerance{3, 0.002});
    }
}

TEST_CASE("Clipmap terrain takes the terrain shading: the height ramp blue over the sea, green on land", "[scene][clipmap][gl]")
{
    ClipmapTerrainOptions options = etopo5Options();
    options.imagery.clear();
    options.lighting = false;
    options.shading.color = TerrainShading::Color::Height;
    options.shading.contourInterval = 1000.0;
    options.shading.contourColor = {1.0f, 0.0f, 0.0f};
    Scene scene(kEarth);
    auto terrain = std::make_shared<ClipmapTerrain>(kEarth, options);
    scene.add(terrain);
    // The Ligurian Sea in front, the Alps behind.
    placeCamera(scene, Geodetic3D::fromDegrees(8.5, 42.5, 150000.0), 0.0, -40.0);
    const RenderedFrame frame = renderConverged(scene, *terrain, 160, 90);
    REQUIRE(terrain->converged());
    const std::vector<std::string> effects = frame.statistics.effectsRun();
    CHECK(std::find(effects.begin(), effects.end(), "terrain shading") != effects.end());
    auto pixel = [&](int x, int y) { return &frame.image.pixels[(static_cast<std::size_t>(y) * 160 + x) * 4]; };
    // The bottom row is sea (2 to 3 km deep): blues.
    const std::uint8_t* sea = pixel(80, 88);
    CHECK(sea[2] > sea[0] + 40);
    // Contour lines in red somewhere (the Alps' slopes cross 1,000 and 2,000 m).
    std::size_t red = 0;
    for (int y = 0; y < 90; ++y) {
        for (int x = 0; x < 160; ++x) {
            const std::uint8_t* p = pixel(x, y);
            red += (p[0] > 200 && p[1] < 80 && p[2] < 80) ? 1 : 0;
        }
    }
    CHECK(red > 20);
}
