#include "SceneTestSupport.h"
#include "TempFiles.h"

#include <orbis/core/Error.h>
#include <orbis/core/OrientedBoundingBox.h>
#include <orbis/core/Transforms.h>
#include <orbis/scene/BillboardCollection.h>
#include <orbis/scene/Effect.h>
#include <orbis/scene/LabelCollection.h>
#include <orbis/scene/ModelPrimitive.h>
#include <orbis/scene/PolygonCollection.h>
#include <orbis/scene/PolylineCollection.h>
#include <orbis/scene/SceneBuilder.h>
#include <orbis/scene/TiledGlobe.h>
#include <orbis/world/FunctionTerrainSource.h>
#include <orbis/world/SceneFile.h>
#include <orbis/world/TerrainHeight.h>
#include <orbis/world/TerrainSource.h>

#include <catch2/catch.hpp>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <random>

using namespace orbis;
using namespace orbis::scene;
using namespace orbis::test;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

/// Grid terrain tiles of levels 0 to deepestLevel from a function of longitude and latitude
/// (degrees) plus `levelOffset` metres per level: the levels disagree, as the levels of a
/// box-filtered pyramid do, while neighbours of one level share their edge samples.
std::shared_ptr<world::TerrainSource> syntheticTerrain(std::function<double(double, double)> height, double levelOffset,
                                                       std::uint32_t deepestLevel = 12)
{
    return std::make_shared<world::FunctionTerrainSource>(
        [height = std::move(height)](const Geodetic2D& g) { return height(toDegrees(g.longitude), toDegrees(g.latitude)); },
        deepestLevel, levelOffset);
}

/// Mountains of a few kilometres, 70 km apart, everywhere: continuous across the antimeridian and
/// one height at each pole, as real elevation is.
double ridges(double longitudeDegrees, double latitudeDegrees)
{
    const double longitude = toRadians(longitudeDegrees);
    const double latitude = toRadians(latitudeDegrees);
    return 1500.0 + 1200.0 * std::sin(400.0 * longitude) * std::cos(latitude) * std::cos(300.0 * latitude) +
           400.0 * std::sin(700.0 * latitude);
}

struct TerrainScene {
    Scene scene{kEarth};
    std::shared_ptr<TiledGlobe> globe;

    explicit TerrainScene(std::shared_ptr<world::TerrainSource> terrain, double exaggeration = 1.0,
                          const std::function<void(TiledGlobeOptions&)>& configure = {})
    {
        TiledGlobeOptions options;
        options.terrain = std::move(terrain);
        options.terrainExaggeration = exaggeration;
        options.lighting = true; // what most of these tests look at
        options.loader.workerThreads = 0;
        options.loader.latencyFrames = 0;
        options.loader.maximumStartsPerFrame = 64;
        options.baseColor = glm::vec4(0.3f, 0.6f, 0.3f, 1.0f);
        scene.options().background = glm::vec4(1.0f, 0.0f, 1.0f, 1.0f); // magenta: a crack or a hole
        if (configure) {
            configure(options);
        }
        globe = std::make_shared<TiledGlobe>(kEarth, options);
        scene.add(globe);
    }

    void look(const Geodetic3D& position, double headingDegrees, double pitchDegrees)
    {
        placeCamera(scene, position, headingDegrees, pitchDegrees);
    }

    RenderedFrame converge(int width, int height) { return renderUntilTilesConverge(scene, width, height, 300); }
};

/// Pixels of the background below the horizon's row band: the sky is at the top of these views.
int magentaBelowSky(const Image& image, int skyRows)
{
    int count = 0;
    for (int y = skyRows; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const std::uint8_t* p = image.pixel(x, y);
            count += p[0] == 255 && p[1] == 0 && p[2] == 255;
        }
    }
    return count;
}

/// The highest green less the lowest over columns [x0, x1) and rows [y0, y1): how much light and
/// shade a block of the view shows.
int greenSpread(const Image& image, int x0, int y0, int x1, int y1)
{
    int lowest = 255;
    int highest = 0;
    for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
            lowest = std::min<int>(lowest, image.pixel(x, y)[1]);
            highest = std::max<int>(highest, image.pixel(x, y)[1]);
        }
    }
    return highest - lowest;
}

/// Triangle edges the drawn surface does not share between exactly two triangles.
struct OpenEdges {
    int cracks = 0;       ///< drawn surface on both sides: a gap between tiles
    int border = 0;       ///< the border of what was drawn
    int sharedByMore = 0; ///< more than two triangles on one edge
};

/// Each triangle edge by its two end points, as the GPU gets them (doubles of the floats); an edge
/// of one triangle must be on the border of what was drawn, with no tile across it.
OpenEdges openEdges(const TiledGlobe& globe)
{
    const std::vector<glm::dvec3> points = globe.drawnTriangles();
    auto less = [](const glm::dvec3& a, const glm::dvec3& b) { return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z); };
    using Edge = std::pair<glm::dvec3, glm::dvec3>;
    std::map<Edge, int, std::function<bool(const Edge&, const Edge&)>> edges([&](const Edge& a, const Edge& b) {
        if (less(a.first, b.first) != less(b.first, a.first)) {
            return less(a.first, b.first);
        }
        return less(a.second, b.second);
    });
    for (std::size_t t = 0; t + 2 < points.size(); t += 3) {
        for (std::size_t e = 0; e < 3; ++e) {
            glm::dvec3 a = points[t + e];
            glm::dvec3 b = points[t + (e + 1) % 3];
            if (a == b) {
                continue; // a pole's collapsed row
            }
            if (less(b, a)) {
                std::swap(a, b);
            }
            ++edges[{a, b}];
        }
    }
    OpenEdges open;
    for (const auto& [edge, count] : edges) {
        if (count != 1) {
            open.sharedByMore += count > 2;
            continue;
        }
        const Geodetic2D a = kEarth.toGeodetic2D(edge.first);
        const Geodetic2D b = kEarth.toGeodetic2D(edge.second);
        const Geodetic2D middle{0.5 * (a.longitude + b.longitude), 0.5 * (a.latitude + b.latitude)};
        // Just off the edge on both sides (a hundredth of its length), square to it in longitude
        // and latitude.
        const glm::dvec2 along(b.longitude - a.longitude, b.latitude - a.latitude);
        const glm::dvec2 across = glm::dvec2(-along.y, along.x) * 0.01;
        const bool left = globe.heightAt({middle.longitude + across.x, middle.latitude + across.y}).has_value();
        const bool right = globe.heightAt({middle.longitude - across.x, middle.latitude - across.y}).has_value();
        (left && right ? open.cracks : open.border) += 1;
    }
    return open;
}

} // namespace

TEST_CASE("Terrain tiles of levels that disagree meet without a crack: the finer edge takes the coarser one's",
          "[scene][tiles][terrain][gl]")
{
    // 37 m a level apart: without stitching every level change would open a visible crack.
    TerrainScene terrain(syntheticTerrain(ridges, 37.0));
    // Low and oblique over the ridges: many levels in one view, with the horizon at the top.
    terrain.look(Geodetic3D::fromDegrees(10.0, 46.0, 9000.0), 30.0, -20.0);
    const RenderedFrame frame = terrain.converge(320, 240);
    const TileStatistics& tiles = *frame.statistics.tiles;
    REQUIRE(tiles.converged);
    REQUIRE(tiles.deepestLevelDrawn >= 8);
    CHECK(hasEffect(frame.statistics.effects, Effect::Terrain));
    CHECK(magentaBelowSky(frame.image, 80) == 0);

    // Across every drawn tile's edges the surface is continuous: a point just inside one tile and
    // just inside its neighbour give heights within what the slope makes of the step.
    std::mt19937 random(42);
    std::uniform_real_distribution<double> along(0.0, 1.0);
    const TilingScheme scheme = TilingScheme::geographic();
    int sampled = 0;
    double largestJump = 0.0;
    // Edge points of the tiles around the view's centre, on each side of the edge.
    for (std::uint32_t level = 6; level <= 12; ++level) {
        const TileKey centre = *scheme.tileAt(Geodetic2D::fromDegrees(10.05, 46.1), level);
        const GeodeticExtent extent = scheme.tileExtent(centre);
        for (int k = 0; k < 200; ++k) {
            const double t = along(random);
            const double epsilon = 1e-10;
            const std::array<std::pair<Geodetic2D, Geodetic2D>, 2> pairs{{
                {{extent.east - epsilon, extent.south + t * extent.height()},
                 {extent.east + epsilon, extent.south + t * extent.height()}},
                {{extent.west + t * extent.width(), extent.north - epsilon},
                 {extent.west + t * extent.width(), extent.north + epsilon}},
            }};
            for (const auto& [inside, outside] : pairs) {
                const std::optional<double> a = terrain.globe->heightAt(inside);
                const std::optional<double> b = terrain.globe->heightAt(outside);
                if (a && b) {
                    ++sampled;
                    largestJump = std::max(largestJump, std::abs(*a - *b));
                }
            }
        }
    }
    CHECK(sampled > 1000);
    CHECK(largestJump < 0.01);
}

