#include "SceneTestSupport.h"

#include "GoldenImage.h"
#include "ProceduralTileSource.h"

#include <orbis/core/IntersectionTests.h>
#include <orbis/core/Transforms.h>
#include <orbis/scene/PageTable.h>
#include <orbis/scene/TiledGlobe.h>
#include <orbis/scene/VirtualTextureGlobe.h>
#include <orbis/world/TileSource.h>

#include <orbis/renderer/Device.h>
#include <orbis/renderer/EmbeddedShaders.h>
#include <orbis/renderer/Framebuffer.h>
#include <orbis/renderer/ShaderCache.h>

#include "RendererTestSupport.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <random>
#include <set>

using namespace orbis;
using namespace orbis::scene;
using namespace orbis::test;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

VirtualTextureGlobeOptions blueMarble()
{
    VirtualTextureGlobeOptions options;
    options.source = world::openTileSource(dataPath("imagery/BlueMarble"));
    options.loader.workerThreads = 0;
    options.loader.latencyFrames = 1;
    return options;
}

/// A camera placement the tests share.
struct CameraView {
    const char* name;
    Geodetic3D position;
    double heading;
    double pitch;
};
const CameraView kAlpsToTheHorizon{"the Alps from 300 km, the horizon in view", Geodetic3D::fromDegrees(8.0, 43.5, 300000.0),
                                   10.0, -35.0};
const CameraView kWholeEarth{"the whole Earth from 20,000 km", Geodetic3D::fromDegrees(15.0, 30.0, 2.0e7), 0.0, -90.0};

/// A scene of one primitive converged on a view at 256 x 144: its last frame.
RenderedFrame convergedOn(std::shared_ptr<Primitive> primitive, const CameraView& view)
{
    Scene scene(kEarth);
    scene.add(std::move(primitive));
    placeCamera(scene, view.position, view.heading, view.pitch);
    return renderUntilTilesConverge(scene, 256, 144, 100);
}

} // namespace

TEST_CASE("A virtual texture over the Alps converges to the Blue Marble's deepest level", "[scene][virtual][gl]")
{
    VirtualTextureGlobeOptions options = blueMarble();
    auto globe = std::make_shared<VirtualTextureGlobe>(kEarth, options);
    Scene scene(kEarth);
    scene.add(globe);
    placeCamera(scene, Geodetic3D::fromDegrees(8.0, 44.0, 300000.0), 0.0, -35.0);
    const RenderedFrame frame = renderUntilTilesConverge(scene, 640, 360, 100);
    INFO(frame.statistics.toText());
    REQUIRE(frame.statistics.virtualTexture);
    CHECK(frame.statistics.virtualTexture->converged);
    CHECK(frame.statistics.virtualTexture->fallbackFraction == 0.0);
}

TEST_CASE("A converged virtual texture draws the tiled globe's golden images", "[scene][virtual][gl][golden]")
{
    struct View {
        const char* name;
        Geodetic3D position;
        double heading;
        double pitch;
        GoldenTolerance tolerance;
    };
    // Measured on llvmpipe against the tiled globe's goldens: Paris within 1 everywhere; the pole
    // 1.6% of pixels beyond 2 and 0.49% beyond 4 (at most 13), the antimeridian 0.17% beyond 2 (at
    // most 10). The per-tile textures clamp at their edges where the pages blend into their
    // borders, and the tiles' own mipmaps stand against the pages' coarser levels; a page read
    // from the wrong slot would differ by far more, over whole pages.
    const View views[] = {
        {"tiles-paris-10km", Geodetic3D::fromDegrees(2.35, 48.75, 10000.0), 0.0, -60.0, {1, 0.0}},
        {"tiles-north-pole", Geodetic3D::fromDegrees(30.0, 87.0, 300000.0), 180.0, -50.0, {4, 0.006}},
        {"tiles-antimeridian", Geodetic3D::fromDegrees(177.0, -17.5, 150000.0), 90.0, -45.0, {2, 0.0025}},
    };
    for (const View& view : views) {
        Scene scene(kEarth);
        scene.add(std::make_shared<VirtualTextureGlobe>(kEarth, blueMarble()));
        placeCamera(scene, view.position, view.heading, view.pitch);
        const RenderedFrame frame = renderUntilTilesConverge(scene, 256, 144, 100);
        INFO(view.name << "\n" << frame.statistics.toText());
        REQUIRE(frame.statistics.virtualTexture->converged);
        ORBIS_REQUIRE_GOLDEN(frame.image, view.name, view.tolerance);
    }
}

TEST_CASE("Only tiles whose pixels may be coarser than level 0 read the mip tail, and the picture stays the tiled globe's",
          "[scene][virtual][gl]")
{
    // Against the tiled globe: pixels beyond 4 apart and the largest difference, measured with
    // the mip tail read for every tile (the Alps' horizon: 8.8%, at most 26, where the two filter
    // grazing footprints differently; the whole Earth 18 pixels) and for none (the Alps at most 69,
    // the whole Earth 1,940 pixels: the limb aliased).
    struct View {
        CameraView camera;
        double differingFraction;
        int largestDifference;
    };
    const View views[] = {
        {{"Paris from 10 km, no horizon", Geodetic3D::fromDegrees(2.35, 48.75, 10000.0), 0.0, -60.0}, 0.0, 4},
        {kAlpsToTheHorizon, 0.09, 30},
        {kWholeEarth, 0.001, 255},
    };
    for (const View& view : views) {
        INFO(view.camera.name);
        const RenderedFrame frame = convergedOn(std::make_shared<VirtualTextureGlobe>(kEarth, blueMarble()), view.camera);
        REQUIRE(frame.statistics.virtualTexture->converged);
        const std::size_t withTail = frame.statistics.virtualTexture->tilesWithMipTail;
        const std::size_t drawn = frame.statistics.tiles->drawn;
        if (&view == &views[0]) {
            CHECK(withTail == 0);
        } else if (&view == &views[1]) {
            CHECK(withTail > 0);
        } else {
            CHECK(withTail == drawn);
        }
        TiledGlobeOptions tiledOptions;
        tiledOptions.imagery.push_back({blueMarble().source, {}});
        const RenderedFrame expected = convergedOn(std::make_shared<TiledGlobe>(kEarth, tiledOptions), view.camera);
        const ImageDifference difference = compareImages(frame.image, expected.image, 4);
        INFO("beyond 4: " << difference.differingPixels << ", largest " << difference.maxChannelDifference);
        CHECK(difference.differingFraction <= view.differingFraction);
        CHECK(difference.maxChannelDifference <= view.largestDifference);
    }
}

TEST_CASE("A tile's rows read only the levels their pixels show: the picture of whole tiles, pixel for pixel",
          "[scene][virtual][gl]")
{
    // Over the Alps towards the horizon a tile's far rows read the mip tail and its near rows do
    // not; over Europe from 1,000 km some rows read one level, others blend two; near the North Pole
    // (where a texel's width narrows to nothing) and across the antimeridian, looking east over it,
    // some rows read the tail and others not; over the whole Earth every row of the 90-degree
    // tiles reaches the limb: the tiles are drawn whole. Drawn again with each tile whole, in the
    // program its most demanding part needs, the frame is the same.
    struct View {
        CameraView camera;
        bool splits;
    };
    const View views[] = {
        {kAlpsToTheHorizon, true},
        {{"Europe from 1,000 km", Geodetic3D::fromDegrees(10.0, 48.0, 1.0e6), 0.0, -90.0}, true},
        {{"the North Pole from 300 km", Geodetic3D::fromDegrees(30.0, 87.0, 300000.0), 180.0, -50.0}, true},
        {{"the antimeridian from 300 km, looking east across it", Geodetic3D::fromDegrees(178.0, -17.5, 300000.0), 90.0, -35.0},
         true},
        {kWholeEarth, false},
    };
    auto render = [](const View& view, bool programsPerRow) {
        VirtualTextureGlobeOptions options = blueMarble();
        options.programsPerRow = programsPerRow;
        return convergedOn(std::make_shared<VirtualTextureGlobe>(kEarth, options), view.camera);
    };
    for (const View& view : views) {
        INFO(view.camera.name);
        const RenderedFrame rows = render(view, true);
        const RenderedFrame whole = render(view, false);
        REQUIRE(rows.statistics.virtualTexture->converged);
        REQUIRE(whole.statistics.virtualTexture->converged);
        const std::size_t drawn = rows.statistics.tiles->drawn;
        CHECK(whole.statistics.tiles->drawn == drawn);
        CHECK(whole.statistics.commandsExecuted == drawn);
        // The commands beyond one a tile are its runs of rows with another program.
        INFO(rows.statistics.commandsExecuted << " commands for " << drawn << " tiles; with the mip tail "
             << rows.statistics.virtualTexture->tilesWithMipTail << " tiles, whole "
             << whole.statistics.virtualTexture->tilesWithMipTail);
        CHECK((rows.statistics.commandsExecuted > drawn) == view.splits);
        CHECK(compareImages(rows.image, whole.image, 0).differingPixels == 0);
    }
}

