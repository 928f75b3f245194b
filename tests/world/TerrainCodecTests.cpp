// Terrain tile decoders and encoders on bytes the tests write themselves: quantized-mesh-1.0 built
// byte by byte from the specification (not by our encoder), heightmap-1.0, 16-bit, Terrain-RGB and
// Terrarium PNGs, SRTM .hgt; and every kind of damage: cut short at every byte, counts that
// overflow, indices out of range, headers that lie, bad gzip.

#include "TempFiles.h"

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/Error.h>
#include <orbis/core/Math.h>
#include <orbis/core/TilingScheme.h>
#include <orbis/world/ImageCodec.h>
#include <orbis/world/TerrainCodec.h>

#include <catch2/catch.hpp>

#include <glm/geometric.hpp>

#include <cstring>
#include <random>

using namespace orbis;
using namespace orbis::world;
using orbis::test::errorMessage;
using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;

namespace {

const std::string kName = "tiles/3/1/2.terrain";
const TileKey kKey{3, 1, 2};

/// Little-endian bytes, as quantized-mesh and heightmap-1.0 store them.
struct Bytes {
    std::vector<std::uint8_t> data;

    // Out of line: GCC 12 at -O3 otherwise warns (-Wstringop-overflow) on the vector growing from empty.
    [[gnu::noinline]] void u8(std::uint8_t v) { data.push_back(v); }
    void u16(std::uint16_t v)
    {
        u8(static_cast<std::uint8_t>(v));
        u8(static_cast<std::uint8_t>(v >> 8));
    }
    void u32(std::uint32_t v)
    {
        for (int i = 0; i < 4; ++i) {
            u8(static_cast<std::uint8_t>(v >> (8 * i)));
        }
    }
    void f32(float v)
    {
        std::uint32_t bits = 0;
        std::memcpy(&bits, &v, 4);
        u32(bits);
    }
    void f64(double v)
    {
        std::uint64_t bits = 0;
        std::memcpy(&bits, &v, 8);
        for (int i = 0; i < 8; ++i) {
            u8(static_cast<std::uint8_t>(bits >> (8 * i)));
        }
    }
};

std::uint16_t zigZag(int value)
{
    return static_cast<std::uint16_t>(value >= 0 ? 2 * value : -2 * value - 1);
}

/// A hand-made quantized-mesh tile: a square of four corners and a centre vertex, four triangles,
/// heights 100 .. 200 m; `extensions` appended as they are.
struct HandmadeMesh {
    // u, v, height (quantized) of the vertices, in the order the indices first use them.
    std::vector<std::array<int, 3>> vertices = {
        {0, 0, 0}, {32767, 0, 32767}, {16384, 16384, 16384}, {32767, 32767, 0}, {0, 32767, 32767}};
    std::vector<std::uint32_t> indices = {0, 1, 2, 1, 3, 2, 3, 4, 2, 4, 0, 2};
    float minimumHeight = 100.0f;
    float maximumHeight = 200.0f;
    std::vector<std::uint8_t> extensions;

