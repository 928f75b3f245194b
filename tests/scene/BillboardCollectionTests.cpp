#include "SceneTestSupport.h"

#include "GoldenImage.h"
#include "RendererTestSupport.h"
#include "VectorTestSupport.h"

#include <orbis/core/BoxTessellator.h>
#include <orbis/core/EllipsoidalOccluder.h>
#include <orbis/scene/BillboardCollection.h>
#include <orbis/scene/Globe.h>
#include <orbis/scene/MeshPrimitive.h>
#include <orbis/scene/ModelPrimitive.h>
#include <orbis/world/CsvPoints.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <limits>
#include <random>

using namespace orbis;
using namespace orbis::world;
using namespace orbis::renderer;
using namespace orbis::scene;
using namespace orbis::test;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();
const glm::ivec4 kBackground(0, 0, 0, 255);

Image solidImage(int width, int height, const glm::ivec4& rgba)
{
    Image image(width, height, 4);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        image.pixels[i] = static_cast<std::uint8_t>(rgba[static_cast<int>(i % 4)]);
    }
    return image;
}

/// An opaque image whose every texel differs from its neighbours.
Image noiseImage(int width, int height, std::mt19937& random)
{
    std::uniform_int_distribution<int> channel(0, 255);
    Image image(width, height, 4);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        image.pixels[i] = static_cast<std::uint8_t>(i % 4 == 3 ? 255 : channel(random));
    }
    return image;
}

/// A scene with no globe, the camera 10,000 km over (0, 0) looking at the Earth's centre.
void lookFromAbove(Scene& scene, double heightMeters = 1e7)
{
    scene.camera().lookAt(kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0, heightMeters)), glm::dvec3(0.0), {0, 0, 1});
}

/// Window coordinates (pixels from the bottom-left corner, continuous) of a world position,
/// projected in double precision as the GPU does in float.
glm::dvec2 windowCoordinates(const Scene& scene, const glm::dvec3& position, int width, int height)
{
    const Camera& camera = scene.camera();
    const glm::dvec4 clip = camera.projectionMatrix(static_cast<double>(width) / height, 1.0, 1e8) *
                            camera.viewMatrix() * glm::dvec4(position, 1.0);
    return {(clip.x / clip.w * 0.5 + 0.5) * width, (clip.y / clip.w * 0.5 + 0.5) * height};
}

/// Pixels (window coordinates, y up) that differ from the background: count and bounding box.
struct Coverage {
    int count = 0;
    int left = 1 << 30;
    int bottom = 1 << 30;
    int right = -1; ///< exclusive
    int top = -1;   ///< exclusive
};

Coverage coverage(const Image& image)
{
    Coverage c;
    for (int row = 0; row < image.height; ++row) {
        for (int x = 0; x < image.width; ++x) {
            if (pixelAt(image, x, row) != kBackground) {
                const int y = image.height - 1 - row;
                ++c.count;
                c.left = std::min(c.left, x);
                c.bottom = std::min(c.bottom, y);
                c.right = std::max(c.right, x + 1);
                c.top = std::max(c.top, y + 1);
            }
        }
    }
    return c;
}

/// True when exactly the pixels of [left, left + width) x [bottom, bottom + height) (window
/// coordinates, clipped to the image) have `inside`, and every other pixel is the background.
/// softEdge: the rectangle's outermost pixels need only differ from the background (a magnified
/// image is filtered there with the atlas's transparent padding).
bool coversExactly(const Image& image, int left, int bottom, int width, int height, const glm::ivec4& inside,
                   std::string& why, bool softEdge = false)
{
    for (int row = 0; row < image.height; ++row) {
        for (int x = 0; x < image.width; ++x) {
            const int y = image.height - 1 - row;
            const bool in = x >= left && x < left + width && y >= bottom && y < bottom + height;
            const bool edge = in && (x == left || x == left + width - 1 || y == bottom || y == bottom + height - 1);
            if (softEdge && edge) {
                if (pixelNear(image, x, row, kBackground, 0)) {
                    why = "window pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                          ") on the edge of the expected rectangle is the background";
                    return false;
                }
                continue;
            }
            if (!pixelNear(image, x, row, in ? inside : kBackground, 0)) {
                why = "window pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is " +
                      describePixel(image, x, row) + (in ? ", inside" : ", outside") + " the expected rectangle";
                return false;
            }
        }
    }
    return true;
}