TEST_CASE("The triangles drawn lie inside the drawn tiles' bounding boxes, the boxes the frustum culls",
          "[scene][tiles][terrain][gl]")
{
    TerrainScene terrain(syntheticTerrain(ridges, 37.0), 3.0);
    terrain.look(Geodetic3D::fromDegrees(10.0, 46.0, 20000.0), 30.0, -20.0);
    REQUIRE(terrain.converge(160, 120).statistics.tiles->converged);
    const std::vector<TiledGlobe::DrawnTile> tiles = terrain.globe->drawnTiles();
    const std::vector<glm::dvec3> triangles = terrain.globe->drawnTriangles();
    REQUIRE(tiles.size() > 10);
    std::size_t outside = 0;
    for (std::size_t i = 0; i < triangles.size(); i += 5) {
        // In box coordinates (-1..1 on each half-axis) of some drawn tile, within a millimetre.
        const bool inside = std::any_of(tiles.begin(), tiles.end(), [&](const TiledGlobe::DrawnTile& tile) {
            const OrientedBoundingBox& box = tile.region.orientedBox();
            const glm::dvec3 local = glm::inverse(box.halfAxes) * (triangles[i] - box.centre);
            const glm::dvec3 slack = 1e-3 / glm::dvec3(glm::length(box.halfAxes[0]), glm::length(box.halfAxes[1]),
                                                       glm::length(box.halfAxes[2]));
            return glm::all(glm::lessThanEqual(glm::abs(local), glm::dvec3(1.0) + slack));
        });
        outside += inside ? 0 : 1;
    }
    CHECK(outside == 0);
}

TEST_CASE("The surface drawn over terrain shares every inner edge between two triangles", "[scene][tiles][terrain][gl]")
{
    TerrainScene terrain(syntheticTerrain(ridges, 37.0));
    terrain.look(Geodetic3D::fromDegrees(10.0, 46.0, 20000.0), 0.0, -35.0);
    REQUIRE(terrain.converge(256, 256).statistics.tiles->converged);

    const OpenEdges open = openEdges(*terrain.globe);
    CHECK(open.sharedByMore == 0);
    CHECK(open.border > 0);
    CHECK(open.cracks == 0);
}

TEST_CASE("Morphing over frames: a tile starts on the surface drawn before it, its parent's or its children's, and reaches its own, with no crack",
          "[scene][tiles][terrain][gl]")
{
    // The eye drops from 60 km to 9 km and stays, then rises back: every change of the drawn
    // surface after each move is the levels refining or coarsening. Levels that disagree by 37 m
    // each make a pop plain.
    struct Phase {
        double largestHeightStep = 0.0; ///< metres, at any probe, from one frame to the next
        double largestImageStep = 0.0;  ///< mean absolute difference of the colour, 0..1
        int framesMorphing = 0;
        int cracks = 0;
        int holes = 0;
        std::vector<std::optional<double>> heights; ///< at the probes, converged
        Image image;                                ///< converged
    };
    std::vector<Geodetic2D> probes;
    for (int row = 0; row < 15; ++row) {
        for (int column = 0; column < 15; ++column) {
            probes.push_back(Geodetic2D::fromDegrees(9.93 + 0.01 * column, 46.0 + 0.008 * row));
        }
    }
    const auto run = [&](int morphFrames, bool skirts) {
        // Coloured by height: a pop shows as a step of colour.
        TerrainScene terrain(syntheticTerrain(ridges, 37.0), 1.0, [&](TiledGlobeOptions& options) {
            options.morphFrames = morphFrames;
            options.skirts = skirts;
            options.shading.color = TerrainShading::Color::Height;
            options.shading.minimumHeight = 0.0;
            options.shading.maximumHeight = 3000.0;
        });
        terrain.look(Geodetic3D::fromDegrees(10.0, 45.75, 60000.0), 0.0, -35.0);
        REQUIRE(terrain.converge(160, 120).statistics.tiles->converged);
        // The heights' steps count from the view before the move; the image's from the first frame
        // after it, the camera being still from then on.
        std::vector<std::optional<double>> before(probes.size());
        for (std::size_t p = 0; p < probes.size(); ++p) {
            before[p] = terrain.globe->heightAt(probes[p]);
        }
        const auto watch = [&](const Geodetic3D& eye) {
            terrain.look(eye, 0.0, -35.0);
            Phase phase;
            Image previous;
            for (int frame = 0; frame < 200; ++frame) {
                const RenderedFrame rendered = renderFrame(terrain.scene, 160, 120);
                const TileStatistics& tiles = *rendered.statistics.tiles;
                std::vector<std::optional<double>> heights;
                for (const Geodetic2D& probe : probes) {
                    heights.push_back(terrain.globe->heightAt(probe));
                }
                for (std::size_t p = 0; p < probes.size(); ++p) {
                    if (heights[p] && before[p]) {
                        phase.largestHeightStep = std::max(phase.largestHeightStep, std::abs(*heights[p] - *before[p]));
                    }
                }
                if (frame > 0) {
                    double difference = 0.0;
                    for (int y = 0; y < 120; ++y) {
                        for (int x = 0; x < 160; ++x) {
                            for (int c = 0; c < 3; ++c) {
                                difference += std::abs(int(rendered.image.pixel(x, y)[c]) - int(previous.pixel(x, y)[c]));
                            }
                        }
                    }
                    phase.largestImageStep = std::max(phase.largestImageStep, difference / (3.0 * 160.0 * 120.0 * 255.0));
                }
                phase.framesMorphing += tiles.morphing > 0;
                phase.cracks += openEdges(*terrain.globe).cracks;
                phase.holes += magentaBelowSky(rendered.image, 40);
                before = heights;
                previous = rendered.image;
                if (tiles.converged) {
                    phase.heights = heights;
                    phase.image = rendered.image;
                    break;
                }
            }
            REQUIRE_FALSE(phase.heights.empty());
            return phase;
        };
        const Phase down = watch(Geodetic3D::fromDegrees(10.0, 45.95, 9000.0));
        const Phase up = watch(Geodetic3D::fromDegrees(10.0, 45.75, 60000.0));
        return std::pair{down, up};
    };
    const auto [poppingDown, poppingUp] = run(0, false);
    const auto [morphingDown, morphingUp] = run(8, false);
    // With skirts, which hang from the edges as drawn: the same surface, no hole either.
    const auto [skirtedDown, skirtedUp] = run(8, true);
    for (const auto* skirted : {&skirtedDown, &skirtedUp}) {
        CHECK(skirted->framesMorphing >= 8);
        CHECK(skirted->cracks == 0);
        CHECK(skirted->holes == 0);
    }
    CHECK(skirtedDown.heights == morphingDown.heights);
    CHECK(skirtedUp.heights == morphingUp.heights);
    for (const auto& [name, popping, morphing] : {std::tuple{"down", &poppingDown, &morphingDown},
                                                  std::tuple{"up", &poppingUp, &morphingUp}}) {
        INFO(name << ": popping " << popping->largestHeightStep << " m, image " << popping->largestImageStep
                  << "; morphing " << morphing->largestHeightStep << " m, image " << morphing->largestImageStep << ", "
                  << morphing->framesMorphing << " frames morphing");
        CHECK(popping->framesMorphing == 0);
        CHECK(morphing->framesMorphing >= 8);
        // A pop moves the surface by the levels' difference at once; a morph by an eighth of it
        // a frame (rising, the detail the coarser tiles lack still goes at once).
        const bool down = name == std::string("down");
        CHECK(popping->largestHeightStep > 100.0);
        CHECK(morphing->largestHeightStep < popping->largestHeightStep / (down ? 4.0 : 2.0));
        if (down) { // rising, every tile changes with the camera's move: the image cannot tell
            CHECK(morphing->largestImageStep < popping->largestImageStep / 3.0);
        }
        // Watertight on every frame of both, and the same surface at the end.
        CHECK(popping->cracks == 0);
        CHECK(morphing->cracks == 0);
        CHECK(popping->holes == 0);
        CHECK(morphing->holes == 0);
        CHECK(morphing->heights == popping->heights);
        CHECK(morphing->image.pixels == popping->image.pixels);
    }
}

