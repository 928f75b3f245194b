#include <orbis/world/SceneFile.h>

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/SunPosition.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

#include <fstream>
#include <random>
#include <limits>
#include <set>
#include <sstream>
#include <string>

using namespace orbis;
using namespace orbis::world;
using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
namespace fs = std::filesystem;

namespace {

const fs::path kSourceDirectory = ORBIS_SOURCE_DIR;
const fs::path kScenes = kSourceDirectory / "data" / "scenes";

// Angles go through degrees-to-radians once; a few ulps of pi/180 is all they can be off.
constexpr double kAngleTolerance = 1e-15;

std::string readText(const fs::path& path)
{
    std::ifstream file(path, std::ios::binary);
    std::ostringstream text;
    text << file.rdbuf();
    return text.str();
}

void writeText(const fs::path& path, std::string_view text)
{
    fs::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << text;
}

/// A fresh folder under the system's temporary folder, removed with the object.
class TemporaryFolder {
public:
    TemporaryFolder()
    {
        std::random_device random;
        _path = fs::temp_directory_path() / ("orbis-scene-test-" + std::to_string(random()));
        fs::create_directories(_path);
    }
    ~TemporaryFolder()
    {
        std::error_code ignored;
        fs::remove_all(_path, ignored);
    }
    TemporaryFolder(const TemporaryFolder&) = delete;
    TemporaryFolder& operator=(const TemporaryFolder&) = delete;
    const fs::path& path() const { return _path; }

private:
    fs::path _path;
};

/// The error parsing text throws ("no error" if none), the files it names not checked unless asked.
std::string errorOf(std::string_view text, bool checkFiles = false, const fs::path& base = kScenes)
{
    try {
        parseSceneText(text, "test.json", base, SceneParseOptions{checkFiles});
    } catch (const SceneFileError& error) {
        return error.what();
    }
    return "no error";
}

SceneDescription parse(std::string_view text, bool checkFiles = false, const fs::path& base = kScenes)
{
    return parseSceneText(text, "test.json", base, SceneParseOptions{checkFiles});
}

/// One layer in an otherwise empty scene.
std::string withLayer(std::string_view layer)
{
    return R"({"version": 2, "layers": [)" + std::string(layer) + "]}";
}

} // namespace

// ---------------------------------------------------------------------------------------------
// Files that must work

TEST_CASE("Every example scene in data/scenes parses, with its files present", "[world][scenefile]")
{
    std::set<std::string> parsed;
    for (const fs::directory_entry& entry : fs::directory_iterator(kScenes)) {
        if (entry.path().extension() != ".json") {
            continue;
        }
        INFO(entry.path());
        const SceneDescription scene = parseSceneFile(entry.path());
        REQUIRE(scene.version == kSceneFileVersion); // written for this build
        parsed.insert(entry.path().stem().string());
    }
    // The examples docs and tests name, every one of them (a new one is added here).
    REQUIRE(parsed == std::set<std::string>{"capitals", "clipmap", "countries", "default", "draped", "model", "routes",
                                            "virtual-texture"});
}