int originShift(int origin, int size)
{
    return origin == 0 ? 0 : origin == 1 ? size / 2 : size;
}

} // namespace

TEST_CASE("A 5x3 billboard with origin bottom-left and offset (+10, -4) covers exactly the expected pixels", "[scene][billboard]")
{
    Scene scene(kEarth);
    lookFromAbove(scene);
    auto billboards = std::make_shared<BillboardCollection>();
    const std::size_t red = billboards->addImage(solidImage(5, 3, {255, 0, 0, 255}));
    Billboard billboard;
    billboard.position = kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0, 0)); // on the view axis: pixel corner (32, 32)
    billboard.image = red;
    billboard.horizontalOrigin = HorizontalOrigin::Left;
    billboard.verticalOrigin = VerticalOrigin::Bottom;
    billboard.pixelOffset = {10, -4};
    billboards->add(billboard);
    scene.add(billboards);

    const RenderedFrame frame = renderFrame(scene, 64, 64);
    // Offsets go right and down: window x 42..46, y 36..38 (image rows 27..25 from the top), the
    // bottom-left pixel 10 right of and 4 above the anchor's pixel corner.
    std::string why;
    const bool exact = coversExactly(frame.image, 42, 36, 5, 3, {255, 0, 0, 255}, why);
    INFO(why);
    REQUIRE(exact);
    REQUIRE(frame.statistics.translucentPasses == 1);
    REQUIRE(frame.statistics.opaquePasses == 0);
    REQUIRE(frame.statistics.renderer.drawCalls == 1);
}

TEST_CASE("Every origin puts the billboard's side or centre on the anchor's pixel corner", "[scene][billboard]")
{
    Scene scene(kEarth);
    lookFromAbove(scene);
    auto billboards = std::make_shared<BillboardCollection>();
    const std::size_t image = billboards->addImage(solidImage(5, 3, {0, 255, 0, 255}));
    Billboard billboard;
    billboard.position = kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0, 0));
    billboard.image = image;
    billboard.pixelOffset = {-7, 6};
    billboards->add(billboard);
    scene.add(billboards);
    for (int h = 0; h < 3; ++h) {
        for (int v = 0; v < 3; ++v) {
            billboards->setOrigin(0, static_cast<HorizontalOrigin>(h), static_cast<VerticalOrigin>(v));
            const RenderedFrame frame = renderFrame(scene, 64, 64);
            // Centre: floor(5 / 2) = 2 columns and floor(3 / 2) = 1 row left of and below the anchor.
            const int left = 32 - 7 - originShift(h, 5);
            const int bottom = 32 - 6 - originShift(v, 3); // the offset's y goes down
            std::string why;
            const bool exact = coversExactly(frame.image, left, bottom, 5, 3, {0, 255, 0, 255}, why);
            INFO("horizontal origin " << h << ", vertical origin " << v << ": " << why);
            REQUIRE(exact);
        }
    }
}

