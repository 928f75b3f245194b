#include "SceneTestSupport.h"
#include "TempFiles.h"

#include "RendererTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/core/Transforms.h>
#include <orbis/scene/Effect.h>
#include <orbis/scene/Globe.h>
#include <orbis/scene/ModelPrimitive.h>
#include <orbis/scene/SceneBuilder.h>
#include <orbis/world/GltfModel.h>
#include <orbis/world/ImageFile.h>
#include <orbis/world/SceneFile.h>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>

using namespace orbis;
using namespace orbis::world;
using namespace orbis::scene;
using namespace orbis::test;
using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

std::filesystem::path modelFile(const char* name)
{
    return std::filesystem::path(ORBIS_SOURCE_DIR) / "data" / "models" / name;
}

std::string readBytes(const std::filesystem::path& file)
{
    std::ifstream in(file, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    return bytes.str();
}

std::string base64(std::string_view bytes)
{
    static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        std::uint32_t group = static_cast<std::uint8_t>(bytes[i]) << 16;
        if (i + 1 < bytes.size()) {
            group |= static_cast<std::uint32_t>(static_cast<std::uint8_t>(bytes[i + 1])) << 8;
        }
        if (i + 2 < bytes.size()) {
            group |= static_cast<std::uint8_t>(bytes[i + 2]);
        }
        out += kDigits[(group >> 18) & 63];
        out += kDigits[(group >> 12) & 63];
        out += i + 1 < bytes.size() ? kDigits[(group >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? kDigits[group & 63] : '=';
    }
    return out;
}

/// A one-mesh glTF written by a test: positions (and optional texture coordinates and u16
/// indices) in one buffer given as a data URI; the rest of the JSON (materials, nodes, ...) as the
/// test says.
struct TestGltf {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec2> textureCoordinates;
    std::vector<std::uint16_t> indices;
    int mode = 4;
    int material = -1;
    std::string nodes = R"([{"mesh": 0}])";
    std::string extra; ///< more top-level members, each followed by a comma

    std::string json() const
    {
        std::string buffer;
        std::string views;
        std::string accessors;
        std::string attributes;
        auto add = [&](const void* data, std::size_t size, std::size_t count, int componentType, const char* type,
                       const std::string& bounds = {}) {
            while (buffer.size() % 4 != 0) {
                buffer.push_back('\0');
            }
            const std::size_t view = std::count(views.begin(), views.end(), '{');
            views += std::string(views.empty() ? "" : ",") + R"({"buffer": 0, "byteOffset": )" +
                     std::to_string(buffer.size()) + R"(, "byteLength": )" + std::to_string(size) + "}";
            accessors += std::string(accessors.empty() ? "" : ",") + R"({"bufferView": )" + std::to_string(view) +
                         R"(, "componentType": )" + std::to_string(componentType) + R"(, "count": )" +
                         std::to_string(count) + R"(, "type": ")" + type + "\"" + bounds + "}";
            buffer.append(static_cast<const char*>(data), size);
            return view;
        };
        attributes = R"("POSITION": )" +
                     std::to_string(add(positions.data(), positions.size() * 12, positions.size(), 5126, "VEC3"));
        if (!textureCoordinates.empty()) {
            attributes += R"(, "TEXCOORD_0": )" + std::to_string(add(textureCoordinates.data(),
                                                                        textureCoordinates.size() * 8,
                                                                        textureCoordinates.size(), 5126, "VEC2"));
        }
        std::string primitive = "{\"attributes\": {" + attributes + "}, \"mode\": " + std::to_string(mode);
        if (!indices.empty()) {
            primitive += ", \"indices\": " +
                         std::to_string(add(indices.data(), indices.size() * 2, indices.size(), 5123, "SCALAR"));
        }
        if (material >= 0) {
            primitive += ", \"material\": " + std::to_string(material);
        }
        primitive += "}";
        return "{\"asset\": {\"version\": \"2.0\"}, " + extra + "\"scene\": 0, \"scenes\": [{\"nodes\": [0]}], " +
               "\"nodes\": " + nodes + ", \"meshes\": [{\"primitives\": [" + primitive + "]}], " +
               "\"accessors\": [" + accessors + "], \"bufferViews\": [" + views + "], " +
               "\"buffers\": [{\"byteLength\": " + std::to_string(buffer.size()) +
               ", \"uri\": \"data:application/octet-stream;base64," + base64(buffer) + "\"}]}";
    }
};

/// A 2 m square lying flat in glTF's x-z plane (facing +y, up), centred on the origin, with
/// texture coordinates that show an image upright when the model faces north: glTF +x is west,
/// +z north, and the image's top-left corner (0, 0) goes to the north-west corner.
TestGltf flatSquare()
{
    TestGltf gltf;
    gltf.positions = {{1, 0, 1}, {-1, 0, 1}, {-1, 0, -1}, {1, 0, -1}}; // NW, NE, SE, SW
    gltf.textureCoordinates = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    gltf.indices = {0, 3, 2, 0, 2, 1}; // counter-clockwise seen from +y
    return gltf;
}

/// A 2x2 image: red, green on top; blue, white below.
Image quadrantImage()
{
    Image image(2, 2, 4);
    const std::uint8_t colours[4][4] = {{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}, {255, 255, 255, 255}};
    for (int i = 0; i < 4; ++i) {
        std::memcpy(image.pixel(i % 2, i / 2), colours[i], 4);
    }
    return image;
}

/// glTF's sRGB encoding of a linear value, as the model shader writes it (0..255).
int srgb(double linear)
{
    const double encoded = linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
    return static_cast<int>(std::lround(encoded * 255.0));
}

/// A camera straight above a position (height metres over it), north up on the image, and the Sun
/// overhead so that surfaces facing up are lit fully (0.3 + 0.7 x 1).
void lookDownAt(Scene& scene, const Geodetic3D& position, double height)
{
    const glm::dvec3 origin = kEarth.toCartesian(position);
    const glm::dmat3 enu = eastNorthUpAxes(kEarth, origin);
    scene.camera().lookAt(origin + height * enu[2], origin, enu[1]);
    scene.setSunDirection(enu[2]);
}

/// Mean position (pixel centres at .5) of the pixels that match; (-1, -1) when none.
template <typename Match>
glm::dvec2 centroidOf(const Image& image, Match match, int* count = nullptr)
{
    glm::dvec2 sum(0.0);
    int n = 0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            if (match(pixelAt(image, x, y))) {
                sum += glm::dvec2(x + 0.5, y + 0.5);
                ++n;
            }
        }
    }
    if (count) {
        *count = n;
    }
    return n > 0 ? sum / static_cast<double>(n) : glm::dvec2(-1.0);
}