TEST_CASE("The built-in default scene is data/scenes/default.json", "[world][scenefile]")
{
    REQUIRE(defaultSceneText() == readText(kScenes / "default.json"));
    const SceneDescription builtIn = parseDefaultScene(kScenes);
    REQUIRE(builtIn == parseSceneFile(kScenes / "default.json"));

    // The default view: the Himalaya from 350 km, looking north, the Blue Marble streamed at its
    // deepest level, lit by the Sun of a fixed time.
    REQUIRE(builtIn.globe.has_value());
    REQUIRE(builtIn.globe->imagery.size() == 1);
    REQUIRE(fs::path(builtIn.globe->imagery[0].source) == (kScenes / "../imagery/BlueMarble").lexically_normal());
    REQUIRE_FALSE(builtIn.globe->texture);
    REQUIRE(builtIn.globe->maximumScreenSpaceError == 2.0);
    REQUIRE(builtIn.sun.source == SunSource::Time);
    REQUIRE(builtIn.depth == DepthStrategy::Automatic);
    REQUIRE_THAT(builtIn.camera.position.height, WithinAbs(350'000.0, 0.0));
    REQUIRE(builtIn.layers.empty());
}

TEST_CASE("A scene of only a version takes the documented defaults", "[world][scenefile]")
{
    const SceneDescription scene = parse(R"({"version": 2})");
    REQUIRE(scene.width == 1280);
    REQUIRE(scene.height == 720);
    REQUIRE(scene.background == glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    REQUIRE(scene.depth == DepthStrategy::Automatic);
    REQUIRE_FALSE(scene.globe.has_value());
    REQUIRE(scene.layers.empty());
    // The camera as docs/scene-format.md states it: lon 10, lat 30, 20,000 km up, heading 0,
    // pitch -90 (straight down), roll 0, a 45-degree field of view.
    REQUIRE_THAT(scene.camera.position.longitude, WithinAbs(toRadians(10.0), 1e-15));
    REQUIRE_THAT(scene.camera.position.latitude, WithinAbs(toRadians(30.0), 1e-15));
    REQUIRE(scene.camera.position.height == 20'000'000.0);
    REQUIRE(std::holds_alternative<HeadingPitchRoll>(scene.camera.aim));
    const HeadingPitchRoll aim = std::get<HeadingPitchRoll>(scene.camera.aim);
    REQUIRE(aim.heading == 0.0);
    REQUIRE_THAT(aim.pitch, WithinAbs(-kHalfPi, 1e-15));
    REQUIRE(aim.roll == 0.0);
    REQUIRE_THAT(scene.camera.fieldOfViewY, WithinAbs(toRadians(45.0), 1e-15));
    // No sun and no time: the Sun is behind the camera.
    REQUIRE(scene.sun.source == SunSource::Camera);
    const glm::dvec3 eye = Ellipsoid::wgs84().toCartesian(scene.camera.position);
    REQUIRE_THAT(glm::dot(scene.sun.directionEarthFixed, glm::normalize(eye)), WithinAbs(1.0, 1e-15));
}

TEST_CASE("Every key reads into the description, degrees to radians", "[world][scenefile]")
{
    const SceneDescription scene = parse(R"({
        "version": 2, "width": 640, "height": 480, "background": "#336699cc",
        "camera": {"position": {"lon": -10, "lat": 45, "height": 1000}, "target": {"lon": -9, "lat": 46}, "fovY": 60},
        "sun": {"lon": 30, "lat": -20},
        "depth": "complementary",
        "globe": {"method": "tessellated", "texture": "tiles", "nightTexture": "night.png", "grid": true},
        "layers": [
          {"type": "geojson", "source": "a.geojson", "fill": {"color": "#ff000080"}},
          {"type": "points", "source": "p.geojson",
           "billboard": {"image": "dot.png", "size": 12, "color": "#00ff00", "origin": "bottom-left", "offset": [2, -3]},
           "label": {"field": "name", "size": 11, "color": "#ffffff", "outlineColor": "#000000", "outlineWidth": 0,
                     "declutter": true}},
          {"type": "polyline", "positions": [[0, 0], [10, 20, 300]], "width": 4, "color": "#0000ff"},
          {"type": "model", "source": "m.glb", "position": {"lon": 1, "lat": 2, "height": 3}, "scale": 2.5,
           "heading": 90, "pitch": 10, "roll": -5}
        ]})");
    REQUIRE(scene.width == 640);
    REQUIRE(scene.height == 480);
    REQUIRE(scene.background == glm::vec4(0x33 / 255.0f, 0x66 / 255.0f, 0x99 / 255.0f, 0xcc / 255.0f));

    REQUIRE(scene.camera.position == Geodetic3D::fromDegrees(-10.0, 45.0, 1000.0));
    REQUIRE(std::get<Geodetic3D>(scene.camera.aim) == Geodetic3D::fromDegrees(-9.0, 46.0, 0.0));
    REQUIRE_THAT(scene.camera.fieldOfViewY, WithinAbs(toRadians(60.0), kAngleTolerance));

    REQUIRE(scene.sun.source == SunSource::Position);
    REQUIRE(scene.sun.subsolarPoint == Geodetic2D::fromDegrees(30.0, -20.0));
    REQUIRE(glm::length(scene.sun.directionEarthFixed - Ellipsoid::geodeticSurfaceNormal(scene.sun.subsolarPoint)) == 0.0);

    REQUIRE(scene.depth == DepthStrategy::Complementary);
    REQUIRE(scene.globe->method == GlobeMethod::Tessellated);
    // Files unchecked: a path without extension is taken for a TMS folder.
    REQUIRE(scene.globe->texture == GlobeTexture{kScenes / "tiles", GlobeTexture::Kind::TileMapService});
    REQUIRE(scene.globe->nightTexture == kScenes / "night.png");
    REQUIRE(scene.globe->grid);

    REQUIRE(scene.layers.size() == 4);
    const auto& geojson = std::get<GeoJsonLayer>(scene.layers[0]);
    REQUIRE(geojson.source == kScenes / "a.geojson");
    REQUIRE_FALSE(geojson.stroke.has_value()); // a fill alone: no default stroke
    REQUIRE(geojson.fill->color == glm::vec4(1.0f, 0.0f, 0.0f, 128 / 255.0f));

    const auto& points = std::get<PointsLayer>(scene.layers[1]);
    REQUIRE(points.format == PointsLayer::Format::GeoJson);
    REQUIRE(points.billboard.image == kScenes / "dot.png");
    REQUIRE(points.billboard.sizePixels == 12.0);
    REQUIRE(points.billboard.color == glm::vec4(0.0f, 1.0f, 0.0f, 1.0f));
    REQUIRE(points.billboard.origin == Origin::BottomLeft);
    REQUIRE(points.billboard.offsetPixels == glm::dvec2(2.0, -3.0));
    REQUIRE(points.label->field == "name");
    REQUIRE(points.label->fontSizePixels == 11.0);
    REQUIRE(points.label->outlineWidthPixels == 0.0);
    REQUIRE(points.label->declutter);

    const auto& polyline = std::get<PolylineLayer>(scene.layers[2]);
    REQUIRE(polyline.positions == std::vector<Geodetic3D>{Geodetic3D::fromDegrees(0.0, 0.0, 0.0),
                                                          Geodetic3D::fromDegrees(10.0, 20.0, 300.0)});
    REQUIRE(polyline.widthPixels == 4.0);
    REQUIRE(polyline.color == glm::vec4(0.0f, 0.0f, 1.0f, 1.0f));

    const auto& model = std::get<ModelLayer>(scene.layers[3]);
    REQUIRE(model.source == kScenes / "m.glb");
    REQUIRE(model.format == ModelLayer::Format::Glb);
    REQUIRE(model.position == Geodetic3D::fromDegrees(1.0, 2.0, 3.0));
    REQUIRE(model.scale == 2.5);
    REQUIRE_THAT(model.orientation.heading, WithinAbs(toRadians(90.0), kAngleTolerance));
    REQUIRE_THAT(model.orientation.pitch, WithinAbs(toRadians(10.0), kAngleTolerance));
    REQUIRE_THAT(model.orientation.roll, WithinAbs(toRadians(-5.0), kAngleTolerance));
}

TEST_CASE("A GeoJSON layer without styles gets the default stroke", "[world][scenefile]")
{
    const auto layer = std::get<GeoJsonLayer>(parse(withLayer(R"({"type": "geojson", "source": "a.json"})")).layers[0]);
    REQUIRE(layer.stroke == StrokeStyle{});
    REQUIRE_FALSE(layer.fill.has_value());
}

TEST_CASE("A GeoJSON layer refuses invalid polygons unless its \"invalid\" says skip", "[world][scenefile]")
{
    CHECK_FALSE(std::get<GeoJsonLayer>(parse(withLayer(R"({"type": "geojson", "source": "a.json"})")).layers[0]).skipInvalid);
    CHECK(std::get<GeoJsonLayer>(parse(withLayer(R"({"type": "geojson", "source": "a.json", "invalid": "skip"})")).layers[0])
              .skipInvalid);
    CHECK_FALSE(std::get<GeoJsonLayer>(parse(withLayer(R"({"type": "geojson", "source": "a.json", "invalid": "error"})")).layers[0])
                    .skipInvalid);
    CHECK_THAT(errorOf(withLayer(R"({"type": "geojson", "source": "a.json", "invalid": "repair"})")),
               Contains(R"(/layers/0/invalid: )") && Contains(R"("error", "skip")"));
}

TEST_CASE("A version 1 file's billboards and labels are never depth-tested unless it says so, as it was written", "[world][scenefile]")
{
    const std::string layer = R"([{"type": "points", "source": "p.geojson", "label": {"field": "name"}},
        {"type": "points", "source": "p.geojson", "billboard": {"size": 4}, "label": {"field": "name", "disableDepthTestDistance": 10}}])";
    for (const int version : {1, 2}) {
        INFO("version " << version);
        const SceneDescription scene = parse(R"({"version": )" + std::to_string(version) + R"(, "layers": )" + layer + "}");
        const double expected = version == 1 ? std::numeric_limits<double>::infinity() : 0.0;
        const auto& plain = std::get<PointsLayer>(scene.layers[0]);
        const auto& styled = std::get<PointsLayer>(scene.layers[1]);
        CHECK(plain.billboard.disableDepthTestDistance == expected); // no "billboard" key at all
        CHECK(plain.label->disableDepthTestDistance == expected);
        CHECK(styled.billboard.disableDepthTestDistance == expected);
        CHECK(styled.label->disableDepthTestDistance == 10.0); // given: the same in both
    }
}

