#include "SceneTestSupport.h"

#include "GoldenImage.h"
#include "RendererTestSupport.h"

#include <orbis/scene/BillboardCollection.h>
#include <orbis/scene/Globe.h>
#include <orbis/scene/LabelCollection.h>
#include <orbis/scene/SceneBuilder.h>
#include <orbis/world/SceneFile.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace orbis;
using namespace orbis::world;
using namespace orbis::renderer;
using namespace orbis::scene;
using namespace orbis::test;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

/// The camera 10,000 km over (0, 0) looking at the centre: the surface point (0, 0) projects to
/// the view's centre, a pixel corner.
void lookFromAbove(Scene& scene)
{
    scene.camera().lookAt(kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0, 1e7)), glm::dvec3(0.0), {0, 0, 1});
}

/// What a label drawn white with no halo over black must look like: each glyph's coverage
/// composited "over" the ones before it, at the pixels its layout and placement give (the
/// anchor's pixel corner at `anchor`, window coordinates). Values 0..1, rows from the top.
std::vector<float> expectedText(LabelCollection& labels, std::size_t index, const glm::ivec2& anchor, int width,
                                int height)
{
    std::vector<float> value(static_cast<std::size_t>(width * height), 0.0f);
    const Label& label = labels.label(index);
    const TextLayout& layout = labels.layout(index);
    const PixelRectangle place = labels.placement(index);
    const TextureAtlas& atlas = labels.glyphAtlas(label.fontSizePixels).atlas();
    // The layout's box, y down from the first baseline, has its top-left at `place` (y down
    // from the anchor's pixel corner).
    const int originX = anchor.x + place.x - layout.bounds.x;
    const int baselineY = anchor.y - (place.y - layout.bounds.y);
    for (const GlyphQuad& quad : layout.quads) {
        const PixelRectangle r = atlas.rectangle(quad.atlasIndex);
        for (int row = 0; row < quad.height; ++row) {
            for (int column = 0; column < quad.width; ++column) {
                const int x = originX + quad.x + column;
                const int y = baselineY - quad.y - row - 1; // window y of the pixel below that line
                if (x < 0 || y < 0 || x >= width || y >= height) {
                    continue;
                }
                const float coverage = atlas.image().pixel(r.x + column, r.y + row)[0] / 255.0f;
                float& v = value[static_cast<std::size_t>((height - 1 - y) * width + x)];
                v = coverage + v * (1.0f - coverage);
            }
        }
    }
    return value;
}

/// The largest difference (0..255) between the image's red channel and the expected values, and
/// whether green and blue equal red everywhere (white over black).
struct TextDifference {
    int maxDifference = 0;
    int worstX = 0;
    int worstY = 0;
    int inked = 0; ///< pixels expected non-zero
};

TextDifference compareText(const Image& image, const std::vector<float>& expected)
{
    TextDifference d;
    for (int row = 0; row < image.height; ++row) {
        for (int x = 0; x < image.width; ++x) {
            const glm::ivec4 p = pixelAt(image, x, row);
            const int want = static_cast<int>(std::lround(expected[static_cast<std::size_t>(row * image.width + x)] * 255.0f));
            d.inked += want > 0 ? 1 : 0;
            const int difference = std::max({std::abs(p.r - want), std::abs(p.g - want), std::abs(p.b - want)});
            if (difference > d.maxDifference) {
                d.maxDifference = difference;
                d.worstX = x;
                d.worstY = row;
            }
        }
    }
    return d;
}

Label whiteText(const std::string& text)
{
    Label label;
    label.position = kEarth.toCartesian(Geodetic3D::fromDegrees(0, 0, 0));
    label.text = text;
    label.fillColor = {1, 1, 1, 1};
    label.haloColor = {0, 0, 0, 0};
    return label;
}

} // namespace