    std::vector<std::uint8_t> bytes() const
    {
        Bytes b;
        for (int i = 0; i < 3; ++i) {
            b.f64(1000.0 * (i + 1)); // centre: not used by decoding
        }
        b.f32(minimumHeight);
        b.f32(maximumHeight);
        for (int i = 0; i < 4; ++i) {
            b.f64(10.0);
        }
        b.f64(0.5);
        b.f64(0.25);
        b.f64(0.75);
        b.u32(static_cast<std::uint32_t>(vertices.size()));
        for (int component = 0; component < 3; ++component) {
            int previous = 0;
            for (const auto& v : vertices) {
                b.u16(zigZag(v[static_cast<std::size_t>(component)] - previous));
                previous = v[static_cast<std::size_t>(component)];
            }
        }
        // 88 + 4 + 6 * 5 = 122: already even for 16-bit indices.
        b.u32(static_cast<std::uint32_t>(indices.size() / 3));
        std::uint32_t highest = 0;
        for (const std::uint32_t index : indices) {
            b.u16(static_cast<std::uint16_t>(highest - index));
            if (index == highest) {
                ++highest;
            }
        }
        // West, south, east, north, deliberately not sorted along the edges.
        const std::vector<std::vector<std::uint16_t>> edges = {{4, 0}, {1, 0}, {3, 1}, {3, 4}};
        for (const auto& edge : edges) {
            b.u32(static_cast<std::uint32_t>(edge.size()));
            for (const auto index : edge) {
                b.u16(index);
            }
        }
        b.data.insert(b.data.end(), extensions.begin(), extensions.end());
        return b.data;
    }
};

std::vector<std::uint8_t> extension(std::uint8_t id, const std::vector<std::uint8_t>& payload)
{
    Bytes b;
    b.u8(id);
    b.u32(static_cast<std::uint32_t>(payload.size()));
    b.data.insert(b.data.end(), payload.begin(), payload.end());
    return b.data;
}

std::vector<std::uint8_t> metadataExtension(const std::string& json)
{
    Bytes payload;
    payload.u32(static_cast<std::uint32_t>(json.size()));
    payload.data.insert(payload.data.end(), json.begin(), json.end());
    return extension(4, payload.data);
}

/// A regular mesh of n x n vertices over the tile with heights from f(u, v).
TerrainTileData gridMesh(int n, const std::function<float(float, float)>& f)
{
    TerrainTileData tile;
    tile.key = kKey;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const float u = static_cast<float>(i) / static_cast<float>(n - 1);
            const float v = static_cast<float>(j) / static_cast<float>(n - 1);
            tile.vertices.emplace_back(u, v, f(u, v));
            tile.normals.push_back(glm::normalize(glm::vec3(u - 0.5f, v - 0.5f, 1.0f)));
        }
    }
    for (int j = 0; j + 1 < n; ++j) {
        for (int i = 0; i + 1 < n; ++i) {
            const auto a = static_cast<std::uint32_t>(j * n + i);
            const auto b = a + 1;
            const auto c = a + static_cast<std::uint32_t>(n);
            const auto d = c + 1;
            tile.indices.insert(tile.indices.end(), {a, b, d, a, d, c});
        }
    }
    return tile;
}