/// Where a point of the model (glTF coordinates) lands on the image, pixel centres at .5.
glm::dvec2 projectModelPoint(const Scene& scene, const ModelPrimitive& model, const glm::dvec3& local, int size)
{
    const glm::dvec3 world(model.modelMatrix() * glm::dvec4(local, 1.0));
    const Camera& camera = scene.camera();
    const glm::dvec4 clip = camera.projectionMatrix(1.0, 1.0, 1e8) * camera.viewMatrix() * glm::dvec4(world, 1.0);
    return {(clip.x / clip.w * 0.5 + 0.5) * size, (1.0 - (clip.y / clip.w * 0.5 + 0.5)) * size};
}

std::shared_ptr<Globe> plainGlobe()
{
    GlobeOptions options;
    options.color = {0.0f, 0.0f, 1.0f, 1.0f};
    return std::make_shared<Globe>(kEarth, options);
}

} // namespace

// -------------------------------------------------------------------------------------------------
// Reading

TEST_CASE("The project's aircraft reads the same from .gltf (with .bin and .png) and .glb", "[scene][model]")
{
    const GltfModel text = GltfModel::read(modelFile("aircraft.gltf"));
    const GltfModel binary = GltfModel::read(modelFile("aircraft.glb"));

    // Six materials (fuselage, nose, wing, fin, two lights), so six batches; 92 triangles: fuselage
    // 12, nose 4, wing and tailplane 20 each, fin 12, lights 12 each.
    REQUIRE(text.batches.size() == 6);
    REQUIRE(text.triangleCount() == 92);
    REQUIRE(text.materials.size() == 6);
    REQUIRE(text.textures.size() == 1);
    REQUIRE(text.images.size() == 1);
    CHECK(text.images[0].width == 16);
    CHECK(text.images[0].height == 16);
    CHECK(text.textures[0].sampler.wrapS == TextureWrap::Clamp);
    CHECK(text.textures[0].sampler.minificationFilter == TextureMinificationFilter::LinearMipmapLinear);

    REQUIRE(binary.batches.size() == text.batches.size());
    for (std::size_t b = 0; b < text.batches.size(); ++b) {
        const Mesh& a = text.batches[b].mesh;
        const Mesh& c = binary.batches[b].mesh;
        CHECK(text.batches[b].material == binary.batches[b].material);
        // The same bytes through the same arithmetic: exactly equal.
        CHECK(a.positions == c.positions);
        CHECK(a.normals == c.normals);
        CHECK(a.textureCoordinates == c.textureCoordinates);
        CHECK(a.indices == c.indices);
        CHECK(a.normals.size() == a.positions.size());
    }
    for (std::size_t m = 0; m < text.materials.size(); ++m) {
        CHECK(text.materials[m].name == binary.materials[m].name);
        CHECK(text.materials[m].baseColorFactor == binary.materials[m].baseColorFactor);
        CHECK(text.materials[m].baseColorTexture == binary.materials[m].baseColorTexture);
    }
    const Image paint = text.decodeImage(0);
    CHECK(paint.pixels == binary.decodeImage(0).pixels);
    CHECK(pixelAt(paint, 3, 8) == glm::ivec4(20, 30, 110, 255)); // the navy cheat line

    // Extents in glTF axes: the nose tip at z = 4.5, the wingtip lights reach x = +-5.65, the fin
    // top at y = 0.35 + 1.5.
    glm::dvec3 lo(1e9);
    glm::dvec3 hi(-1e9);
    for (const GltfBatch& batch : text.batches) {
        for (const glm::dvec3& p : batch.mesh.positions) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
    }
    // Float data read into doubles: 1e-6 m covers the float rounding of the file's values.
    CHECK_THAT(hi.z, WithinAbs(4.5, 1e-6));
    CHECK_THAT(lo.z, WithinAbs(-4.6, 1e-6));
    CHECK_THAT(hi.x, WithinAbs(5.65, 1e-6));
    CHECK_THAT(lo.x, WithinAbs(-5.65, 1e-6));
    CHECK_THAT(hi.y, WithinAbs(1.85, 1e-6));
}