TEST_CASE("Billboards take a built-in shape, and billboards and labels a distance within which they are not depth-tested", "[world][scenefile]")
{
    const auto defaults = std::get<PointsLayer>(
        parse(withLayer(R"({"type": "points", "source": "p.geojson", "label": {"field": "name"}})")).layers[0]);
    // As docs/scene-format.md states: a dot, depth-tested everywhere.
    REQUIRE_FALSE(defaults.billboard.image);
    REQUIRE(defaults.billboard.shape == BillboardShape::Dot);
    REQUIRE(defaults.billboard.disableDepthTestDistance == 0.0);
    REQUIRE(defaults.label->disableDepthTestDistance == 0.0);

    const auto points = std::get<PointsLayer>(parse(withLayer(R"({"type": "points", "source": "p.geojson",
        "billboard": {"shape": "square", "disableDepthTestDistance": 5000},
        "label": {"field": "name", "disableDepthTestDistance": "always"}})")).layers[0]);
    REQUIRE(points.billboard.shape == BillboardShape::Square);
    REQUIRE(points.billboard.disableDepthTestDistance == 5000.0);
    REQUIRE(points.label->disableDepthTestDistance == std::numeric_limits<double>::infinity());

    CHECK_THAT(errorOf(withLayer(R"({"type": "points", "source": "a.csv", "billboard": {"shape": "circle"}})")),
               Contains(R"(/layers/0/billboard/shape: unknown value "circle"; expected one of "dot", "square")"));
    CHECK_THAT(errorOf(withLayer(R"({"type": "points", "source": "a.csv", "billboard": {"image": "dot.png", "shape": "dot"}})")),
               Contains(R"(/layers/0/billboard/shape: give either "image" or "shape", not both)"));
    CHECK_THAT(errorOf(withLayer(R"({"type": "points", "source": "a.csv", "billboard": {"disableDepthTestDistance": -1}})")),
               Contains("/layers/0/billboard/disableDepthTestDistance: -1 is out of range (expected >= 0)"));
    CHECK_THAT(errorOf(withLayer(R"({"type": "points", "source": "a.csv", "label": {"field": "n", "disableDepthTestDistance": "never"}})")),
               Contains(R"(/layers/0/label/disableDepthTestDistance: unknown value "never"; expected a distance in metres or "always")"));
    CHECK_THAT(errorOf(withLayer(R"({"type": "points", "source": "a.csv", "billboard": {"disableDepthTestDistance": true}})")),
               Contains(R"(/layers/0/billboard/disableDepthTestDistance: expected a distance in metres or "always", got true)"));
}

TEST_CASE("Lines take their granularity in degrees and their curve", "[world][scenefile]")
{
    const auto geojson = std::get<GeoJsonLayer>(
        parse(withLayer(R"({"type": "geojson", "source": "a.json", "granularity": 0.25, "curve": "geodesic"})")).layers[0]);
    REQUIRE_THAT(geojson.path.granularityRadians, WithinAbs(toRadians(0.25), kAngleTolerance));
    REQUIRE(geojson.path.curve == CurveType::Geodesic);

    const auto polyline = std::get<PolylineLayer>(
        parse(withLayer(R"({"type": "polyline", "positions": [[0, 0], [1, 1]], "granularity": 10, "curve": "section"})")).layers[0]);
    REQUIRE_THAT(polyline.path.granularityRadians, WithinAbs(toRadians(10.0), kAngleTolerance));
    REQUIRE(polyline.path.curve == CurveType::PlaneSection);

    const auto defaults = std::get<PolylineLayer>(parse(withLayer(R"({"type": "polyline", "positions": [[0, 0], [1, 1]]})")).layers[0]);
    REQUIRE(defaults.path == LinePath{});
    REQUIRE_THAT(defaults.path.granularityRadians, WithinAbs(toRadians(1.0), kAngleTolerance));

    CHECK(errorOf(withLayer(R"({"type": "geojson", "source": "a.json", "granularity": 0.05})")) ==
          "test.json:1:82: /layers/0/granularity: 0.05 is out of range [0.1, 10]");
    CHECK(errorOf(withLayer(R"({"type": "polyline", "positions": [[0, 0], [1, 1]], "granularity": "fine"})")) ==
          R"(test.json:1:94: /layers/0/granularity: expected a number, got "fine")");
    CHECK(errorOf(withLayer(R"({"type": "geojson", "source": "a.json", "curve": "geodetic"})")) ==
          R"(test.json:1:76: /layers/0/curve: unknown value "geodetic" (did you mean "geodesic"?))");
}

TEST_CASE("The Sun from a time is the core's Sun direction at that time", "[world][scenefile]")
{
    const SceneDescription scene = parse(R"({"version": 2, "time": "2026-06-21T12:00:00Z"})");
    const auto utc = parseUtcTime("2026-06-21T12:00:00Z");
    REQUIRE(scene.sun.source == SunSource::Time);
    REQUIRE(scene.sun.time == utc);
    const glm::dvec3 expected = sunDirectionEarthFixed(*utc);
    REQUIRE(glm::length(scene.sun.directionEarthFixed - expected) < 1e-15);
    // Near the June solstice at noon UTC the Sun stands over the Tropic of Cancer, close to Greenwich
    // (equation of time: under 2 degrees of longitude; the formulas: about 0.01 degrees).
    REQUIRE_THAT(toDegrees(scene.sun.subsolarPoint.latitude), WithinAbs(23.44, 0.05));
    REQUIRE_THAT(toDegrees(scene.sun.subsolarPoint.longitude), WithinAbs(0.0, 2.0));
}

TEST_CASE("Relative paths resolve against the scene file's folder", "[world][scenefile]")
{
    const TemporaryFolder folder;
    writeText(folder.path() / "data" / "countries.geojson", "{}");
    writeText(folder.path() / "scenes" / "cities.csv", "name,lat,lon\nA,1,2\n");
    writeText(folder.path() / "scenes" / "tiles" / "tilemapresource.xml", "<TileMap/>");
    writeText(folder.path() / "scenes" / "model.gltf", "{}");
    const std::string text = R"({"version": 2,
        "globe": {"texture": "tiles"},
        "layers": [
          {"type": "geojson", "source": "../data/countries.geojson"},
          {"type": "points", "source": "cities.csv", "label": {"field": "name"}},
          {"type": "model", "source": "./model.gltf", "position": {"lon": 0, "lat": 0}}
        ]})";
    writeText(folder.path() / "scenes" / "scene.json", text);

    const SceneDescription scene = parseSceneFile(folder.path() / "scenes" / "scene.json");
    REQUIRE(scene.globe->texture == GlobeTexture{folder.path() / "scenes" / "tiles", GlobeTexture::Kind::TileMapService});
    REQUIRE(std::get<GeoJsonLayer>(scene.layers[0]).source == folder.path() / "data" / "countries.geojson");
    REQUIRE(std::get<PointsLayer>(scene.layers[1]).source == folder.path() / "scenes" / "cities.csv");
    REQUIRE(std::get<PointsLayer>(scene.layers[1]).format == PointsLayer::Format::Csv);
    REQUIRE(std::get<ModelLayer>(scene.layers[2]).source == folder.path() / "scenes" / "model.gltf");
    REQUIRE(std::get<ModelLayer>(scene.layers[2]).format == ModelLayer::Format::Gltf);

    // The same text with its folder given explicitly, and a relative scene path from the current folder.
    REQUIRE(parseSceneText(text, "scene.json", folder.path() / "scenes") == scene);
    const fs::path previous = fs::current_path();
    fs::current_path(folder.path());
    const SceneDescription relative = parseSceneFile("scenes/scene.json");
    fs::current_path(previous);
    REQUIRE(relative == scene);
}

// ---------------------------------------------------------------------------------------------
// Errors: each names the file, line and column, the JSON pointer, and what was expected

TEST_CASE("Scene file errors carry the origin, pointer, line, column and reason", "[world][scenefile][errors]")
{
    try {
        parseSceneText("{\n  \"version\": 1,\n  \"width\": \"wide\"\n}", "scenes/bad.json", kScenes);
        FAIL("no error");
    } catch (const SceneFileError& error) {
        REQUIRE(std::string(error.what()) == "scenes/bad.json:3:12: /width: expected a positive integer, got \"wide\"");
        REQUIRE(error.origin() == "scenes/bad.json");
        REQUIRE(error.pointer() == "/width");
        REQUIRE(error.line() == 3);
        REQUIRE(error.column() == 12);
        REQUIRE(error.reason() == "expected a positive integer, got \"wide\"");
    }
}