TEST_CASE("Billboards anywhere in the view land on the pixels their projection, offset, origin and scale give", "[scene][billboard]")
{
    const unsigned seed = 20260;
    std::mt19937 random(seed);
    INFO("seed " << seed);
    const int size = 96;
    Scene scene(kEarth);
    lookFromAbove(scene);
    auto billboards = std::make_shared<BillboardCollection>();
    std::vector<glm::ivec2> sizes;
    for (int i = 0; i < 6; ++i) {
        sizes.push_back({1 + i, 7 - i});
        billboards->addImage(solidImage(sizes.back().x, sizes.back().y, {255, 255, 255, 255}));
    }
    scene.add(billboards);
    std::uniform_real_distribution<double> degrees(-8.0, 8.0);
    std::uniform_real_distribution<double> height(0.0, 2e5);
    std::uniform_int_distribution<int> offset(-20, 20);
    std::uniform_int_distribution<int> origin(0, 2);
    std::uniform_int_distribution<int> pick(0, 5);
    std::uniform_int_distribution<int> scaleSteps(1, 3);
    int checked = 0;
    for (int trial = 0; trial < 24; ++trial) {
        Billboard b;
        b.position = kEarth.toCartesian(Geodetic3D::fromDegrees(degrees(random), degrees(random), height(random)));
        b.image = static_cast<std::size_t>(pick(random));
        b.pixelOffset = {offset(random), offset(random)};
        b.horizontalOrigin = static_cast<HorizontalOrigin>(origin(random));
        b.verticalOrigin = static_cast<VerticalOrigin>(origin(random));
        b.scale = static_cast<float>(scaleSteps(random));
        const glm::dvec2 window = windowCoordinates(scene, b.position, size, size);
        // A window coordinate within 0.01 px of a half pixel may round either way in float.
        const glm::dvec2 fraction = window - glm::floor(window);
        if (std::abs(fraction.x - 0.5) < 0.01 || std::abs(fraction.y - 0.5) < 0.01) {
            continue;
        }
        billboards->clear();
        billboards->add(b);
        const RenderedFrame frame = renderFrame(scene, size, size);
        const glm::ivec2 anchor(static_cast<int>(std::floor(window.x + 0.5)), static_cast<int>(std::floor(window.y + 0.5)));
        const glm::ivec2 extent = sizes[b.image] * static_cast<int>(b.scale);
        const int left = anchor.x + b.pixelOffset.x - originShift(static_cast<int>(b.horizontalOrigin), extent.x);
        const int bottom = anchor.y - b.pixelOffset.y - originShift(static_cast<int>(b.verticalOrigin), extent.y);
        std::string why;
        const bool exact =
            coversExactly(frame.image, left, bottom, extent.x, extent.y, {255, 255, 255, 255}, why, b.scale > 1.0f);
        INFO("trial " << trial << ": anchor (" << window.x << ", " << window.y << "), " << extent.x << "x" << extent.y
                      << " px: " << why);
        REQUIRE(exact);
        ++checked;
    }
    REQUIRE(checked >= 20);
}

TEST_CASE("Images added one by one never overlap in the atlas and each billboard draws its own texels 1:1", "[scene][billboard][atlas]")
{
    const unsigned seed = 97;
    std::mt19937 random(seed);
    INFO("seed " << seed);
    Scene scene(kEarth);
    lookFromAbove(scene);
    BillboardCollectionOptions options;
    options.atlasInitialSize = 16; // grows several times below
    auto billboards = std::make_shared<BillboardCollection>(options);
    scene.add(billboards);
    std::uniform_int_distribution<int> side(1, 13);
    std::vector<Image> images;
    const glm::dvec3 anchor = kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0, 0));
    for (int i = 0; i < 16; ++i) {
        images.push_back(noiseImage(side(random), side(random), random));
        billboards->addImage(images.back());
        // A 4x4 grid of 16 x 16 px cells from (2, 2), each billboard at its cell's bottom-left.
        Billboard b;
        b.position = anchor;
        b.image = static_cast<std::size_t>(i);
        b.horizontalOrigin = HorizontalOrigin::Left;
        b.verticalOrigin = VerticalOrigin::Bottom;
        b.pixelOffset = {2 + 16 * (i % 4) - 32, 32 - (2 + 16 * (i / 4))}; // y down
        billboards->add(b);
        // Drawn after each addition, so the texture follows the atlas as it grows.
        renderFrame(scene, 64, 64);
    }
    const TextureAtlas& atlas = billboards->atlas();
    REQUIRE(atlas.width() > options.atlasInitialSize);
    const int padding = atlas.options().padding;
    for (std::size_t a = 0; a < atlas.size(); ++a) {
        const PixelRectangle ra = atlas.rectangle(a);
        REQUIRE(ra.x >= padding);
        REQUIRE(ra.y >= padding);
        REQUIRE(ra.x + ra.width + padding <= atlas.width());
        REQUIRE(ra.y + ra.height + padding <= atlas.height());
        for (std::size_t b = a + 1; b < atlas.size(); ++b) {
            const PixelRectangle rb = atlas.rectangle(b);
            const bool apart = ra.x + ra.width + padding <= rb.x || rb.x + rb.width + padding <= ra.x ||
                               ra.y + ra.height + padding <= rb.y || rb.y + rb.height + padding <= ra.y;
            INFO("images " << a << " and " << b);
            REQUIRE(apart);
        }
    }

    const RenderedFrame frame = renderFrame(scene, 64, 64);
    const BillboardUploadStatistics upload = billboards->lastUpload();
    REQUIRE(upload.bytesUploaded == 0); // nothing changed since the last frame
    REQUIRE(upload.textureBytesUploaded == 0);
    for (int i = 0; i < 16; ++i) {
        const Image& image = images[static_cast<std::size_t>(i)];
        const int left = 2 + 16 * (i % 4);
        const int bottom = 2 + 16 * (i / 4);
        for (int y = 0; y < image.height; ++y) {
            for (int x = 0; x < image.width; ++x) {
                // Image row y is drawn top down from the billboard's top edge.
                const int row = frame.image.height - 1 - (bottom + image.height - 1 - y);
                const std::uint8_t* texel = image.pixel(x, y);
                INFO("image " << i << " texel (" << x << ", " << y << "): " << describePixel(frame.image, left + x, row));
                // Linear filtering at texel centres: interpolation may leave a weight of 1e-6 on
                // a neighbour, which can move a channel by one step at most.
                REQUIRE(pixelNear(frame.image, left + x, row, {texel[0], texel[1], texel[2], 255}, 1));
            }
        }
    }
    // Nothing else was drawn: every other pixel is the background.
    int drawn = 0;
    for (const Image& image : images) {
        drawn += image.width * image.height;
    }
    REQUIRE(coverage(frame.image).count <= drawn);
}