TEST_CASE("Node transforms (translation, rotation, scale or a matrix) reach the positions and normals", "[scene][model]")
{
    TempDirectory directory;
    TestGltf gltf;
    gltf.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}; // facing +z
    // Parent: translate (10, 0, 0), turn 90 degrees about +y; child: translate (0, 0, 1), scale 2.
    const double s = std::sqrt(0.5);
    gltf.nodes = R"([{"children": [1], "translation": [10, 0, 0], "rotation": [0, )" + std::to_string(s) + ", 0, " +
                 std::to_string(s) + R"(]}, {"mesh": 0, "translation": [0, 0, 1], "scale": [2, 2, 2]}])";
    const GltfModel trs = GltfModel::read(directory.write("trs.gltf", gltf.json()));

    const glm::dmat4 parent =
        glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(10, 0, 0)), kHalfPi, glm::dvec3(0, 1, 0));
    const glm::dmat4 child = glm::scale(glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, 1)), glm::dvec3(2.0));
    const glm::dmat4 expected = parent * child;

    REQUIRE(trs.batches.size() == 1);
    const Mesh& mesh = trs.batches[0].mesh;
    REQUIRE(mesh.positions.size() == 3);
    for (std::size_t i = 0; i < 3; ++i) {
        const glm::dvec3 want(expected * glm::dvec4(gltf.positions[i], 1.0));
        // The quaternion's components went through decimal text (std::to_string, 6 digits): 1e-5.
        CHECK_THAT(mesh.positions[i].x, WithinAbs(want.x, 1e-5));
        CHECK_THAT(mesh.positions[i].y, WithinAbs(want.y, 1e-5));
        CHECK_THAT(mesh.positions[i].z, WithinAbs(want.z, 1e-5));
        // The face's +z turned 90 degrees about +y: +x. Float normals: 1e-6.
        CHECK_THAT(mesh.normals[i].x, WithinAbs(1.0, 1e-6));
        CHECK_THAT(mesh.normals[i].z, WithinAbs(0.0, 1e-6));
    }
    CHECK_THAT(mesh.positions[1].z, WithinAbs(-2.0, 1e-5)); // (1, 0, 0) scaled 2, turned to -z
    CHECK_THAT(mesh.positions[0].x, WithinAbs(11.0, 1e-5)); // (0, 0, 0) moved to (0, 0, 1), turned to +x, + 10

    // The same transform as one matrix on the child (column-major, as glTF stores it).
    std::string matrix;
    for (int column = 0; column < 4; ++column) {
        for (int row = 0; row < 4; ++row) {
            matrix += (matrix.empty() ? "" : ", ") + std::to_string(expected[column][row]);
        }
    }
    gltf.nodes = R"([{"children": [1]}, {"mesh": 0, "matrix": [)" + matrix + "]}]";
    const GltfModel byMatrix = GltfModel::read(directory.write("matrix.gltf", gltf.json()));
    for (std::size_t i = 0; i < 3; ++i) {
        // std::to_string keeps 6 decimals of each matrix element: 1e-5 m.
        CHECK_THAT(byMatrix.batches[0].mesh.positions[i].x, WithinAbs(mesh.positions[i].x, 1e-5));
        CHECK_THAT(byMatrix.batches[0].mesh.positions[i].y, WithinAbs(mesh.positions[i].y, 1e-5));
        CHECK_THAT(byMatrix.batches[0].mesh.positions[i].z, WithinAbs(mesh.positions[i].z, 1e-5));
    }

    // A mirroring scale turns the winding back, so the triangle still faces its (mirrored) normal.
    gltf.nodes = R"([{"mesh": 0, "scale": [-1, 1, 1]}])";
    const GltfModel mirrored = GltfModel::read(directory.write("mirror.gltf", gltf.json()));
    const Mesh& m = mirrored.batches[0].mesh;
    const glm::dvec3 faceNormal = glm::cross(m.positions[m.indices[1]] - m.positions[m.indices[0]],
                                             m.positions[m.indices[2]] - m.positions[m.indices[0]]);
    CHECK(glm::dot(faceNormal, glm::dvec3(m.normals[0])) > 0.0);
}

TEST_CASE("Triangle strips and fans become triangle lists with glTF's winding", "[scene][model]")
{
    TempDirectory directory;
    TestGltf gltf;
    gltf.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    gltf.mode = 5; // strip: (0 1 2) (2 1 3)
    const Mesh strip = GltfModel::read(directory.write("strip.gltf", gltf.json())).batches[0].mesh;
    REQUIRE(strip.triangleCount() == 2);
    gltf.mode = 6; // fan: (1 2 0) (2 3 0)
    gltf.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const Mesh fan = GltfModel::read(directory.write("fan.gltf", gltf.json())).batches[0].mesh;
    REQUIRE(fan.triangleCount() == 2);
    // Every triangle counter-clockwise seen from +z, so its flat normal is +z.
    for (const Mesh* mesh : {&strip, &fan}) {
        for (const glm::vec3& normal : mesh->normals) {
            CHECK(normal == glm::vec3(0, 0, 1));
        }
    }
}

