// Scenes that differ by one key of the scene file: exactly that effect appears in the frame
// statistics, and the pixels change. A scene pays for nothing it does not contain.
#include "SceneTestSupport.h"

#include "RendererTestSupport.h"

#include <orbis/scene/Globe.h>
#include <orbis/scene/SceneBuilder.h>
#include <orbis/world/SceneFile.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>

using namespace orbis;
using namespace orbis::world;
using namespace orbis::scene;
using namespace orbis::test;

namespace {

const std::filesystem::path kScenes = std::filesystem::path(ORBIS_SOURCE_DIR) / "data/scenes";

/// A night-side view of Europe in winter dusk, globe textured; `extra` adds keys to the root and
/// `globeExtra` to the globe object.
std::string sceneText(const std::string& extra = "", const std::string& globeExtra = "",
                      const std::string& cameraHeight = "12000000")
{
    return R"({"version": 2, "width": 96, "height": 96,
      "camera": {"position": {"lon": 20, "lat": 45, "height": )" +
           cameraHeight + R"(}, "target": {"lon": 20, "lat": 45, "height": 0}, "fovY": 40},
      "globe": {"texture": "/usr/share/xplanet/images/earth.jpg")" +
           globeExtra + "}" + extra + "}";
}

struct Frame {
    std::set<std::string> effects;
    Image image;
};

Frame render(const std::string& text)
{
    const SceneDescription description = parseSceneText(text, "test", kScenes);
    Scene scene;
    populateScene(description, scene);
    RenderedFrame frame = renderFrame(scene, description.width, description.height);
    const std::vector<std::string> names = frame.statistics.effectsRun();
    return {std::set<std::string>(names.begin(), names.end()), std::move(frame.image)};
}

/// Effects in `with` but not in `without`, and the other way round.
std::set<std::string> difference(const std::set<std::string>& a, const std::set<std::string>& b)
{
    std::set<std::string> result;
    std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::inserter(result, result.begin()));
    return result;
}

/// Pixels whose colour differs by more than 8 in some channel.
long changedPixels(const Image& a, const Image& b)
{
    long changed = 0;
    for (int y = 0; y < a.height; ++y) {
        for (int x = 0; x < a.width; ++x) {
            for (int c = 0; c < 3; ++c) {
                if (std::abs(int(a.pixel(x, y)[c]) - int(b.pixel(x, y)[c])) > 8) {
                    ++changed;
                    break;
                }
            }
        }
    }
    return changed;
}

void requireOnlyEffect(const Frame& without, const Frame& with, const std::set<std::string>& expected)
{
    INFO("without: " << without.effects.size() << " effects, with: " << with.effects.size());
    REQUIRE(difference(with.effects, without.effects) == expected);
    REQUIRE(difference(without.effects, with.effects).empty());
    REQUIRE(changedPixels(without.image, with.image) > 20);
}

} // namespace

TEST_CASE("The base scene draws a bare globe and nothing else", "[scene][effects]")
{
    const Frame base = render(sceneText());
    REQUIRE(base.effects == std::set<std::string>{"globe"});
}

TEST_CASE("Placing the Sun adds lighting and nothing else", "[scene][effects]")
{
    requireOnlyEffect(render(sceneText()), render(sceneText(R"(, "time": "2026-12-21T18:00:00Z")")), {"lighting"});
}

TEST_CASE("A globe built through the API is unlit by default, as a file's without a Sun, and the same picture",
          "[scene][effects]")
{
    // The file's globe and the API's default one: the same options but for the texture and lighting.
    const Frame file = render(sceneText());
    const SceneDescription description = parseSceneText(sceneText(), "test", kScenes);
    for (const bool lighting : {false, true}) {
        INFO("lighting " << lighting);
        Scene scene;
        scene.camera() = makeCamera(description.camera, scene.ellipsoid());
        GlobeOptions options;
        options.dayTexture = "/usr/share/xplanet/images/earth.jpg";
        if (lighting) {
            options.lighting = true;
        }
        scene.add(std::make_shared<Globe>(scene.ellipsoid(), options));
        const RenderedFrame frame = renderFrame(scene, description.width, description.height);
        const std::vector<std::string> names = frame.statistics.effectsRun();
        CHECK(std::set<std::string>(names.begin(), names.end()) ==
              (lighting ? std::set<std::string>{"globe", "lighting"} : file.effects));
        if (lighting) {
            CHECK(changedPixels(frame.image, file.image) > 20);
        } else {
            CHECK(changedPixels(frame.image, file.image) == 0);
        }
    }
}