double signedArea(const TerrainTileData& tile, std::size_t t)
{
    const glm::vec3& a = tile.vertices[tile.indices[t]];
    const glm::vec3& b = tile.vertices[tile.indices[t + 1]];
    const glm::vec3& c = tile.vertices[tile.indices[t + 2]];
    return static_cast<double>((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
}

} // namespace

TEST_CASE("A hand-made quantized-mesh tile decodes as the specification says", "[world][terrain][codec]")
{
    HandmadeMesh mesh;
    mesh.extensions = extension(2, {255});
    const TerrainTileData tile = decodeQuantizedMesh(mesh.bytes(), kKey, kName);
    CHECK(tile.key == kKey);
    CHECK(tile.isMesh());
    REQUIRE(tile.vertices.size() == 5);
    CHECK(tile.vertices[0] == glm::vec3(0.0f, 0.0f, 100.0f));
    CHECK(tile.vertices[1] == glm::vec3(1.0f, 0.0f, 200.0f));
    CHECK_THAT(tile.vertices[2].x, WithinAbs(16384.0 / 32767.0, 1e-7));
    CHECK_THAT(tile.vertices[2].z, WithinAbs(100.0 + 100.0 * 16384.0 / 32767.0, 1e-4));
    CHECK(tile.indices == mesh.indices);
    for (std::size_t t = 0; t < tile.indices.size(); t += 3) {
        CHECK(signedArea(tile, t) > 0.0); // counter-clockwise seen from above
    }
    // Sorted along each edge: north and south west to east, east and west south to north.
    CHECK(tile.edgeVertices[0] == std::vector<std::uint32_t>{4, 3});
    CHECK(tile.edgeVertices[1] == std::vector<std::uint32_t>{1, 3});
    CHECK(tile.edgeVertices[2] == std::vector<std::uint32_t>{0, 1});
    CHECK(tile.edgeVertices[3] == std::vector<std::uint32_t>{0, 4});
    CHECK(tile.minimumHeight == 100.0);
    CHECK(tile.maximumHeight == 200.0);
    REQUIRE(tile.horizonOcclusionPoint);
    CHECK(*tile.horizonOcclusionPoint == glm::dvec3(0.5, 0.25, 0.75));
    CHECK(tile.waterMaskSize == 1);
    CHECK(tile.waterMask == std::vector<std::uint8_t>{255});
    CHECK(tile.normals.empty());

    // Gzip-compressed, as servers store .terrain files: the same tile.
    const TerrainTileData compressed = decodeQuantizedMesh(gzipBytes(mesh.bytes()), kKey, kName);
    CHECK(compressed.vertices == tile.vertices);
    CHECK(compressed.indices == tile.indices);
}

TEST_CASE("Quantized-mesh extensions: oct normals, a 256 x 256 water mask, metadata availability; unknown ones skipped",
          "[world][terrain][codec]")
{
    HandmadeMesh mesh;
    std::vector<std::uint8_t> normals;
    for (int i = 0; i < 5; ++i) {
        const auto oct = octEncodeNormal(glm::vec3(0.0f, 0.0f, 1.0f));
        normals.insert(normals.end(), oct.begin(), oct.end());
    }
    std::vector<std::uint8_t> water(256 * 256);
    for (std::size_t i = 0; i < water.size(); ++i) {
        water[i] = static_cast<std::uint8_t>(i % 256 < 128 ? 255 : 0);
    }
    const std::string json = R"({"geometricerror": 12, "available": [[{"startX": 2, "startY": 4, "endX": 3, "endY": 5}],
        [{"startX": 4, "startY": 8, "endX": 7, "endY": 11}, {"startX": 0, "startY": 0, "endX": 0, "endY": 0}]]})";
    for (const auto& part : {extension(1, normals), extension(2, water), extension(9, {1, 2, 3}), metadataExtension(json)}) {
        mesh.extensions.insert(mesh.extensions.end(), part.begin(), part.end());
    }
    const TerrainTileData tile = decodeQuantizedMesh(mesh.bytes(), kKey, kName);
    REQUIRE(tile.normals.size() == 5);
    for (const glm::vec3& n : tile.normals) {
        CHECK_THAT(glm::length(n - glm::vec3(0, 0, 1)), WithinAbs(0.0, 1e-2));
    }
    CHECK(tile.waterMaskSize == 256);
    CHECK(tile.waterMask == water);
    REQUIRE(tile.availableBelow.size() == 2);
    CHECK(tile.availableBelow[0] == LevelAvailability{{2, 4, 3, 5}});
    CHECK(tile.availableBelow[1] == LevelAvailability{{4, 8, 7, 11}, {0, 0, 0, 0}});
}