TEST_CASE("A scene file's morphFrames makes its terrain morph: counted in the statistics, the converged view unchanged",
          "[scene][tiles][terrain][scenefile][gl]")
{
    const auto render = [](const std::string& morphKey) {
        const std::string text = R"({"version": 2, "camera": {"position": {"lon": 86.9, "lat": 27.0, "height": 300000},
            "heading": 0, "pitch": -30}, "globe": {"terrain": {"source": "../terrain/etopo5", "exaggeration": 10)" +
                                 morphKey + "}}}";
        Scene scene(kEarth);
        populateScene(world::parseSceneText(text, "morph.json", ORBIS_SOURCE_DIR "/data/scenes"), scene);
        std::shared_ptr<TiledGlobe> globe;
        for (const auto& primitive : scene.primitives()) {
            globe = globe ? globe : std::dynamic_pointer_cast<TiledGlobe>(primitive);
        }
        REQUIRE(globe);
        int framesMorphing = 0;
        for (int frame = 0; frame < 400; ++frame) {
            RenderedFrame rendered = renderFrame(scene, 160, 90);
            framesMorphing += rendered.statistics.tiles->morphing > 0;
            if (rendered.statistics.tiles->converged) {
                return std::tuple{globe->options().morphFrames, framesMorphing, std::move(rendered.image)};
            }
        }
        FAIL("not converged");
        return std::tuple{0, 0, Image{}};
    };
    const auto [noFrames, noneMorphing, popped] = render("");
    const auto [frames, framesMorphing, morphed] = render(R"(, "morphFrames": 6)");
    CHECK(noFrames == 0);
    CHECK(noneMorphing == 0);
    CHECK(frames == 6);
    CHECK(framesMorphing >= 6);
    CHECK(morphed.pixels == popped.pixels);
}

TEST_CASE("heightAt gives the terrain's height on the drawn triangles, at edges and corners too", "[scene][tiles][terrain][gl]")
{
    // A plane in longitude and latitude: the triangles' interpolation is then exact, so any
    // difference is an error of the lookup, the stitching or the exaggeration.
    auto plane = [](double longitude, double latitude) { return 800.0 + 40.0 * longitude - 25.0 * latitude; };
    TerrainScene terrain(syntheticTerrain(plane, 0.0), 2.5);
    terrain.look(Geodetic3D::fromDegrees(10.0, 46.0, 30000.0), 0.0, -60.0);
    REQUIRE(terrain.converge(256, 256).statistics.tiles->converged);

    const TilingScheme scheme = TilingScheme::geographic();
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int answered = 0;
    double largestError = 0.0;
    for (int k = 0; k < 20000; ++k) {
        // Points of the drawn tiles around the view's centre, a quarter on edges or corners.
        const std::uint32_t level = 10 + static_cast<std::uint32_t>(k % 4);
        const TileKey key = *scheme.tileAt(
            Geodetic2D::fromDegrees(10.0 + 0.1 * (unit(random) - 0.5), 46.15 + 0.05 * (unit(random) - 0.5)), level);
        const GeodeticExtent extent = scheme.tileExtent(key);
        double u = unit(random);
        double v = unit(random);
        if (k % 4 == 0) {
            u = std::round(u);
        }
        if (k % 8 == 0) {
            v = std::round(v);
        }
        const Geodetic2D point{extent.west + u * extent.width(), extent.south + v * extent.height()};
        const std::optional<double> height = terrain.globe->heightAt(point);
        REQUIRE(height.has_value());
        ++answered;
        const double expected = plane(toDegrees(point.longitude), toDegrees(point.latitude));
        largestError = std::max(largestError, std::abs(*height - expected));
    }
    CHECK(answered == 20000);
    // Heights travel as floats (2,000 m x 2.5: a few millimetres).
    CHECK(largestError < 0.01);
}

TEST_CASE("Terrain shades the tiles by their own normals and a globe without terrain pays nothing for it",
          "[scene][tiles][terrain][gl]")
{
    TerrainScene flat(syntheticTerrain([](double, double) { return 0.0; }, 0.0));
    TerrainScene hills(syntheticTerrain(ridges, 0.0), 3.0);
    for (TerrainScene* terrain : {&flat, &hills}) {
        terrain->look(Geodetic3D::fromDegrees(10.0, 46.0, 60000.0), 0.0, -50.0);
        terrain->scene.setSunDirection(glm::normalize(kEarth.geodeticSurfaceNormal(Geodetic3D::fromDegrees(75.0, 46.0, 0.0))));
    }
    const Image flatImage = flat.converge(128, 128).image;
    const Image hillImage = hills.converge(128, 128).image;
    // Flat terrain is lit like the ellipsoid: smooth; the ridges make light and shadow under a
    // Sun low in the east.
    auto spread = [](const Image& image) { return greenSpread(image, 0, 64, image.width, image.height); };
    INFO("green spread over the lower half: flat " << spread(flatImage) << ", ridges " << spread(hillImage));
    CHECK(spread(flatImage) < 12);
    CHECK(spread(hillImage) > 15); // 20 on llvmpipe, lit in linear space (the flat terrain: 1)

    TiledGlobeOptions options;
    options.loader.workerThreads = 0;
    Scene plain(kEarth);
    plain.add(std::make_shared<TiledGlobe>(kEarth, options));
    const RenderedFrame frame = renderFrame(plain, 64, 64);
    CHECK_FALSE(hasEffect(frame.statistics.effects, Effect::Terrain));
}

namespace {

/// A terrain source stating a geometric error for every tile of levels up to `level`, as our
/// tiler's layer.json does, over another source's tiles.
class StatedErrorSource final : public world::TerrainSource {
public:
    StatedErrorSource(std::shared_ptr<world::TerrainSource> tiles, std::uint32_t level, double error)
        : _tiles(std::move(tiles)), _level(level), _error(error)
    {
    }
    const world::TerrainSourceInfo& info() const noexcept override { return _tiles->info(); }
    world::TerrainFetch load(const TileKey& key) override { return _tiles->load(key); }
    bool hasTile(const TileKey& key) const override { return _tiles->hasTile(key); }
    std::optional<double> geometricError(const TileKey& key) const override
    {
        return key.level <= _level ? std::optional<double>(_error) : std::nullopt;
    }

private:
    std::shared_ptr<world::TerrainSource> _tiles;
    std::uint32_t _level;
    double _error;
};

} // namespace

TEST_CASE("A tile whose data states a larger geometric error than its level's estimate is refined for it",
          "[scene][tiles][terrain][gl]")
{
    const auto levelsDrawn = [](std::shared_ptr<world::TerrainSource> source, double exaggeration) {
        TerrainScene terrain(std::move(source), exaggeration);
        terrain.look(Geodetic3D::fromDegrees(10.0, 46.0, 3.0e6), 0.0, -90.0);
        const RenderedFrame frame = terrain.converge(128, 128);
        REQUIRE(frame.statistics.tiles->converged);
        return frame.statistics.tiles->deepestLevelDrawn;
    };
    const auto ridgesTerrain = [] { return syntheticTerrain(ridges, 0.0); };
    const std::uint32_t estimated = levelsDrawn(ridgesTerrain(), 1.0);
    REQUIRE(estimated < 7);
    // 2,000 km stated for every tile down to level 6: from 3,000 km up every one of them is
    // refined, however small its level's estimate; smaller stated errors change nothing.
    CHECK(levelsDrawn(std::make_shared<StatedErrorSource>(ridgesTerrain(), 6, 2.0e6), 1.0) == 7);
    CHECK(levelsDrawn(std::make_shared<StatedErrorSource>(ridgesTerrain(), 6, 1.0e4), 1.0) == estimated);
    // The stated error is in the data's metres: the exaggeration scales it (10 km is 0.4 px a
    // tile from 3,000 km up, ten times exaggerated 4 px).
    REQUIRE(levelsDrawn(ridgesTerrain(), 10.0) < 7);
    CHECK(levelsDrawn(std::make_shared<StatedErrorSource>(ridgesTerrain(), 6, 1.0e4), 10.0) == 7);
}