TEST_CASE("Unknown keys are errors with their path and a suggestion", "[world][scenefile][errors]")
{
    CHECK(errorOf(withLayer(R"({"type": "polyline", "positions": [[0, 0], [1, 1]], "colour": "#ff0000"})")) ==
            R"(test.json:1:79: /layers/0/colour: unknown key "colour" (did you mean "color"?))");
    CHECK(errorOf(R"({"version": 2, "camera": {"FovY": 30}})") ==
            R"(test.json:1:27: /camera/FovY: unknown key "FovY" (did you mean "fovY"?))");
    CHECK(errorOf(R"({"version": 2, "camera": {"position": {"lon": 0, "lat": 0, "hieght": 1}}})") ==
            R"(test.json:1:60: /camera/position/hieght: unknown key "hieght" (did you mean "height"?))");
    // Nothing close: the keys that are known.
    CHECK(errorOf(R"({"version": 2, "sun": {"lon": 0, "lat": 0, "elevation": 3}})") ==
            R"(test.json:1:44: /sun/elevation: unknown key "elevation"; expected one of "lon", "lat")");
    // A key that belongs to another layer type.
    CHECK(errorOf(withLayer(R"({"type": "geojson", "source": "a.json", "positions": []})")) ==
            R"(test.json:1:67: /layers/0/positions: unknown key "positions"; expected one of "type", "source", "stroke", "fill", "granularity", "curve", "heightReference", "invalid")");
    // Keys with "/" and "~" are escaped in the pointer (RFC 6901).
    CHECK(errorOf(R"({"version": 2, "a/b~c": 0})") ==
            R"(test.json:1:16: /a~1b~0c: unknown key "a/b~c"; expected one of "version", "width", "height", "background", "camera", "sun", "time", "depth", "samples", "globe", "layers")");
}

TEST_CASE("Out-of-range values are errors naming the range", "[world][scenefile][errors]")
{
    CHECK(errorOf(R"({"version": 2, "camera": {"position": {"lon": 0, "lat": 95}}})") ==
            "test.json:1:57: /camera/position/lat: 95 is out of range [-90, 90]");
    CHECK(errorOf(R"({"version": 2, "sun": {"lon": -180.5, "lat": 0}})") ==
            "test.json:1:31: /sun/lon: -180.5 is out of range [-180, 180]");
    CHECK(errorOf(R"({"version": 2, "width": 0})") == "test.json:1:25: /width: 0 is out of range [1, 16384]");
    CHECK(errorOf(R"({"version": 2, "height": 16385})") == "test.json:1:26: /height: 16385 is out of range [1, 16384]");
    CHECK(errorOf(R"({"version": 2, "height": -720})") == "test.json:1:26: /height: -720 is out of range [1, 16384]");
    CHECK(errorOf(R"({"version": 2, "width": 18446744073709551615})") ==
            "test.json:1:25: /width: 18446744073709551615 is out of range [1, 16384]");
    CHECK(errorOf(R"({"version": 2, "camera": {"fovY": 180}})") == "test.json:1:35: /camera/fovY: 180 is out of range (0, 180)");
    CHECK(errorOf(R"({"version": 2, "camera": {"fovY": 0}})") == "test.json:1:35: /camera/fovY: 0 is out of range (0, 180)");
    CHECK(errorOf(R"({"version": 2, "camera": {"pitch": -91}})") == "test.json:1:36: /camera/pitch: -91 is out of range [-90, 90]");
    CHECK(errorOf(R"({"version": 2, "camera": {"position": {"lon": 0, "lat": 0, "height": 1e13}}})") ==
            "test.json:1:70: /camera/position/height: 10000000000000.0 is out of range [-1000000, 1000000000000]");
    // Negative sizes.
    CHECK(errorOf(withLayer(R"({"type": "geojson", "source": "a.json", "stroke": {"width": -1}})")) ==
            "test.json:1:87: /layers/0/stroke/width: -1 is out of range (0, 1024]");
    CHECK(errorOf(withLayer(R"({"type": "points", "source": "a.json", "label": {"field": "n", "outlineWidth": -0.5}})")) ==
            "test.json:1:106: /layers/0/label/outlineWidth: -0.5 is out of range [0, 1024]");
    CHECK(errorOf(withLayer(R"({"type": "polyline", "positions": [[0, 0], [1, 1]], "width": 0})")) ==
            "test.json:1:88: /layers/0/width: 0 is out of range (0, 1024]");
    CHECK(errorOf(withLayer(R"({"type": "model", "source": "m.glb", "position": {"lon": 0, "lat": 0}, "scale": -2})")) ==
            "test.json:1:107: /layers/0/scale: -2 is out of range (expected > 0)");
    CHECK(errorOf(withLayer(R"({"type": "polyline", "positions": [[0, 0], [1, 91]]})")) ==
            "test.json:1:74: /layers/0/positions/1/1: 91 is out of range [-90, 90]");
}

TEST_CASE("Wrong types are errors saying what was expected and what came", "[world][scenefile][errors]")
{
    CHECK(errorOf(R"({"version": 2, "width": 12.5})") == "test.json:1:25: /width: expected a positive integer, got 12.5");
    CHECK(errorOf(R"({"version": 2, "camera": []})") == "test.json:1:26: /camera: expected an object, got an empty array");
    CHECK(errorOf(R"({"version": 2, "camera": {"fovY": "45"}})") ==
            R"(test.json:1:35: /camera/fovY: expected a number, got "45")");
    CHECK(errorOf(R"({"version": 2, "layers": {}})") ==
            "test.json:1:26: /layers: expected an array of layers, got an empty object");
    CHECK(errorOf(withLayer(R"({"type": "points", "source": "a.csv", "label": {"field": "n", "declutter": 1}})")) ==
          "test.json:1:102: /layers/0/label/declutter: expected true or false, got 1");
    CHECK(errorOf(R"({"version": 2, "globe": {"grid": "yes"}})") ==
            R"(test.json:1:34: /globe/grid: expected true or false, got "yes")");
    CHECK(errorOf(R"({"version": 2, "background": "black"})") ==
            R"(test.json:1:30: /background: expected a color "#rrggbb" or "#rrggbbaa", got "black")");
    CHECK(errorOf(R"({"version": 2, "background": "#12345g"})") ==
            R"(test.json:1:30: /background: expected a color "#rrggbb" or "#rrggbbaa", got "#12345g")");
    CHECK(errorOf(withLayer(R"({"type": "polyline", "positions": [[0, 0]]})")) ==
            "test.json:1:61: /layers/0/positions: expected an array of at least two [lon, lat] or [lon, lat, height], "
            "got an array of 1 element");
    CHECK(errorOf(withLayer(R"({"type": "polyline", "positions": [[0, 0], [1, 2, 3, 4]]})")) ==
            "test.json:1:70: /layers/0/positions/1: expected [lon, lat] or [lon, lat, height], got an array of 4 elements");
    CHECK(errorOf(withLayer(R"({"type": "points", "source": "a.csv", "billboard": {"offset": [1]}})")) ==
            "test.json:1:89: /layers/0/billboard/offset: expected [x, y] in pixels, got an array of 1 element");
    CHECK(errorOf(R"({"version": 2, "depth": 3})") ==
          R"(test.json:1:25: /depth: expected one of "auto", "multi-frustum", "logarithmic", "complementary", "single", got 3)");
    CHECK(errorOf(withLayer(R"({"type": ["points"]})")) ==
          R"(test.json:1:36: /layers/0/type: expected one of "geojson", "points", "polyline", "model", got an array of 1 element)");
    CHECK(errorOf(withLayer(R"({"type": "points", "source": "a.csv", "label": {"field": ""}})")) ==
          "test.json:1:84: /layers/0/label/field: expected a column or property name, got an empty string");
    CHECK(errorOf(withLayer(R"({"type": "geojson", "source": "a\u0000b.json"})")) ==
          "test.json:1:57: /layers/0/source: a path cannot contain a NUL character");
    CHECK(errorOf(withLayer(R"({"type": "geojson", "source": ""})")) ==
            "test.json:1:57: /layers/0/source: expected a path, got an empty string");
    CHECK(errorOf("[1, 2]") == "test.json:1:1: expected a JSON object at the top of the file, got an array of 2 elements");
    // Long strings are cut in messages.
    CHECK(errorOf(R"({"version": 2, "depth": ")" + std::string(100, 'x') + "\"}") ==
            R"(test.json:1:25: /depth: unknown value ")" + std::string(60, 'x') +
                R"(..."; expected one of "auto", "multi-frustum", "logarithmic", "complementary", "single")");
    // So is a key of a megabyte, in the JSON pointer as in the quote.
    const std::string longKey = errorOf(R"({"version": 2, ")" + std::string(1 << 20, 'k') + "\": 1}");
    CHECK_THAT(longKey, Contains("test.json:1:16: /kkkk") && Contains("... (1048577 bytes): unknown key \"kkkk"));
    CHECK(longKey.size() < 1000);
}

TEST_CASE("Samples per pixel: 1 by default, 1 to 16", "[world][scenefile]")
{
    REQUIRE(parse(R"({"version": 2})").samples == 1);
    REQUIRE(parse(R"({"version": 2, "samples": 4})").samples == 4);
    CHECK_THAT(errorOf(R"({"version": 2, "samples": 0})"), Contains("/samples:"));
    CHECK_THAT(errorOf(R"({"version": 2, "samples": 32})"), Contains("/samples:"));
    CHECK_THAT(errorOf(R"({"version": 2, "samples": 2.5})"), Contains("/samples:"));
}

TEST_CASE("The depth strategy reads by the name the statistics print, and by the spelling files had before", "[world][scenefile]")
{
    REQUIRE(std::string(depthStrategyName(DepthStrategy::MultiFrustum)) == "multi-frustum");
    for (const DepthStrategy strategy : {DepthStrategy::Automatic, DepthStrategy::MultiFrustum, DepthStrategy::Logarithmic,
                                         DepthStrategy::Complementary, DepthStrategy::Single}) {
        INFO(depthStrategyName(strategy));
        REQUIRE(parse(R"({"version": 2, "depth": ")" + std::string(depthStrategyName(strategy)) + "\"}").depth == strategy);
    }
    REQUIRE(parse(R"({"version": 2, "depth": "multifrustum"})").depth == DepthStrategy::MultiFrustum);
}

TEST_CASE("Unknown enumeration values are errors with a suggestion", "[world][scenefile][errors]")
{
    CHECK(errorOf(R"({"version": 2, "depth": "logarithmc"})") ==
            R"(test.json:1:25: /depth: unknown value "logarithmc" (did you mean "logarithmic"?))");
    CHECK(errorOf(R"({"version": 2, "depth": "fast"})") ==
            R"(test.json:1:25: /depth: unknown value "fast"; expected one of "auto", "multi-frustum", "logarithmic", "complementary", "single")");
    CHECK(errorOf(R"({"version": 2, "globe": {"method": "ray-cast"}})") ==
            R"(test.json:1:36: /globe/method: unknown value "ray-cast" (did you mean "raycast"?))");
    CHECK(errorOf(withLayer(R"({"type": "points", "source": "a.csv", "billboard": {"origin": "centre"}})")) ==
            R"(test.json:1:89: /layers/0/billboard/origin: unknown value "centre" (did you mean "center"?))");
    CHECK(errorOf(withLayer(R"({"type": "polylines"})")) ==
            R"(test.json:1:36: /layers/0/type: unknown layer type "polylines" (did you mean "polyline"?))");
    CHECK(errorOf(withLayer(R"({"source": "a.json"})")) ==
            R"(test.json:1:27: /layers/0: missing required key "type" (one of "geojson", "points", "polyline", "model"))");
}

TEST_CASE("The version is required and only versions 1 and 2 are understood", "[world][scenefile][errors]")
{
    CHECK(errorOf(R"({"width": 640})") ==
          R"(test.json:1:1: missing required key "version" (this orbis reads version 2 and earlier))");
    CHECK(errorOf(R"({"version": 3, "newKey": true})") ==
            "test.json:1:13: /version: version 3 is newer than this orbis understands (it reads version 2 and earlier)");
    CHECK(parse(R"({"version": 1})").version == 1);
    CHECK(parse(R"({"version": 2})").version == 2);
    // Camera paths have versions of their own.
    CHECK_THROWS_WITH(parseCameraPathText(R"({"version": 2, "keyframes": []})", "path.json"),
                      Contains("version 2 is newer than this orbis understands (it reads version 1)"));
    CHECK(errorOf(R"({"version": 0})") == "test.json:1:13: /version: 0 is not a version; versions start at 1");
    CHECK(errorOf(R"({"version": "1"})") == R"(test.json:1:13: /version: expected an integer, got "1")");
    CHECK(errorOf(R"({"version": 1.0})") == "test.json:1:13: /version: expected an integer, got 1.0");
}

TEST_CASE("Missing required keys are errors naming the key", "[world][scenefile][errors]")
{
    CHECK(errorOf(R"({"version": 2, "camera": {"position": {"lon": 10}}})") ==
            R"(test.json:1:39: /camera/position: missing required key "lat")");
    CHECK(errorOf(withLayer(R"({"type": "geojson"})")) == R"(test.json:1:27: /layers/0: missing required key "source")");
    CHECK(errorOf(withLayer(R"({"type": "polyline"})")) == R"(test.json:1:27: /layers/0: missing required key "positions")");
    CHECK(errorOf(withLayer(R"({"type": "model", "source": "m.gltf"})")) ==
            R"(test.json:1:27: /layers/0: missing required key "position")");
    CHECK(errorOf(withLayer(R"({"type": "points", "source": "a.csv", "label": {}})")) ==
            R"(test.json:1:74: /layers/0/label: missing required key "field")");
}

TEST_CASE("Keys that contradict each other are errors", "[world][scenefile][errors]")
{
    CHECK(errorOf(R"({"version": 2, "camera": {"target": {"lon": 0, "lat": 0}, "pitch": -30}})") ==
            R"(test.json:1:59: /camera/pitch: "target" and "heading"/"pitch"/"roll" both aim the camera; give one or the other)");
    CHECK(errorOf(R"({"version": 2, "sun": {"lon": 0, "lat": 0}, "time": "2026-06-21T12:00:00Z"})") ==
            R"(test.json:1:45: /time: "sun" and "time" both place the Sun; give one or the other)");
    CHECK(errorOf(R"({"version": 2, "camera": {"position": {"lon": 5, "lat": 5, "height": 10}, "target": {"lon": 5, "lat": 5, "height": 10}}})") ==
            "test.json:1:85: /camera/target: the target is the camera's position; the camera would look nowhere");
    CHECK(errorOf(R"({"version": 2, "time": "2026-02-30T12:00:00Z"})") ==
            R"(test.json:1:24: /time: expected a UTC time "YYYY-MM-DDTHH:MM:SSZ", got "2026-02-30T12:00:00Z")");
}

TEST_CASE("Invalid JSON is an error at the line and column where it fails", "[world][scenefile][errors]")
{
    // NaN and Infinity are not JSON.
    CHECK(errorOf("{\"version\": 1,\n \"width\": NaN}") ==
            "test.json:2:11: invalid JSON: syntax error while parsing value - invalid literal; last read: "
            "'\"width\": N' (JSON has no NaN or Infinity; write a finite number)");
    CHECK(errorOf(R"({"version": 2, "sun": {"lon": -Infinity, "lat": 0}})") ==
            "test.json:1:32: invalid JSON: syntax error while parsing value - invalid number; expected digit after "
            "'-'; last read: '-I' (JSON has no NaN or Infinity; write a finite number)");
    CHECK(errorOf(R"({"version": 2, "width": 1e999})") == "test.json:1:25: invalid JSON: 1e999 is too large for a double");
    CHECK(errorOf("{\"version\": 1, // one\n}") ==
            "test.json:1:16: invalid JSON: syntax error while parsing object key - invalid literal; last read: "
            "'1, /'; expected string literal (JSON has no comments)");
    CHECK(errorOf("{\"version\": 1,\n}") ==
            "test.json:2:1: invalid JSON: syntax error while parsing object key - unexpected '}'; expected string "
            "literal (a comma before a closing bracket?)");
    CHECK(errorOf("{\"version\": 1") ==
            "test.json:1:14: invalid JSON: syntax error while parsing object - unexpected end of input; expected '}'");
    CHECK(errorOf(" \n ") == "test.json: the file is empty; expected a JSON object");
    CHECK(errorOf(std::string(100, '[') + std::string(100, ']')) ==
            "test.json:1:65: invalid JSON: nested deeper than 64 levels");
    // Everything after a NUL byte would be ignored without a word.
    CHECK(errorOf(std::string("{\"version\": 1}\0{\"width\": -1}", 28)) ==
            "test.json:1:15: invalid JSON: a NUL byte (JSON text has none; is this a binary file?)");
}

TEST_CASE("A key given twice is an error at the second", "[world][scenefile][errors]")
{
    CHECK(errorOf("{\"version\": 1,\n \"camera\": {\"fovY\": 30,\n  \"fovY\": 40}}") ==
            R"(test.json:3:3: /camera/fovY: duplicate key "fovY" (first given at line 2))");
}

TEST_CASE("Missing and unsuitable files are errors naming the key and the file", "[world][scenefile][errors]")
{
    const TemporaryFolder folder;
    const fs::path base = folder.path();
    writeText(base / "empty" / "readme.txt", "not tiles");
    writeText(base / "cities.csv", "name,x,y\nA,1,2\n");
    writeText(base / "places.csv", "\xEF\xBB\xBF\"name\", \"lat\",lon\r\nA,1,2\r\n");
    writeText(base / "blank.csv", "");
    writeText(base / "wide.csv", std::string(70'000, 'x') + "\n");

    const std::string missing = errorOf(withLayer(R"({"type": "geojson", "source": "countries.geojson"})"), true, base);
    REQUIRE(missing == "test.json:1:57: /layers/0/source: file \"countries.geojson\" not found (looked for \"" +
                           (base / "countries.geojson").string() + "\")");
    CHECK(errorOf(R"({"version": 2, "globe": {"nightTexture": "/nonexistent/night.jpg"}})", true, base) ==
            R"(test.json:1:42: /globe/nightTexture: file "/nonexistent/night.jpg" not found)");
    CHECK(errorOf(R"({"version": 2, "globe": {"texture": "empty"}})", true, base) ==
            R"(test.json:1:37: /globe/texture: the folder "empty" is not a TMS tile set: it has no tilemapresource.xml)");
    CHECK(errorOf(R"({"version": 2, "globe": {"nightTexture": "empty"}})", true, base) ==
            R"(test.json:1:42: /globe/nightTexture: "empty" is a folder; expected a file)");
    CHECK(errorOf(withLayer(R"({"type": "points", "source": "cities.txt"})"), true, base) ==
            R"(test.json:1:56: /layers/0/source: expected a .csv, .geojson or .json file, got "cities.txt")");
    CHECK(errorOf(withLayer(R"({"type": "model", "source": "plane.obj", "position": {"lon": 0, "lat": 0}})"), true, base) ==
            R"(test.json:1:55: /layers/0/source: expected a .gltf or .glb file, got "plane.obj")");
    CHECK(errorOf(withLayer(R"({"type": "points", "source": "cities.csv"})"), true, base) ==
            R"(test.json:1:56: /layers/0/source: "cities.csv" has no longitude column (one of "lon", "lng", "long", "longitude"); its columns are "name", "x", "y")");
    CHECK(errorOf(withLayer(R"({"type": "points", "source": "wide.csv"})"), true, base) ==
          "test.json:1:56: /layers/0/source: " + (base / "wide.csv").string() +
              ":1: has a first line longer than 64 KiB; expected a header row");
    CHECK(errorOf(R"({"version": 2, "globe": {"texture": "/dev/null"}})", true, base) ==
          R"(test.json:1:37: /globe/texture: "/dev/null" is not a regular file)");
    CHECK(errorOf(withLayer(R"({"type": "points", "source": "blank.csv"})"), true, base) ==
            "test.json:1:56: /layers/0/source: " + (base / "blank.csv").string() + ": has no header row");
    // A byte-order mark, quotes, blanks and CRLF around column names are fine; a misspelt field is not.
    CHECK(errorOf(withLayer(R"({"type": "points", "source": "places.csv", "label": {"field": "name"}})"), true, base) ==
            "no error");
    CHECK(errorOf(withLayer(R"({"type": "points", "source": "places.csv", "label": {"field": "nmae"}})"), true, base) ==
            R"(test.json:1:89: /layers/0/label/field: no column "nmae" in "places.csv" (did you mean "name"?))");
}

TEST_CASE("parseSceneFile names files it cannot read", "[world][scenefile][errors]")
{
    const TemporaryFolder folder;
    const fs::path missing = folder.path() / "missing.json";
    try {
        parseSceneFile(missing);
        FAIL("no error");
    } catch (const SceneFileError& error) {
        REQUIRE(std::string(error.what()) == missing.string() + ": no such file");
    }
    try {
        parseSceneFile(folder.path());
        FAIL("no error");
    } catch (const SceneFileError& error) {
        REQUIRE(std::string(error.what()) == folder.path().string() + ": is a folder; expected a scene file");
    }
}

// ---------------------------------------------------------------------------------------------
// Every fault of a file in one run (orbis validate)

TEST_CASE("Collecting faults lists every fault of a file, each at its line and column", "[world][scenefile][errors]")
{
    const fs::path file = kSourceDirectory / "tests" / "world" / "scenes" / "seven-faults.json";
    DiagnosticList faults;
    SceneParseOptions options;
    options.diagnostics = &faults;
    const SceneDescription scene = parseSceneFile(file, options);
    const std::string origin = file.string();
    const std::vector<std::string> expected = {
        origin + ":3:3: /widht: unknown key \"widht\" (did you mean \"width\"?)",
        origin + ":4:13: /height: expected a positive integer, got \"tall\"",
        origin + ":5:17: /background: expected a color \"#rrggbb\" or \"#rrggbbaa\", got \"#12345\"",
        origin + ":6:36: /camera/position/lon: 200 is out of range [-180, 180]",
        origin + ":7:12: /depth: unknown value \"logarithmc\" (did you mean \"logarithmic\"?)",
        origin + ":8:43: /globe/grid: expected true or false, got \"yes\"",
        origin + ":10:69: /layers/0/width: -2 is out of range (0, 1024]",
    };
    std::vector<std::string> found;
    for (const Diagnostic& fault : faults.entries()) {
        found.push_back(fault.text());
    }
    CHECK(found == expected);
    REQUIRE(faults.size() == 7);
    CHECK(faults.entries()[3].line == 6);
    CHECK(faults.entries()[3].column == 36);
    CHECK(faults.entries()[3].where == "/camera/position/lon");
    // What could be read is kept: the globe's method, the layer's positions.
    REQUIRE(scene.globe);
    CHECK(scene.globe->method == GlobeMethod::RayCast);
    REQUIRE(scene.layers.size() == 1);
    CHECK(std::get<PolylineLayer>(scene.layers[0]).positions.size() == 2);

    // Without collecting, the first of them is thrown, word for word.
    try {
        parseSceneFile(file);
        FAIL("no error");
    } catch (const SceneFileError& error) {
        CHECK(error.what() == expected.front());
    }
}

TEST_CASE("Collecting faults of text that is not JSON gives the one syntax fault", "[world][scenefile][errors]")
{
    DiagnosticList faults;
    SceneParseOptions options;
    options.diagnostics = &faults;
    parseSceneText("{\n  \"version\": 1,\n  \"width\": 640,,\n}", "bad.json", kScenes, options);
    REQUIRE(faults.size() == 1);
    CHECK_THAT(faults.entries()[0].text(), Catch::Matchers::StartsWith("bad.json:3:16: invalid JSON: "));
    faults = {};
    parseSceneFile("/nonexistent/scene.json", options);
    REQUIRE(faults.size() == 1);
    CHECK(faults.entries()[0].text() == "/nonexistent/scene.json: no such file");
}

TEST_CASE("An imagery layer's virtualTexture reads every key, and the defaults without them", "[world][scenefile]")
{
    const SceneDescription defaults = parse(R"({"version": 2, "globe": {"imagery": [
        {"source": "tiles", "virtualTexture": {}}]}})");
    REQUIRE(defaults.globe->imagery.front().virtualTexture);
    CHECK(*defaults.globe->imagery.front().virtualTexture == VirtualTextureDescription{});
    CHECK_FALSE(parse(R"({"version": 2, "globe": {"imagery": [{"source": "tiles"}]}})").globe->imagery.front().virtualTexture);

    const SceneDescription all = parse(R"({"version": 2, "globe": {"imagery": [{"source": "tiles", "virtualTexture": {
        "pageSize": 128, "border": 2, "physicalPages": 1024, "feedbackDivisor": 2, "feedbackLatencyFrames": 3,
        "priorities": false, "trilinear": false, "maximumAnisotropy": 4, "lodBias": 0.5, "dynamicLodBias": false,
        "uploadMegabytesPerFrame": 8}}]}})");
    const VirtualTextureDescription& vt = *all.globe->imagery.front().virtualTexture;
    CHECK(vt.pageSize == 128);
    CHECK(vt.border == 2);
    CHECK(vt.physicalPages == 1024);
    CHECK(vt.feedbackDivisor == 2);
    CHECK(vt.feedbackLatencyFrames == 3);
    CHECK_FALSE(vt.priorities);
    CHECK_FALSE(vt.trilinear);
    CHECK(vt.maximumAnisotropy == 4.0);
    CHECK(vt.lodBias == 0.5);
    CHECK_FALSE(vt.dynamicLodBias);
    CHECK(vt.uploadMegabytesPerFrame == 8.0);
    CHECK_FALSE(vt.sparse);
    CHECK(parse(R"({"version": 2, "globe": {"imagery": [{"source": "tiles", "virtualTexture": {"sparse": true}}]}})")
              .globe->imagery.front()
              .virtualTexture->sparse);
}