TEST_CASE("Our quantized-mesh encoder round-trips meshes, normals, masks and 32-bit indices", "[world][terrain][codec]")
{
    const auto f = [](float u, float v) { return 500.0f + 300.0f * std::sin(6.0f * u) * std::cos(4.0f * v); };
    for (const int n : {9, 257}) { // 257^2 = 66,049 vertices: 32-bit indices, with the padding before them
        TerrainTileData tile = gridMesh(n, f);
        tile.waterMask = {0};
        QuantizedMeshEncoding encoding;
        encoding.normals = true;
        encoding.waterMask = true;
        encoding.metadataJson = R"({"available":[[{"startX":2,"startY":4,"endX":3,"endY":5}]]})";
        encoding.gzipLevel = n == 9 ? 6 : 0;
        const std::vector<std::uint8_t> bytes = encodeQuantizedMesh(tile, encoding);
        CHECK(isGzip(bytes) == (n == 9));
        const TerrainTileData decoded = decodeQuantizedMesh(bytes, kKey, kName);
        REQUIRE(decoded.vertices.size() == tile.vertices.size());
        REQUIRE(decoded.indices.size() == tile.indices.size());
        const double heightStep = (decoded.maximumHeight - decoded.minimumHeight) / 32767.0;
        // Vertices come back in first-use order: compare the triangles' corners.
        double worstPosition = 0.0;
        double worstHeight = 0.0;
        double worstNormal = 0.0;
        for (std::size_t i = 0; i < tile.indices.size(); ++i) {
            const glm::vec3& a = tile.vertices[tile.indices[i]];
            const glm::vec3& b = decoded.vertices[decoded.indices[i]];
            worstPosition = std::max({worstPosition, std::abs(double(a.x - b.x)), std::abs(double(a.y - b.y))});
            worstHeight = std::max(worstHeight, std::abs(double(a.z - b.z)));
            worstNormal = std::max(worstNormal, double(glm::length(tile.normals[tile.indices[i]] - decoded.normals[decoded.indices[i]])));
        }
        CHECK(worstPosition <= 0.5 / 32767.0 + 1e-7);
        CHECK(worstHeight <= 0.5 * heightStep + 1e-3);
        CHECK(worstNormal < 0.02);
        for (std::size_t t = 0; t < decoded.indices.size(); t += 3) {
            REQUIRE(signedArea(decoded, t) > 0.0);
        }
        for (int edge = 0; edge < 4; ++edge) {
            CHECK(decoded.edgeVertices[static_cast<std::size_t>(edge)].size() == static_cast<std::size_t>(n));
        }
        CHECK(decoded.waterMask == std::vector<std::uint8_t>{0});
        CHECK(decoded.availableBelow.size() == 1);
        // The header's occlusion point hides the tile only when every vertex is hidden (below).
        CHECK(decoded.horizonOcclusionPoint.has_value());
    }
}

TEST_CASE("Every truncation of a quantized-mesh tile is an error naming the tile, never a crash", "[world][terrain][codec]")
{
    HandmadeMesh mesh;
    mesh.extensions = extension(2, {255});
    const std::vector<std::uint8_t> whole = mesh.bytes();
    const std::size_t extensionStart = whole.size() - 6;
    for (std::size_t length = 0; length < whole.size(); ++length) {
        const std::vector<std::uint8_t> cut(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(length));
        if (length == extensionStart) {
            CHECK_NOTHROW(decodeQuantizedMesh(cut, kKey, kName)); // a tile without extensions is whole
            continue;
        }
        const std::string message = errorMessage([&] { decodeQuantizedMesh(cut, kKey, kName); });
        INFO("cut after " << length << " bytes");
        CHECK_THAT(message, Contains(kName + ": cut short"));
    }
    // And gzip cut short is said to be so.
    const std::vector<std::uint8_t> compressed = gzipBytes(whole);
    for (const std::size_t length : {std::size_t{2}, std::size_t{10}, compressed.size() / 2, compressed.size() - 1}) {
        const std::vector<std::uint8_t> cut(compressed.begin(), compressed.begin() + static_cast<std::ptrdiff_t>(length));
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(cut, kKey, kName); }),
                   Contains(kName) && (Contains("truncated gzip") || Contains("corrupt gzip")));
    }
}

