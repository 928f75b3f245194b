// Files as an attacker makes them: named pipes and folders where a reader expects a file, glTF
// nesting that would exhaust tinygltf's stack, buffers that name a folder or a pipe, messages that
// would echo megabytes. Each is a clear error naming the file, and nothing blocks.

#include <orbis/world/CsvPoints.h>
#include <orbis/world/GeoJson.h>
#include <orbis/world/GltfModel.h>
#include <orbis/world/ImageFile.h>
#include <orbis/world/TileMapResource.h>
#include <orbis/world/TopoJson.h>

#include <orbis/core/Error.h>

#include "TempFiles.h"

#include <catch2/catch.hpp>

#include <chrono>
#include <future>

#include <sys/stat.h>

using namespace orbis;
using namespace orbis::world;
using Catch::Matchers::Contains;

namespace {

/// The error of `read`, run where a hang would show as a timeout instead of blocking the suite.
template <typename Read>
std::string errorWithin20Seconds(Read read)
{
    auto reading = std::async(std::launch::async, [&] { return test::errorMessage(read); });
    REQUIRE(reading.wait_for(std::chrono::seconds(20)) == std::future_status::ready);
    return reading.get();
}

std::string readError(const std::filesystem::path& file)
{
    return errorWithin20Seconds([&] { GltfModel::read(file); });
}

/// A model of one triangle whose buffer is `uri`.
std::string triangleWithBuffer(const std::string& uri)
{
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                     "min": [0, 0, 0], "max": [1, 1, 0]}],
      "bufferViews": [{"buffer": 0, "byteLength": 36}],
      "buffers": [{"byteLength": 36, "uri": ")" + uri + R"("}]})";
}

} // namespace

TEST_CASE("A glTF nested 100,000 deep is refused before tinygltf parses it", "[world][gltf][hostile]")
{
    const test::TempDirectory folder;
    const std::string deep = R"({"asset": {"version": "2.0"}, "extras": )" + std::string(100000, '[') +
                             std::string(100000, ']') + "}";
    CHECK_THAT(readError(folder.write("deep.gltf", deep)), Contains("deep.gltf:1:168: invalid JSON: nested deeper than 128 levels"));
    // The same JSON as a .glb's chunk: header (magic, version 2, length), chunk length and "JSON".
    std::string glb = "glTF";
    auto word = [&](std::uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
    word(2);
    word(static_cast<std::uint32_t>(20 + deep.size()));
    word(static_cast<std::uint32_t>(deep.size()));
    glb += "JSON";
    glb += deep;
    CHECK_THAT(readError(folder.write("deep.glb", glb)), Contains("deep.glb:1:168: invalid JSON: nested deeper than 128 levels"));
}

TEST_CASE("A glTF buffer that is a folder or a named pipe is refused, and nothing blocks", "[world][gltf][hostile]")
{
    const test::TempDirectory folder;
    std::filesystem::create_directory(folder.path() / "buffer.bin");
    CHECK_THAT(readError(folder.write("folder.gltf", triangleWithBuffer("buffer.bin"))),
               Contains("folder.gltf") && Contains("buffer.bin: glTF buffer or image is a folder, not a regular file"));
    REQUIRE(::mkfifo((folder.path() / "pipe.bin").c_str(), 0600) == 0);
    CHECK_THAT(readError(folder.write("pipe.gltf", triangleWithBuffer("pipe.bin"))),
               Contains("pipe.bin: glTF buffer or image is a named pipe, not a regular file"));
    // The model file itself too.
    REQUIRE(::mkfifo((folder.path() / "model.gltf").c_str(), 0600) == 0);
    CHECK_THAT(readError(folder.path() / "model.gltf"), Contains("model.gltf: glTF model is a named pipe, not a regular file"));
    // A shell-style name is a name: nothing is expanded.
    CHECK_THAT(readError(folder.write("expand.gltf", triangleWithBuffer("$(touch x)~"))), Contains("$(touch x)~"));
    CHECK_FALSE(std::filesystem::exists(folder.path() / "x"));
}

TEST_CASE("A glTF error quoting a long data URI is cut", "[world][gltf][hostile]")
{
    const test::TempDirectory folder;
    const std::string uri = "data:application/octet-stream;base64," + std::string(1 << 20, '!');
    const std::string message = readError(folder.write("long.gltf", triangleWithBuffer(uri)));
    CHECK(message.size() < 2000);
    CHECK_THAT(message, Contains("long.gltf"));
}

TEST_CASE("Every reader refuses a named pipe or a folder where it expects a file, without blocking", "[world][files][hostile]")
{
    const test::TempDirectory folder;
    const std::filesystem::path pipe = folder.path() / "pipe";
    REQUIRE(::mkfifo(pipe.c_str(), 0600) == 0);
    CHECK_THAT(errorWithin20Seconds([&] { loadGeoJson(pipe); }), Contains("pipe: GeoJSON file is a named pipe"));
    CHECK_THAT(errorWithin20Seconds([&] { loadTopoJson(pipe); }), Contains("pipe: TopoJSON file is a named pipe"));
    CHECK_THAT(errorWithin20Seconds([&] { loadCsvPoints(pipe); }), Contains("pipe: CSV file is a named pipe"));
    CHECK_THAT(errorWithin20Seconds([&] { readImage(pipe); }), Contains("pipe: image is a named pipe"));
    CHECK_THAT(errorWithin20Seconds([&] { readTileMapResource(pipe); }), Contains("is a named pipe"));
    CHECK_THAT(errorWithin20Seconds([&] { loadGeoJson(folder.path()); }), Contains("GeoJSON file is a folder"));
}