TEST_CASE("A label's text pixels are where its layout says, texel for pixel, for every origin and offset", "[scene][label]")
{
    const int width = 160;
    const int height = 64;
    Scene scene(kEarth);
    lookFromAbove(scene);
    auto labels = std::make_shared<LabelCollection>();
    labels->add(whiteText("Zürich, Wąchock"));
    scene.add(labels);
    const glm::ivec2 anchor(width / 2, height / 2);
    const glm::ivec2 offsets[] = {{0, 0}, {3, -5}, {-11, 7}};
    int trial = 0;
    for (int h = 0; h < 3; ++h) {
        for (int v = 0; v < 3; ++v) {
            labels->setOrigin(0, static_cast<HorizontalOrigin>(h), static_cast<VerticalOrigin>(v));
            labels->setPixelOffset(0, offsets[trial++ % 3]);
            const RenderedFrame frame = renderFrame(scene, width, height);
            const TextDifference d = compareText(frame.image, expectedText(*labels, 0, anchor, width, height));
            INFO("origin " << h << ", " << v << ": worst pixel (" << d.worstX << ", " << d.worstY << ") "
                           << describePixel(frame.image, d.worstX, d.worstY) << " off by " << d.maxDifference);
            REQUIRE(d.inked > 200);
            // One step for the texture's 8-bit coverage and one for each blend of overlapping glyphs.
            REQUIRE(d.maxDifference <= 2);
        }
    }
    REQUIRE(labels->lastDrawCalls() == 1);
}

TEST_CASE("Placement centres a label above its point by default, and offsets go right and down", "[scene][label]")
{
    auto labels = std::make_shared<LabelCollection>();
    Label label = whiteText("Orbis");
    labels->add(label);
    const PixelRectangle box = labels->layout(0).bounds;
    const PixelRectangle place = labels->placement(0);
    REQUIRE(place.width == box.width);
    REQUIRE(place.height == box.height);
    REQUIRE(place.x == -(box.width / 2));
    REQUIRE(place.y == -box.height); // its bottom edge on the anchor: the top a box height above
    labels->setPixelOffset(0, {4, 9});
    labels->setOrigin(0, HorizontalOrigin::Right, VerticalOrigin::Top);
    REQUIRE(labels->placement(0).x == 4 - box.width);
    REQUIRE(labels->placement(0).y == 9); // top edge on the anchor, 9 px down
}

TEST_CASE("A label's halo surrounds the fill in the halo colour", "[scene][label]")
{
    const int size = 64;
    SceneOptions options;
    options.background = {0.0f, 0.0f, 1.0f, 1.0f};
    Scene scene(kEarth, options);
    lookFromAbove(scene);
    LabelCollectionOptions labelOptions;
    labelOptions.haloPixels = 2;
    auto labels = std::make_shared<LabelCollection>(labelOptions);
    Label label = whiteText("O");
    label.fontSizePixels = 24.0f;
    label.haloColor = {0, 0, 0, 1};
    label.horizontalOrigin = HorizontalOrigin::Left;
    labels->add(label);
    scene.add(labels);
    const Image image = renderFrame(scene, size, size).image;

    const TextLayout& layout = labels->layout(0);
    REQUIRE(layout.quads.size() == 1);
    const GlyphQuad& quad = layout.quads[0];
    const PixelRectangle place = labels->placement(0);
    const TextureAtlas& atlas = labels->glyphAtlas(24.0f).atlas();
    const PixelRectangle r = atlas.rectangle(quad.atlasIndex);
    int fill = 0;
    int halo = 0;
    for (int row = 0; row < quad.height; ++row) {
        for (int column = 0; column < quad.width; ++column) {
            const std::uint8_t* texel = atlas.image().pixel(r.x + column, r.y + row);
            // One glyph: its quad is the label's box.
            const int x = size / 2 + place.x + column;
            const int imageRow = size / 2 + place.y + row; // y down from the anchor's row line
            INFO("glyph texel (" << column << ", " << row << ") coverage " << int(texel[0]) << " halo " << int(texel[1])
                                 << ": " << describePixel(image, x, imageRow));
            if (texel[0] == 255) {
                REQUIRE(pixelNear(image, x, imageRow, {255, 255, 255, 255}, 0));
                ++fill;
            } else if (texel[0] == 0 && texel[1] == 255) {
                REQUIRE(pixelNear(image, x, imageRow, {0, 0, 0, 255}, 0));
                ++halo;
            } else if (texel[1] == 0) {
                REQUIRE(pixelNear(image, x, imageRow, {0, 0, 255, 255}, 0));
            }
        }
    }
    REQUIRE(fill > 20);
    REQUIRE(halo > 40); // a ring two pixels wide outside the O and inside its counter
}