TEST_CASE("The exaggeration changes at run time: tiles rebuilt at once, bounds following, no crack", "[scene][tiles][terrain][gl]")
{
    // Levels that agree: the next frame may pick other levels (the bounds grew), which then
    // differ only by the interpolation between their samples.
    TerrainScene terrain(syntheticTerrain(ridges, 0.0));
    terrain.look(Geodetic3D::fromDegrees(10.0, 46.0, 30000.0), 0.0, -30.0);
    REQUIRE(terrain.converge(256, 192).statistics.tiles->converged);
    const Geodetic2D probe = Geodetic2D::fromDegrees(10.0, 46.2);
    const std::optional<double> before = terrain.globe->heightAt(probe);
    REQUIRE(before);
    // The drawn surface's height at the probe, from the triangles the GPU gets.
    auto drawnHeightNear = [&] {
        double nearest = 1e300;
        double height = 0.0;
        const glm::dvec3 target = kEarth.toCartesian(Geodetic3D(probe.longitude, probe.latitude, 0.0));
        for (const glm::dvec3& point : terrain.globe->drawnTriangles()) {
            const double distance = glm::distance(kEarth.scaleToGeodeticSurface(point), target);
            if (distance < nearest) {
                nearest = distance;
                height = kEarth.toGeodetic3D(point).height;
            }
        }
        return height;
    };
    const double drawnBefore = drawnHeightNear();

    terrain.globe->setTerrainExaggeration(3.0);
    // At once: the tiles drawn are rebuilt three times as high, the terrain's height the same.
    REQUIRE(terrain.globe->heightAt(probe));
    CHECK(std::abs(*terrain.globe->heightAt(probe) - *before) < 0.01);
    CHECK(std::abs(drawnHeightNear() - 3.0 * drawnBefore) < 0.05);
    // The next frame may want finer tiles near the eye (the bounds grew): what stands in for
    // them covers the view.
    CHECK(magentaBelowSky(renderFrame(terrain.scene, 256, 192).image, 60) == 0);
    REQUIRE(terrain.converge(256, 192).statistics.tiles->converged);
    CHECK(std::abs(*terrain.globe->heightAt(probe) - *before) < 5.0);

    // From 0 the tiles have no heights to scale: they load again, with the heights.
    terrain.globe->setTerrainExaggeration(0.0);
    REQUIRE(terrain.converge(256, 192).statistics.tiles->converged);
    CHECK(std::abs(drawnHeightNear()) < 0.01);
    terrain.globe->setTerrainExaggeration(2.0);
    const RenderedFrame reloaded = terrain.converge(256, 192);
    REQUIRE(reloaded.statistics.tiles->converged);
    CHECK(magentaBelowSky(reloaded.image, 60) == 0);
    CHECK(std::abs(*terrain.globe->heightAt(probe) - *before) < 5.0);
    CHECK_THROWS_AS(terrain.globe->setTerrainExaggeration(-1.0), Error);
}

TEST_CASE("Meshes kept for stitching do not count as uploads waiting: a small upload budget still converges",
          "[scene][tiles][terrain][gl]")
{
    TiledGlobeOptions options;
    options.terrain = syntheticTerrain(ridges, 0.0);
    options.loader.workerThreads = 0;
    options.loader.latencyFrames = 0;
    // Four frames of this budget are less than the meshes the view keeps: loads must go on anyway.
    options.uploadBytesPerFrame = 256 * 1024;
    Scene scene(kEarth);
    auto globe = std::make_shared<TiledGlobe>(kEarth, options);
    scene.add(globe);
    const glm::dvec3 eye = kEarth.toCartesian(Geodetic3D::fromDegrees(10.0, 46.0, 9000.0));
    const ViewOrientation view = headingPitchRollToView(kEarth, eye, toRadians(30.0), toRadians(-20.0), 0.0);
    scene.camera().lookAt(eye, eye + view.direction * glm::length(eye), view.up);
    TileStatistics tiles;
    for (int frame = 0; frame < 400 && !tiles.converged; ++frame) {
        tiles = *renderFrame(scene, 160, 120).statistics.tiles;
    }
    CHECK(tiles.converged);
    CHECK(tiles.drawn > 10);
    CHECK(tiles.residentBytesCpu > 4 * options.uploadBytesPerFrame);
}

namespace {

/// Metres per degree of longitude on the ellipsoid at 45 degrees of latitude.
double metresPerDegreeAt45()
{
    const glm::dvec3 a = kEarth.toCartesian(Geodetic3D::fromDegrees(10.0, 45.0, 0.0));
    const glm::dvec3 b = kEarth.toCartesian(Geodetic3D::fromDegrees(10.001, 45.0, 0.0));
    return glm::length(b - a) / 0.001;
}

/// Heights rising eastwards at `degrees` of slope, 0 m on the meridian of 10 degrees east.
double slopeHeight(double longitudeDegrees, double degrees)
{
    return std::tan(toRadians(degrees)) * metresPerDegreeAt45() * (longitudeDegrees - 10.0);
}

/// The centre pixel of a view straight down on (10, 45) from 60 km, shaded without the Sun.
glm::dvec3 shadedCentre(std::function<double(double, double)> height, const std::function<void(TerrainShading&)>& shade)
{
    TerrainScene terrain(syntheticTerrain(std::move(height), 0.0), 1.0, [&](TiledGlobeOptions& options) {
        options.lighting = false;
        options.baseColor = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
        shade(options.shading);
    });
    terrain.look(Geodetic3D::fromDegrees(10.0, 45.0, 60000.0), 0.0, -90.0);
    const RenderedFrame frame = terrain.converge(64, 64);
    REQUIRE(frame.statistics.tiles->converged);
    CHECK(hasEffect(frame.statistics.effects, Effect::TerrainShading));
    const std::uint8_t* p = frame.image.pixel(32, 32);
    return glm::dvec3(p[0], p[1], p[2]) / 255.0;
}

} // namespace

TEST_CASE("Terrain shading colours by height and by slope as its ramps state", "[scene][tiles][terrain][gl]")
{
    // 1,500 m at the centre, in [0, 3,000] m: 4/7 of the way from the ramp's yellow to its brown.
    const glm::dvec3 height = shadedCentre([](double longitude, double) { return 1500.0 + 500.0 * (longitude - 10.0); },
                                           [](TerrainShading& shading) {
                                               shading.color = TerrainShading::Color::Height;
                                               shading.minimumHeight = 0.0;
                                               shading.maximumHeight = 3000.0;
                                           });
    const glm::dvec3 expectedHeight = glm::mix(glm::dvec3(0.85, 0.8, 0.45), glm::dvec3(0.5, 0.36, 0.22), 0.2 / 0.35);
    CHECK(glm::length(height - expectedHeight) < 0.015);

    // A 30 degree slope is the ramp's orange, half way from pale (0 degrees) to red (60).
    const glm::dvec3 slope = shadedCentre([](double longitude, double) { return slopeHeight(longitude, 30.0); },
                                          [](TerrainShading& shading) { shading.color = TerrainShading::Color::Slope; });
    CHECK(glm::length(slope - glm::dvec3(0.95, 0.6, 0.1)) < 0.03);
}

TEST_CASE("The hillshade darkens slopes facing away from its light and brightens those facing it",
          "[scene][tiles][terrain][gl]")
{
    // The slope rises eastwards: its normal leans 30 degrees to the west. A light 30 degrees up in
    // the east grazes it (0.3 of the colour); from the west it meets it at 30 degrees from the
    // normal (0.3 + 0.7 cos 30 / sin 30 = 1.51 of the colour).
    const auto rising = [](double longitude, double) { return slopeHeight(longitude, 30.0); };
    const auto lit = [&](double azimuth) {
        return shadedCentre(rising, [=](TerrainShading& shading) {
            shading.hillshade = true;
            shading.hillshadeAzimuth = azimuth;
            shading.hillshadeAltitude = 30.0;
        });
    };
    CHECK(std::abs(lit(90.0).g - 0.5 * 0.3) < 0.02);
    CHECK(std::abs(lit(270.0).g - 0.5 * (0.3 + 0.7 * std::cos(toRadians(30.0)) / 0.5)) < 0.02);
    // Flat ground keeps its colour under any light.
    const glm::dvec3 flat =
        shadedCentre([](double, double) { return 800.0; }, [](TerrainShading& shading) { shading.hillshade = true; });
    CHECK(std::abs(flat.g - 0.5) < 0.01);
}