TEST_CASE("Changing one billboard uploads only its vertex, and nearby changes share one upload", "[scene][billboard][upload]")
{
    Scene scene(kEarth);
    lookFromAbove(scene);
    auto billboards = std::make_shared<BillboardCollection>();
    const std::size_t dot = billboards->addImage(solidImage(3, 3, {255, 255, 255, 255}));
    const std::size_t count = 1000;
    for (std::size_t i = 0; i < count; ++i) {
        Billboard b;
        b.position = kEarth.toCartesian(Geodetic3D::fromDegrees(150.0 + 0.01 * static_cast<double>(i), 0, 0)); // behind the Earth
        b.image = dot;
        billboards->add(b);
    }
    Billboard shown;
    shown.position = kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0, 0));
    shown.image = dot;
    const std::size_t centre = billboards->add(shown);
    scene.add(billboards);
    const std::size_t vertex = BillboardCollection::vertexSizeInBytes();
    REQUIRE(vertex == 44);

    RenderedFrame frame = renderFrame(scene, 32, 32);
    REQUIRE(billboards->lastUpload().fullUpload);
    REQUIRE(billboards->lastUpload().bytesUploaded == (count + 1) * vertex);
    REQUIRE(pixelNear(frame.image, 16, 16, {255, 255, 255, 255}, 0));

    frame = renderFrame(scene, 32, 32);
    REQUIRE(billboards->lastUpload().bytesUploaded == 0);
    REQUIRE(billboards->lastUpload().uploadCalls == 0);

    billboards->setColor(centre, {1, 0, 0, 1});
    frame = renderFrame(scene, 32, 32);
    REQUIRE(billboards->lastUpload().bytesUploaded == vertex);
    REQUIRE(billboards->lastUpload().uploadCalls == 1);
    REQUIRE_FALSE(billboards->lastUpload().fullUpload);
    REQUIRE(pixelNear(frame.image, 16, 16, {255, 0, 0, 255}, 0));

    // Three far apart: three writes of one vertex. Two 3 apart (within the merge gap of 8): one
    // write of 4 vertices.
    billboards->setScale(10, 2.0f);
    billboards->setPixelOffset(500, {1, 1});
    billboards->setVisible(900, false);
    frame = renderFrame(scene, 32, 32);
    REQUIRE(billboards->lastUpload().uploadCalls == 3);
    REQUIRE(billboards->lastUpload().bytesUploaded == 3 * vertex);
    billboards->setPosition(100, kEarth.toCartesian(Geodetic3D::fromDegrees(151, 1, 0)));
    billboards->setPosition(103, kEarth.toCartesian(Geodetic3D::fromDegrees(151, 2, 0)));
    frame = renderFrame(scene, 32, 32);
    REQUIRE(billboards->lastUpload().uploadCalls == 1);
    REQUIRE(billboards->lastUpload().bytesUploaded == 4 * vertex);

    // Moving the shown billboard moves its pixels.
    billboards->setPixelOffset(centre, {-6, 5});
    frame = renderFrame(scene, 32, 32);
    REQUIRE(billboards->lastUpload().bytesUploaded == vertex);
    REQUIRE(pixelNear(frame.image, 16, 16, {0, 0, 0, 255}, 0));
    REQUIRE(pixelNear(frame.image, 10, 20, {255, 0, 0, 255}, 0)); // window (10, 11): the 3x3's centre pixel
}