TEST_CASE("Tiles whose every pixel magnifies the finest level read it alone", "[scene][virtual][gl]")
{
    // A tile reads one level where every pixel's level of detail is below 0 (the finest level's
    // texels span more than a pixel), where blending two would draw the finest alone. Checked
    // through the same view with the level of detail raised by one and its feedback drawn at full
    // resolution (the main pass's pixels): where the tiles read one level, no pixel asks for a
    // level coarser than the finest. Over Paris from 10 km the Blue Marble's finest texels (5 km)
    // span many pixels: both tiles read one level; over the antimeridian from 50 km, looking 45
    // degrees down, too, where the tiles reach past the view's far edge (the footprints of rays
    // through the view's pixels say so, not the bound at the view's reach alone); from 1,000 km
    // over Europe the pixels span more than a texel, and from 20,000 km several: every tile blends.
    struct View {
        CameraView camera;
        bool magnified;
    };
    const View views[] = {
        {{"Paris from 10 km", Geodetic3D::fromDegrees(2.35, 48.75, 10000.0), 0.0, -60.0}, true},
        {{"the antimeridian from 50 km, 45 degrees down", Geodetic3D::fromDegrees(177.0, -17.5, 50000.0), 0.0, -45.0}, true},
        {{"Europe from 1,000 km", Geodetic3D::fromDegrees(10.0, 48.0, 1.0e6), 0.0, -90.0}, false},
        {kWholeEarth, false},
    };
    for (const View& view : views) {
        INFO(view.camera.name);
        const RenderedFrame frame = convergedOn(std::make_shared<VirtualTextureGlobe>(kEarth, blueMarble()), view.camera);
        INFO(frame.statistics.toText());
        REQUIRE(frame.statistics.virtualTexture->converged);
        const std::size_t blending = frame.statistics.virtualTexture->tilesBlendingLevels;

        VirtualTextureGlobeOptions raised = blueMarble();
        raised.virtualTexture.lodBias = 1.0;
        raised.virtualTexture.feedbackDivisor = 1;
        const auto globe = std::make_shared<VirtualTextureGlobe>(kEarth, raised);
        const RenderedFrame raisedFrame = convergedOn(globe, view.camera);
        REQUIRE(raisedFrame.statistics.virtualTexture->converged);
        const Image feedback = globe->feedbackImage();
        REQUIRE(feedback.width == 256);
        const std::array<std::uint8_t, 4> finest = VirtualTextureGlobe::levelColor(globe->layout().finestLevel);
        std::size_t coarser = 0;
        std::size_t covered = 0;
        for (int y = 0; y < feedback.height; ++y) {
            for (int x = 0; x < feedback.width; ++x) {
                const std::uint8_t* pixel = feedback.pixel(x, y);
                if (pixel[0] == 0 && pixel[1] == 0 && pixel[2] == 0) {
                    continue; // no globe there
                }
                ++covered;
                coarser += std::memcmp(pixel, finest.data(), 4) != 0 ? 1 : 0;
            }
        }
        INFO(blending << " tiles blending; " << coarser << " of " << covered << " pixels ask for a coarser level");
        CHECK(covered > 1000);
        if (blending == 0) {
            CHECK(coarser == 0);
        }
        CHECK(blending == (view.magnified ? 0 : frame.statistics.tiles->drawn));
        CHECK((coarser > 0) == !view.magnified);
    }
}

namespace {

/// The shader's functions (virtual_texture.frag.glsl) run per vertex: each point is a tile
/// coordinate and a level, and captures where the page table sends it, the level it shows, and
/// the same one level coarser through the parent's entry fetched with it (the level itself at
/// level 0), and the level of detail of a footprint (its two axes in "normal" and "color").
const char* kTranslationMain = R"(
in vec3 position;          // s, t within the tile; the level asked for
in vec3 normal;            // dx: the derivatives of s and t across a pixel (z unused)
in vec4 color;             // dy in xy
out vec4 v_physical;       // physical x, y; the level shown; texels per tile unit there
out vec4 v_coarser;        // the same one level coarser
out float v_levelOfDetail;

vec4 translate(PageEntry entry, int level)
{
    float texelsPerTile;
    vec2 physical = vtPhysicalPosition(entry, level, vtPagePosition(level, position.xy), position.xy, texelsPerTile);
    return vec4(physical, float(entry.level), texelsPerTile);
}

void main()
{
    int level = int(position.z);
    PageEntries entries = vtPageEntries(level, vtPagePosition(level, position.xy).page);
    v_physical = translate(entries.own, level);
    v_coarser = translate(entries.parent, max(level - 1, 0));
    v_levelOfDetail = vtLevelOfDetail(normal.xy, color.xy);
    gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
}
)";

} // namespace