TEST_CASE("Quantized-mesh headers and counts that lie are refused before anything is allocated", "[world][terrain][codec]")
{
    const std::vector<std::uint8_t> valid = HandmadeMesh().bytes();
    auto patched = [&](std::size_t offset, std::uint32_t value) {
        std::vector<std::uint8_t> bytes = valid;
        for (int i = 0; i < 4; ++i) {
            bytes[offset + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(value >> (8 * i));
        }
        return bytes;
    };
    constexpr std::size_t kVertexCount = 88;
    constexpr std::size_t kTriangleCount = 88 + 4 + 30;
    SECTION("a vertex count that overflows the bytes, or the limit")
    {
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(patched(kVertexCount, 0xffffffffu), kKey, kName); }),
                   Contains(kName + ": the header claims 4294967295 vertices, more than the 4194304 allowed"));
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(patched(kVertexCount, 1000000u), kKey, kName); }),
                   Contains("cut short: 1000000 vertices needs 6000000 bytes"));
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(patched(kVertexCount, 0u), kKey, kName); }),
                   Contains("a mesh without vertices"));
    }
    SECTION("a triangle count the bytes cannot hold")
    {
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(patched(kTriangleCount, 0x80000000u), kKey, kName); }),
                   Contains("cut short: 2147483648 triangles needs 12884901888 bytes"));
    }
    SECTION("a height range upside down or not finite")
    {
        HandmadeMesh mesh;
        mesh.minimumHeight = 300.0f;
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(mesh.bytes(), kKey, kName); }),
                   Contains("height range 300") && Contains("not a range of finite heights"));
        mesh.minimumHeight = std::numeric_limits<float>::quiet_NaN();
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(mesh.bytes(), kKey, kName); }), Contains("not a range"));
    }
    SECTION("indices out of range")
    {
        HandmadeMesh mesh;
        mesh.indices = {0, 1, 2, 1, 3, 7}; // 7: coded beyond the high-water mark
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(mesh.bytes(), kKey, kName); }),
                   Contains("beyond the highest vertex so far"));
        mesh = HandmadeMesh();
        mesh.vertices.resize(3); // the indices use vertex 3 and 4 of 3
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(mesh.bytes(), kKey, kName); }),
                   Contains(kName) && (Contains("beyond the 3 vertices") || Contains("beyond the highest")));
    }
    SECTION("vertices outside the tile")
    {
        HandmadeMesh mesh;
        mesh.vertices[2][0] = 52767; // u beyond 32767, by a delta of 20000 from vertex 1
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(mesh.bytes(), kKey, kName); }),
                   Contains("vertex 2 has u 52767, outside 0..32767"));
    }
    SECTION("edge lists naming vertices beyond the mesh or off their edge")
    {
        std::vector<std::uint8_t> bytes = valid;
        const std::size_t west = kTriangleCount + 4 + 24;
        bytes[west + 4] = 9; // west edge's first vertex: 9 of 5
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(bytes, kKey, kName); }),
                   Contains("the west edge lists vertex 9, beyond the 5 vertices"));
        bytes = valid;
        bytes[west + 4] = 1; // vertex 1 is at u = 32767: not on the west edge
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(bytes, kKey, kName); }),
                   Contains("the west edge lists vertex 1 at u 32767, v 0, which is not on that edge"));
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(patched(west, 6u), kKey, kName); }),
                   Contains("the west edge lists 6 vertices, more than the mesh's 5"));
    }
    SECTION("extensions of the wrong size, or whose JSON is broken")
    {
        HandmadeMesh mesh;
        mesh.extensions = extension(1, {1, 2, 3});
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(mesh.bytes(), kKey, kName); }),
                   Contains("the oct-encoded normals extension has 3 bytes, not 2 for each of the 5 vertices"));
        mesh.extensions = extension(2, {1, 2});
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(mesh.bytes(), kKey, kName); }),
                   Contains("the water mask extension has 2 bytes, not 1 or 65536"));
        mesh.extensions = metadataExtension("{\"available\": [[{\"startX\": 0}");
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(mesh.bytes(), kKey, kName); }),
                   Contains(kName + " (metadata extension):1:") && Contains("invalid JSON"));
        mesh.extensions = metadataExtension(R"({"available": [[{"startX": 0, "startY": 0, "endX": 99, "endY": 0}]]})");
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(mesh.bytes(), kKey, kName); }),
                   Contains("/available/0/0/endX: expected a whole number from 0 to 31"));
        mesh.extensions = extension(4, {200, 0, 0, 0}); // a JSON length beyond the extension
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(mesh.bytes(), kKey, kName); }), Contains("cut short"));
        mesh.extensions = {4, 0xff, 0xff, 0xff, 0x7f}; // an extension length beyond the tile
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(mesh.bytes(), kKey, kName); }),
                   Contains("cut short: extension 4 needs 2147483647 bytes"));
    }
    SECTION("gzip that is corrupt, or followed by other bytes")
    {
        std::vector<std::uint8_t> compressed = gzipBytes(valid);
        compressed[compressed.size() / 2] ^= 0x5a;
        compressed[12] ^= 0xff;
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(compressed, kKey, kName); }),
                   Contains(kName) && (Contains("corrupt gzip") || Contains("truncated gzip")));
        std::vector<std::uint8_t> trailing = gzipBytes(valid);
        trailing.push_back(0);
        CHECK_THAT(errorMessage([&] { decodeQuantizedMesh(trailing, kKey, kName); }),
                   Contains("1 bytes after the end of the gzip data"));
        CHECK_THAT(errorMessage([&] { gunzipIfCompressed(gzipBytes(std::vector<std::uint8_t>(5000, 7)), kName, 4096); }),
                   Contains("inflates to more than the 4096 bytes allowed"));
    }
}