TEST_CASE("Billboards behind the Earth are hidden by the horizon test, and beside it they show", "[scene][billboard][horizon]")
{
    const int size = 64;
    Scene scene(kEarth);
    lookFromAbove(scene, 3e7); // the horizon cone's half angle: asin(1 / 5.7) = 10 degrees
    const double r = kEarth.radii().x;
    const glm::dvec3 behind(-2.0 * r, 0.5 * r, 0.0);   // 3.7 degrees off the axis, beyond the horizon plane
    const glm::dvec3 beside(-1.0 * r, 1.8 * r, 0.0);   // 15 degrees off: past the Earth's limb
    const glm::dvec3 front = kEarth.toCartesian(Geodetic3D::fromDegrees(5, 0, 0));
    const EllipsoidalOccluder occluder(kEarth, scene.camera().eye());
    REQUIRE_FALSE(occluder.isPointVisible(behind));
    REQUIRE(occluder.isPointVisible(beside));
    REQUIRE(occluder.isPointVisible(front));

    auto billboards = std::make_shared<BillboardCollection>();
    const std::size_t image = billboards->addImage(solidImage(3, 3, {255, 255, 0, 255}));
    for (const glm::dvec3& p : {behind, beside, front}) {
        Billboard b;
        b.position = p;
        b.image = image;
        billboards->add(b);
    }
    scene.add(billboards);
    auto visibleAt = [&](const Image& frame, const glm::dvec3& p) {
        const glm::dvec2 w = windowCoordinates(scene, p, size, size);
        return pixelNear(frame, static_cast<int>(w.x), size - 1 - static_cast<int>(w.y), {255, 255, 0, 255}, 0);
    };
    const Image culled = renderFrame(scene, size, size).image;
    REQUIRE_FALSE(visibleAt(culled, behind));
    REQUIRE(visibleAt(culled, beside));
    REQUIRE(visibleAt(culled, front));
    REQUIRE(coverage(culled).count == 2 * 9);

    billboards->setDepthOptions({.horizonCulling = false});
    const Image all = renderFrame(scene, size, size).image;
    REQUIRE(visibleAt(all, behind));
    REQUIRE(coverage(all).count == 3 * 9);
}

TEST_CASE("A billboard on the surface shows whole over the globe, and with the depth test a cube in front hides it", "[scene][billboard][depth]")
{
    const int size = 64;
    for (const GlobeMethod method : {GlobeMethod::RayCast, GlobeMethod::Tessellated}) {
        INFO((method == GlobeMethod::RayCast ? "ray cast" : "tessellated"));
        Scene scene(kEarth);
        GlobeOptions globeOptions;
        globeOptions.method = method;
        globeOptions.color = {0.0f, 0.0f, 1.0f, 1.0f};
        scene.add(std::make_shared<Globe>(kEarth, globeOptions));
        auto billboards = std::make_shared<BillboardCollection>();
        const std::size_t image = billboards->addImage(solidImage(7, 5, {255, 0, 0, 255}));
        Billboard b;
        b.position = kEarth.toCartesian(Geodetic3D::fromDegrees(10, 30, 0));
        b.image = image;
        billboards->add(b);
        scene.add(billboards);
        auto redPixels = [&](const Image& frame) {
            const glm::dvec2 w = windowCoordinates(scene, b.position, size, size);
            const int left = static_cast<int>(std::floor(w.x + 0.5)) - 3;
            const int bottom = static_cast<int>(std::floor(w.y + 0.5)) - 2;
            int n = 0;
            for (int y = bottom; y < bottom + 5; ++y) {
                for (int x = left; x < left + 7; ++x) {
                    n += pixelNear(frame, x, size - 1 - y, {255, 0, 0, 255}, 0) ? 1 : 0;
                }
            }
            return n;
        };

        // Oblique, 1,000 km up and 10 degrees away: the ground under the lower half of the quad
        // is tens of kilometres nearer the eye than the anchor. The depth test (the default) takes
        // the quad's depth nearer than the anchor by as much as the quad reaches on the screen
        // (about 5 pixels of 26 km), so the ground it stands on does not cut it.
        scene.camera().lookAt(kEarth.toCartesian(Geodetic3D::fromDegrees(0, 30, 1e6)), b.position, {0, 0, 1});
        REQUIRE(redPixels(renderFrame(scene, size, size).image) == 35);

        // Straight down: the surface around the anchor curves away from the eye: no z-fighting.
        scene.camera().lookAt(kEarth.toCartesian(Geodetic3D::fromDegrees(10, 30, 1e6)), b.position, {0, 0, 1});
        REQUIRE(redPixels(renderFrame(scene, size, size).image) == 35);

        // A 200 km cube halfway along the line of sight covers the billboard (about 20 px wide).
        const glm::dvec3 halfway = 0.5 * (scene.camera().eye() + b.position);
        scene.add(std::make_shared<MeshPrimitive>(BoxTessellator::cube(halfway, 1e5), glm::vec4(0, 1, 0, 1)));
        REQUIRE(redPixels(renderFrame(scene, size, size).image) == 0);
        // The depth test is off only for anchors nearer than disableDepthTestDistance (1,000 km).
        billboards->setDepthOptions({.disableDepthTestDistance = 0.9e6});
        REQUIRE(redPixels(renderFrame(scene, size, size).image) == 0);
        billboards->setDepthOptions({.disableDepthTestDistance = 1.1e6});
        REQUIRE(redPixels(renderFrame(scene, size, size).image) == 35);
        billboards->setDepthOptions({.disableDepthTestDistance = std::numeric_limits<double>::infinity()});
        REQUIRE(redPixels(renderFrame(scene, size, size).image) == 35);
    }
}