namespace {

/// Another source's tiles with a water mask (quantized-mesh's extension) that is water west of a
/// meridian: one value for a tile wholly on one side, else 256 x 256 rows from the north.
class WestIsWaterSource final : public world::TerrainSource {
public:
    WestIsWaterSource(std::shared_ptr<world::TerrainSource> tiles, double coastDegrees)
        : _tiles(std::move(tiles)), _coast(toRadians(coastDegrees))
    {
    }
    const world::TerrainSourceInfo& info() const noexcept override { return _tiles->info(); }
    bool hasTile(const TileKey& key) const override { return _tiles->hasTile(key); }
    world::TerrainFetch load(const TileKey& key) override
    {
        world::TerrainFetch fetched = _tiles->load(key);
        const GeodeticExtent extent = TilingScheme::geographic().tileExtent(key);
        if (extent.east <= _coast || extent.west >= _coast) {
            fetched.tile.waterMask = {static_cast<std::uint8_t>(extent.east <= _coast ? 255 : 0)};
            fetched.tile.waterMaskSize = 1;
            return fetched;
        }
        constexpr int size = 256;
        fetched.tile.waterMaskSize = size;
        fetched.tile.waterMask.resize(size * size);
        for (int row = 0; row < size; ++row) {
            for (int column = 0; column < size; ++column) {
                const double longitude = extent.west + (column + 0.5) / size * (extent.east - extent.west);
                fetched.tile.waterMask[static_cast<std::size_t>(row * size + column)] = longitude < _coast ? 255 : 0;
            }
        }
        return fetched;
    }

private:
    std::shared_ptr<world::TerrainSource> _tiles;
    double _coast;
};

} // namespace

TEST_CASE("The water mask makes water level and mirror the Sun, and leaves the land as it was",
          "[scene][tiles][terrain][gl]")
{
    // A sea floor of ridges, water west of 10 degrees east. The Sun is placed where the eye sees
    // its reflection at a point of the sea; a point of land as near the glint stays as it was.
    const auto terrain = [] { return std::make_shared<WestIsWaterSource>(syntheticTerrain(ridges, 0.0), 10.0); };
    const Geodetic3D eye = Geodetic3D::fromDegrees(10.0, 45.8, 60000.0);
    const glm::dvec3 sea = kEarth.toCartesian(Geodetic3D::fromDegrees(9.8, 46.3, 0.0));
    const glm::dvec3 land = kEarth.toCartesian(Geodetic3D::fromDegrees(10.2, 46.3, 0.0));
    const glm::dvec3 toEye = glm::normalize(kEarth.toCartesian(eye) - sea);
    const glm::dvec3 up = kEarth.geodeticSurfaceNormal(sea);
    const glm::dvec3 sun = 2.0 * glm::dot(toEye, up) * up - toEye; // toEye mirrored about the level sea

    auto render = [&](bool water) {
        TerrainScene scene(terrain(), 1.0, [&](TiledGlobeOptions& options) { options.water = water; });
        scene.look(eye, 0.0, -45.0);
        scene.scene.setSunDirection(glm::vec3(sun));
        return scene.converge(160, 120);
    };
    const RenderedFrame dry = render(false);
    const RenderedFrame wet = render(true);
    CHECK_FALSE(hasEffect(dry.statistics.effects, Effect::Water));
    CHECK(hasEffect(wet.statistics.effects, Effect::Water));

    Scene camera(kEarth); // only for its camera: the pixels of the two points
    placeCamera(camera, eye, 0.0, -45.0);
    const glm::ivec2 seaPixel = projectToPixel(camera, sea, 160, 120);
    const glm::ivec2 landPixel = projectToPixel(camera, land, 160, 120);
    auto at = [](const RenderedFrame& frame, glm::ivec2 pixel) {
        const std::uint8_t* p = frame.image.pixel(pixel.x, pixel.y);
        return glm::ivec3(p[0], p[1], p[2]);
    };
    INFO("sea " << seaPixel.x << "," << seaPixel.y << ": dry " << at(dry, seaPixel).g << ", wet " << at(wet, seaPixel).g
                << "; land " << landPixel.x << "," << landPixel.y << ": dry " << at(dry, landPixel).g << ", wet "
                << at(wet, landPixel).g);
    // The glint: the Sun's reflection adds 0.8 of white in linear light.
    CHECK(glm::all(glm::greaterThan(at(wet, seaPixel), at(dry, seaPixel) + 60)));
    CHECK(at(wet, landPixel) == at(dry, landPixel));

    // Under a low Sun in the east, far from any glint, the ridges under the sea cast light and
    // shade without the mask and none with it: the sea is lit as level ground. The lower left of
    // the view is all sea (the coast is the meridian the eye looks north along).
    auto spreadWestOfCoast = [&](bool water) {
        TerrainScene scene(terrain(), 3.0, [&](TiledGlobeOptions& options) { options.water = water; });
        scene.look(eye, 0.0, -45.0);
        scene.scene.setSunDirection(
            glm::vec3(glm::normalize(up * std::sin(toRadians(15.0)) +
                                     glm::normalize(glm::cross(glm::dvec3(0.0, 0.0, 1.0), up)) * std::cos(toRadians(15.0)))));
        return greenSpread(scene.converge(160, 120).image, 0, 60, 70, 120);
    };
    const int drySpread = spreadWestOfCoast(false);
    const int wetSpread = spreadWestOfCoast(true);
    INFO("green spread west of the coast: without the mask " << drySpread << ", with it " << wetSpread);
    CHECK(drySpread > 15);
    CHECK(wetSpread < 8);
}

TEST_CASE("Contour lines lie on the heights that are multiples of their interval, and nowhere else",
          "[scene][tiles][terrain][gl]")
{
    // 500 m a degree eastwards: a line every 0.2 degrees of longitude, running north-south.
    const auto height = [](double longitude, double) { return 1500.0 + 500.0 * (longitude - 10.0); };
    TerrainScene terrain(syntheticTerrain(height, 0.0), 1.0, [](TiledGlobeOptions& options) {
        options.lighting = false;
        options.shading.contourInterval = 100.0;
        options.shading.contourColor = glm::vec3(1.0f, 0.0f, 0.0f);
        options.shading.contourWidth = 2.0;
    });
    terrain.look(Geodetic3D::fromDegrees(10.0, 45.0, 120000.0), 0.0, -90.0);
    const int size = 128;
    const RenderedFrame frame = terrain.converge(size, size);
    REQUIRE(frame.statistics.tiles->converged);
    const auto isLine = [](const std::uint8_t* p) { return p[0] > 200 && p[1] < 100; };
    int lines = 0;
    for (int k = -5; k <= 5; ++k) {
        const double longitude = 10.0 + 0.2 * k;
        const glm::ivec2 onLine = projectToPixel(
            terrain.scene, kEarth.toCartesian(Geodetic3D::fromDegrees(longitude, 45.0, height(longitude, 45.0))), size, size);
        const glm::ivec2 between = projectToPixel(
            terrain.scene,
            kEarth.toCartesian(Geodetic3D::fromDegrees(longitude + 0.1, 45.0, height(longitude + 0.1, 45.0))), size, size);
        if (onLine.x < 1 || onLine.x >= size - 1 || between.x < 0 || between.x >= size) {
            continue;
        }
        ++lines;
        INFO("contour at " << longitude << " degrees, pixel " << onLine.x);
        CHECK(isLine(frame.image.pixel(onLine.x, onLine.y)));
        CHECK_FALSE(isLine(frame.image.pixel(between.x, between.y)));
    }
    CHECK(lines >= 4);
    // Everywhere else the base colour: the lines are thin.
    int linePixels = 0;
    for (int x = 0; x < size; ++x) {
        linePixels += isLine(frame.image.pixel(x, size / 2));
    }
    CHECK(linePixels <= 3 * lines + 2);

    // Without shading options the effect is absent and no shading uniform is set.
    TerrainScene plain(syntheticTerrain(height, 0.0));
    plain.look(Geodetic3D::fromDegrees(10.0, 45.0, 60000.0), 0.0, -90.0);
    CHECK_FALSE(hasEffect(plain.converge(32, 32).statistics.effects, Effect::TerrainShading));
}