TEST_CASE("virtualTexture values out of range are errors naming the key", "[world][scenefile][errors]")
{
    auto errorWith = [](const std::string& keys) {
        return errorOf(R"({"version": 2, "globe": {"imagery": [{"source": "tiles", "virtualTexture": {)" + keys + "}}]}}");
    };
    using Catch::Matchers::Contains;
    CHECK_THAT(errorWith(R"("pageSize": 100)"), Contains("/globe/imagery/0/virtualTexture/pageSize: 100 is not a power of two"));
    CHECK_THAT(errorWith(R"("pageSize": 2048)"), Contains("/virtualTexture/pageSize: 2048 is out of range [16, 1024]"));
    CHECK_THAT(errorWith(R"("pageSize": 64, "border": 17)"), Contains("/virtualTexture/border: 17 is out of range [0, 16]"));
    CHECK_THAT(errorWith(R"("physicalPages": 2)"), Contains("/virtualTexture/physicalPages: 2 is out of range [4, 65536]"));
    CHECK_THAT(errorWith(R"("feedbackDivisor": 0)"), Contains("/virtualTexture/feedbackDivisor"));
    CHECK_THAT(errorWith(R"("border": 1, "maximumAnisotropy": 4)"), Contains("/virtualTexture/maximumAnisotropy: 4 is out of range [1, 2]"));
    CHECK_THAT(errorWith(R"("maximumAnisotropy": 2, "sparse": true)"),
               Contains("/virtualTexture/maximumAnisotropy: the sparse path filters trilinearly"));
    CHECK_THAT(errorWith(R"("sparse": "yes")"), Contains("/virtualTexture/sparse"));
    CHECK_THAT(errorWith(R"("pagesize": 256)"), Contains("unknown key \"pagesize\" (did you mean \"pageSize\"?)"));
    CHECK_THAT(errorOf(R"({"version": 2, "globe": {"imagery": [{"source": "tiles", "virtualTexture": {},
        "rectangle": {"west": 0, "south": 0, "east": 10, "north": 10}}]}})"),
               Contains("a virtual texture covers the whole globe"));
    CHECK_THAT(errorOf(R"({"version": 2, "globe": {"imagery": [{"source": "tiles"},
        {"source": "tiles", "virtualTexture": {}}]}})"),
               Contains("/globe/imagery/1/virtualTexture: a virtual texture must be the globe's only imagery layer"));
    CHECK_THAT(errorOf(R"({"version": 2, "globe": {"imagery": [{"source": "tiles", "virtualTexture": {}}],
        "terrain": {"source": "t"}}})"),
               Contains("/globe/terrain: a virtual texture is drawn on the ellipsoid's surface"));
}