// -------------------------------------------------------------------------------------------------
// Errors: every bad file is an orbis::Error naming the file and what is wrong; none crashes.

TEST_CASE("Bad glTF files raise errors naming the file, the part at fault and what is wrong", "[scene][model][errors]")
{
    TempDirectory directory;
    auto readError = [&](const std::string& name, const std::string& text) {
        const std::filesystem::path file = directory.write(name, text);
        return errorMessage([&] { GltfModel::read(file); });
    };
    TestGltf triangle;
    triangle.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

    CHECK_THAT(errorMessage([&] { GltfModel::read(directory.path() / "nowhere.gltf"); }),
               Contains("nowhere.gltf: no such file"));
    CHECK_THAT(readError("syntax.gltf", "{ \"asset\": "), Contains("syntax.gltf: "));
    CHECK_THAT(readError("array.gltf", "[1, 2, 3]"), Contains("array.gltf: "));
    CHECK_THAT(readError("version.gltf", R"({"asset": {"version": "1.0"}})"),
               Contains("version.gltf: asset version \"1.0\": only glTF 2.0 is read"));
    CHECK_THAT(readError("empty.gltf", R"({"asset": {"version": "2.0"}})"),
               Contains("empty.gltf: the default scene has no triangles to draw"));

    TestGltf points = triangle;
    points.mode = 0;
    CHECK_THAT(readError("points.gltf", points.json()),
               Contains("points.gltf: mesh 0 primitive 0: mode 0 (POINTS) is not drawn"));
    TestGltf lines = triangle;
    lines.mode = 1;
    CHECK_THAT(readError("lines.gltf", lines.json()), Contains("mode 1 (LINES) is not drawn"));

    TestGltf badIndex = triangle;
    badIndex.indices = {0, 1, 7};
    CHECK_THAT(readError("index.gltf", badIndex.json()),
               Contains("index.gltf: mesh 0 primitive 0: indices: accessor 1: index 2 is 7, but there are 3 vertices"));

    // An accessor asking for more elements than its buffer view holds.
    std::string tooMany = triangle.json();
    tooMany.replace(tooMany.find("\"count\": 3"), 10, "\"count\": 300");
    CHECK_THAT(readError("count.gltf", tooMany),
               Contains("count.gltf: mesh 0 primitive 0: POSITION: accessor 0: 300 elements of 12 bytes from byte 0 "
                        "(stride 12) run past the end of buffer view 0 (36 bytes)"));

    // A buffer view outside its buffer.
    std::string view = triangle.json();
    view.replace(view.find("\"byteOffset\": 0"), 15, "\"byteOffset\": 4000");
    CHECK_THAT(readError("view.gltf", view), Contains("view.gltf: mesh 0 primitive 0: POSITION: accessor 0: buffer view 0 "
                                                      "(bytes 4000 to 4036) lies outside buffer 0 (36 bytes)"));

    // A missing .bin.
    std::string missing = triangle.json();
    const std::size_t uri = missing.find("data:");
    missing.replace(uri, missing.find('"', uri) - uri, "missing.bin");
    const std::string missingMessage = readError("missing.gltf", missing);
    CHECK_THAT(missingMessage, Contains("missing.gltf: "));
    CHECK_THAT(missingMessage, Contains("missing.bin"));

    TestGltf draco = triangle;
    draco.extra = R"("extensionsUsed": ["KHR_draco_mesh_compression"], "extensionsRequired": ["KHR_draco_mesh_compression"], )";
    CHECK_THAT(readError("draco.gltf", draco.json()),
               Contains("draco.gltf: requires the extension KHR_draco_mesh_compression, which Orbis does not support"));

    TestGltf cycle = triangle;
    cycle.nodes = R"([{"children": [1]}, {"children": [0], "mesh": 0}])";
    CHECK_THAT(readError("cycle.gltf", cycle.json()),
               Contains("cycle.gltf: node 0 is reached twice: nodes must form trees"));

    TestGltf noMesh = triangle;
    noMesh.nodes = R"([{"mesh": 4}])";
    CHECK_THAT(readError("mesh.gltf", noMesh.json()), Contains("mesh.gltf: node 0: mesh 4 does not exist (1 meshes)"));

    TestGltf badMaterial = triangle;
    badMaterial.material = 2;
    CHECK_THAT(readError("material.gltf", badMaterial.json()),
               Contains("material.gltf: mesh 0 primitive 0: material 2 does not exist (0 materials)"));

    TestGltf notAnImage = flatSquare();
    notAnImage.material = 0;
    notAnImage.extra = R"("materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}], )"
                       R"("textures": [{"source": 0}], "images": [{"uri": "data:image/png;base64,)" +
                       base64("not a png at all") + R"("}], )";
    CHECK_THAT(readError("image.gltf", notAnImage.json()),
               Contains("image.gltf: mesh 0 primitive 0: material 0: texture 0: image 0: not a PNG or JPEG image "
                        "that can be decoded"));

    TestGltf missingImage = notAnImage;
    missingImage.extra = R"("materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}], )"
                         R"("textures": [{"source": 0}], "images": [{"uri": "paint-missing.png"}], )";
    CHECK_THAT(readError("noimage.gltf", missingImage.json()),
               Contains("noimage.gltf: mesh 0 primitive 0: material 0: texture 0: image 0 (\"paint-missing.png\"): "
                        "cannot read the file"));

    TestGltf basis = notAnImage;
    basis.extra = R"("materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}], "textures": [{}], )";
    CHECK_THAT(readError("basis.gltf", basis.json()), Contains("basis.gltf: mesh 0 primitive 0: material 0: texture 0: no source image"));

    // An accessor without a buffer view is zeros; a count no file backs is refused, not allocated.
    std::string zeros = triangle.json();
    zeros.replace(zeros.find("\"bufferView\": 0, "), 17, "");
    zeros.replace(zeros.find("\"count\": 3"), 10, "\"count\": 3000000000");
    CHECK_THAT(readError("zeros.gltf", zeros),
               Contains("zeros.gltf: mesh 0 primitive 0: POSITION: accessor 0: 3000000000 zero elements without a "
                        "buffer view is too many"));

    const std::string glb = readBytes(modelFile("aircraft.glb"));
    CHECK_THAT(readError("header.glb", glb.substr(0, 10)), Contains("header.glb: "));
    CHECK_THAT(readError("half.glb", glb.substr(0, glb.size() / 2)), Contains("half.glb: "));
}