TEST_CASE("A billboard at 0 m is hidden behind an aircraft 1,500 m above it, and shown with the depth test off", "[scene][billboard][depth][model]")
{
    // Straight down from 5 km over a point of the ray-cast globe: the aircraft (scale 100: 1.1 km
    // long) 1,500 m up, centred over the billboard, covers it.
    constexpr int size = 64;
    const Geodetic2D place = Geodetic2D::fromDegrees(-100.0, 40.0);
    const glm::dvec3 ground = kEarth.toCartesian(Geodetic3D{place.longitude, place.latitude, 0.0});
    Scene scene(kEarth);
    GlobeOptions globeOptions;
    globeOptions.color = {0.0f, 0.0f, 1.0f, 1.0f};
    scene.add(std::make_shared<Globe>(kEarth, globeOptions));
    const std::filesystem::path aircraft = std::filesystem::path(ORBIS_SOURCE_DIR) / "data" / "models" / "aircraft.glb";
    // Lit, so that no shaded pixel of it matches the billboard's pure red (its left wingtip light is red).
    scene.add(ModelPrimitive::fromFile(aircraft, kEarth,
                                       ModelPlacement{Geodetic3D{place.longitude, place.latitude, 1500.0}, {}, 100.0},
                                       ModelOptions{.lighting = true}));
    auto billboards = std::make_shared<BillboardCollection>();
    Billboard b;
    b.position = ground;
    b.image = billboards->addImage(solidImage(3, 3, {255, 0, 0, 255}));
    billboards->add(b);
    scene.add(billboards);
    scene.camera().lookAt(kEarth.toCartesian(Geodetic3D{place.longitude, place.latitude, 5000.0}), ground, {0, 0, 1});
    const Image hidden = renderFrame(scene, size, size).image;
    CHECK(countPixelsNear(hidden, {255, 0, 0, 255}, 0) == 0);
    const glm::ivec4 centre = pixelAt(hidden, size / 2, size / 2);
    INFO(describePixel(hidden, size / 2, size / 2));
    CHECK(centre.b < 200); // the aircraft, not the globe

    billboards->setDepthOptions({.disableDepthTestDistance = std::numeric_limits<double>::infinity()});
    CHECK(countPixelsNear(renderFrame(scene, size, size).image, {255, 0, 0, 255}, 0) == 9);
}