TEST_CASE("The shader's address translation and level of detail match a CPU reference", "[scene][virtual][gl]")
{
    using namespace orbis::renderer;
    const std::uint32_t seed = 7031;
    INFO("seed " << seed);
    std::mt19937 random(seed);
    Device& device = sharedDevice();
    Context& context = device.context();

    // A page table as the globe keeps it: the roots, then pages whose ancestors are all mapped.
    const VirtualTextureLayout layout{128, 4, 5};
    const int slotsX = 16;
    const int slotsY = 12;
    PageTable table(layout.finestLevel);
    int nextSlot = 0;
    auto mapPage = [&](const PageKey& page) {
        table.map(page, static_cast<std::uint8_t>(nextSlot % slotsX), static_cast<std::uint8_t>(nextSlot / slotsX));
        ++nextSlot;
    };
    mapPage({0, 0, 0});
    mapPage({0, 1, 0});
    while (nextSlot < slotsX * slotsY) {
        const std::uint32_t level = std::uniform_int_distribution<std::uint32_t>(1, layout.finestLevel)(random);
        const PageKey page{level, std::uniform_int_distribution<std::uint32_t>(0, VirtualTextureLayout::pagesX(level) - 1)(random),
                           std::uniform_int_distribution<std::uint32_t>(0, VirtualTextureLayout::pagesY(level) - 1)(random)};
        if (!table.isMapped(page) && table.isMapped(page.parent())) {
            mapPage(page);
        }
    }
    const glm::uvec2 tableSize = VirtualTextureLayout::pageTableSize(layout.finestLevel);
    Texture2D pageTableTexture = device.createTexture2D(
        {static_cast<int>(tableSize.x), static_cast<int>(tableSize.y), TextureFormat::RG32F, false});
    std::vector<float> texels;
    for (std::uint32_t level = 0; level <= layout.finestLevel; ++level) {
        const PageRectangle whole{0, 0, VirtualTextureLayout::pagesX(level), VirtualTextureLayout::pagesY(level)};
        table.texels(level, whole, texels);
        const glm::uvec2 origin = VirtualTextureLayout::pageTableOrigin(level, layout.finestLevel);
        pageTableTexture.copyFromSystemMemory(std::as_bytes(std::span(texels)),
                                              {static_cast<int>(origin.x), static_cast<int>(origin.y),
                                               static_cast<int>(whole.x1), static_cast<int>(whole.y1)});
    }
    SamplerDescription point;
    point.minificationFilter = TextureMinificationFilter::NearestMipmapNearest;
    point.magnificationFilter = TextureMagnificationFilter::Nearest;
    const Sampler sampler = device.createSampler(point);
    const int physicalWidth = slotsX * layout.slotSize();
    const int physicalHeight = slotsY * layout.slotSize();
    // The level of detail with anisotropic filtering (up to 4 probes) and without (the long axis).
    const bool anisotropic = GENERATE(true, false);
    INFO((anisotropic ? "anisotropic" : "isotropic"));
    const float anisotropyLog2 = anisotropic ? 2.0f : 0.0f;

    ShaderProgramDescription description;
    description.name = "virtual texture translation";
    description.vertex = ShaderSource::fromText(
        "virtual_texture.frag.glsl + translation main",
        ShaderSource::embedded("scene/virtual/virtual_texture.frag.glsl").text + kTranslationMain);
    description.fragment = ShaderSource::fromText("nothing.frag.glsl", "out vec4 c;\nvoid main() { c = vec4(1.0); }\n");
    description.transformFeedbackVaryings = {"v_physical", "v_coarser", "v_levelOfDetail"};
    if (anisotropic) {
        description.defines.push_back({"VT_ANISOTROPIC"});
    }
    ShaderProgram program = device.createShaderProgram(description);
    Framebuffer framebuffer = context.createFramebuffer(1, 1);

    std::size_t checked = 0;
    std::size_t fallbacks = 0;
    for (int tileIndex = 0; tileIndex < 40; ++tileIndex) {
        const std::uint32_t tileLevel = std::uniform_int_distribution<std::uint32_t>(0, 7)(random);
        const TileKey tile{tileLevel,
                           std::uniform_int_distribution<std::uint32_t>(0, VirtualTextureLayout::pagesX(tileLevel) - 1)(random),
                           std::uniform_int_distribution<std::uint32_t>(0, VirtualTextureLayout::pagesY(tileLevel) - 1)(random)};
        struct Point {
            float s, t;
            int level;
            glm::vec2 dx, dy;
        };
        std::vector<Point> points;
        std::vector<float> positions, dxs, dys;
        std::uniform_real_distribution<float> unit(0.0f, 1.0f);
        for (int i = 0; i < 64; ++i) {
            Point p{unit(random), unit(random), std::uniform_int_distribution<int>(0, static_cast<int>(layout.finestLevel))(random),
                    glm::vec2(unit(random) - 0.5f, unit(random) - 0.5f) * std::exp2(-unit(random) * 16.0f),
                    glm::vec2(unit(random) - 0.5f, unit(random) - 0.5f) * std::exp2(-unit(random) * 16.0f)};
            points.push_back(p);
            positions.insert(positions.end(), {p.s, p.t, static_cast<float>(p.level)});
            dxs.insert(dxs.end(), {p.dx.x, p.dx.y, 0.0f});
            dys.insert(dys.end(), {p.dy.x, p.dy.y, 0.0f, 0.0f});
        }
        const VertexBuffer positionBuffer = device.createVertexBuffer(std::as_bytes(std::span(positions)));
        const VertexBuffer dxBuffer = device.createVertexBuffer(std::as_bytes(std::span(dxs)));
        const VertexBuffer dyBuffer = device.createVertexBuffer(std::as_bytes(std::span(dys)));
        VertexArray array = context.createVertexArray();
        array.setAttribute("position", positionBuffer, {ComponentType::Float, 3});
        array.setAttribute("normal", dxBuffer, {ComponentType::Float, 3});
        array.setAttribute("color", dyBuffer, {ComponentType::Float, 4});
        DrawCommand command;
        command.vertexArray = &array;
        command.shaderProgram = &program;
        command.primitiveType = PrimitiveType::Points;
        command.framebuffer = &framebuffer;
        command.textures = {{0, &pageTableTexture, &sampler}};
        command.uniforms.set("u_tileKey", glm::ivec3(static_cast<int>(tile.level), static_cast<int>(tile.x), static_cast<int>(tile.y)));
        command.uniforms.set("u_layout", glm::ivec4(static_cast<int>(layout.finestLevel), layout.pageSize, layout.border,
                                                     layout.slotSize()));
        command.uniforms.set("u_physicalTexelSize", glm::vec2(1.0f / static_cast<float>(physicalWidth), 1.0f / static_cast<float>(physicalHeight)));
        command.uniforms.set("u_lodBias", 0.25f);
        if (anisotropic) {
            command.uniforms.set("u_maximumAnisotropyLog2", anisotropyLog2);
        }
        const std::vector<float> captured = context.captureVertexOutputs(command, SceneState{});
        REQUIRE(captured.size() == points.size() * 9);

        for (std::size_t i = 0; i < points.size(); ++i) {
            const Point& p = points[i];
            // The reference, in doubles from the same floats.
            const double u = (tile.x + static_cast<double>(p.s)) / VirtualTextureLayout::pagesX(tile.level);
            const double v = (tile.y + static_cast<double>(p.t)) / VirtualTextureLayout::pagesY(tile.level);
            struct Translation {
                glm::dvec2 physical;
                std::uint32_t shownLevel;
                double texelsPerTile;
            };
            auto reference = [&](std::uint32_t level) {
                const PageKey wanted = VirtualTextureLayout::pageAt(level, u, v);
                const PageTableEntry& entry = table.entry(wanted);
                const PageKey shown = wanted.ancestor(entry.level);
                const glm::dvec2 inSlot = layout.contractToSlot(VirtualTextureLayout::positionInPage(shown, u, v));
                return Translation{{(entry.slotX + inSlot.x) * layout.slotSize() / physicalWidth,
                                    (entry.slotY + inSlot.y) * layout.slotSize() / physicalHeight},
                                   entry.level,
                                   layout.pageSize * std::exp2(static_cast<double>(entry.level) - tile.level)};
            };
            // The level of detail: the course's anisotropic formula at the finest level's texels
            // (the long axis alone without anisotropy: anisotropyLog2 0).
            const double finestTexelsPerTile = layout.pageSize * std::exp2(static_cast<double>(layout.finestLevel) - tile.level);
            const double a = glm::dot(glm::dvec2(p.dx), glm::dvec2(p.dx)) * finestTexelsPerTile * finestTexelsPerTile;
            const double b = glm::dot(glm::dvec2(p.dy), glm::dvec2(p.dy)) * finestTexelsPerTile * finestTexelsPerTile;
            const double maxLod = 0.5 * std::log2(std::max(a, b));
            const double minLod = 0.5 * std::log2(std::min(a, b));
            const double lod = maxLod - std::min(maxLod - minLod, static_cast<double>(anisotropyLog2)) + 0.25;

            const float* gpu = captured.data() + i * 9;
            INFO("tile " << tile.level << "/" << tile.x << "/" << tile.y << ", s " << p.s << ", t " << p.t << ", level "
                         << p.level);
            const auto level = static_cast<std::uint32_t>(p.level);
            for (const std::uint32_t translated : {level, level > 0 ? level - 1 : 0u}) {
                INFO("translated at level " << translated);
                const Translation expected = reference(translated);
                const float* got = gpu + (translated == level ? 0 : 4);
                REQUIRE(static_cast<std::uint32_t>(got[2]) == expected.shownLevel);
                // A hundredth of a texel of the physical texture; the float of a level-7 tile's
                // position carries 2^-24 of the tile, 2^-17 of a page two levels up.
                REQUIRE(std::abs(static_cast<double>(got[0]) - expected.physical.x) * physicalWidth < 0.01);
                REQUIRE(std::abs(static_cast<double>(got[1]) - expected.physical.y) * physicalHeight < 0.01);
                REQUIRE(got[3] == Approx(expected.texelsPerTile).epsilon(1e-6));
            }
            // The shader's log2 (vtLog2) is within 9e-4, a level of detail half that.
            REQUIRE(gpu[8] == Approx(lod).margin(5e-4));
            fallbacks += reference(level).shownLevel < level ? 1 : 0;
            ++checked;
        }
    }
    CHECK(checked == 40 * 64);
    // Both kinds were met: pages shown themselves, and coarser ones in their place.
    CHECK(fallbacks > 100);
    CHECK(fallbacks < checked - 100);
}