TEST_CASE("Truncated and corrupted model files load or raise orbis::Error, never crash", "[scene][model][errors]")
{
    TempDirectory directory;
    const std::string glb = readBytes(modelFile("aircraft.glb"));
    const std::string gltf = readBytes(modelFile("aircraft.gltf"));
    REQUIRE(glb.size() > 1000);

    auto tryRead = [&](const std::string& name, const std::string& bytes) {
        const std::filesystem::path file = directory.write(name, bytes);
        try {
            GltfModel::read(file);
        } catch (const Error& error) {
            // Every message starts with the file (and where the JSON has a fault, its line and column).
            CHECK_THAT(error.what(), Catch::Matchers::StartsWith(file.string() + ": ") ||
                                         Catch::Matchers::StartsWith(file.string() + ":1:"));
        }
    };
    // Every length of the header and the JSON chunk's start, then every 13th byte.
    for (std::size_t length = 0; length < glb.size(); length += length < 64 ? 1 : 13) {
        INFO("glb cut to " << length << " bytes");
        tryRead("cut.glb", glb.substr(0, length));
    }
    for (std::size_t length = 0; length < gltf.size(); length += 97) {
        INFO("gltf cut to " << length << " bytes");
        tryRead("cut.gltf", gltf.substr(0, length));
    }
    const unsigned seed = 20240607;
    std::mt19937 random(seed);
    for (int round = 0; round < 300; ++round) {
        std::string bytes = glb;
        const int changes = 1 + static_cast<int>(random() % 8);
        for (int c = 0; c < changes; ++c) {
            bytes[random() % bytes.size()] = static_cast<char>(random() & 0xff);
        }
        INFO("seed " << seed << ", round " << round);
        tryRead("corrupt.glb", bytes);
    }
}

// -------------------------------------------------------------------------------------------------
// Drawing

TEST_CASE("The base colour texture and factor reach the pixels, upright and in sRGB", "[scene][model][pixels]")
{
    TempDirectory directory;
    writePng(quadrantImage(), directory.path() / "quadrants.png");
    TestGltf gltf = flatSquare();
    gltf.material = 0;
    auto write = [&](const std::string& factor) {
        gltf.extra = R"("materials": [{"pbrMetallicRoughness": {"baseColorFactor": )" + factor +
                     R"(, "baseColorTexture": {"index": 0}}}], "textures": [{"source": 0, "sampler": 0}], )"
                     R"("samplers": [{"magFilter": 9728, "minFilter": 9728, "wrapS": 33071, "wrapT": 33071}], )"
                     R"("images": [{"uri": "quadrants.png"}], )";
        return directory.write("square.gltf", gltf.json());
    };

    const Geodetic3D position = Geodetic3D::fromDegrees(-70.0, 20.0, 100.0);
    constexpr int kSize = 64;
    // From 2.2 m above, with a 45 degree field of view, the 2 m square covers the middle 55
    // pixels; the quadrants' centres are 14 pixels from the image centre.
    auto render = [&](const std::filesystem::path& file) {
        Scene scene(kEarth);
        scene.add(ModelPrimitive::fromFile(file, kEarth, ModelPlacement{position, {}, 1.0}));
        lookDownAt(scene, position, 2.2);
        return renderFrame(scene, kSize, kSize).image;
    };
    const int near = kSize / 2 - 14;
    const int far = kSize / 2 + 13;

    // Factor 1: the texels themselves (decoded to linear, lit fully, encoded back): within 2 of
    // 255 or 0 for 8-bit rounding and the Sun a hair off the normal.
    const Image plain = render(write("[1, 1, 1, 1]"));
    INFO(describePixel(plain, near, near) << " " << describePixel(plain, far, near) << " "
                                          << describePixel(plain, near, far) << " " << describePixel(plain, far, far));
    CHECK(pixelNear(plain, near, near, {255, 0, 0, 255}, 2));   // north-west: the image's top-left
    CHECK(pixelNear(plain, far, near, {0, 255, 0, 255}, 2));    // north-east
    CHECK(pixelNear(plain, near, far, {0, 0, 255, 255}, 2));    // south-west
    CHECK(pixelNear(plain, far, far, {255, 255, 255, 255}, 2)); // south-east

    // Factor (0.5, 0.25, 1): linear, multiplied before the sRGB encoding: 255 becomes 188 and 137.
    const Image tinted = render(write("[0.5, 0.25, 1, 1]"));
    INFO(describePixel(tinted, far, far));
    CHECK(pixelNear(tinted, near, near, {srgb(0.5), 0, 0, 255}, 2));
    CHECK(pixelNear(tinted, far, far, {srgb(0.5), srgb(0.25), 255, 255}, 2));

    // No texture: the factor alone.
    gltf.extra = R"("materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1]}}], )";
    const Image factorOnly = render(directory.write("plain.gltf", gltf.json()));
    INFO(describePixel(factorOnly, kSize / 2, kSize / 2));
    CHECK(pixelNear(factorOnly, kSize / 2, kSize / 2, {srgb(0.2), srgb(0.4), srgb(0.6), 255}, 2));
}