TEST_CASE("Random damage to quantized-mesh tiles gives errors, never a crash", "[world][terrain][codec]")
{
    HandmadeMesh mesh;
    mesh.extensions = metadataExtension(R"({"available":[[{"startX":2,"startY":4,"endX":3,"endY":5}]]})");
    const std::vector<std::uint8_t> valid = mesh.bytes();
    std::mt19937 random(7);
    int errors = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        std::vector<std::uint8_t> bytes = trial % 2 ? valid : gzipBytes(valid);
        const int flips = 1 + trial % 4;
        for (int f = 0; f < flips; ++f) {
            bytes[random() % bytes.size()] ^= static_cast<std::uint8_t>(1 + random() % 255);
        }
        try {
            const TerrainTileData tile = decodeQuantizedMesh(bytes, kKey, kName);
            for (const std::uint32_t index : tile.indices) {
                REQUIRE(index < tile.vertices.size());
            }
        } catch (const Error& error) {
            REQUIRE_THAT(error.what(), Contains(kName));
            ++errors;
        }
    }
    CHECK(errors > 1000);
}

TEST_CASE("heightmap-1.0 tiles decode, encode and refuse what the format cannot be", "[world][terrain][codec]")
{
    Bytes b;
    for (int i = 0; i < 65 * 65; ++i) {
        b.u16(static_cast<std::uint16_t>(5000 + i)); // 0 m, then 0.2 m more per sample
    }
    b.u8(0x0b); // SW, SE, NE
    b.u8(255);  // all water
    const TerrainTileData tile = decodeHeightmapTerrain(b.data, kKey, kName);
    CHECK(tile.size == 65);
    REQUIRE(tile.heights.size() == 65 * 65);
    CHECK(tile.heights[0] == 0.0f);
    CHECK_THAT(tile.heights[65], WithinAbs(13.0, 1e-4)); // row 1 (south of row 0), column 0
    CHECK(tile.childMask == 0x0b);
    CHECK(tile.waterMaskSize == 1);
    CHECK(tile.minimumHeight == 0.0);
    CHECK_THAT(tile.maximumHeight, WithinAbs(4224 * 0.2, 1e-3));

    const TerrainTileData again = decodeHeightmapTerrain(encodeHeightmapTerrain(tile, 9), kKey, kName);
    CHECK(again.heights == tile.heights);
    CHECK(again.childMask == tile.childMask);
    CHECK(again.waterMask == tile.waterMask);
    CHECK(heightmapTerrainQuantize(123.45) == 123.4f);
    CHECK(heightmapTerrainQuantize(-5000.0) == -1000.0f);
    CHECK(heightmapTerrainQuantize(std::nan("")) == 0.0f);

    std::vector<std::uint8_t> cut(b.data.begin(), b.data.begin() + 8000);
    CHECK_THAT(errorMessage([&] { decodeHeightmapTerrain(cut, kKey, kName); }),
               Contains(kName + ": cut short: a heightmap-1.0 tile holds 65 x 65 heights (8450 bytes), these are 8000"));
    std::vector<std::uint8_t> odd = b.data;
    odd.insert(odd.end(), 10, 0);
    CHECK_THAT(errorMessage([&] { decodeHeightmapTerrain(odd, kKey, kName); }), Contains("12 bytes after the heights"));
    std::vector<std::uint8_t> mask = b.data;
    mask[65 * 65 * 2] = 0x30;
    CHECK_THAT(errorMessage([&] { decodeHeightmapTerrain(mask, kKey, kName); }),
               Contains("child mask 48 has bits beyond the four children"));
    TerrainTileData small;
    small.size = 33;
    small.heights.resize(33 * 33);
    CHECK_THAT(errorMessage([&] { encodeHeightmapTerrain(small); }), Contains("65 x 65 samples, not 33"));
}