TEST_CASE("A camera path whose eye meets its target, at a keyframe or between two, is refused", "[world][scenefile][errors]")
{
    auto pathError = [](std::string_view keyframes) {
        try {
            parseCameraPathText("{\"version\": 1, \"keyframes\": [" + std::string(keyframes) + "]}", "path.json");
        } catch (const SceneFileError& error) {
            return std::string(error.what());
        }
        return std::string("no error");
    };
    const std::string above = R"({"time": 0, "position": {"lon": 0, "lat": 0, "height": 2000000}, "target": {"lon": 0, "lat": 0}})";
    CHECK(pathError(above + R"(, {"time": 1, "position": {"lon": 5, "lat": 5, "height": 10}, "target": {"lon": 5, "lat": 5, "height": 10}})") ==
          "path.json:1:198: /keyframes/1/target: the target is the camera's position; the camera would look nowhere");
    // Eye and target swap places: halfway, both are 1,000 km above (0, 0).
    CHECK(pathError(above + R"(, {"time": 4, "position": {"lon": 0, "lat": 0}, "target": {"lon": 0, "lat": 0, "height": 2000000}})") ==
          "path.json:1:128: /keyframes/1: flying here from the keyframe before, the camera passes through its target at 2 s "
          "and would look nowhere; move a position or a target");
    // Crossing paths that meet off the samples (at a third of the way) are found too.
    CHECK_THAT(pathError(above + R"(, {"time": 3, "position": {"lon": 0, "lat": 0}, "target": {"lon": 0, "lat": 0, "height": 4000000}})"),
               Contains("/keyframes/1: flying here from the keyframe before, the camera passes through its target at 1 s"));
    // Passing a metre from the target is a flight, not a fault.
    CHECK(parseCameraPathText(R"({"version": 1, "keyframes": [)" + above +
                                  R"(, {"time": 4, "position": {"lon": 0, "lat": 0}, "target": {"lon": 0.00001, "lat": 0, "height": 2000000}}]})",
                              "path.json")
              .size() == 2);
}