TEST_CASE("Each feedback pixel names the page and level its own ray asks for, against a CPU reference",
          "[scene][virtual][gl]")
{
    // A virtual texture 12 levels deep (the deepest a feedback sample names: 19 m texels), so
    // that the views below ask for many levels. Pages need not load: the feedback names the page
    // each pixel asks for whether or not it is resident.
    ProceduralTileSourceOptions tiles;
    tiles.maximumLevel = kMaximumVirtualTextureLevel;
    VirtualTextureGlobeOptions options;
    options.source = std::make_shared<ProceduralTileSource>(tiles);
    options.loader.workerThreads = 0;
    options.loader.latencyFrames = 1;
    const int width = 256, height = 144;
    struct View {
        CameraView camera;
        float maximumAnisotropy;
        std::size_t levels; ///< at least so many levels among the pixels checked
    };
    // The whole Earth at 256 x 144 asks for one level; its views check the rectangle drawn
    // around the outline (off the view's centre too).
    const View views[] = {
        {{"1 km up, the horizon in view", Geodetic3D::fromDegrees(8.0, 45.0, 1000.0), 30.0, -8.0}, 1.0f, 6},
        {{"the same, anisotropic", Geodetic3D::fromDegrees(8.0, 45.0, 1000.0), 30.0, -8.0}, 8.0f, 4},
        {{"the north pole from 300 km", Geodetic3D::fromDegrees(30.0, 86.0, 300000.0), 0.0, -50.0}, 1.0f, 2},
        {{"the antimeridian from 150 km", Geodetic3D::fromDegrees(179.5, -17.5, 150000.0), 90.0, -45.0}, 1.0f, 3},
        {kWholeEarth, 1.0f, 1},
        {{"the whole Earth, off the view's centre", Geodetic3D::fromDegrees(15.0, 30.0, 2.0e7), 0.0, -75.0}, 1.0f, 1},
    };
    for (const View& view : views) {
        INFO(view.camera.name);
        options.virtualTexture.maximumAnisotropy = view.maximumAnisotropy;
        auto globe = std::make_shared<VirtualTextureGlobe>(kEarth, options);
        Scene scene(kEarth);
        scene.add(globe);
        placeCamera(scene, view.camera.position, view.camera.heading, view.camera.pitch);
        for (int frame = 0; frame < 3; ++frame) {
            renderFrame(scene, width, height); // the feedback drawn in the first comes back a frame late
        }
        const VirtualTextureGlobe::Feedback feedback = globe->feedback();
        REQUIRE(feedback.width == width / 4);
        REQUIRE(feedback.height == height / 4);
        const VirtualTextureLayout& layout = globe->layout();
        const Camera& camera = scene.camera();

        // The reference: the frame's own pixel there cast in double, its footprint from the rays a
        // pixel apart, the level of detail as the shader defines it (vtLevelOfDetail).
        struct Hit {
            bool hit = false;
            double longitude = 0.0, latitude = 0.0;
            glm::dvec3 direction{0.0}, normal{0.0};
        };
        auto cast = [&](const glm::dvec2& window) {
            const Ray ray = camera.pickRay(window, width, height);
            const std::optional<RayInterval> interval = intersectRayEllipsoid(ray, kEarth);
            Hit hit;
            if (interval) {
                const glm::dvec3 ground = ray.pointAt(interval->nearDistance);
                hit.hit = true;
                hit.normal = kEarth.geodeticSurfaceNormal(ground);
                hit.longitude = std::atan2(ground.y, ground.x);
                hit.latitude = std::asin(std::clamp(hit.normal.z, -1.0, 1.0));
                hit.direction = glm::normalize(ray.direction);
            }
            return hit;
        };
        const double texelsAcrossLevel0Tile = layout.pageSize * std::exp2(layout.finestLevel);
        int checked = 0, skipped = 0, mismatched = 0, covered = 0;
        std::set<std::uint32_t> levels;
        std::string mismatches;
        for (int j = 0; j < feedback.height; ++j) {
            for (int i = 0; i < feedback.width; ++i) {
                const FeedbackSample& sample = feedback.samples[static_cast<std::size_t>(j) * feedback.width + i];
                // The feedback's pixel centre in the frame's window positions (y down).
                const glm::dvec2 window((i + 0.5) * width / feedback.width, height - (j + 0.5) * height / feedback.height);
                const Hit centre = cast(window);
                // Within 3 degrees of grazing, a pixel's footprint changes faster than a difference
                // over the pixel can follow: the limb is left out.
                if (centre.hit && -glm::dot(centre.direction, centre.normal) < 0.05) {
                    ++skipped;
                    continue;
                }
                INFO("pixel " << i << ", " << j);
                REQUIRE(sample.covered == centre.hit);
                if (!centre.hit) {
                    continue;
                }
                ++covered;
                auto squaredFootprint = [&](const glm::dvec2& step) {
                    const Hit a = cast(window - 0.5 * step), b = cast(window + 0.5 * step);
                    const glm::dvec2 change(std::remainder(b.longitude - a.longitude, kTwoPi), b.latitude - a.latitude);
                    const glm::dvec2 texels = change / kPi * texelsAcrossLevel0Tile;
                    return glm::dot(texels, texels);
                };
                const double across = squaredFootprint({1.0, 0.0}), up = squaredFootprint({0.0, 1.0});
                const double longAxis = 0.5 * std::log2(std::max(across, up));
                const double shortAxis = 0.5 * std::log2(std::min(across, up));
                const double lod = longAxis - std::min(longAxis - shortAxis, std::log2(static_cast<double>(view.maximumAnisotropy)));
                const double asked = std::clamp(std::floor(lod), 0.0, static_cast<double>(layout.finestLevel));
                const std::uint32_t level = layout.finestLevel - static_cast<std::uint32_t>(asked);
                const double u = (centre.longitude + kPi) / kTwoPi * std::exp2(level + 1.0);
                const double v = (centre.latitude + 0.5 * kPi) / kPi * std::exp2(level);
                // Float's rounding: near a level's boundary (the shader's log2 is within 9e-4) or
                // within a two-thousandth of a page of a page's edge either may be named.
                auto nearBoundary = [](double x, double margin) { return std::abs(x - std::round(x)) < margin; };
                if ((lod > 0.0 && lod < layout.finestLevel + 1.0 && nearBoundary(lod, 0.01)) || nearBoundary(u, 2e-3) ||
                    nearBoundary(v, 2e-3)) {
                    ++skipped;
                    continue;
                }
                ++checked;
                levels.insert(level);
                const PageKey expected{level, static_cast<std::uint32_t>(std::floor(u)), static_cast<std::uint32_t>(std::floor(v))};
                if (sample.page != expected) {
                    ++mismatched;
                    auto name = [](const PageKey& page) {
                        return std::to_string(page.level) + "/" + std::to_string(page.x) + "/" + std::to_string(page.y);
                    };
                    mismatches += "pixel " + std::to_string(i) + ", " + std::to_string(j) + ": " + name(sample.page) +
                                  " named, " + name(expected) + " expected (level of detail " + std::to_string(lod) +
                                  ", page row " + std::to_string(v) + ")\n";
                }
            }
        }
        INFO(mismatches);
        CHECK(mismatched == 0);
        // Most pixels were checked, over several levels.
        CHECK(checked > 200);
        CHECK(skipped * 10 < covered);
        CHECK(levels.size() >= view.levels);
    }
}