TEST_CASE("Height images: 16-bit PNG, Terrain-RGB and Terrarium give their heights", "[world][terrain][codec]")
{
    HeightGrid grid;
    grid.width = 3;
    grid.height = 2;
    grid.heights = {-10376.0f, 0.0f, 7833.0f, 1.0f, -1.0f, 32767.0f};
    const HeightGrid png16 = decodeHeightImage(encodeHeightPng16(grid), HeightEncoding::Png16, kName);
    CHECK(png16.width == 3);
    CHECK(png16.heights == grid.heights);

    // Terrain-RGB: -10000 + (R 65536 + G 256 + B) / 10; Terrarium: R 256 + G + B / 256 - 32768.
    Image rgb(2, 1, 4);
    const std::uint8_t pixels[] = {1, 134, 160, 255, 0, 0, 0, 0};
    std::copy(std::begin(pixels), std::end(pixels), rgb.pixels.begin());
    const HeightGrid terrainRgb = decodeHeightImage(encodePng(rgb, 6), HeightEncoding::TerrainRgb, kName);
    CHECK_THAT(terrainRgb.heights[0], WithinAbs(-10000.0 + (65536 + 134 * 256 + 160) * 0.1, 1e-3));
    CHECK(std::isnan(terrainRgb.heights[1])); // transparent: no data
    const HeightGrid terrarium = decodeHeightImage(encodePng(rgb, 6), HeightEncoding::Terrarium, kName);
    CHECK_THAT(terrarium.heights[0], WithinAbs(1 * 256.0 + 134 + 160 / 256.0 - 32768.0, 1e-3));

    CHECK_THAT(errorMessage([&] { decodeHeightImage(encodePng(rgb, 6), HeightEncoding::Png16, kName); }),
               Contains(kName) && Contains("16-bit") && Contains("Terrain-RGB or Terrarium tile? name its format"));
    CHECK_THAT(errorMessage([&] { decodeHeightImage(encodePng(Image(4, 4, 1), 6), HeightEncoding::TerrainRgb, kName); }),
               Contains("a grey image, not Terrain-RGB colours"));
    CHECK_THAT(errorMessage([&] { decodeHeightImage(std::vector<std::uint8_t>{1, 2, 3}, HeightEncoding::Terrarium, kName); }),
               Contains(kName));
}

TEST_CASE("SRTM .hgt files: big-endian samples, voids, the corner from the name", "[world][terrain][codec]")
{
    std::vector<std::uint8_t> bytes(2 * 1201 * 1201);
    auto put = [&](int column, int row, std::int16_t value) {
        const std::size_t i = 2 * (static_cast<std::size_t>(row) * 1201 + static_cast<std::size_t>(column));
        bytes[i] = static_cast<std::uint8_t>(static_cast<std::uint16_t>(value) >> 8);
        bytes[i + 1] = static_cast<std::uint8_t>(value);
    };
    put(0, 0, 1234);
    put(1200, 0, -12);
    put(5, 7, -32768);
    const HeightGrid grid = decodeHgt(bytes, "N37W123.hgt");
    CHECK(grid.width == 1201);
    CHECK(grid.at(0, 0) == 1234.0f);
    CHECK(grid.at(1200, 0) == -12.0f);
    CHECK(std::isnan(grid.at(5, 7)));
    CHECK(grid.at(600, 600) == 0.0f);
    bytes.pop_back();
    CHECK_THAT(errorMessage([&] { decodeHgt(bytes, "N37W123.hgt"); }),
               Contains("N37W123.hgt: 2884801 bytes: an SRTM .hgt file holds 1201 x 1201"));

    CHECK(hgtCorner("N37W123.hgt") == std::pair(-123, 37));
    CHECK(hgtCorner("/data/srtm/s01e005.HGT") == std::pair(5, -1));
    CHECK_FALSE(hgtCorner("N37W123.tif"));
    CHECK_FALSE(hgtCorner("N95W123.hgt"));
    CHECK_FALSE(hgtCorner("N37W181.hgt"));
    CHECK_FALSE(hgtCorner("X37W123.hgt"));
}