TEST_CASE("Layers take a height reference: absolute by default, clampToGround or relativeToGround, nothing else",
          "[world][scenefile][terrain]")
{
    const SceneDescription scene = parse(R"({"version": 2, "layers": [
        {"type": "polyline", "positions": [[0, 0], [1, 1]]},
        {"type": "polyline", "positions": [[0, 0], [1, 1]], "heightReference": "clampToGround"},
        {"type": "model", "source": "m.glb", "position": {"lon": 0, "lat": 0}, "heightReference": "relativeToGround"},
        {"type": "points", "source": "p.csv", "heightReference": "absolute"},
        {"type": "geojson", "source": "a.geojson", "heightReference": "clampToGround"},
        {"type": "geojson", "source": "a.json", "fill": {"color": "#ff0000"}, "heightReference": "relativeToGround"}]})");
    REQUIRE(scene.layers.size() == 6);
    CHECK(std::get<PolylineLayer>(scene.layers[0]).heightReference == HeightReference::Absolute);
    CHECK(std::get<PolylineLayer>(scene.layers[1]).heightReference == HeightReference::ClampToGround);
    CHECK(std::get<ModelLayer>(scene.layers[2]).heightReference == HeightReference::RelativeToGround);
    CHECK(std::get<PointsLayer>(scene.layers[3]).heightReference == HeightReference::Absolute);
    CHECK(std::get<GeoJsonLayer>(scene.layers[4]).heightReference == HeightReference::ClampToGround);
    CHECK(std::get<GeoJsonLayer>(scene.layers[5]).heightReference == HeightReference::RelativeToGround);
    CHECK(errorOf(R"({"version": 2, "layers": [{"type": "polyline", "positions": [[0, 0], [1, 1]], "heightReference": "ground"}]})")
              .find("/layers/0/heightReference: unknown value \"ground\"; expected one of \"absolute\", \"clampToGround\", \"relativeToGround\"") != std::string::npos);
    // GeoJSON (and TopoJSON) layers are refused a bad value as the others are, the file and the key named.
    CHECK(errorOf(R"({"version": 2, "layers": [{"type": "geojson", "source": "a.geojson", "heightReference": "draped"}]})")
              .find("test.json:1:89: /layers/0/heightReference: unknown value \"draped\"; expected one of \"absolute\", "
                    "\"clampToGround\", \"relativeToGround\"") != std::string::npos);
    CHECK(errorOf(R"({"version": 2, "layers": [{"type": "geojson", "source": "a.json", "heightReference": true}]})")
              .find("/layers/0/heightReference") != std::string::npos);
}