TEST_CASE("Layers stand on the terrain: clampToGround and relativeToGround for points, polylines, GeoJSON and models",
          "[scene][terrain][scenefile]")
{
    // The layers' ground is the terrain's, whichever way the globe draws it.
    const std::string method = GENERATE(std::string("quadtree"), std::string("clipmap"));
    INFO("terrain method " << method);
    const TempDirectory directory;
    directory.write("peaks.csv", "name,lon,lat,height\nA,-84.30,36.55,5000\nB,-84.20,36.62,5000\n");
    directory.write("area.geojson", R"({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"name": "area"}, "geometry": {"type": "Polygon",
         "coordinates": [[[-84.30, 36.53], [-84.20, 36.55], [-84.22, 36.63], [-84.31, 36.60], [-84.30, 36.53]]]}},
        {"type": "Feature", "properties": {}, "geometry": {"type": "LineString",
         "coordinates": [[-84.34, 36.52, 900], [-84.16, 36.64, 900]]}}]})");
    const std::string dem = dataPath("terrain/cumberland/jacksboro_fault.vrt");
    const std::string model = dataPath("models/aircraft.glb");
    const std::filesystem::path file = directory.write("scene.json", R"({"version": 2,
        "globe": {"terrain": {"source": ")" + dem + R"(", "exaggeration": 2, "method": ")" + method + R"("}},
        "layers": [
          {"type": "points", "source": "peaks.csv", "heightReference": "clampToGround", "label": {"field": "name"}},
          {"type": "polyline", "positions": [[-84.35, 36.5], [-84.15, 36.65]], "granularity": 0.1,
           "heightReference": "clampToGround"},
          {"type": "polyline", "positions": [[-84.35, 36.5, 300], [-84.15, 36.65, 300]], "granularity": 0.1},
          {"type": "model", "source": ")" + model + R"(", "position": {"lon": -84.25, "lat": 36.6, "height": 100},
           "heightReference": "relativeToGround"},
          {"type": "geojson", "source": "area.geojson", "fill": {"color": "#ff000080"}, "stroke": {"color": "#ffff00"},
           "granularity": 0.1, "heightReference": "clampToGround"}]})");
    Scene scene(kEarth);
    populateScene(world::parseSceneFile(file), scene);

    const auto source = world::openTerrainSource(dem);
    world::TerrainHeightQuery query(*source);
    const auto ground = [&](const glm::dvec3& position) {
        const Geodetic3D g = kEarth.toGeodetic3D(position);
        return 2.0 * query.at(Geodetic2D(g.longitude, g.latitude))->height;
    };
    const auto heightOf = [](const glm::dvec3& position) { return kEarth.toGeodetic3D(position).height; };
    const auto& primitives = scene.primitives();
    REQUIRE(primitives.size() == 8); // globe, billboards, labels, two polylines, model, GeoJSON fills and borders

    const auto* billboards = dynamic_cast<const BillboardCollection*>(primitives[1].get());
    const auto* labels = dynamic_cast<const LabelCollection*>(primitives[2].get());
    REQUIRE((billboards && labels));
    REQUIRE(billboards->size() == 2);
    for (std::size_t i = 0; i < 2; ++i) {
        const glm::dvec3 position = billboards->billboard(i).position;
        CHECK(ground(position) > 2.0 * 236.0); // on the DEM, the file's 5000 m ignored
        CHECK(std::abs(heightOf(position) - ground(position)) < 1e-3);
        CHECK(glm::distance(labels->label(i).position, position) < 1e-6);
    }

    // Every drawn vertex of the clamped line on the ground, not only its two ends; the absolute
    // line keeps its 300 m over the ellipsoid.
    const auto* clamped = dynamic_cast<const PolylineCollection*>(primitives[3].get());
    const auto* absolute = dynamic_cast<const PolylineCollection*>(primitives[4].get());
    REQUIRE((clamped && absolute));
    const std::span<const glm::dvec3> drawn = clamped->positions(0);
    REQUIRE(drawn.size() > 20);
    double spread = 0.0;
    for (const glm::dvec3& position : drawn) {
        CHECK(std::abs(heightOf(position) - clamped->liftMeters(0) - ground(position)) < 1e-3);
        spread = std::max(spread, std::abs(ground(position) - ground(drawn.front())));
    }
    CHECK(spread > 100.0); // the ground it follows is not flat
    for (const glm::dvec3& position : absolute->positions(0)) {
        CHECK(std::abs(heightOf(position) - absolute->liftMeters(0) - 300.0) < 1e-3);
    }

    const auto* aircraft = dynamic_cast<const ModelPrimitive*>(primitives[5].get());
    REQUIRE(aircraft);
    const Geodetic3D placed = aircraft->placement().position;
    CHECK(std::abs(placed.height - (100.0 + ground(kEarth.toCartesian(Geodetic3D(placed.longitude, placed.latitude, 0.0))))) < 1e-3);

    // The GeoJSON layer's lines on the ground as the polyline layer's are (the LineString's 900 m
    // dropped), every drawn vertex; its fill draped: a volume from below to above the ground under it.
    const auto* fills = dynamic_cast<const PolygonCollection*>(primitives[6].get());
    const auto* borders = dynamic_cast<const PolylineCollection*>(primitives[7].get());
    REQUIRE((fills && borders));
    REQUIRE(borders->size() == 2); // the ring and the LineString
    for (std::size_t line = 0; line < borders->size(); ++line) {
        REQUIRE(borders->positions(line).size() > 20);
        for (const glm::dvec3& position : borders->positions(line)) {
            CHECK(std::abs(heightOf(position) - borders->liftMeters(line) - ground(position)) < 1e-3);
        }
    }
    REQUIRE(fills->draped());
    REQUIRE(fills->size() == 1);
    // Its volume reaches from below to above the ground drawn under it: once the view over it has
    // converged, every height of the drawn surface over its footprint lies between its bottom and top.
    placeCamera(scene, Geodetic3D::fromDegrees(-84.25, 36.58, 30000.0), 0.0, -90.0);
    bool converged = false;
    for (int frame = 0; frame < 300 && !converged; ++frame) {
        const FrameStatistics statistics = renderFrame(scene, 64, 48).statistics;
        converged = statistics.tiles ? statistics.tiles->converged : statistics.clipmap->converged;
    }
    REQUIRE(converged);
    const std::optional<HeightInterval> volume = fills->drapedHeights(0);
    REQUIRE(volume);
    double lowest = 1e9;
    double highest = -1e9;
    for (double lon = -84.32; lon <= -84.19; lon += 0.001) {
        for (double lat = 36.52; lat <= 36.64; lat += 0.001) {
            const Geodetic2D point = Geodetic2D::fromDegrees(lon, lat);
            if (fills->footprint(0).contains(point)) {
                lowest = std::min(lowest, scene.groundHeight(point));
                highest = std::max(highest, scene.groundHeight(point));
            }
        }
    }
    CHECK(highest - lowest > 200.0); // the ground it covers is far from flat
    CHECK(volume->lowest < lowest);
    CHECK(volume->highest > highest);

    // Without terrain the same layer lies on the ellipsoid, as it always has: nothing draped.
    const std::filesystem::path flat = directory.write("flat.json", R"({"version": 2, "layers": [
          {"type": "geojson", "source": "area.geojson", "fill": {"color": "#ff000080"}, "heightReference": "clampToGround"}]})");
    Scene plain(kEarth);
    populateScene(world::parseSceneFile(flat), plain);
    REQUIRE(plain.primitives().size() == 1);
    const auto* ellipsoidFills = dynamic_cast<const PolygonCollection*>(plain.primitives()[0].get());
    REQUIRE(ellipsoidFills);
    CHECK_FALSE(ellipsoidFills->draped());
    CHECK(ellipsoidFills->liftMeters(0) >= 0.0);
}

TEST_CASE("relativeToGround fills stand at their heights above the ground, following it; at 0 m they are draped",
          "[scene][terrain][scenefile][polygons]")
{
    const TempDirectory directory;
    // Three polygons: at 0 m (draped), 300 m everywhere, and 200 m rising to 800 m at one corner.
    directory.write("areas.geojson", R"({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"name": "flat"}, "geometry": {"type": "Polygon",
         "coordinates": [[[-84.40, 36.45], [-84.33, 36.45], [-84.33, 36.50], [-84.40, 36.45]]]}},
        {"type": "Feature", "properties": {"name": "level"}, "geometry": {"type": "Polygon",
         "coordinates": [[[-84.30, 36.53, 300], [-84.20, 36.55, 300], [-84.22, 36.63, 300], [-84.30, 36.53, 300]]]}},
        {"type": "Feature", "properties": {"name": "sloping"}, "geometry": {"type": "Polygon",
         "coordinates": [[[-84.18, 36.50, 200], [-84.10, 36.50, 200], [-84.10, 36.58, 800], [-84.18, 36.58, 200],
                          [-84.18, 36.50, 200]]]}}]})");
    const std::string dem = dataPath("terrain/cumberland/jacksboro_fault.vrt");
    const std::filesystem::path file = directory.write("scene.json", R"({"version": 2,
        "globe": {"terrain": {"source": ")" + dem + R"(", "exaggeration": 2}},
        "layers": [{"type": "geojson", "source": "areas.geojson", "fill": {"color": "#ff000080"},
                    "heightReference": "relativeToGround"}]})");
    Scene scene(kEarth);
    populateScene(world::parseSceneFile(file), scene);
    REQUIRE(scene.primitives().size() == 3); // globe, draped fills, raised fills (no stroke: no borders)
    const auto* draped = dynamic_cast<const PolygonCollection*>(scene.primitives()[1].get());
    const auto* raised = dynamic_cast<const PolygonCollection*>(scene.primitives()[2].get());
    REQUIRE((draped && raised));
    CHECK(draped->draped());
    CHECK(draped->size() == 1);
    CHECK_FALSE(raised->draped());
    REQUIRE(raised->size() == 2);

    const auto source = world::openTerrainSource(dem);
    world::TerrainHeightQuery query(*source);
    // Each drawn vertex's height above the ground, less the lift that keeps flat triangles up.
    const auto aboveGround = [&](std::size_t polygon, const glm::dvec3& position) {
        const Geodetic3D g = kEarth.toGeodetic3D(position);
        return g.height - raised->liftMeters(polygon) - 2.0 * query.at(Geodetic2D(g.longitude, g.latitude))->height;
    };
    double lowestGround = 1e9;
    double highestGround = -1e9;
    const std::vector<glm::dvec3>& level = raised->mesh(0).positions;
    REQUIRE(level.size() > 100); // a drawn vertex about every terrain sample
    for (const glm::dvec3& position : level) {
        CHECK(std::abs(aboveGround(0, position) - 300.0) < 1e-3);
        const double ground = kEarth.toGeodetic3D(position).height - raised->liftMeters(0) - 300.0;
        lowestGround = std::min(lowestGround, ground);
        highestGround = std::max(highestGround, ground);
    }
    CHECK(highestGround - lowestGround > 200.0); // it follows ground that is far from flat
    // The sloping one: 200 m at three corners, 800 m at the fourth, linear in between.
    const Geodetic2D high = Geodetic2D::fromDegrees(-84.10, 36.58);
    bool sawHigh = false;
    for (const glm::dvec3& position : raised->mesh(1).positions) {
        const double height = aboveGround(1, position);
        CHECK(height >= 200.0 - 1e-3);
        CHECK(height <= 800.0 + 1e-3);
        const Geodetic3D g = kEarth.toGeodetic3D(position);
        if (std::abs(g.longitude - high.longitude) < 1e-9 && std::abs(g.latitude - high.latitude) < 1e-9) {
            CHECK(std::abs(height - 800.0) < 1e-3);
            sawHigh = true;
        }
    }
    CHECK(sawHigh);
}