TEST_CASE("Changing a label uploads only its glyphs, and a new glyph count rewrites its font size", "[scene][label][upload]")
{
    Scene scene(kEarth);
    lookFromAbove(scene);
    auto labels = std::make_shared<LabelCollection>();
    labels->add(whiteText("Alpha"));
    labels->add(whiteText("Beta"));
    Label big = whiteText("Gamma");
    big.fontSizePixels = 24.0f;
    labels->add(big);
    scene.add(labels);
    constexpr std::size_t kGlyphVertex = 48;

    renderFrame(scene, 32, 32);
    REQUIRE(labels->lastDrawCalls() == 2); // 16 px and 24 px
    REQUIRE(labels->lastUpload().fullUpload);
    REQUIRE(labels->lastUpload().bytesUploaded == 14 * kGlyphVertex);
    REQUIRE(labels->lastUpload().textureBytesUploaded > 0);

    renderFrame(scene, 32, 32);
    REQUIRE(labels->lastUpload().bytesUploaded == 0);
    REQUIRE(labels->lastUpload().textureBytesUploaded == 0);

    labels->setColors(1, {1, 0, 0, 1}, {0, 0, 0, 1});
    renderFrame(scene, 32, 32);
    REQUIRE(labels->lastUpload().bytesUploaded == 4 * kGlyphVertex);
    REQUIRE(labels->lastUpload().uploadCalls == 1);

    labels->setText(1, "Bête"); // same glyph count; one new glyph in the atlas
    renderFrame(scene, 32, 32);
    REQUIRE(labels->lastUpload().bytesUploaded == 4 * kGlyphVertex);
    REQUIRE(labels->lastUpload().textureBytesUploaded > 0);
    REQUIRE(labels->lastUpload().textureBytesUploaded < 256 * 256 * 4); // the glyph's rectangle, not the atlas

    labels->setText(1, "Be"); // the 16 px labels' runs move: that size is written again
    renderFrame(scene, 32, 32);
    REQUIRE(labels->lastUpload().fullUpload);
    REQUIRE(labels->lastUpload().bytesUploaded == (5 + 2) * kGlyphVertex);
}

TEST_CASE("Labels behind the Earth are hidden", "[scene][label][horizon]")
{
    Scene scene(kEarth);
    lookFromAbove(scene);
    auto labels = std::make_shared<LabelCollection>();
    Label label = whiteText("Antipode");
    label.position = kEarth.toCartesian(Geodetic3D::fromDegrees(180, 0, 0)); // straight behind, on the axis
    labels->add(label);
    scene.add(labels);
    const Image hidden = renderFrame(scene, 64, 64).image;
    for (int y = 0; y < 64; ++y) {
        for (int x = 0; x < 64; ++x) {
            INFO(x << ", " << y);
            REQUIRE(pixelNear(hidden, x, y, {0, 0, 0, 255}, 0));
        }
    }
    labels->setDepthOptions({.horizonCulling = false});
    const Image shown = renderFrame(scene, 64, 64).image;
    int inked = 0;
    for (int y = 0; y < 64; ++y) {
        for (int x = 0; x < 64; ++x) {
            inked += pixelNear(shown, x, y, {0, 0, 0, 255}, 0) ? 0 : 1;
        }
    }
    REQUIRE(inked > 50);
}