TEST_CASE("Terrain shading: colour ramps, contours and hillshade read with their documented defaults, each checked",
          "[world][scenefile][terrain]")
{
    const TerrainShadingDescription none =
        parse(R"({"version": 2, "globe": {"terrain": {"source": "t"}}})", false).globe->terrain->shading;
    CHECK(none.color == TerrainShadingDescription::Color::Base);
    CHECK(none.contourInterval == 0.0);
    CHECK_FALSE(none.hillshade);
    CHECK_FALSE(none.water);

    const TerrainShadingDescription all = parse(R"({"version": 2, "globe": {"terrain": {"source": "t", "shading": {
        "color": "height", "heightRange": [-8000, 6000], "contours": {"interval": 250, "color": "#ff0000", "width": 2},
        "hillshade": {"azimuth": 270, "altitude": 30}, "water": true}}}})", false).globe->terrain->shading;
    CHECK(all.color == TerrainShadingDescription::Color::Height);
    CHECK(all.minimumHeight == -8000.0);
    CHECK(all.maximumHeight == 6000.0);
    CHECK(all.contourInterval == 250.0);
    CHECK(all.contourColor == glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
    CHECK(all.contourWidth == 2.0);
    CHECK(all.hillshade);
    CHECK(all.hillshadeAzimuth == 270.0);
    CHECK(all.hillshadeAltitude == 30.0);
    CHECK(all.water);

    // Documented defaults: white contours 1 px wide; the hillshade's light from the north-west, 45 degrees up.
    const TerrainShadingDescription defaults = parse(R"({"version": 2, "globe": {"terrain": {"source": "t", "shading": {
        "color": "slope", "contours": {"interval": 100}, "hillshade": true}}}})", false).globe->terrain->shading;
    CHECK(defaults.color == TerrainShadingDescription::Color::Slope);
    CHECK(defaults.contourColor == glm::vec4(1.0f));
    CHECK(defaults.contourWidth == 1.0);
    CHECK(defaults.hillshadeAzimuth == 315.0);
    CHECK(defaults.hillshadeAltitude == 45.0);

    const auto shadingError = [](const std::string& shading) {
        return errorOf(R"({"version": 2, "globe": {"terrain": {"source": "t", "shading": )" + shading + "}}}");
    };
    CHECK(shadingError(R"({"color": "aspect"})").find("/globe/terrain/shading/color: unknown value \"aspect\"; expected one of \"base\", \"height\", \"slope\"") != std::string::npos);
    CHECK(shadingError(R"({"heightRange": [100, 100]})").find("/globe/terrain/shading/heightRange: the lowest height must be below the highest") != std::string::npos);
    CHECK(shadingError(R"({"heightRange": [0]})").find("expected [lowest, highest] in metres") != std::string::npos);
    CHECK(shadingError(R"({"contours": {"color": "#fff"}})").find("/globe/terrain/shading/contours") != std::string::npos);
    CHECK(shadingError(R"({"contours": {"interval": 0}})").find("/globe/terrain/shading/contours/interval: 0 is out of range") != std::string::npos);
    CHECK(shadingError(R"({"hillshade": {"altitude": 0}})").find("/globe/terrain/shading/hillshade/altitude: 0 is out of range") != std::string::npos);
    CHECK(shadingError(R"({"hillshade": "yes"})").find("expected true, false or") != std::string::npos);
    CHECK(shadingError(R"({"water": 1})").find("/globe/terrain/shading/water") != std::string::npos);
    CHECK(shadingError(R"({"hilshade": true})").find("unknown key \"hilshade\"") != std::string::npos);
}

TEST_CASE("Terrain under a tiled globe: its source, format, exaggeration and cache folder, each checked",
          "[world][scenefile][terrain]")
{
    const SceneDescription scene = parse(R"({"version": 2, "globe": {
        "imagery": [{"source": "../imagery/BlueMarble"}],
        "terrain": {"source": "../terrain/etopo5", "format": "png16", "exaggeration": 2.5, "cacheFolder": "cache"}}})");
    REQUIRE(scene.globe);
    REQUIRE(scene.globe->terrain);
    const TerrainDescription& terrain = *scene.globe->terrain;
    CHECK(fs::path(terrain.source) == (kScenes / "../terrain/etopo5").lexically_normal());
    CHECK(terrain.format == "png16");
    CHECK(terrain.exaggeration == 2.5);
    CHECK(terrain.cacheFolder == (kScenes / "cache").lexically_normal());
    // A URL stays as it is; terrain alone makes a tiled globe too.
    const SceneDescription remote =
        parse(R"({"version": 2, "globe": {"terrain": {"source": "https://example.org/terrain/layer.json"}}})");
    CHECK(remote.globe->terrain->source == "https://example.org/terrain/layer.json");
    CHECK(remote.globe->terrain->exaggeration == 1.0);

    CHECK(errorOf(R"({"version": 2, "globe": {"terrain": {"source": "t", "format": "geotiff"}}})") ==
          R"(test.json:1:63: /globe/terrain/format: "geotiff" is not a terrain format (quantized-mesh, heightmap, png16, terrain-rgb, terrarium, hgt, gdal))");
    CHECK(errorOf(R"({"version": 2, "globe": {"terrain": {"source": "t", "exaggeration": -1}}})") ==
          "test.json:1:69: /globe/terrain/exaggeration: -1 is out of range [0, 100]");
    CHECK(errorOf(R"({"version": 2, "globe": {"terrain": {"sourc": "t"}}})").find("unknown key \"sourc\"") != std::string::npos);
    CHECK(errorOf(R"({"version": 2, "globe": {"texture": "a.jpg", "terrain": {"source": "t"}}})")
              .find("a globe with terrain has no \"texture\"") != std::string::npos);
    CHECK(errorOf(R"({"version": 2, "globe": {"terrain": {"source": "no-such-folder"}}})", true)
              .find("/globe/terrain/source") != std::string::npos);
}

TEST_CASE("Terrain morphing: the frames a refined tile takes from its parent's surface to its own, checked; none by default",
          "[world][scenefile][terrain]")
{
    CHECK(parse(R"({"version": 2, "globe": {"terrain": {"source": "../terrain/etopo5"}}})").globe->terrain->morphFrames == 0);
    CHECK(parse(R"({"version": 2, "globe": {"terrain": {"source": "../terrain/etopo5", "morphFrames": 12}}})")
              .globe->terrain->morphFrames == 12);
    CHECK(errorOf(R"({"version": 2, "globe": {"terrain": {"source": "t", "morphFrames": -1}}})") ==
          "test.json:1:68: /globe/terrain/morphFrames: -1 is out of range [0, 600]");
    CHECK(errorOf(R"({"version": 2, "globe": {"terrain": {"source": "t", "morphFrames": 2.5}}})") ==
          "test.json:1:68: /globe/terrain/morphFrames: expected a number of frames, got 2.5");
}

TEST_CASE("Terrain drawn as clipmaps: the method and the posts, each checked; the quadtree stays the default",
          "[world][scenefile][terrain][clipmap]")
{
    const SceneDescription quadtree = parse(R"({"version": 2, "globe": {"terrain": {"source": "../terrain/etopo5"}}})");
    CHECK(quadtree.globe->terrain->method == TerrainMethod::Quadtree);
    CHECK(quadtree.globe->terrain->posts == 255);
    const SceneDescription clipmap = parse(
        R"({"version": 2, "globe": {"terrain": {"source": "../terrain/etopo5", "method": "clipmap", "posts": 127}}})");
    CHECK(clipmap.globe->terrain->method == TerrainMethod::Clipmap);
    CHECK(clipmap.globe->terrain->posts == 127);
    CHECK(errorOf(R"({"version": 2, "globe": {"terrain": {"source": "t", "method": "geoclipmap"}}})") ==
          R"(test.json:1:63: /globe/terrain/method: unknown value "geoclipmap"; expected one of "quadtree", "clipmap")");
    CHECK(errorOf(R"({"version": 2, "globe": {"terrain": {"source": "t", "method": "clipmap", "posts": 256}}})") ==
          "test.json:1:83: /globe/terrain/posts: 256 is not 2^k - 1 (15, 31, 63, 127, 255, 511, 1023)");
    CHECK(errorOf(R"({"version": 2, "globe": {"terrain": {"source": "t", "posts": 7}}})") ==
          "test.json:1:62: /globe/terrain/posts: 7 is out of range [15, 1023]");
}