TEST_CASE("A model stands at its geodetic position, drawn relative to its centre far from the Earth's", "[scene][model][placement]")
{
    TempDirectory directory;
    TestGltf gltf = flatSquare();
    gltf.extra = R"("materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1]}}], )";
    gltf.material = 0;
    const std::filesystem::path file = directory.write("square.gltf", gltf.json());

    // Sydney at 50 m: 6.4e6 m from the centre, where a float's step is 0.5 m. From 5 m above, a
    // pixel is 3 mm: only offsets from the model's origin keep the square's edges where they are.
    const Geodetic3D position = Geodetic3D::fromDegrees(151.2, -33.9, 50.0);
    constexpr int kSize = 128;
    Scene scene(kEarth);
    auto model = ModelPrimitive::fromFile(file, kEarth, ModelPlacement{position, {toRadians(30.0), 0.0, 0.0}, 1.0});
    scene.add(model);
    lookDownAt(scene, position, 5.0);
    const Image image = renderFrame(scene, kSize, kSize).image;

    int count = 0;
    const glm::dvec2 centre = centroidOf(image, [](const glm::ivec4& p) { return p.r > 250 && p.g > 250 && p.b > 250; }, &count);
    const glm::ivec2 expected = projectToPixel(scene, kEarth.toCartesian(position), kSize, kSize);
    INFO("white pixels " << count << " centred at " << centre.x << ", " << centre.y);
    REQUIRE(count > 1000);
    // The centroid of a square's pixels is its centre to within a fraction of a pixel; the projected
    // point is floored to a pixel: 1 pixel.
    CHECK_THAT(centre.x, WithinAbs(expected.x + 0.5, 1.0));
    CHECK_THAT(centre.y, WithinAbs(expected.y + 0.5, 1.0));
    // Turned 30 degrees: its corner (glTF (1, 0, 1), north-west before the turn) is covered, and a
    // pixel just inside each corner is white.
    for (const glm::dvec3 corner : {glm::dvec3(1, 0, 1), glm::dvec3(-1, 0, 1), glm::dvec3(-1, 0, -1), glm::dvec3(1, 0, -1)}) {
        const glm::dvec2 pixel = projectModelPoint(scene, *model, 0.9 * corner, kSize);
        CHECK(pixelNear(image, static_cast<int>(pixel.x), static_cast<int>(pixel.y), {255, 255, 255, 255}, 3));
    }
}

TEST_CASE("Heading 0 points the aircraft's nose (glTF +z) north and its left wing (+x) west; heading 90 east", "[scene][model][placement]")
{
    const Geodetic3D position = Geodetic3D::fromDegrees(10.0, 45.0, 300.0);
    constexpr int kSize = 128;
    // Lit from straight above: the nose's orange (1, 0.6, 0), a little darker on its slopes; the
    // lights' tops, facing up, in their full red and green.
    auto orange = [](const glm::ivec4& p) { return p.r > 180 && p.g > 120 && p.g < 230 && p.b < 60; };
    auto red = [](const glm::ivec4& p) { return p.r > 200 && p.g < 40 && p.b < 40; };
    auto green = [](const glm::ivec4& p) { return p.g > 200 && p.r < 40 && p.b < 40; };

    for (const double headingDegrees : {0.0, 90.0}) {
        INFO("heading " << headingDegrees);
        Scene scene(kEarth);
        auto model = ModelPrimitive::fromFile(modelFile("aircraft.glb"), kEarth,
                                              ModelPlacement{position, {toRadians(headingDegrees), 0.0, 0.0}, 1.0});
        scene.add(model);
        lookDownAt(scene, position, 25.0); // north up on the image, east to the right
        const Image image = renderFrame(scene, kSize, kSize).image;
        const glm::dvec2 origin = projectModelPoint(scene, *model, glm::dvec3(0.0), kSize);

        int noseCount = 0;
        int leftCount = 0;
        int rightCount = 0;
        const glm::dvec2 nose = centroidOf(image, orange, &noseCount) - origin;
        const glm::dvec2 left = centroidOf(image, red, &leftCount) - origin;
        const glm::dvec2 right = centroidOf(image, green, &rightCount) - origin;
        INFO("nose " << nose.x << ", " << nose.y << "; left " << left.x << ", " << left.y << "; right " << right.x
                     << ", " << right.y);
        REQUIRE(noseCount > 5);
        REQUIRE(leftCount > 2);
        REQUIRE(rightCount > 2);
        // 25 m up, 45 degrees: 5 pixels a metre. The nose's top view centres 3.5 m ahead; the lights
        // 5.5 m to each side. Image y grows southwards.
        const double ahead = 3.5 * kSize / (2.0 * 25.0 * std::tan(toRadians(22.5)));
        if (headingDegrees == 0.0) {
            CHECK(nose.y < -0.8 * ahead);         // north
            CHECK(std::abs(nose.x) < 2.0);
            CHECK(left.x < -20.0);                // west
            CHECK(right.x > 20.0);                // east
        } else {
            CHECK(nose.x > 0.8 * ahead);          // east
            CHECK(std::abs(nose.y) < 2.0);
            CHECK(left.y < -20.0);                // north: the left wing of an aircraft flying east
            CHECK(right.y > 20.0);                // south
        }
    }
}