namespace {

/// A procedural virtual texture: tiles and pages of `pageSize` texels (64 by default), levels 0..5.
VirtualTextureGlobeOptions procedural(int physicalPages, TexelPattern pattern = placePattern,
                                      std::function<bool(const TileKey&)> failing = {}, int pageSize = 64)
{
    ProceduralTileSourceOptions tiles;
    tiles.pattern = std::move(pattern);
    tiles.maximumLevel = 5;
    tiles.tileSize = pageSize;
    tiles.failing = std::move(failing);
    VirtualTextureGlobeOptions options;
    options.source = std::make_shared<ProceduralTileSource>(tiles);
    options.virtualTexture.pageSize = pageSize;
    options.virtualTexture.border = 2;
    options.virtualTexture.physicalPages = physicalPages;
    options.loader.workerThreads = 0;
    options.loader.latencyFrames = 1;
    return options;
}

/// The place pattern, with the level in blue: 50 a level.
std::array<std::uint8_t, 4> levelPattern(std::uint32_t level, double u, double v)
{
    std::array<std::uint8_t, 4> texel = placePattern(level, u, v);
    texel[2] = static_cast<std::uint8_t>(50 * level);
    return texel;
}

/// The deepest level with a page in the physical texture.
std::uint32_t deepestMapped(const PageTable& table)
{
    std::uint32_t deepest = 0;
    for (std::uint32_t level = 0; level <= table.finestLevel(); ++level) {
        for (std::uint32_t y = 0; y < VirtualTextureLayout::pagesY(level); ++y) {
            for (std::uint32_t x = 0; x < VirtualTextureLayout::pagesX(level); ++x) {
                if (table.isMapped({level, x, y})) {
                    deepest = level;
                }
            }
        }
    }
    return deepest;
}

std::uint64_t hashOf(const Image& image)
{
    std::uint64_t hash = 1469598103934665603ull;
    for (const std::uint8_t byte : image.pixels) {
        hash = (hash ^ byte) * 1099511628211ull;
    }
    return hash;
}

} // namespace

TEST_CASE("A tiny physical texture shows coarser texels, never another page's", "[scene][virtual][gl][golden]")
{
    const Geodetic3D position = Geodetic3D::fromDegrees(8.0, 44.0, 400000.0);
    Scene reference(kEarth);
    reference.add(std::make_shared<VirtualTextureGlobe>(kEarth, procedural(512, levelPattern)));
    placeCamera(reference, position, 20.0, -60.0);
    const RenderedFrame fine = renderUntilTilesConverge(reference, 256, 144, 100);
    REQUIRE(fine.statistics.virtualTexture->converged);
    CHECK_FALSE(fine.statistics.virtualTexture->lodBiasRaised);

    // Four slots: the two level-0 pages and two more. The view needs more, so the bias rises
    // until what it asks for fits.
    auto tinyGlobe = std::make_shared<VirtualTextureGlobe>(kEarth, procedural(4, levelPattern));
    Scene tiny(kEarth);
    tiny.add(tinyGlobe);
    placeCamera(tiny, position, 20.0, -60.0);
    const RenderedFrame coarse = renderUntilTilesConverge(tiny, 256, 144, 100);
    INFO(coarse.statistics.toText());
    const VirtualTextureStatistics& stats = *coarse.statistics.virtualTexture;
    REQUIRE(stats.converged);
    CHECK(stats.lodBiasRaised);
    CHECK(stats.lodBias > 0.0);
    CHECK(stats.pagesResident <= 4);
    CHECK(stats.fallbackFraction == 0.0);
    const std::uint32_t deepest = deepestMapped(tinyGlobe->pageTable());
    CHECK(deepest < 5);

    long coarser = 0;
    long placeMismatches = 0;
    for (int y = 0; y < coarse.image.height; ++y) {
        for (int x = 0; x < coarse.image.width; ++x) {
            const std::uint8_t* a = coarse.image.pixel(x, y);
            const std::uint8_t* b = fine.image.pixel(x, y);
            // Blue is the level: never finer than the converged frame's, nor than what is resident.
            REQUIRE(a[2] <= b[2] + 2);
            REQUIRE(a[2] <= 50 * deepest + 2);
            coarser += a[2] + 8 < b[2] ? 1 : 0;
            // Red and green are the place, the same at every level but for the blur of coarser
            // texels at the wave's peaks: a texel of another page would be off by far more.
            placeMismatches += (std::abs(a[0] - b[0]) > 40 || std::abs(a[1] - b[1]) > 40) ? 1 : 0;
        }
    }
    CHECK(coarser > coarse.image.width * coarse.image.height / 2);
    CHECK(placeMismatches == 0);
}

TEST_CASE("Virtual texture frames are the same whatever the loader's thread count", "[scene][virtual][gl]")
{
    auto run = [](int threads) {
        VirtualTextureGlobeOptions options = blueMarble();
        options.loader.workerThreads = threads;
        options.loader.maximumStartsPerFrame = 3;
        options.virtualTexture.physicalPages = 24;
        Scene scene(kEarth);
        scene.add(std::make_shared<VirtualTextureGlobe>(kEarth, options));
        std::vector<std::uint64_t> hashes;
        for (int frame = 0; frame < 24; ++frame) {
            placeCamera(scene, Geodetic3D::fromDegrees(-5.0 + frame * 1.5, 40.0 + frame * 0.3, 350000.0), 60.0, -40.0);
            const RenderedFrame rendered = renderFrame(scene, 160, 96);
            hashes.push_back(hashOf(rendered.image));
            hashes.push_back(rendered.statistics.virtualTexture->pagesLoaded * 1000 +
                             rendered.statistics.virtualTexture->pagesEvicted);
        }
        return hashes;
    };
    const std::vector<std::uint64_t> inline_ = run(0);
    CHECK(run(2) == inline_);
}

TEST_CASE("An imagery layer's brightness or gamma adds the colour adjustment, which a layer as it is compiles out",
          "[scene][virtual][tiles][gl]")
{
    // Both globes, converged over the Alps: as they are, no "colour adjustment" among the frame's
    // effects; with brightness 0.5, or gamma 0.5, the effect, and every pixel of the ground the
    // adjustment of the same pixel as it was (colours scaled, or squared), background untouched.
    auto render = [](bool virtualTexture, const ImageryLayerStyle& style) {
        Scene scene(kEarth);
        scene.options().background = glm::vec4(1.0f, 0.0f, 1.0f, 1.0f);
        if (virtualTexture) {
            VirtualTextureGlobeOptions options = blueMarble();
            options.style = style;
            scene.add(std::make_shared<VirtualTextureGlobe>(kEarth, options));
        } else {
            TiledGlobeOptions options;
            options.imagery.push_back({world::openTileSource(dataPath("imagery/BlueMarble")), style});
            scene.add(std::make_shared<TiledGlobe>(kEarth, options));
        }
        placeCamera(scene, Geodetic3D::fromDegrees(8.0, 44.0, 300000.0), 0.0, -35.0);
        return renderUntilTilesConverge(scene, 160, 90, 100);
    };
    auto adjusts = [](const RenderedFrame& frame) {
        const std::vector<std::string> effects = frame.statistics.effectsRun();
        return std::find(effects.begin(), effects.end(), "colour adjustment") != effects.end();
    };
    for (const bool virtualTexture : {false, true}) {
        INFO((virtualTexture ? "virtual texture" : "tiled imagery"));
        const RenderedFrame plain = render(virtualTexture, {});
        CHECK_FALSE(adjusts(plain));
        ImageryLayerStyle darker;
        darker.brightness = 0.5;
        ImageryLayerStyle squared;
        squared.gamma = 0.5;
        for (const auto& [style, expected] :
             {std::pair<ImageryLayerStyle, double (*)(double)>{darker, [](double c) { return 0.5 * c; }},
              std::pair<ImageryLayerStyle, double (*)(double)>{squared, [](double c) { return c * c; }}}) {
            const RenderedFrame adjusted = render(virtualTexture, style);
            CHECK(adjusts(adjusted));
            int ground = 0;
            for (int y = 0; y < 90; ++y) {
                for (int x = 0; x < 160; ++x) {
                    const std::uint8_t* before = plain.image.pixel(x, y);
                    const std::uint8_t* after = adjusted.image.pixel(x, y);
                    const bool background = before[0] == 255 && before[1] == 0 && before[2] == 255;
                    ground += background ? 0 : 1;
                    for (int c = 0; c < 3; ++c) {
                        INFO("pixel " << x << ", " << y << " channel " << c);
                        const double wanted = background ? before[c] : 255.0 * expected(before[c] / 255.0);
                        REQUIRE(std::abs(after[c] - wanted) <= 2.0);
                    }
                }
            }
            CHECK(ground > 160 * 90 / 2);
        }
    }
}