TEST_CASE("Oct-encoded normals come back within a degree", "[world][terrain][codec]")
{
    std::mt19937 random(3);
    std::normal_distribution<float> gaussian;
    double worst = 0.0;
    for (int i = 0; i < 10000; ++i) {
        const glm::vec3 n = glm::normalize(glm::vec3(gaussian(random), gaussian(random), gaussian(random)));
        const auto oct = octEncodeNormal(n);
        const glm::vec3 back = octDecodeNormal(oct[0], oct[1]);
        CHECK_THAT(glm::length(back), WithinAbs(1.0, 1e-5));
        worst = std::max(worst, std::acos(std::clamp(double(glm::dot(n, back)), -1.0, 1.0)));
    }
    CHECK(toDegrees(worst) < 1.0);
}

TEST_CASE("The horizon occlusion point is hidden only when every point it stands for is", "[world][terrain][codec]")
{
    const Ellipsoid earth = Ellipsoid::wgs84();
    const GeodeticExtent tile = TilingScheme::geographic().tileExtent({4, 9, 11});
    std::vector<glm::dvec3> points;
    for (int i = 0; i <= 8; ++i) {
        for (int j = 0; j <= 8; ++j) {
            const double height = 3000.0 * ((i * 7 + j * 3) % 5);
            points.push_back(earth.toCartesian(Geodetic3D(tile.west + (tile.east - tile.west) * i / 8.0,
                                                          tile.south + (tile.north - tile.south) * j / 8.0, height)));
        }
    }
    const glm::dvec3 direction = glm::normalize(earth.toCartesian(tile.centre()) * earth.oneOverRadii());
    const auto occlusion = horizonOcclusionPoint(earth, points, direction);
    REQUIRE(occlusion);
    // In the scaled space: a point is hidden from a viewer when the segment between them meets
    // the unit sphere.
    auto hidden = [](const glm::dvec3& viewer, const glm::dvec3& target) {
        const glm::dvec3 d = target - viewer;
        const double a = glm::dot(d, d);
        const double b = 2.0 * glm::dot(viewer, d);
        const double c = glm::dot(viewer, viewer) - 1.0;
        const double discriminant = b * b - 4.0 * a * c;
        if (discriminant <= 0.0) {
            return false;
        }
        const double t = (-b - std::sqrt(discriminant)) / (2.0 * a);
        return t > 0.0 && t < 1.0 - 1e-9;
    };
    std::mt19937 random(11);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    int hiddenViews = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        glm::dvec3 viewer(unit(random), unit(random), unit(random));
        viewer = glm::normalize(viewer) * (1.0001 + 3.0 * (unit(random) + 1.0));
        if (!hidden(viewer, *occlusion)) {
            continue;
        }
        ++hiddenViews;
        for (const glm::dvec3& p : points) {
            REQUIRE(hidden(viewer, p * earth.oneOverRadii()));
        }
    }
    CHECK(hiddenViews > 1000);
    // A tile over a hemisphere has no such point.
    const std::vector<glm::dvec3> hemisphere = {earth.toCartesian(Geodetic2D{-kPi, 0.0}),
                                                earth.toCartesian(Geodetic2D{0.0, 0.0})};
    CHECK_FALSE(horizonOcclusionPoint(earth, hemisphere, glm::dvec3(0.0, -1.0, 0.0)));
}