namespace {

/// The corners of a convex quadrilateral over the ridges, counter-clockwise seen from above.
const std::array<Geodetic2D, 4> kDrapedCorners = {Geodetic2D::fromDegrees(9.90, 45.93), Geodetic2D::fromDegrees(10.17, 45.97),
                                                  Geodetic2D::fromDegrees(10.12, 46.16), Geodetic2D::fromDegrees(9.94, 46.10)};

world::Polygon drapedQuadrilateral()
{
    world::LinearRing ring;
    for (const Geodetic2D& corner : kDrapedCorners) {
        ring.push_back(Geodetic3D(corner.longitude, corner.latitude, 0.0));
    }
    ring.push_back(ring.front());
    return world::Polygon{{ring}};
}

/// Whether a point's foot on the ellipsoid lies inside the quadrilateral, whose edges are the
/// curves cut by planes through the centre (as PolygonCollection triangulates them).
bool insideDrapedQuadrilateral(const glm::dvec3& point)
{
    const Geodetic3D g = kEarth.toGeodetic3D(point);
    const glm::dvec3 foot = kEarth.toCartesian(Geodetic2D(g.longitude, g.latitude));
    for (std::size_t i = 0; i < kDrapedCorners.size(); ++i) {
        const glm::dvec3 a = kEarth.toCartesian(kDrapedCorners[i]);
        const glm::dvec3 b = kEarth.toCartesian(kDrapedCorners[(i + 1) % kDrapedCorners.size()]);
        if (glm::dot(glm::cross(a, b), foot) <= 0.0) {
            return false;
        }
    }
    return true;
}

/// What a frame shows of the draped quadrilateral, pixel by pixel against the ground picked under
/// each (the surface the frame drew): red expected exactly where that ground is inside, except
/// within a pixel of its outline; blue (the absolute copy at 0 m) nowhere.
struct DrapedCoverage {
    int wrong = 0;         ///< red outside, or not red inside, off the outline
    int blue = 0;
    int insidePixels = 0;
    int outsidePixels = 0;
    double lowest = std::numeric_limits<double>::infinity(); ///< of the ground inside
    double highest = -std::numeric_limits<double>::infinity();
};

DrapedCoverage drapedCoverage(TerrainScene& terrain, const Image& image)
{
    const int width = image.width;
    const int height = image.height;
    const auto isRed = [](const std::uint8_t* p) { return p[0] > 200 && p[1] < 80 && p[2] < 80; };
    const auto isBlue = [](const std::uint8_t* p) { return p[2] > 200 && p[0] < 80 && p[1] < 80; };
    DrapedCoverage coverage;
    // Whether the ground under each pixel's centre is inside; -1 where the pixel sees no ground.
    std::vector<int> expected(static_cast<std::size_t>(width * height), -1);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const std::optional<glm::dvec3> ground = terrain.scene.pickGround({x + 0.5, y + 0.5}, width, height);
            if (!ground) {
                continue;
            }
            const bool inside = insideDrapedQuadrilateral(*ground);
            expected[static_cast<std::size_t>(y * width + x)] = inside ? 1 : 0;
            if (inside) {
                const double groundHeight = kEarth.toGeodetic3D(*ground).height;
                coverage.lowest = std::min(coverage.lowest, groundHeight);
                coverage.highest = std::max(coverage.highest, groundHeight);
            }
        }
    }
    const auto onOutline = [&](int x, int y) {
        const int own = expected[static_cast<std::size_t>(y * width + x)];
        for (int dy = -1; dy <= 1; ++dy) {
            for (int dx = -1; dx <= 1; ++dx) {
                const int nx = std::clamp(x + dx, 0, width - 1);
                const int ny = std::clamp(y + dy, 0, height - 1);
                if (expected[static_cast<std::size_t>(ny * width + nx)] != own) {
                    return true;
                }
            }
        }
        return false;
    };
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const int want = expected[static_cast<std::size_t>(y * width + x)];
            const bool red = isRed(image.pixel(x, y));
            coverage.blue += isBlue(image.pixel(x, y));
            (want == 1 ? coverage.insidePixels : coverage.outsidePixels) += 1;
            if (red != (want == 1) && !onOutline(x, y)) {
                UNSCOPED_INFO("pixel " << x << ", " << y << (red ? " red outside" : " not red inside"));
                ++coverage.wrong;
            }
        }
    }
    return coverage;
}

/// Renders the terrain scene until it converges and checks its drapedCoverage: no pixel wrong,
/// none blue, the ground inside far from flat and above 0 m. Returns the frame.
RenderedFrame checkDrapedCoverage(TerrainScene& terrain, int width, int height)
{
    const RenderedFrame frame = terrain.converge(width, height);
    REQUIRE(frame.statistics.tiles->converged);
    const DrapedCoverage coverage = drapedCoverage(terrain, frame.image);
    CHECK(coverage.wrong == 0);
    CHECK(coverage.blue == 0); // the absolute polygon at 0 m is under the ground everywhere
    CHECK(coverage.insidePixels > width * height / 10);
    CHECK(coverage.outsidePixels > width * height / 10);
    CHECK(coverage.highest - coverage.lowest > 300.0); // the ground it covers is far from flat
    CHECK(coverage.lowest > 0.0);                      // and above the absolute polygon everywhere
    CHECK(hasEffect(frame.statistics.effects, Effect::DrapedPolygons));
    return frame;
}

/// The quadrilateral draped in red over terrain, and the same one in blue at 0 m (absolute).
void addDrapedAndAbsolute(Scene& scene)
{
    PolygonCollectionOptions drape;
    drape.draped = true;
    auto draped = std::make_shared<PolygonCollection>(kEarth, drape);
    draped->add(drapedQuadrilateral(), glm::vec4(1.0f, 0.0f, 0.0f, 1.0f), "draped");
    auto absolute = std::make_shared<PolygonCollection>(kEarth);
    absolute->add(drapedQuadrilateral(), glm::vec4(0.0f, 0.0f, 1.0f, 1.0f), "absolute");
    scene.add(absolute);
    scene.add(draped);
}

} // namespace