TEST_CASE("A scene without a virtual texture runs no feedback pass, nor does a still view once converged", "[scene][virtual][gl]")
{
    TiledGlobeOptions tiledOptions;
    tiledOptions.imagery.push_back({world::openTileSource(dataPath("imagery/BlueMarble")), {}});
    Scene tiled(kEarth);
    tiled.add(std::make_shared<TiledGlobe>(kEarth, tiledOptions));
    placeCamera(tiled, Geodetic3D::fromDegrees(8.0, 44.0, 300000.0), 0.0, -35.0);
    const RenderedFrame without = renderUntilTilesConverge(tiled, 160, 90, 100);
    const std::vector<std::string> effects = without.statistics.effectsRun();
    CHECK_FALSE(without.statistics.virtualTexture);
    CHECK(std::find(effects.begin(), effects.end(), "virtual texture") == effects.end());
    CHECK(std::find(effects.begin(), effects.end(), "feedback pass") == effects.end());
    CHECK(without.statistics.renderer.drawCalls == without.statistics.commandsExecuted);
    CHECK(without.statistics.toJson().find("virtualTexture") == std::string::npos);

    Scene virtualScene(kEarth);
    virtualScene.add(std::make_shared<VirtualTextureGlobe>(kEarth, blueMarble()));
    placeCamera(virtualScene, Geodetic3D::fromDegrees(8.0, 44.0, 300000.0), 0.0, -35.0);
    const RenderedFrame first = renderFrame(virtualScene, 160, 90);
    const std::vector<std::string> withEffects = first.statistics.effectsRun();
    CHECK(std::find(withEffects.begin(), withEffects.end(), "virtual texture") != withEffects.end());
    CHECK(std::find(withEffects.begin(), withEffects.end(), "feedback pass") != withEffects.end());
    // One rectangle into the feedback buffer (its pixels cast their rays), then each tile into the
    // frame (in parts, each with the program its pixels need).
    REQUIRE(first.statistics.tiles);
    CHECK(first.statistics.renderer.drawCalls == 1 + first.statistics.commandsExecuted);
    CHECK(first.statistics.commandsExecuted > first.statistics.tiles->drawn);
    CHECK(first.statistics.toJson().find("\"virtualTexture\": {\"pagesWanted\"") != std::string::npos);
    CHECK(first.statistics.toText().find("virtual texture:") != std::string::npos);

    // Converged and still: the view, the tiles and the page table are those the last feedback
    // pass drew, so no frame draws another, and the picture stays the same.
    const RenderedFrame converged = renderUntilTilesConverge(virtualScene, 160, 90, 100);
    REQUIRE(converged.statistics.virtualTexture->converged);
    for (int frame = 0; frame < 3; ++frame) {
        const RenderedFrame still = renderFrame(virtualScene, 160, 90);
        const std::vector<std::string> stillEffects = still.statistics.effectsRun();
        CHECK(std::find(stillEffects.begin(), stillEffects.end(), "feedback pass") == stillEffects.end());
        CHECK(still.statistics.virtualTexture->feedbackWidth == 0);
        CHECK(still.statistics.renderer.drawCalls == still.statistics.commandsExecuted);
        CHECK(still.statistics.virtualTexture->converged);
        CHECK(compareImages(still.image, converged.image, 0).differingPixels == 0);
    }
    // A step of the camera draws one again.
    placeCamera(virtualScene, Geodetic3D::fromDegrees(8.01, 44.0, 300000.0), 0.0, -35.0);
    const RenderedFrame moved = renderFrame(virtualScene, 160, 90);
    CHECK(moved.statistics.virtualTexture->feedbackWidth == 40);
    CHECK(moved.statistics.renderer.drawCalls == 1 + moved.statistics.commandsExecuted);
}

TEST_CASE("A scene without a virtual texture compiles no virtual-texture program", "[scene][virtual][gl]")
{
    // A device of its own, so that its shader cache holds only what these scenes compiled.
    renderer::Device device;
    renderer::Context& context = device.context();
    renderer::Framebuffer framebuffer = context.createFramebuffer(160, 90);
    context.setFramebuffer(&framebuffer);
    auto converge = [&](Scene& scene) {
        FrameStatistics statistics;
        for (int frame = 0; frame < 100 && !(statistics.tiles && statistics.tiles->converged); ++frame) {
            statistics = scene.render(context);
        }
        return statistics;
    };
    TiledGlobeOptions tiledOptions;
    tiledOptions.imagery.push_back({world::openTileSource(dataPath("imagery/BlueMarble")), {}});
    Scene tiled(kEarth);
    tiled.add(std::make_shared<TiledGlobe>(kEarth, tiledOptions));
    placeCamera(tiled, Geodetic3D::fromDegrees(8.0, 44.0, 300000.0), 0.0, -35.0);
    REQUIRE(converge(tiled).tiles->converged);
    const std::uint64_t tiledCompiles = device.shaderCache().compiles();
    const std::uint64_t tiledHits = device.shaderCache().hits();
    CHECK(tiledCompiles > 0);

    // Every program the virtual texture asks for (the feedback pass's, the frame's under each depth
    // strategy the frame tries) is compiled now, none found in the cache: the tiled scene had
    // compiled none of them.
    Scene virtualScene(kEarth);
    virtualScene.add(std::make_shared<VirtualTextureGlobe>(kEarth, blueMarble()));
    placeCamera(virtualScene, Geodetic3D::fromDegrees(8.0, 44.0, 300000.0), 0.0, -35.0);
    REQUIRE(converge(virtualScene).virtualTexture->converged);
    CHECK(device.shaderCache().compiles() >= tiledCompiles + 2);
    CHECK(device.shaderCache().hits() == tiledHits);
    context.setFramebuffer(nullptr);
}

TEST_CASE("A flight with few slots evicts the least recently used pages and keeps its memory", "[scene][virtual][gl]")
{
    VirtualTextureGlobeOptions options = blueMarble();
    options.virtualTexture.physicalPages = 16;
    options.loader.maximumStartsPerFrame = 4;
    auto globe = std::make_shared<VirtualTextureGlobe>(kEarth, options);
    Scene scene(kEarth);
    scene.add(globe);
    std::size_t evicted = 0;
    std::size_t loaded = 0;
    std::optional<std::size_t> gpuBytes;
    for (int frame = 0; frame < 60; ++frame) {
        placeCamera(scene, Geodetic3D::fromDegrees(-10.0 + frame * 1.0, 45.0, 200000.0), 90.0, -50.0);
        const RenderedFrame rendered = renderFrame(scene, 128, 72);
        const VirtualTextureStatistics& stats = *rendered.statistics.virtualTexture;
        INFO("frame " << frame << "\n" << rendered.statistics.toText());
        REQUIRE(stats.pagesResident <= stats.physicalPages);
        REQUIRE(stats.physicalPages == 16);
        REQUIRE(stats.pagesRequested <= 4);
        REQUIRE(stats.feedbackLatencyFrames == (frame == 0 ? 0u : 1u));
        if (!gpuBytes) {
            gpuBytes = stats.gpuBytes;
        }
        REQUIRE(stats.gpuBytes == *gpuBytes);
        evicted += stats.pagesEvicted;
        loaded += stats.pagesLoaded;
        // Every mapped page's parent is mapped: pages go in coarse to fine and leave fine first.
        const PageTable& table = globe->pageTable();
        for (std::uint32_t level = 1; level <= table.finestLevel(); ++level) {
            for (std::uint32_t y = 0; y < VirtualTextureLayout::pagesY(level); ++y) {
                for (std::uint32_t x = 0; x < VirtualTextureLayout::pagesX(level); ++x) {
                    if (table.isMapped({level, x, y})) {
                        REQUIRE(table.isMapped(PageKey{level, x, y}.parent()));
                    }
                }
            }
        }
    }
    CHECK(loaded > 16);
    CHECK(evicted > 0);
    CHECK(evicted + 16 >= loaded);
}