TEST_CASE("A night texture adds night lights and nothing else", "[scene][effects]")
{
    const std::string dusk = R"(, "time": "2026-12-21T18:00:00Z")";
    requireOnlyEffect(render(sceneText(dusk)),
                      render(sceneText(dusk, R"(, "nightTexture": "/usr/share/xplanet/images/night.jpg")")),
                      {"night lights"});
}

TEST_CASE("The grid key adds the grid and nothing else", "[scene][effects]")
{
    requireOnlyEffect(render(sceneText()), render(sceneText("", R"(, "grid": true)")), {"grid"});
}

TEST_CASE("A points layer adds billboards and the translucent pass, its label key adds labels", "[scene][effects]")
{
    const std::string points = R"(, "layers": [{"type": "points", "source": "capitals.csv", "billboard": {"size": 6}}])";
    const std::string labelled = R"(, "layers": [{"type": "points", "source": "capitals.csv", "billboard": {"size": 6},
                                    "label": {"field": "name", "size": 12}}])";
    requireOnlyEffect(render(sceneText()), render(sceneText(points)), {"billboards", "translucent pass"});
    requireOnlyEffect(render(sceneText(points)), render(sceneText(labelled)), {"labels"});
}

TEST_CASE("Flying low adds a depth strategy only when the depth range needs it", "[scene][effects]")
{
    // From orbit the globe fits one frustum. 300 m up, looking along the ground at a billboard
    // 40 km away, the range is too deep for one: near ~250 m, far past the horizon. "auto" then
    // pays for complementary depth where the driver has glClipControl and for logarithmic depth
    // where it does not (docs/precision.md); "multi-frustum" for more frustums.
    const std::string low = R"({"version": 2, "width": 96, "height": 96,
      "camera": {"position": {"lon": 20, "lat": 45, "height": 300}, "heading": 0, "pitch": -2, "fovY": 40},
      "globe": {"texture": "/usr/share/xplanet/images/earth.jpg"}, "depth": "%s"})";
    auto withDepth = [&](const std::string& depth) {
        std::string text = low;
        text.replace(text.find("%s"), 2, depth);
        return text;
    };
    const Frame high = render(sceneText());
    const Frame automatic = render(withDepth("auto"));
    const std::string resolving = sharedDevice().info().clipControl ? "complementary depth" : "logarithmic depth";
    REQUIRE(difference(automatic.effects, high.effects) == std::set<std::string>{resolving});
    REQUIRE(difference(high.effects, automatic.effects).empty());
    const Frame split = render(withDepth("multi-frustum"));
    REQUIRE(difference(split.effects, high.effects) == std::set<std::string>{"multi-frustum"});
    REQUIRE(difference(high.effects, split.effects).empty());
}

TEST_CASE("A GeoJSON layer's stroke adds polylines, its translucent fill adds polygons and the translucent pass", "[scene][effects]")
{
    const std::string source = R"("source": "../natural-earth/countries-110m.geojson")";
    requireOnlyEffect(render(sceneText()),
                      render(sceneText(R"(, "layers": [{"type": "geojson", )" + source +
                                       R"(, "stroke": {"color": "#ffff00", "width": 2}}])")),
                      {"polylines"});
    requireOnlyEffect(render(sceneText()),
                      render(sceneText(R"(, "layers": [{"type": "geojson", )" + source +
                                       R"(, "fill": {"color": "#ff000080"}}])")),
                      {"polygons", "translucent pass"});
}

TEST_CASE("A polyline layer adds polylines and nothing else", "[scene][effects]")
{
    requireOnlyEffect(render(sceneText()),
                      render(sceneText(R"(, "layers": [{"type": "polyline", "width": 3, "color": "#ff0000ff",
                                             "positions": [[0, 40, 0], [40, 50, 0]]}])")),
                      {"polylines"});
}

TEST_CASE("A model layer adds models and nothing else", "[scene][effects]")
{
    // The project's aircraft scaled up some 100,000 times, so that it covers pixels from orbit.
    requireOnlyEffect(render(sceneText()),
                      render(sceneText(R"(, "layers": [{"type": "model", "source": "../models/aircraft.glb",
                                             "position": {"lon": 20, "lat": 45, "height": 3000000}, "scale": 100000}])")),
                      {"models"});
}