TEST_CASE("A depth-tested label hanging below its anchor at a slant is not cut by the globe it stands on", "[scene][label][depth]")
{
    // 1,000 km up and 10 degrees away, the label hangs below its anchor (origin top): the ground
    // under its box is tens of kilometres nearer the eye than the anchor. Its depth is taken
    // nearer by as many metres as the box reaches on the screen, so the depth test (the default)
    // draws exactly what no depth test does.
    constexpr int size = 96;
    Scene scene(kEarth);
    GlobeOptions globeOptions;
    globeOptions.color = {0.0f, 0.0f, 1.0f, 1.0f};
    scene.add(std::make_shared<Globe>(kEarth, globeOptions));
    const glm::dvec3 anchor = kEarth.toCartesian(Geodetic3D::fromDegrees(10, 30, 0));
    scene.camera().lookAt(kEarth.toCartesian(Geodetic3D::fromDegrees(0, 30, 1e6)), anchor, {0, 0, 1});
    auto labels = std::make_shared<LabelCollection>();
    Label label = whiteText("Wien\nBratislava");
    label.position = anchor;
    label.haloColor = {0, 0, 0, 1};
    label.verticalOrigin = VerticalOrigin::Top;
    labels->add(label);
    scene.add(labels);
    const Image tested = renderFrame(scene, size, size).image;
    labels->setDepthOptions({.disableDepthTestDistance = std::numeric_limits<double>::infinity()});
    const Image untested = renderFrame(scene, size, size).image;
    int inked = 0;
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            INFO(x << ", " << y << ": " << describePixel(tested, x, y) << " untested " << describePixel(untested, x, y));
            REQUIRE(pixelAt(tested, x, y) == pixelAt(untested, x, y));
            inked += pixelAt(tested, x, y).r > 128 ? 1 : 0;
        }
    }
    REQUIRE(inked > 50);
}

TEST_CASE("Labels over billboards on a globe render as their golden image", "[scene][label][golden]")
{
    Scene scene(kEarth);
    GlobeOptions globeOptions;
    globeOptions.color = {0.1f, 0.3f, 0.2f, 1.0f};
    scene.add(std::make_shared<Globe>(kEarth, globeOptions));
    scene.camera().lookAt(kEarth.toCartesian(Geodetic3D::fromDegrees(9.5, 48.6, 1.1e6)),
                          kEarth.toCartesian(Geodetic3D::fromDegrees(9.5, 48.6, 0)), {0, 0, 1});
    auto billboards = std::make_shared<BillboardCollection>();
    Image dot(3, 3, 4);
    std::fill(dot.pixels.begin(), dot.pixels.end(), std::uint8_t{255});
    const std::size_t dotImage = billboards->addImage(dot);
    auto labels = std::make_shared<LabelCollection>();
    struct City {
        const char* name;
        double lon;
        double lat;
    };
    for (const City& city : {City{"Paris", 2.35, 48.86}, City{"München", 11.58, 48.14}, City{"Wien", 16.37, 48.21},
                             City{"Zürich", 8.54, 47.37}, City{"Praha", 14.42, 50.09}}) {
        const glm::dvec3 position = kEarth.toCartesian(Geodetic3D::fromDegrees(city.lon, city.lat, 0));
        Billboard b;
        b.position = position;
        b.image = dotImage;
        b.color = {1.0f, 0.9f, 0.3f, 1.0f};
        billboards->add(b);
        Label label;
        label.position = position;
        label.text = city.name;
        label.fontSizePixels = 13.0f;
        label.pixelOffset = {0, -3}; // 3 px above
        labels->add(label);
    }
    scene.add(billboards);
    scene.add(labels);
    const RenderedFrame frame = renderFrame(scene, 192, 128);
    REQUIRE(frame.statistics.translucentPasses == 1);
    // Exact on llvmpipe; a GPU may round the globe's edge and blends differently.
    ORBIS_REQUIRE_GOLDEN(frame.image, "scene/labels", test::exactOnLlvmpipe(test::sharedDevice(), {2, 0.01}));
}