TEST_CASE("Without the horizon test, the globe's depth hides a billboard behind it unless the depth test is off", "[scene][billboard][depth][globe]")
{
    // A billboard on the far side of the globe, seen through it: only the depth test hides it.
    constexpr int size = 64;
    Scene scene(kEarth);
    GlobeOptions globeOptions;
    globeOptions.color = {0.0f, 0.0f, 1.0f, 1.0f};
    scene.add(std::make_shared<Globe>(kEarth, globeOptions));
    lookFromAbove(scene, 2e7);
    auto billboards = std::make_shared<BillboardCollection>(
        BillboardCollectionOptions{.depth = {.horizonCulling = false}});
    Billboard b;
    b.position = kEarth.toCartesian(Geodetic3D::fromDegrees(180, 0, 0)); // the antipode, on the axis
    b.image = billboards->addImage(solidImage(3, 3, {255, 0, 0, 255}));
    billboards->add(b);
    scene.add(billboards);
    CHECK(countPixelsNear(renderFrame(scene, size, size).image, {255, 0, 0, 255}, 0) == 0);
    billboards->setDepthOptions({.horizonCulling = false, .disableDepthTestDistance = std::numeric_limits<double>::infinity()});
    CHECK(countPixelsNear(renderFrame(scene, size, size).image, {255, 0, 0, 255}, 0) == 9);
}

TEST_CASE("The built-in dot and square are white, their size across, the square opaque to its edge", "[scene][billboard]")
{
    const Image square = billboardShapeImage(BillboardShape::Square, 6);
    REQUIRE(square.width == 6);
    REQUIRE(square.height == 6);
    REQUIRE(square.channels == 4);
    for (int y = 0; y < 6; ++y) {
        for (int x = 0; x < 6; ++x) {
            const std::uint8_t* p = square.pixel(x, y);
            REQUIRE((p[0] == 255 && p[1] == 255 && p[2] == 255 && p[3] == 255));
        }
    }
    // The dot: opaque at the centre, clear in the corners, its edge pixels partly covered; 10 px
    // across covers pi 25 = 78.5 pixels.
    const Image dot = billboardShapeImage(BillboardShape::Dot, 10);
    REQUIRE(dot.width == 10);
    REQUIRE(dot.pixel(4, 4)[3] == 255);
    REQUIRE(dot.pixel(0, 0)[3] == 0);
    double coverage = 0.0;
    int partial = 0;
    for (int y = 0; y < 10; ++y) {
        for (int x = 0; x < 10; ++x) {
            const int alpha = dot.pixel(x, y)[3];
            coverage += alpha / 255.0;
            partial += alpha > 0 && alpha < 255 ? 1 : 0;
            REQUIRE(dot.pixel(x, y)[0] == 255);
        }
    }
    CHECK_THAT(coverage, Catch::Matchers::WithinAbs(78.5, 1.0)); // within a pixel of the disc's area
    CHECK(partial >= 20);
    REQUIRE(billboardShapeImage(BillboardShape::Square, 0).width == 1);
}

TEST_CASE("A billboard collection renders as its golden image", "[scene][billboard][golden]")
{
    Scene scene(kEarth);
    GlobeOptions globeOptions;
    globeOptions.color = {0.1f, 0.2f, 0.45f, 1.0f};
    scene.add(std::make_shared<Globe>(kEarth, globeOptions));
    lookFromAbove(scene, 1.2e7);
    auto billboards = std::make_shared<BillboardCollection>();
    // A 5x5 ring with a transparent centre, and a 3x3 dot.
    Image ring = solidImage(5, 5, {255, 255, 255, 255});
    for (int y = 1; y < 4; ++y) {
        for (int x = 1; x < 4; ++x) {
            ring.pixel(x, y)[3] = 0;
        }
    }
    const std::size_t ringImage = billboards->addImage(ring);
    const std::size_t dotImage = billboards->addImage(solidImage(3, 3, {255, 255, 255, 255}));
    for (int lat = -80; lat <= 80; lat += 10) {
        for (int lon = -180; lon < 180; lon += 10) {
            Billboard b;
            b.position = kEarth.toCartesian(Geodetic3D::fromDegrees(lon, lat, 0));
            const bool ringed = (lat + lon) % 20 == 0;
            b.image = ringed ? ringImage : dotImage;
            b.color = ringed ? glm::vec4(1.0f, 0.8f, 0.2f, 1.0f) : glm::vec4(0.9f, 0.9f, 0.9f, 0.8f);
            billboards->add(b);
        }
    }
    scene.add(billboards);
    const RenderedFrame frame = renderFrame(scene, 128, 128);
    // Exact on llvmpipe; a GPU may round the globe's edge and blends differently.
    ORBIS_REQUIRE_GOLDEN(frame.image, "scene/billboards", test::exactOnLlvmpipe(test::sharedDevice(), {2, 0.01}));
}