TEST_CASE("Pitch lifts the nose and roll lowers the right wing", "[scene][model][placement]")
{
    const Geodetic3D position = Geodetic3D::fromDegrees(10.0, 45.0, 300.0);
    auto world = [&](const HeadingPitchRoll& orientation, const glm::dvec3& local) {
        return glm::dvec3(modelToFixedFrame(kEarth, ModelPlacement{position, orientation, 2.0}) * glm::dvec4(local, 1.0));
    };
    const glm::dvec3 origin = kEarth.toCartesian(position);
    const glm::dvec3 up = eastNorthUpAxes(kEarth, origin)[2];
    // Nose 4.5 m ahead, scale 2: 9 m; pitched 30 degrees up it rises 9 sin 30 = 4.5 m. Doubles: 1e-6 m.
    CHECK_THAT(glm::dot(world({0.0, toRadians(30.0), 0.0}, {0, 0, 4.5}) - origin, up), WithinAbs(4.5, 1e-6));
    // Rolled 30 degrees, the right wing (glTF -x) at 5.5 m, scale 2, drops 11 sin 30 = 5.5 m.
    CHECK_THAT(glm::dot(world({0.0, 0.0, toRadians(30.0)}, {-5.5, 0, 0}) - origin, up), WithinAbs(-5.5, 1e-6));
    // The axis change is a rotation: glTF up (+y) is the local vertical.
    CHECK_THAT(glm::dot(world({toRadians(123.0), 0.0, 0.0}, {0, 1, 0}) - origin, up), WithinAbs(2.0, 1e-6));
    CHECK_THAT(glm::determinant(gltfToEastNorthUp()), WithinAbs(1.0, 1e-15));
}

TEST_CASE("A model 500 m above the ray-cast globe shows; one below the surface is hidden by it", "[scene][model][depth]")
{
    constexpr int kSize = 64;
    const Geodetic2D place = Geodetic2D::fromDegrees(-100.0, 40.0);
    struct Seen {
        glm::ivec4 pixel;
        FrameStatistics statistics;
    };
    auto render = [&](double heightMeters) {
        Scene scene(kEarth);
        scene.add(plainGlobe());
        // Scale 40: a 450 m aircraft, its fin 74 m above its origin.
        const Geodetic3D position{place.longitude, place.latitude, heightMeters};
        scene.add(ModelPrimitive::fromFile(modelFile("aircraft.glb"), kEarth, ModelPlacement{position, {}, 40.0}));
        // Looking down from 3 km above the surface (not above the model).
        lookDownAt(scene, Geodetic3D{place.longitude, place.latitude, 0.0}, 3000.0);
        const RenderedFrame frame = renderFrame(scene, kSize, kSize);
        const glm::ivec2 pixel = projectToPixel(scene, kEarth.toCartesian(position), kSize, kSize);
        return Seen{pixelAt(frame.image, pixel.x, pixel.y), frame.statistics};
    };
    const Seen above = render(500.0);
    INFO("above: " << above.pixel.r << ", " << above.pixel.g << ", " << above.pixel.b);
    CHECK(above.pixel.r > 150); // the white fuselage, not the blue globe
    const Seen below = render(-500.0);
    INFO("below: " << below.pixel.r << ", " << below.pixel.g << ", " << below.pixel.b);
    CHECK(below.pixel == glm::ivec4(0, 0, 255, 255)); // the globe's plain blue
    // Drawn, not culled: the ray-cast globe's depth hides it (the globe and six materials).
    CHECK(below.statistics.commandsCulledByHorizon == 0);
    CHECK(below.statistics.commandsSubmitted == 7);
    CHECK(below.statistics.commandsExecuted >= 7);
}