TEST_CASE("A draped polygon covers exactly the terrain's pixels inside it, seen from above and obliquely, in any depth strategy",
          "[scene][terrain][polygons][gl]")
{
    TerrainScene terrain(syntheticTerrain(ridges, 0.0));
    const int width = 128;
    const int height = 96;
    // Without draped polygons nothing of them is drawn, or paid for.
    terrain.look(Geodetic3D::fromDegrees(10.03, 45.78, 20000.0), 0.0, -45.0);
    const RenderedFrame plain = terrain.converge(width, height);
    CHECK_FALSE(hasEffect(plain.statistics.effects, Effect::DrapedPolygons));
    addDrapedAndAbsolute(terrain.scene);

    SECTION("from above, Automatic depth (complementary here, with a float depth and stencil buffer of the scene's)")
    {
        terrain.look(Geodetic3D::fromDegrees(10.03, 46.04, 45000.0), 0.0, -90.0);
        checkDrapedCoverage(terrain, width, height);
    }
    SECTION("obliquely, the polygon's volume across several frustums")
    {
        terrain.scene.options().depthStrategy = DepthStrategy::MultiFrustum;
        // Frustum boundaries across the polygon: without depth clamping the faces beyond each
        // frustum's far plane would go uncounted there.
        terrain.scene.options().multiFrustum.farToNearRatio = 1.5;
        terrain.look(Geodetic3D::fromDegrees(10.03, 45.78, 20000.0), 0.0, -45.0);
        const RenderedFrame frame = checkDrapedCoverage(terrain, width, height);
        CHECK(frame.statistics.frustums.size() >= 5);
        CHECK(frame.statistics.commandsExecutedMoreThanOnce > 0);
        // The same view without the polygons: only the two polygons' commands are added (the
        // absolute one's and the draped one's two draws, in each frustum they span).
        CHECK(frame.statistics.commandsSubmitted == plain.statistics.commandsSubmitted + 3);
    }
    SECTION("logarithmic depth")
    {
        terrain.scene.options().depthStrategy = DepthStrategy::Logarithmic;
        terrain.look(Geodetic3D::fromDegrees(10.03, 45.78, 20000.0), 0.0, -45.0);
        checkDrapedCoverage(terrain, width, height);
    }
}

TEST_CASE("A draped polygon covers the ground drawn under it in every frame while tiles stream, coarse levels included",
          "[scene][terrain][polygons][gl]")
{
    // Hills of 300 m, each level 300 m below the one before: the levels drawn while the finer tiles
    // load, and the level the view settles on, stand hundreds of metres to kilometres above the
    // finest level's surface, which a volume sized from the finest heights alone would miss.
    constexpr double kLevelOffset = -300.0;
    const auto hills = [](double longitude, double latitude) { return 0.1 * ridges(longitude, latitude); };
    // A few loads a frame, each a frame late: many frames draw coarser levels over the polygon.
    TerrainScene terrain(syntheticTerrain(hills, kLevelOffset), 1.0, [](TiledGlobeOptions& options) {
        options.loader.latencyFrames = 1;
        options.loader.maximumStartsPerFrame = 4;
    });
    PolygonCollectionOptions drape;
    drape.draped = true;
    auto draped = std::make_shared<PolygonCollection>(kEarth, drape);
    draped->add(drapedQuadrilateral(), glm::vec4(1.0f, 0.0f, 0.0f, 1.0f), "draped");
    terrain.scene.add(draped);
    const int width = 96;
    const int height = 72;
    // Descending from 100 km to 20 km, then waiting for the tiles: every frame draws levels coarser
    // than the view asks for somewhere over the polygon.
    int streamingFrames = 0;
    std::uint32_t deepestFirst = ~0u;
    for (int frame = 0; frame < 100; ++frame) {
        const double descent = std::min(frame, 12) / 12.0;
        terrain.look(Geodetic3D::fromDegrees(10.03, 45.95 - 0.17 * descent, 100000.0 - 80000.0 * descent), 0.0,
                     -90.0 + 45.0 * descent);
        const RenderedFrame rendered = renderFrame(terrain.scene, width, height);
        const TileStatistics& tiles = *rendered.statistics.tiles;
        deepestFirst = std::min(deepestFirst, tiles.deepestLevelDrawn);
        const DrapedCoverage coverage = drapedCoverage(terrain, rendered.image);
        INFO("frame " << frame << ", deepest level drawn " << tiles.deepestLevelDrawn << ", stand-ins " << tiles.standIns);
        CHECK(coverage.wrong == 0);
        CHECK(coverage.insidePixels > width * height / 50);
        if (frame >= 12 && tiles.converged) {
            CHECK(tiles.deepestLevelDrawn > deepestFirst + 3);
            CHECK(coverage.highest - coverage.lowest > 100.0);
            break;
        }
        streamingFrames += tiles.standIns > 0;
    }
    CHECK(streamingFrames >= 5);
}

TEST_CASE("Each draped polygon is culled by its own volume, and one with no ground drawn under it is not drawn",
          "[scene][terrain][polygons][gl]")
{
    TerrainScene terrain(syntheticTerrain(ridges, 0.0));
    terrain.look(Geodetic3D::fromDegrees(10.03, 46.04, 45000.0), 0.0, -90.0);
    const FrameStatistics plain = terrain.converge(64, 48).statistics;
    // One polygon in view, the same shape a degree east (out of view, over a tile drawn partly in
    // view, in the first one's group of the collection) and 180 degrees east (beyond the horizon:
    // no ground is drawn there).
    PolygonCollectionOptions drape;
    drape.draped = true;
    auto draped = std::make_shared<PolygonCollection>(kEarth, drape);
    for (const double east : {0.0, 1.0, 180.0}) {
        world::Polygon polygon = drapedQuadrilateral();
        for (Geodetic3D& corner : polygon.rings[0]) {
            corner.longitude += toRadians(east);
        }
        draped->add(polygon, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f), "draped");
    }
    terrain.scene.add(draped);
    const FrameStatistics statistics = terrain.converge(64, 48).statistics;
    CHECK(draped->drapedHeights(0).has_value());
    CHECK(draped->drapedHeights(1).has_value());
    CHECK_FALSE(draped->drapedHeights(2).has_value());
    // Two draws each for the first two, of which the second's are culled by the frustum (by the
    // collection's sphere, around the first too, they would not be).
    CHECK(statistics.commandsSubmitted == plain.commandsSubmitted + 4);
    CHECK(statistics.commandsCulledByFrustum == plain.commandsCulledByFrustum + 2);
    CHECK(hasEffect(statistics.effects, Effect::DrapedPolygons));
}

TEST_CASE("A pick finds the terrain drawn under the pixel, and the camera is kept above the ground",
          "[scene][tiles][terrain][gl]")
{
    TerrainScene terrain(syntheticTerrain(ridges, 0.0), 3.0);
    terrain.look(Geodetic3D::fromDegrees(10.0, 46.0, 12000.0), 30.0, -10.0); // the top rows are sky
    const int width = 160;
    const int height = 120;
    REQUIRE(terrain.converge(width, height).statistics.tiles->converged);
    Scene& scene = terrain.scene;
    int hits = 0;
    for (int y = 70; y < height; y += 10) {
        for (int x = 5; x < width; x += 15) {
            const glm::dvec2 pixel(x + 0.5, y + 0.5);
            const std::optional<glm::dvec3> picked = scene.pickGround(pixel, width, height);
            REQUIRE(picked);
            REQUIRE(std::isfinite(glm::length(*picked)));
            // On the drawn surface (the ellipsoid is thousands of metres below these ridges) and
            // under the pixel.
            const Geodetic3D g = kEarth.toGeodetic3D(*picked);
            const double ground = scene.groundHeight(Geodetic2D(g.longitude, g.latitude));
            CHECK(ground > 500.0);
            CHECK(std::abs(g.height - ground) < 0.05);
            const std::optional<glm::dvec2> back = scene.camera().worldToWindow(*picked, width, height);
            REQUIRE(back);
            CHECK(glm::distance(*back, pixel) < 1e-3);
            ++hits;
        }
    }
    CHECK(hits > 40);
    // The sky picks nothing.
    CHECK_FALSE(scene.pickGround({80.5, 0.5}, width, height));

    // An eye above the ground stays where it is; one put below the ridges rises to 2 m above them,
    // looking the same way.
    CHECK_FALSE(scene.keepCameraAboveGround(2.0));
    const Geodetic2D under = Geodetic2D::fromDegrees(10.05, 46.05);
    const double ground = scene.groundHeight(under);
    REQUIRE(ground > 1000.0);
    const glm::dvec3 buried = kEarth.toCartesian(Geodetic3D(under.longitude, under.latitude, ground - 300.0));
    const glm::dvec3 direction = glm::normalize(glm::dvec3(1.0, 2.0, -0.5));
    scene.camera().lookAt(buried, buried + 1000.0 * direction, kEarth.geodeticSurfaceNormal(buried));
    CHECK(scene.keepCameraAboveGround(2.0));
    const Geodetic3D lifted = kEarth.toGeodetic3D(scene.camera().eye());
    CHECK(std::abs(lifted.height - (ground + 2.0)) < 1e-6);
    CHECK(glm::length(scene.camera().direction() - direction) < 1e-9);
}