TEST_CASE("Pages still loading blur their resident neighbours over a few pixels only: a flight stays under 1% "
          "fallback in every frame", "[scene][virtual][gl]")
{
    // The first tenth of the benchmark's 2,000-frame flyover (bench/VirtualTexturing.cpp), in its
    // configuration: down from 4,000 km towards 150 km over the Atlantic. Pages the view comes to
    // ask for wait two frames; the LOD clamp's ramp around them once reached an eighth of a page
    // into the resident pages beside them (1.6% of the view at frame 29 here, 15% of it late in
    // the flight); a level per 4 pixels keeps it to a band along their edges.
    VirtualTextureGlobeOptions options = blueMarble();
    options.loader.latencyFrames = 2;
    options.loader.maximumStartsPerFrame = 8;
    options.virtualTexture.physicalPages = 256;
    Scene scene(kEarth);
    scene.add(std::make_shared<VirtualTextureGlobe>(kEarth, options));
    auto fly = [&](double t) {
        const double descent = std::min(1.0, 4.0 * t);
        const double height = std::exp(std::log(4.0e6) + (std::log(1.5e5) - std::log(4.0e6)) * descent);
        placeCamera(scene, Geodetic3D::fromDegrees(-20.0 + 60.0 * t, 44.0 + 6.0 * std::sin(2.0 * kPi * t), height),
                    90.0 + 35.0 * std::sin(4.0 * kPi * t), -40.0);
    };
    fly(0.0);
    renderUntilTilesConverge(scene, 640, 360, 200);
    const int frames = 2000;
    double worst = 0.0;
    std::size_t loaded = 0;
    for (int frame = 0; frame < frames / 10; ++frame) {
        fly(static_cast<double>(frame) / (frames - 1));
        const VirtualTextureStatistics stats = *renderFrame(scene, 640, 360).statistics.virtualTexture;
        INFO("frame " << frame);
        CHECK(stats.fallbackFraction <= 0.01);
        worst = std::max(worst, stats.fallbackFraction);
        loaded += stats.pagesLoaded;
    }
    CHECK(loaded > 10); // pages did arrive during the flight: the view waited for some
    CHECK(worst > 0.0);
}

TEST_CASE("A failing page is named once, its ancestor stays, and the view converges", "[scene][virtual][gl]")
{
    VirtualTextureGlobeOptions options = procedural(256, placePattern, [](const TileKey& key) { return key.level == 3; });
    std::vector<std::string> warnings;
    options.onWarning = [&](const std::string& message) { warnings.push_back(message); };
    Scene scene(kEarth);
    scene.add(std::make_shared<VirtualTextureGlobe>(kEarth, options));
    placeCamera(scene, Geodetic3D::fromDegrees(8.0, 44.0, 1500000.0), 0.0, -70.0);
    const RenderedFrame frame = renderUntilTilesConverge(scene, 160, 90, 100);
    INFO(frame.statistics.toText());
    const VirtualTextureStatistics& stats = *frame.statistics.virtualTexture;
    CHECK(stats.converged);
    CHECK(stats.pagesFailed > 0);
    CHECK(warnings.size() == stats.pagesFailed);
    REQUIRE_FALSE(warnings.empty());
    CHECK_THAT(warnings.front(), Catch::Matchers::Contains("procedural/3/") && Catch::Matchers::Contains("failed"));
    // What fails is final: no pixel counts as waiting for it.
    CHECK(stats.fallbackFraction == 0.0);
}

TEST_CASE("With asynchronous timing the feedback and the pages arrive when ready, and the view converges",
          "[scene][virtual][gl]")
{
    VirtualTextureGlobeOptions options = blueMarble();
    options.loader.workerThreads = 2;
    options.loader.latencyFrames = 0;
    options.virtualTexture.feedbackLatencyFrames = 2;
    Scene scene(kEarth);
    scene.add(std::make_shared<VirtualTextureGlobe>(kEarth, options));
    placeCamera(scene, Geodetic3D::fromDegrees(2.35, 48.75, 10000.0), 0.0, -60.0);
    const RenderedFrame frame = renderUntilTilesConverge(scene, 160, 90, 400);
    INFO(frame.statistics.toText());
    CHECK(frame.statistics.virtualTexture->converged);
    CHECK(frame.statistics.virtualTexture->feedbackLatencyFrames >= 2);
}

TEST_CASE("A virtual texture refuses options it cannot honour", "[scene][virtual]")
{
    auto make = [](const std::function<void(VirtualTextureGlobeOptions&)>& change) {
        VirtualTextureGlobeOptions options = procedural(64);
        change(options);
        return std::make_shared<VirtualTextureGlobe>(kEarth, options);
    };
    using Catch::Matchers::Contains;
    CHECK_THROWS_WITH(make([](auto& o) { o.virtualTexture.physicalPages = 3; }), Contains("physicalPages"));
    CHECK_THROWS_WITH(make([](auto& o) { o.virtualTexture.feedbackDivisor = 0; }), Contains("feedbackDivisor"));
    CHECK_THROWS_WITH(make([](auto& o) { o.virtualTexture.maximumAnisotropy = 8.0f; }), Contains("twice the border"));
    CHECK_THROWS_WITH(make([](auto& o) { o.virtualTexture.pageSize = 48; }), Contains("power of two"));
    CHECK_THROWS_WITH(make([](auto& o) { o.style.rectangle = GeodeticExtent{}; }), Contains("rectangle"));
    CHECK_THROWS_WITH(make([](auto& o) { o.source = nullptr; }), Contains("no imagery source"));
    CHECK_NOTHROW(make([](auto&) {}));
}

namespace {

/// A procedural virtual texture of `pageSize`-texel pages asked for the sparse path, converged on
/// Europe from 1,500 km at 160 x 90; its warnings collected.
RenderedFrame convergedAskingForSparse(int pageSize, std::vector<std::string>& warnings)
{
    VirtualTextureGlobeOptions options = procedural(64, placePattern, {}, pageSize);
    options.virtualTexture.sparse = true;
    options.onWarning = [&](const std::string& message) { warnings.push_back(message); };
    Scene scene(kEarth);
    scene.add(std::make_shared<VirtualTextureGlobe>(kEarth, options));
    placeCamera(scene, Geodetic3D::fromDegrees(8.0, 44.0, 1500000.0), 0.0, -70.0);
    return renderUntilTilesConverge(scene, 160, 90, 100);
}

} // namespace

TEST_CASE("A virtual texture asked for the sparse path takes it only where the device has it", "[scene][virtual][gl]")
{
    std::vector<std::string> warnings;
    const RenderedFrame frame = convergedAskingForSparse(64, warnings);
    INFO(frame.statistics.toText());
    CHECK(frame.statistics.virtualTexture->converged);
    using Catch::Matchers::Contains;
    if (test::sharedDevice().info().sparseTexture) {
        // 64-texel pages: whole sparse pages on a device with pages of 64 texels or fewer.
        const renderer::SparsePageSize page = test::sharedDevice().sparsePageSize(renderer::TextureFormat::RGBA8);
        CHECK(frame.statistics.virtualTexture->sparse == (64 % page.width == 0 && 64 % page.height == 0));
    } else {
        // The software path, said once.
        CHECK_FALSE(frame.statistics.virtualTexture->sparse);
        REQUIRE(warnings.size() == 1);
        CHECK_THAT(warnings.front(), Contains("software path") && Contains("lacks GL_ARB_sparse_texture"));
    }
    VirtualTextureGlobeOptions anisotropic = procedural(64);
    anisotropic.virtualTexture.sparse = true;
    anisotropic.virtualTexture.maximumAnisotropy = 2.0f;
    CHECK_THROWS_WITH(std::make_shared<VirtualTextureGlobe>(kEarth, anisotropic), Contains("maximumAnisotropy must be 1"));
}