TEST_CASE("Decluttering hides a label that overlaps an earlier one shown, and nothing else", "[scene][label][declutter]")
{
    Scene scene(kEarth);
    lookFromAbove(scene);
    auto labels = std::make_shared<LabelCollection>();
    const auto colored = [](const std::string& text, const glm::vec4& color, int offsetY) {
        Label label = whiteText(text);
        label.fillColor = color;
        label.pixelOffset = {0, offsetY};
        return label;
    };
    // First, behind the Earth on the same line of sight: it takes no room.
    Label antipode = colored("Antipode", {1, 1, 0, 1}, 0);
    antipode.position = kEarth.toCartesian(Geodetic3D::fromDegrees(180, 0, 0));
    labels->add(antipode);
    labels->add(colored("Alpha", {1, 0, 0, 1}, 0));  // shown
    labels->add(colored("Beta", {0, 1, 0, 1}, 0));   // on top of Alpha
    labels->add(colored("Gamma", {0, 0, 1, 1}, 26)); // below Alpha, clear of it
    scene.add(labels);
    const auto count = [](const Image& image, const glm::ivec3& color) {
        int n = 0;
        for (int y = 0; y < image.height; ++y) {
            for (int x = 0; x < image.width; ++x) {
                const std::uint8_t* p = image.pixel(x, y);
                n += (color.r ? p[0] > 128 : p[0] < 64) && (color.g ? p[1] > 128 : p[1] < 64) &&
                             (color.b ? p[2] > 128 : p[2] < 64)
                         ? 1
                         : 0;
            }
        }
        return n;
    };
    constexpr int kWidth = 96;
    constexpr int kHeight = 80;
    constexpr std::size_t kGlyphVertex = 48;

    const Image cluttered = renderFrame(scene, kWidth, kHeight).image;
    REQUIRE(labels->lastDecluttered() == 0);
    REQUIRE(count(cluttered, {1, 0, 0}) > 10);
    REQUIRE(count(cluttered, {0, 1, 0}) > 10);
    REQUIRE(count(cluttered, {0, 0, 1}) > 10);
    REQUIRE(count(cluttered, {1, 1, 0}) == 0); // the antipode's label is behind the horizon

    labels->setDeclutter(true);
    const Image decluttered = renderFrame(scene, kWidth, kHeight).image;
    REQUIRE(labels->lastDecluttered() == 1);
    REQUIRE(labels->lastUpload().bytesUploaded == 4 * kGlyphVertex); // Beta's glyphs alone
    REQUIRE(count(decluttered, {0, 1, 0}) == 0);
    REQUIRE(count(decluttered, {1, 0, 0}) > 10);
    REQUIRE(count(decluttered, {0, 0, 1}) == count(cluttered, {0, 0, 1}));

    // Steady view: nothing changes, nothing is uploaded.
    renderFrame(scene, kWidth, kHeight);
    REQUIRE(labels->lastUpload().bytesUploaded == 0);

    // Earlier labels win only while shown: with Alpha hidden, Beta takes its place.
    labels->setVisible(1, false);
    const Image betaShown = renderFrame(scene, kWidth, kHeight).image;
    REQUIRE(labels->lastDecluttered() == 0);
    REQUIRE(count(betaShown, {0, 1, 0}) > 10);
    REQUIRE(count(betaShown, {1, 0, 0}) == 0);

    // Off again: every label as asked.
    labels->setVisible(1, true);
    labels->setDeclutter(false);
    const Image again = renderFrame(scene, kWidth, kHeight).image;
    REQUIRE(labels->lastDecluttered() == 0);
    REQUIRE(again.pixels == cluttered.pixels);
}

TEST_CASE("A scene file's label declutter key turns decluttering on for its layer", "[scene][label][declutter][scenefile]")
{
    const auto labelsOf = [](const std::string& labelKeys) {
        const std::string text = R"({"version": 2, "camera": {"position": {"lon": 10, "lat": 20, "height": 15000000}},
            "layers": [{"type": "points", "source": "capitals.csv", "label": {"field": "name")" + labelKeys + "}}]}";
        auto scene = std::make_unique<Scene>(kEarth);
        populateScene(parseSceneText(text, "labels.json", ORBIS_SOURCE_DIR "/data/scenes"), *scene);
        std::shared_ptr<LabelCollection> labels;
        for (const auto& primitive : scene->primitives()) {
            if (auto found = std::dynamic_pointer_cast<LabelCollection>(primitive)) {
                labels = found;
            }
        }
        REQUIRE(labels);
        renderFrame(*scene, 160, 90);
        return std::pair{labels->options().declutter, labels->lastDecluttered()};
    };
    // The capitals of Europe and Africa on 160 x 90 pixels: many names overlap (14 are left out).
    const auto [on, hidden] = labelsOf(R"(, "declutter": true)");
    REQUIRE(on);
    REQUIRE(hidden >= 10);
    const auto [off, none] = labelsOf("");
    REQUIRE_FALSE(off);
    REQUIRE(none == 0);
}
