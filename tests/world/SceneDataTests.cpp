#include "TempFiles.h"

#include <orbis/world/SceneData.h>

#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

using namespace orbis;
using namespace orbis::world;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
namespace fs = std::filesystem;

namespace {

const fs::path kSourceDirectory = ORBIS_SOURCE_DIR;

/// Each fault's text.
std::vector<std::string> texts(const DiagnosticList& faults)
{
    std::vector<std::string> lines;
    for (const Diagnostic& fault : faults.entries()) {
        lines.push_back(fault.text());
    }
    return lines;
}

} // namespace

TEST_CASE("Every example scene and the files it names read without a fault", "[world][validate]")
{
    for (const auto& entry : fs::directory_iterator(kSourceDirectory / "data" / "scenes")) {
        if (entry.path().extension() == ".json") {
            INFO(entry.path());
            CHECK(texts(validateSceneFile(entry.path())).empty());
        }
    }
}

TEST_CASE("validate reads the files a scene names as rendering would, and places their faults at the key naming them",
          "[world][validate]")
{
    const test::TempDirectory folder;
    fs::copy_file(kSourceDirectory / "tests" / "world" / "scenes" / "garbage.glb", folder.path() / "garbage.glb");
    folder.write("rows.csv", "name,lat,lon\nA,1,2\nB,north,3\n");
    folder.write("label.csv", "name,lat,lon\nA,1,2\n");
    folder.write("lines.geojson", R"({"type": "LineString", "coordinates": [[0, 0], [1, 95]]})");
    folder.write("dot.png", "not a PNG at all");
    folder.write("night.jpg", "\xFF\xD8\xFF but no JPEG after it");
    const fs::path scene = folder.write("scene.json", R"({
  "version": 2,
  "globe": {"nightTexture": "night.jpg"},
  "layers": [
    {"type": "model", "source": "garbage.glb", "position": {"lon": 0, "lat": 0}},
    {"type": "points", "source": "rows.csv"},
    {"type": "geojson", "source": "lines.geojson"},
    {"type": "points", "source": "label.csv", "billboard": {"image": "dot.png"}},
    {"type": "polyline", "positions": [[0, 0], [1, 1]]}
  ]
})");
    const std::vector<std::string> found = texts(validateSceneFile(scene));
    REQUIRE(found.size() == 5);
    const std::string at = scene.string();
    const std::string in = folder.path().string() + "/";
    CHECK_THAT(found[0], StartsWith(at + ":3:29: /globe/nightTexture: " + in + "night.jpg"));
    CHECK_THAT(found[1], StartsWith(at + ":5:33: /layers/0/source: " + in + "garbage.glb: "));
    CHECK(found[2] == at + ":6:34: /layers/1/source: " + in +
                          "rows.csv:3: column 2 \"lat\": expected a finite number (latitude), got \"north\"");
    CHECK(found[3] == at + ":7:35: /layers/2/source: " + in +
                          "lines.geojson:1:48: coordinates[1]: latitude 95 out of range [-90, 90]");
    CHECK_THAT(found[4], StartsWith(at + ":8:70: /layers/3/billboard/image: " + in + "dot.png"));
}

TEST_CASE("validate reads the files only once the scene file itself has no fault", "[world][validate]")
{
    const test::TempDirectory folder;
    fs::copy_file(kSourceDirectory / "tests" / "world" / "scenes" / "garbage.glb", folder.path() / "garbage.glb");
    const fs::path scene = folder.write("scene.json", R"({"version": 2, "colour": 1,
  "layers": [{"type": "model", "source": "garbage.glb", "position": {"lon": 0, "lat": 0}}]})");
    const std::vector<std::string> found = texts(validateSceneFile(scene));
    REQUIRE(found.size() == 1);
    CHECK_THAT(found[0], Contains("/colour: unknown key"));
}

TEST_CASE("validate opens a globe's tile sources as rendering would", "[world][validate]")
{
    const test::TempDirectory folder;
    fs::create_directories(folder.path() / "pyramid");
    folder.write("pyramid/tilemapresource.xml", "<TileMap><TileSets profile=\"geodetic\">");
    const fs::path scene = folder.write("scene.json", R"({"version": 2,
  "globe": {"imagery": [{"source": "pyramid"}]}})");
    const std::vector<std::string> found = texts(validateSceneFile(scene));
    REQUIRE(found.size() == 1);
    CHECK_THAT(found[0], StartsWith(scene.string() + ":2:36: /globe/imagery/0/source: "));
    CHECK_THAT(found[0], Contains("tilemapresource.xml"));
}