// The sparse path's own tests: hidden from the suite's run on the system's llvmpipe, which lacks
// GL_ARB_sparse_texture; ctest runs them on zink over lavapipe (tests/CMakeLists.txt), where they
// must find it.

TEST_CASE("The sparse path draws the software path's picture, converged, with no fallback", "[.sparse]")
{
    REQUIRE(test::sharedDevice().info().sparseTexture);
    struct View {
        const char* name;
        Geodetic3D position;
        double heading;
        double pitch;
    };
    const View views[] = {
        {"Paris from 10 km", Geodetic3D::fromDegrees(2.35, 48.75, 10000.0), 0.0, -60.0},
        {"the north pole", Geodetic3D::fromDegrees(30.0, 87.0, 300000.0), 180.0, -50.0},
        {"the antimeridian", Geodetic3D::fromDegrees(177.0, -17.5, 150000.0), 90.0, -45.0},
        {kAlpsToTheHorizon.name, kAlpsToTheHorizon.position, kAlpsToTheHorizon.heading, kAlpsToTheHorizon.pitch},
        {kWholeEarth.name, kWholeEarth.position, kWholeEarth.heading, kWholeEarth.pitch},
    };
    for (const View& view : views) {
        auto frameOf = [&](bool sparse) {
            VirtualTextureGlobeOptions options = blueMarble();
            options.virtualTexture.sparse = sparse;
            return convergedOn(std::make_shared<VirtualTextureGlobe>(kEarth, options),
                               {view.name, view.position, view.heading, view.pitch});
        };
        const RenderedFrame software = frameOf(false);
        const RenderedFrame sparse = frameOf(true);
        INFO(view.name << "\n" << sparse.statistics.toText());
        const VirtualTextureStatistics& stats = *sparse.statistics.virtualTexture;
        REQUIRE(stats.sparse);
        CHECK_FALSE(software.statistics.virtualTexture->sparse);
        CHECK(stats.converged);
        CHECK(stats.fallbackFraction == 0.0);
        CHECK_THAT(sparse.statistics.toJson(), Catch::Matchers::Contains("\"sparse\": true"));
        int worst = 0;
        for (std::size_t i = 0; i < sparse.image.pixels.size(); ++i) {
            worst = std::max(worst, std::abs(sparse.image.pixels[i] - software.image.pixels[i]));
        }
        // Measured on zink over lavapipe: 1 at most in all five views. The hardware's filtering
        // across pages gives the texels the software path reads from the pages' borders; a page
        // at the wrong place, or a level not blended, would differ by tens over whole regions.
        INFO("largest difference " << worst);
        CHECK(worst <= 2);
    }
}

namespace {

/// A diagonal wave in red over the globe, green its complement (red + green = 255 in every texel
/// and every blend of texels), the level in blue: a texel of no page breaks the sum, one of
/// another place the wave.
std::uint8_t waveAt(double u, double v)
{
    return static_cast<std::uint8_t>(std::lround(128.0 + 120.0 * std::sin(kTwoPi * (16.0 * u + 8.0 * v))));
}

std::array<std::uint8_t, 4> wavePattern(std::uint32_t level, double u, double v)
{
    const std::uint8_t red = waveAt(u, v);
    return {red, static_cast<std::uint8_t>(255 - red), static_cast<std::uint8_t>(50 * level), 255};
}

} // namespace

TEST_CASE("The sparse path with few pages committed shows coarser texels, never a page that is not resident",
          "[.sparse]")
{
    REQUIRE(test::sharedDevice().info().sparseTexture);
    // Nine pages of 128 texels (lavapipe's sparse pages are 128 x 128): the two of level 0 and seven
    // more, along a flight that asks for many more, so that pages are evicted (released) and
    // committed again all the way.
    VirtualTextureGlobeOptions options = procedural(8, wavePattern, {}, 128);
    options.virtualTexture.sparse = true;
    options.loader.maximumStartsPerFrame = 4;
    auto globe = std::make_shared<VirtualTextureGlobe>(kEarth, options);
    Scene scene(kEarth);
    scene.add(globe);
    const int width = 128, height = 72;
    std::size_t evicted = 0, loaded = 0;
    bool biasRaised = false;
    std::optional<std::size_t> fixedBytes;
    for (int frame = 0; frame < 40; ++frame) {
        placeCamera(scene, Geodetic3D::fromDegrees(-10.0 + 1.5 * frame, 45.0 - 0.5 * frame, 400000.0 - 7000.0 * frame),
                    90.0, -70.0);
        const RenderedFrame rendered = renderFrame(scene, width, height);
        const VirtualTextureStatistics& stats = *rendered.statistics.virtualTexture;
        INFO("frame " << frame << "\n" << rendered.statistics.toText());
        REQUIRE(stats.sparse);
        REQUIRE(stats.physicalPages == 9); // a grid of 3 x 3 slots
        REQUIRE(stats.pagesResident <= stats.physicalPages);
        // The memory: the pages committed, beside what never changes.
        const std::size_t pageBytes = std::size_t{128} * 128 * 4;
        if (!fixedBytes) {
            fixedBytes = stats.gpuBytes - stats.pagesResident * pageBytes;
        }
        REQUIRE(stats.gpuBytes == *fixedBytes + stats.pagesResident * pageBytes);
        evicted += stats.pagesEvicted;
        loaded += stats.pagesLoaded;
        biasRaised = biasRaised || stats.lodBiasRaised;
        // Every pixel shows the wave where its ray meets the ground, red and green summing to 255.
        const Camera& camera = scene.camera();
        long broken = 0, misplaced = 0;
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                const Ray ray = camera.pickRay(glm::dvec2(x + 0.5, y + 0.5), width, height);
                const std::optional<RayInterval> hit = intersectRayEllipsoid(ray, kEarth);
                REQUIRE(hit);
                const Geodetic2D ground = kEarth.toGeodetic2D(ray.pointAt(hit->nearDistance));
                const double u = (ground.longitude + kPi) / kTwoPi, v = ground.latitude / kPi + 0.5;
                const std::uint8_t* pixel = rendered.image.pixel(x, y);
                broken += std::abs(pixel[0] + pixel[1] - 255) > 3 ? 1 : 0;
                misplaced += std::abs(pixel[0] - waveAt(u, v)) > 24 ? 1 : 0;
            }
        }
        CHECK(broken == 0);
        CHECK(misplaced == 0);
    }
    CHECK(loaded > 8);
    CHECK(evicted > 0);
    CHECK(biasRaised);
}

TEST_CASE("The sparse path is refused, with the software path drawn, for pages that are not whole sparse pages",
          "[.sparse]")
{
    REQUIRE(test::sharedDevice().info().sparseTexture);
    const renderer::SparsePageSize page = test::sharedDevice().sparsePageSize(renderer::TextureFormat::RGBA8);
    REQUIRE(page.width > 16);
    std::vector<std::string> warnings;
    const RenderedFrame frame = convergedAskingForSparse(page.width / 2, warnings);
    INFO(frame.statistics.toText());
    CHECK(frame.statistics.virtualTexture->converged);
    CHECK_FALSE(frame.statistics.virtualTexture->sparse);
    REQUIRE(warnings.size() == 1);
    CHECK_THAT(warnings.front(), Catch::Matchers::Contains("not whole sparse pages"));
}