TEST_CASE("A model behind the Earth is culled by the horizon; one behind the camera never loads", "[scene][model][effects]")
{
    const Geodetic3D position = Geodetic3D::fromDegrees(0.0, 0.0, 1000.0);
    auto model = ModelPrimitive::fromFile(modelFile("aircraft.glb"), kEarth, ModelPlacement{position, {}, 1.0});
    REQUIRE(model->horizonOcclusionPoint().has_value());
    REQUIRE_FALSE(model->resourcesCreated());

    Scene scene(kEarth);
    scene.add(model);
    // Behind the camera: culled whole, so no buffers, textures or programs, and no image decoded.
    const glm::dvec3 origin = kEarth.toCartesian(position);
    scene.camera().lookAt(origin * 1.5, origin * 3.0, {0, 0, 1});
    FrameStatistics statistics = renderFrame(scene, 32, 32).statistics;
    CHECK(statistics.primitivesCulled == 1);
    CHECK_FALSE(model->resourcesCreated());

    // On the far side of the Earth, in the view frustum: the horizon culls every command.
    scene.camera().lookAt(-origin * 3.0, glm::dvec3(0.0), {0, 0, 1});
    statistics = renderFrame(scene, 32, 32).statistics;
    CHECK(statistics.commandsSubmitted == model->batchCount());
    CHECK(statistics.commandsCulledByHorizon == model->batchCount());
    CHECK(statistics.commandsExecuted == 0);
    CHECK(model->resourcesCreated()); // updated (its sphere is in view), so made

    // In view: one draw per material, one program per variant (textured, plain).
    scene.camera().lookAt(origin + glm::dvec3(40.0, 0.0, 0.0), origin, {0, 0, 1});
    statistics = renderFrame(scene, 32, 32).statistics;
    CHECK(statistics.commandsExecuted == 6);
    CHECK(statistics.translucentPasses == 0);
}

TEST_CASE("A model adds the models effect, and lighting only when lit; unlit it shows its base colour", "[scene][model][effects]")
{
    TempDirectory directory;
    TestGltf gltf = flatSquare();
    gltf.material = 0;
    gltf.extra = R"("materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1]}}], )";
    const std::filesystem::path file = directory.write("square.gltf", gltf.json());
    const Geodetic3D position = Geodetic3D::fromDegrees(-20.0, 60.0, 10.0);
    for (const bool lighting : {true, false}) {
        INFO("lighting " << lighting);
        Scene scene(kEarth);
        ModelOptions options;
        options.lighting = lighting;
        scene.add(ModelPrimitive::fromFile(file, kEarth, ModelPlacement{position, {}, 1.0}, options));
        lookDownAt(scene, position, 2.2);
        // The Sun low in the west: lit, the square facing up gets 0.3 + 0.7 cos(80 degrees).
        const glm::dmat3 enu = eastNorthUpAxes(kEarth, kEarth.toCartesian(position));
        scene.setSunDirection(std::cos(toRadians(10.0)) * -enu[0] + std::sin(toRadians(10.0)) * enu[2]);
        const RenderedFrame frame = renderFrame(scene, 16, 16);
        const std::uint32_t expected = lighting ? Effect::Models | Effect::Lighting : static_cast<std::uint32_t>(Effect::Models);
        CHECK(frame.statistics.effects == expected);
        const double shade = lighting ? 0.3 + 0.7 * std::sin(toRadians(10.0)) : 1.0;
        INFO(describePixel(frame.image, 8, 8));
        CHECK(pixelNear(frame.image, 8, 8, {srgb(0.2 * shade), srgb(0.4 * shade), srgb(0.6 * shade), 255}, 2));
    }
}

TEST_CASE("Blended materials draw in the translucent pass, over what is behind them", "[scene][model][pixels]")
{
    TempDirectory directory;
    TestGltf gltf = flatSquare();
    gltf.material = 0;
    gltf.extra = R"("materials": [{"alphaMode": "BLEND", "doubleSided": true, )"
                 R"("pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 0.5]}}], )";
    const Geodetic3D position = Geodetic3D::fromDegrees(30.0, 10.0, 20.0);
    Scene scene(kEarth);
    scene.options().background = {0.0f, 0.0f, 0.0f, 1.0f};
    scene.add(ModelPrimitive::fromFile(directory.write("glass.gltf", gltf.json()), kEarth, ModelPlacement{position, {}, 1.0}));
    lookDownAt(scene, position, 2.2);
    const RenderedFrame frame = renderFrame(scene, 32, 32);
    CHECK(frame.statistics.translucentPasses == 1);
    CHECK(frame.statistics.opaquePasses == 0);
    // Half of full red over black: 255 x 0.5 (blending after the sRGB encoding).
    INFO(describePixel(frame.image, 16, 16));
    CHECK(pixelNear(frame.image, 16, 16, {128, 0, 0, 255}, 2));
}

// -------------------------------------------------------------------------------------------------
// Scene files

TEST_CASE("A scene file's model layer becomes a ModelPrimitive; a bad model names the layer", "[scene][model][scenefile]")
{
    const std::filesystem::path sceneFile = std::filesystem::path(ORBIS_SOURCE_DIR) / "data" / "scenes" / "model.json";
    Scene scene(kEarth);
    populateScene(parseSceneFile(sceneFile), scene);
    REQUIRE(scene.primitives().size() == 2); // the globe and the aircraft
    const auto* model = dynamic_cast<const ModelPrimitive*>(scene.primitives()[1].get());
    REQUIRE(model != nullptr);
    CHECK(model->triangleCount() == 92);
    CHECK_FALSE(model->resourcesCreated());

    TempDirectory directory;
    directory.write("broken.glb", "glTF but nothing more");
    const std::filesystem::path badScene = directory.write(
        "scene.json", R"({"version": 2, "layers": [{"type": "model", "source": "broken.glb", "position": {"lon": 0, "lat": 0}}]})");
    Scene other(kEarth);
    CHECK_THAT(errorMessage([&] { populateScene(parseSceneFile(badScene), other); }),
               Contains("/layers/0: " + (directory.path() / "broken.glb").string() + ": "));
}