TEST_CASE("All 171,075 GeoNames cities draw in one call and exactly those in front of the horizon show", "[scene][billboard][horizon][cities]")
{
    const CsvPoints cities =
        loadCsvPoints(std::filesystem::path(ORBIS_SOURCE_DIR) / "data" / "geonames" / "cities.csv");
    REQUIRE(cities.size() == 171075);
    const int size = 256;
    Scene scene(kEarth);
    // Over the Atlantic at 35 N: Europe, Africa and the Americas in front, Asia and Oceania behind.
    scene.camera().lookAt(kEarth.toCartesian(Geodetic3D::fromDegrees(-30, 35, 1.5e7)), glm::dvec3(0.0), {0, 0, 1});
    auto billboards = std::make_shared<BillboardCollection>();
    const std::size_t pixel = billboards->addImage(solidImage(1, 1, {255, 255, 255, 255}));
    billboards->reserve(cities.size());
    for (const Geodetic3D& city : cities.positions) {
        Billboard b;
        b.position = kEarth.toCartesian(city);
        b.image = pixel;
        b.horizontalOrigin = HorizontalOrigin::Left;
        b.verticalOrigin = VerticalOrigin::Bottom;
        billboards->add(b);
    }
    scene.add(billboards);
    const RenderedFrame frame = renderFrame(scene, size, size);
    REQUIRE(frame.statistics.renderer.drawCalls == 1);
    REQUIRE(frame.statistics.renderer.primitives == cities.size());

    // The shader's horizon test in double: pixels of cities clearly in front must be lit, and a
    // lit pixel must belong to a city in front or within rounding of the horizon (1e-5 of the
    // test's terms; float carries about 6e-8) or of a half pixel (0.01 px).
    const glm::dvec3 eyeScaled = scene.camera().eye() * kEarth.oneOverRadii();
    const double horizon = glm::dot(eyeScaled, eyeScaled) - 1.0;
    std::vector<std::uint8_t> must(static_cast<std::size_t>(size * size), 0);
    std::vector<std::uint8_t> may(static_cast<std::size_t>(size * size), 0);
    std::size_t inFront = 0;
    std::size_t behind = 0;
    for (const Geodetic3D& city : cities.positions) {
        const glm::dvec3 p = kEarth.toCartesian(city);
        const glm::dvec3 toCity = (p - scene.camera().eye()) * kEarth.oneOverRadii();
        const double along = -glm::dot(toCity, eyeScaled);
        const double coneTerm = along * along - horizon * glm::dot(toCity, toCity);
        const bool hidden = along > horizon && coneTerm > 0.0;
        const bool marginal = std::abs(along - horizon) < 1e-5 * horizon || std::abs(coneTerm) < 1e-5 * along * along;
        (hidden ? behind : inFront) += 1;
        if (hidden && !marginal) {
            continue;
        }
        const glm::dvec2 w = windowCoordinates(scene, p, size, size);
        const glm::dvec2 fraction = w - glm::floor(w);
        const bool sure = !marginal && std::abs(fraction.x - 0.5) > 0.01 && std::abs(fraction.y - 0.5) > 0.01;
        for (const double dx : {-0.01, 0.0, 0.01}) {
            for (const double dy : {-0.01, 0.0, 0.01}) {
                const int x = static_cast<int>(std::floor(w.x + dx + 0.5));
                const int y = static_cast<int>(std::floor(w.y + dy + 0.5));
                if (x >= 0 && y >= 0 && x < size && y < size) {
                    const auto index = static_cast<std::size_t>((size - 1 - y) * size + x);
                    may[index] = 1;
                    if (sure && dx == 0.0 && dy == 0.0) {
                        must[index] = 1;
                    }
                }
            }
        }
    }
    INFO(inFront << " cities in front, " << behind << " behind");
    REQUIRE(behind > 20000);
    REQUIRE(inFront > 20000);
    int lit = 0;
    for (int row = 0; row < size; ++row) {
        for (int x = 0; x < size; ++x) {
            const auto index = static_cast<std::size_t>(row * size + x);
            const bool on = !pixelNear(frame.image, x, row, kBackground, 0);
            lit += on ? 1 : 0;
            INFO("pixel (" << x << ", " << row << ") " << describePixel(frame.image, x, row));
            if (must[index]) {
                REQUIRE(on);
            }
            if (on) {
                REQUIRE(may[index]);
            }
        }
    }
    REQUIRE(lit > 5000);
}
