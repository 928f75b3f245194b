#include "orbis/world/TerrainCodec.h"

#include "TerrainJson.h"

#include "orbis/world/FileAccess.h"
#include "orbis/world/ImageCodec.h"

#include <orbis/core/Error.h>
#include <orbis/core/TilingScheme.h>

#include <glm/geometric.hpp>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace orbis::world {

namespace {

std::string prefix(std::string_view name)
{
    return cutForMessage(name) + ": ";
}

/// Little-endian reads with every length checked against what is left, before it is used.
class ByteReader {
public:
    ByteReader(std::span<const std::uint8_t> bytes, std::string_view name) : _bytes(bytes), _name(name) {}

    std::size_t position() const noexcept { return _position; }
    std::size_t remaining() const noexcept { return _bytes.size() - _position; }

    /// Throws unless `count` more bytes are there; `what` names what they were to hold.
    void need(std::uint64_t count, const std::string& what) const
    {
        if (count > remaining()) {
            throw Error(prefix(_name) + "cut short: " + what + " needs " + std::to_string(count) + " bytes at byte " +
                        std::to_string(_position) + ", only " + std::to_string(remaining()) + " left");
        }
    }
    void skip(std::size_t count, const std::string& what)
    {
        need(count, what);
        _position += count;
    }
    std::uint8_t u8(const std::string& what)
    {
        need(1, what);
        return _bytes[_position++];
    }
    std::uint16_t u16(const std::string& what)
    {
        need(2, what);
        const auto value = static_cast<std::uint16_t>(_bytes[_position] | (_bytes[_position + 1] << 8));
        _position += 2;
        return value;
    }
    std::uint32_t u32(const std::string& what)
    {
        need(4, what);
        std::uint32_t value = 0;
        for (int i = 3; i >= 0; --i) {
            value = (value << 8) | _bytes[_position + static_cast<std::size_t>(i)];
        }
        _position += 4;
        return value;
    }
    double f64(const std::string& what)
    {
        need(8, what);
        std::uint64_t bits = 0;
        for (int i = 7; i >= 0; --i) {
            bits = (bits << 8) | _bytes[_position + static_cast<std::size_t>(i)];
        }
        _position += 8;
        double value = 0.0;
        std::memcpy(&value, &bits, sizeof value);
        return value;
    }
    float f32(const std::string& what)
    {
        const std::uint32_t bits = u32(what);
        float value = 0.0f;
        std::memcpy(&value, &bits, sizeof value);
        return value;
    }
    std::span<const std::uint8_t> take(std::size_t count, const std::string& what)
    {
        need(count, what);
        const auto part = _bytes.subspan(_position, count);
        _position += count;
        return part;
    }

private:
    std::span<const std::uint8_t> _bytes;
    std::string_view _name;
    std::size_t _position = 0;
};

class ByteWriter {
public:
    void u8(std::uint8_t value) { bytes.push_back(value); }
    void u16(std::uint16_t value)
    {
        bytes.push_back(static_cast<std::uint8_t>(value));
        bytes.push_back(static_cast<std::uint8_t>(value >> 8));
    }
    void u32(std::uint32_t value)
    {
        for (int i = 0; i < 4; ++i) {
            bytes.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
        }
    }
    void f64(double value)
    {
        std::uint64_t bits = 0;
        std::memcpy(&bits, &value, sizeof bits);
        for (int i = 0; i < 8; ++i) {
            bytes.push_back(static_cast<std::uint8_t>(bits >> (8 * i)));
        }
    }
    void f32(float value)
    {
        std::uint32_t bits = 0;
        std::memcpy(&bits, &value, sizeof bits);
        u32(bits);
    }
    void append(std::span<const std::uint8_t> data) { bytes.insert(bytes.end(), data.begin(), data.end()); }

    std::vector<std::uint8_t> bytes;
};

std::uint16_t zigZagEncode(int value) noexcept
{
    return static_cast<std::uint16_t>((static_cast<unsigned>(value) << 1) ^ static_cast<unsigned>(value >> 31));
}

int zigZagDecode(std::uint16_t value) noexcept
{
    return static_cast<int>(value >> 1) ^ -static_cast<int>(value & 1);
}

constexpr int kQuantizedMax = 32767;
constexpr std::size_t kHeaderBytes = 88;
constexpr int kHeightmapSide = 65;
constexpr std::size_t kWaterMaskBytes = 256 * 256;

/// Which edge a quantized vertex lies on: north, east, south, west (the order of edgeVertices).
bool onEdge(int edge, int u, int v) noexcept
{
    switch (edge) {
    case 0: return v == kQuantizedMax;
    case 1: return u == kQuantizedMax;
    case 2: return v == 0;
    default: return u == 0;
    }
}

/// Sorts edge lists along their edge: north and south by u, east and west by v.
void sortEdges(std::array<std::vector<std::uint32_t>, 4>& edges, const std::vector<glm::vec3>& vertices)
{
    for (int edge = 0; edge < 4; ++edge) {
        const int axis = (edge == 0 || edge == 2) ? 0 : 1;
        std::stable_sort(edges[edge].begin(), edges[edge].end(),
                         [&](std::uint32_t a, std::uint32_t b) { return vertices[a][axis] < vertices[b][axis]; });
    }
}

void setHeightRange(TerrainTileData& tile, std::span<const float> heights)
{
    float minimum = std::numeric_limits<float>::infinity();
    float maximum = -minimum;
    for (const float h : heights) {
        minimum = std::min(minimum, h);
        maximum = std::max(maximum, h);
    }
    tile.minimumHeight = heights.empty() ? 0.0 : static_cast<double>(minimum);
    tile.maximumHeight = heights.empty() ? 0.0 : static_cast<double>(maximum);
}

} // namespace

std::size_t TerrainTileData::memoryBytes() const noexcept
{
    std::size_t bytes = heights.capacity() * sizeof(float) + vertices.capacity() * sizeof(glm::vec3) +
                        indices.capacity() * sizeof(std::uint32_t) + normals.capacity() * sizeof(glm::vec3) +
                        waterMask.capacity();
    for (const auto& edge : edgeVertices) {
        bytes += edge.capacity() * sizeof(std::uint32_t);
    }
    for (const auto& level : availableBelow) {
        bytes += level.capacity() * sizeof(TileRectangle);
    }
    return bytes + availableBelow.capacity() * sizeof(LevelAvailability);
}

// ---- gzip ----------------------------------------------------------------------------------------

bool isGzip(std::span<const std::uint8_t> bytes) noexcept
{
    return bytes.size() >= 2 && bytes[0] == 0x1f && bytes[1] == 0x8b;
}

std::vector<std::uint8_t> gunzipIfCompressed(std::span<const std::uint8_t> bytes, std::string_view nameForMessages,
                                             std::size_t maximumBytes)
{
    if (!isGzip(bytes)) {
        return {bytes.begin(), bytes.end()};
    }
    z_stream stream{};
    if (inflateInit2(&stream, 16 + MAX_WBITS) != Z_OK) {
        throw Error(prefix(nameForMessages) + "cannot start zlib");
    }
    std::vector<std::uint8_t> out;
    stream.next_in = const_cast<Bytef*>(bytes.data());
    stream.avail_in = static_cast<uInt>(std::min<std::size_t>(bytes.size(), std::numeric_limits<uInt>::max()));
    int status = Z_OK;
    std::size_t chunk = std::max<std::size_t>(4096, std::min<std::size_t>(bytes.size() * 4, maximumBytes));
    while (status != Z_STREAM_END) {
        if (out.size() >= maximumBytes) {
            inflateEnd(&stream);
            throw Error(prefix(nameForMessages) + "gzip data inflates to more than the " + std::to_string(maximumBytes) +
                        " bytes allowed");
        }
        const std::size_t used = out.size();
        out.resize(std::min(maximumBytes, used + chunk));
        chunk *= 2;
        stream.next_out = out.data() + used;
        stream.avail_out = static_cast<uInt>(out.size() - used);
        status = inflate(&stream, Z_NO_FLUSH);
        out.resize(out.size() - stream.avail_out);
        if (status == Z_STREAM_END) {
            break;
        }
        if (status == Z_BUF_ERROR && stream.avail_in == 0) {
            inflateEnd(&stream);
            throw Error(prefix(nameForMessages) + "truncated gzip data (" + std::to_string(bytes.size()) +
                        " bytes end before the compressed stream does)");
        }
        if (status != Z_OK && status != Z_BUF_ERROR) {
            const std::string reason = stream.msg ? stream.msg : "error " + std::to_string(status);
            inflateEnd(&stream);
            throw Error(prefix(nameForMessages) + "corrupt gzip data: " + reason);
        }
        if (status == Z_OK && stream.avail_in == 0 && stream.avail_out != 0) {
            inflateEnd(&stream);
            throw Error(prefix(nameForMessages) + "truncated gzip data (" + std::to_string(bytes.size()) +
                        " bytes end before the compressed stream does)");
        }
    }
    const std::size_t left = stream.avail_in;
    inflateEnd(&stream);
    if (left != 0) {
        throw Error(prefix(nameForMessages) + std::to_string(left) + " bytes after the end of the gzip data");
    }
    return out;
}

std::vector<std::uint8_t> gzipBytes(std::span<const std::uint8_t> bytes, int level)
{
    z_stream stream{};
    if (deflateInit2(&stream, std::clamp(level, 1, 9), Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY) != Z_OK) {
        throw Error("gzip: cannot start zlib");
    }
    std::vector<std::uint8_t> out(deflateBound(&stream, static_cast<uLong>(bytes.size())));
    stream.next_in = const_cast<Bytef*>(bytes.data());
    stream.avail_in = static_cast<uInt>(bytes.size());
    stream.next_out = out.data();
    stream.avail_out = static_cast<uInt>(out.size());
    const int status = deflate(&stream, Z_FINISH);
    out.resize(out.size() - stream.avail_out);
    deflateEnd(&stream);
    if (status != Z_STREAM_END) {
        throw Error("gzip: zlib failed (" + std::to_string(status) + ")");
    }
    return out;
}

// ---- quantized-mesh-1.0 --------------------------------------------------------------------------

TerrainTileData decodeQuantizedMesh(std::span<const std::uint8_t> compressed, const TileKey& key,
                                    std::string_view nameForMessages)
{
    const std::vector<std::uint8_t> bytes = gunzipIfCompressed(compressed, nameForMessages);
    ByteReader in(bytes, nameForMessages);
    const std::string where = prefix(nameForMessages);
    TerrainTileData tile;
    tile.key = key;

    in.need(kHeaderBytes, "the quantized-mesh header");
    for (int i = 0; i < 3; ++i) {
        in.f64("the centre");
    }
    const float minimumHeight = in.f32("the minimum height");
    const float maximumHeight = in.f32("the maximum height");
    for (int i = 0; i < 4; ++i) {
        in.f64("the bounding sphere");
    }
    glm::dvec3 occlusion;
    for (int i = 0; i < 3; ++i) {
        occlusion[i] = in.f64("the horizon occlusion point");
    }
    if (!std::isfinite(minimumHeight) || !std::isfinite(maximumHeight) || minimumHeight > maximumHeight) {
        throw Error(where + "the header's height range " + std::to_string(minimumHeight) + " to " +
                    std::to_string(maximumHeight) + " is not a range of finite heights");
    }
    if (std::isfinite(occlusion.x) && std::isfinite(occlusion.y) && std::isfinite(occlusion.z)) {
        tile.horizonOcclusionPoint = occlusion;
    }

    const std::uint32_t vertexCount = in.u32("the vertex count");
    if (vertexCount == 0) {
        throw Error(where + "a mesh without vertices");
    }
    if (vertexCount > kMaximumMeshVertices) {
        throw Error(where + "the header claims " + std::to_string(vertexCount) + " vertices, more than the " +
                    std::to_string(kMaximumMeshVertices) + " allowed");
    }
    const std::size_t n = vertexCount;
    in.need(std::uint64_t{6} * n, std::to_string(n) + " vertices");
    std::vector<int> quantized(3 * n); // u, v, height per vertex
    for (int component = 0; component < 3; ++component) {
        int value = 0;
        for (std::size_t i = 0; i < n; ++i) {
            value += zigZagDecode(in.u16("a vertex"));
            if (value < 0 || value > kQuantizedMax) {
                static const char* const names[] = {"u", "v", "height"};
                throw Error(where + "vertex " + std::to_string(i) + " has " + names[component] + " " +
                            std::to_string(value) + ", outside 0..32767");
            }
            quantized[3 * i + static_cast<std::size_t>(component)] = value;
        }
    }
    const double heightScale = (static_cast<double>(maximumHeight) - static_cast<double>(minimumHeight)) / kQuantizedMax;
    tile.vertices.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        tile.vertices[i] = glm::vec3(static_cast<float>(quantized[3 * i]) / kQuantizedMax,
                                     static_cast<float>(quantized[3 * i + 1]) / kQuantizedMax,
                                     static_cast<float>(static_cast<double>(minimumHeight) + heightScale * quantized[3 * i + 2]));
    }

    const bool wide = n > 65536;
    const std::size_t indexBytes = wide ? 4 : 2;
    if (in.position() % indexBytes != 0) {
        in.skip(indexBytes - in.position() % indexBytes, "the padding before the indices");
    }
    auto readIndex = [&](const std::string& what) -> std::uint32_t { return wide ? in.u32(what) : in.u16(what); };

    const std::uint32_t triangleCount = in.u32("the triangle count");
    in.need(std::uint64_t{triangleCount} * 3 * indexBytes, std::to_string(triangleCount) + " triangles");
    tile.indices.resize(std::size_t{triangleCount} * 3);
    std::uint32_t highest = 0;
    for (std::size_t i = 0; i < tile.indices.size(); ++i) {
        const std::uint32_t code = readIndex("an index");
        if (code > highest) {
            throw Error(where + "index " + std::to_string(i) + " is coded " + std::to_string(code) +
                        ", beyond the highest vertex so far (" + std::to_string(highest) + ")");
        }
        const std::uint32_t index = highest - code;
        if (index >= n) {
            throw Error(where + "index " + std::to_string(i) + " is " + std::to_string(index) + ", beyond the " +
                        std::to_string(n) + " vertices");
        }
        tile.indices[i] = index;
        if (code == 0) {
            ++highest;
        }
    }

    static const char* const edgeNames[] = {"north", "east", "south", "west"};
    for (const int edge : {3, 2, 1, 0}) { // the file's order: west, south, east, north
        const std::string what = std::string("the ") + edgeNames[edge] + " edge";
        const std::uint32_t count = in.u32(what + "'s vertex count");
        if (count > n) {
            throw Error(where + what + " lists " + std::to_string(count) + " vertices, more than the mesh's " +
                        std::to_string(n));
        }
        in.need(std::uint64_t{count} * indexBytes, what + "'s " + std::to_string(count) + " vertices");
        auto& list = tile.edgeVertices[static_cast<std::size_t>(edge)];
        list.resize(count);
        for (std::uint32_t i = 0; i < count; ++i) {
            const std::uint32_t index = readIndex(what);
            if (index >= n) {
                throw Error(where + what + " lists vertex " + std::to_string(index) + ", beyond the " +
                            std::to_string(n) + " vertices");
            }
            if (!onEdge(edge, quantized[3 * index], quantized[3 * index + 1])) {
                throw Error(where + what + " lists vertex " + std::to_string(index) + " at u " +
                            std::to_string(quantized[3 * index]) + ", v " + std::to_string(quantized[3 * index + 1]) +
                            ", which is not on that edge");
            }
            list[i] = index;
        }
    }
    sortEdges(tile.edgeVertices, tile.vertices);

    while (in.remaining() > 0) {
        const std::uint8_t id = in.u8("an extension's id");
        const std::uint32_t length = in.u32("extension " + std::to_string(id) + "'s length");
        const std::span<const std::uint8_t> data = in.take(length, "extension " + std::to_string(id));
        if (id == 1) {
            if (data.size() != 2 * n) {
                throw Error(where + "the oct-encoded normals extension has " + std::to_string(data.size()) +
                            " bytes, not 2 for each of the " + std::to_string(n) + " vertices");
            }
            tile.normals.resize(n);
            for (std::size_t i = 0; i < n; ++i) {
                tile.normals[i] = octDecodeNormal(data[2 * i], data[2 * i + 1]);
            }
        } else if (id == 2) {
            if (data.size() != 1 && data.size() != kWaterMaskBytes) {
                throw Error(where + "the water mask extension has " + std::to_string(data.size()) +
                            " bytes, not 1 or 65536");
            }
            tile.waterMask.assign(data.begin(), data.end());
            tile.waterMaskSize = data.size() == 1 ? 1 : 256;
        } else if (id == 4) {
            ByteReader metadata(data, nameForMessages);
            const std::uint32_t jsonLength = metadata.u32("the metadata's JSON length");
            const auto json = metadata.take(jsonLength, "the metadata's JSON");
            tile.availableBelow = detail::parseMetadataAvailability(
                std::string_view(reinterpret_cast<const char*>(json.data()), json.size()), key.level + 1,
                std::string(nameForMessages) + " (metadata extension)");
        }
        // Other extensions are someone else's: skipped.
    }
    tile.minimumHeight = static_cast<double>(minimumHeight);
    tile.maximumHeight = static_cast<double>(maximumHeight);
    return tile;
}

namespace {

/// Bounding sphere of points: the centre of their box and the farthest point's distance.
std::pair<glm::dvec3, double> boundingSphere(std::span<const glm::dvec3> points)
{
    glm::dvec3 low(std::numeric_limits<double>::infinity());
    glm::dvec3 high(-std::numeric_limits<double>::infinity());
    for (const glm::dvec3& p : points) {
        low = glm::min(low, p);
        high = glm::max(high, p);
    }
    const glm::dvec3 centre = 0.5 * (low + high);
    double radius = 0.0;
    for (const glm::dvec3& p : points) {
        radius = std::max(radius, glm::length(p - centre));
    }
    return {centre, radius};
}

} // namespace

std::vector<std::uint8_t> encodeQuantizedMesh(const TerrainTileData& tile, const QuantizedMeshEncoding& encoding,
                                              const Ellipsoid& ellipsoid)
{
    const std::string where = "tile " + std::to_string(tile.key.level) + "/" + std::to_string(tile.key.x) + "/" +
                              std::to_string(tile.key.y) + ": ";
    const std::size_t n = tile.vertices.size();
    const TilingScheme scheme = TilingScheme::geographic();
    if (n == 0 || n > kMaximumMeshVertices || tile.indices.empty() || tile.indices.size() % 3 != 0 ||
        !scheme.isValid(tile.key)) {
        throw Error(where + "not a mesh quantized-mesh can hold (" + std::to_string(n) + " vertices, " +
                    std::to_string(tile.indices.size()) + " indices)");
    }
    if (encoding.normals && tile.normals.size() != n) {
        throw Error(where + std::to_string(tile.normals.size()) + " normals for " + std::to_string(n) + " vertices");
    }
    if (encoding.waterMask && tile.waterMask.size() != 1 && tile.waterMask.size() != kWaterMaskBytes) {
        throw Error(where + "a water mask of " + std::to_string(tile.waterMask.size()) + " bytes (1 or 65536)");
    }
    // Vertices in the order the triangles first use them, as high-water-mark coding needs;
    // vertices no triangle uses go last.
    std::vector<std::uint32_t> newIndex(n, std::numeric_limits<std::uint32_t>::max());
    std::vector<std::uint32_t> order;
    order.reserve(n);
    for (const std::uint32_t index : tile.indices) {
        if (index >= n) {
            throw Error(where + "index " + std::to_string(index) + " beyond the " + std::to_string(n) + " vertices");
        }
        if (newIndex[index] == std::numeric_limits<std::uint32_t>::max()) {
            newIndex[index] = static_cast<std::uint32_t>(order.size());
            order.push_back(index);
        }
    }
    for (std::uint32_t i = 0; i < n; ++i) {
        if (newIndex[i] == std::numeric_limits<std::uint32_t>::max()) {
            newIndex[i] = static_cast<std::uint32_t>(order.size());
            order.push_back(i);
        }
    }

    float minimum = std::numeric_limits<float>::infinity();
    float maximum = -minimum;
    for (const glm::vec3& v : tile.vertices) {
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z) || v.x < 0.0f || v.x > 1.0f || v.y < 0.0f ||
            v.y > 1.0f) {
            throw Error(where + "a vertex outside the tile or not finite");
        }
        minimum = std::min(minimum, v.z);
        maximum = std::max(maximum, v.z);
    }
    const double low = static_cast<double>(minimum);
    const double range = static_cast<double>(maximum) - low;
    std::vector<int> qu(n), qv(n), qh(n);
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3& v = tile.vertices[order[i]];
        qu[i] = static_cast<int>(std::lround(static_cast<double>(v.x) * kQuantizedMax));
        qv[i] = static_cast<int>(std::lround(static_cast<double>(v.y) * kQuantizedMax));
        qh[i] = range > 0.0 ? static_cast<int>(std::lround((static_cast<double>(v.z) - low) / range * kQuantizedMax)) : 0;
    }

    // Geometry on the ellipsoid: the header's centre, bounding sphere and occlusion point.
    const GeodeticExtent extent = scheme.tileExtent(tile.key);
    std::vector<glm::dvec3> positions(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double longitude = extent.west + (extent.east - extent.west) * qu[i] / kQuantizedMax;
        const double latitude = extent.south + (extent.north - extent.south) * qv[i] / kQuantizedMax;
        const double height = low + range * qh[i] / kQuantizedMax;
        positions[i] = ellipsoid.toCartesian(Geodetic3D(longitude, latitude, height));
    }
    const Geodetic2D middle = extent.centre();
    const glm::dvec3 centre = ellipsoid.toCartesian(Geodetic3D(middle, low + 0.5 * range));
    const auto [sphereCentre, radius] = boundingSphere(positions);
    const glm::dvec3 direction = glm::normalize(ellipsoid.toCartesian(middle) * ellipsoid.oneOverRadii());
    // A tile spread over a hemisphere has no occlusion point; one far along its direction is never
    // hidden wrongly, only seldom hidden.
    const glm::dvec3 occlusion = horizonOcclusionPoint(ellipsoid, positions, direction).value_or(direction * 1e9);

    ByteWriter out;
    for (int i = 0; i < 3; ++i) {
        out.f64(centre[i]);
    }
    out.f32(minimum);
    out.f32(maximum);
    for (int i = 0; i < 3; ++i) {
        out.f64(sphereCentre[i]);
    }
    out.f64(radius);
    for (int i = 0; i < 3; ++i) {
        out.f64(occlusion[i]);
    }
    out.u32(static_cast<std::uint32_t>(n));
    for (const std::vector<int>* values : {&qu, &qv, &qh}) {
        int previous = 0;
        for (const int value : *values) {
            out.u16(zigZagEncode(value - previous));
            previous = value;
        }
    }
    const bool wide = n > 65536;
    const std::size_t indexBytes = wide ? 4 : 2;
    while (out.bytes.size() % indexBytes != 0) {
        out.u8(0);
    }
    auto writeIndex = [&](std::uint32_t value) {
        if (wide) {
            out.u32(value);
        } else {
            out.u16(static_cast<std::uint16_t>(value));
        }
    };
    out.u32(static_cast<std::uint32_t>(tile.indices.size() / 3));
    std::uint32_t highest = 0;
    for (const std::uint32_t index : tile.indices) {
        const std::uint32_t mapped = newIndex[index];
        writeIndex(highest - mapped);
        if (mapped == highest) {
            ++highest;
        }
    }
    // Edge lists from the quantized positions, sorted along each edge; the file's order is west,
    // south, east, north.
    std::array<std::vector<std::uint32_t>, 4> edges;
    for (std::uint32_t i = 0; i < n; ++i) {
        for (int edge = 0; edge < 4; ++edge) {
            if (onEdge(edge, qu[i], qv[i])) {
                edges[static_cast<std::size_t>(edge)].push_back(i);
            }
        }
    }
    for (int edge = 0; edge < 4; ++edge) {
        const std::vector<int>& along = (edge == 0 || edge == 2) ? qu : qv;
        auto& list = edges[static_cast<std::size_t>(edge)];
        std::stable_sort(list.begin(), list.end(), [&](std::uint32_t a, std::uint32_t b) { return along[a] < along[b]; });
    }
    for (const int edge : {3, 2, 1, 0}) {
        const auto& list = edges[static_cast<std::size_t>(edge)];
        out.u32(static_cast<std::uint32_t>(list.size()));
        for (const std::uint32_t index : list) {
            writeIndex(index);
        }
    }
    if (encoding.normals) {
        out.u8(1);
        out.u32(static_cast<std::uint32_t>(2 * n));
        for (std::size_t i = 0; i < n; ++i) {
            const auto oct = octEncodeNormal(tile.normals[order[i]]);
            out.u8(oct[0]);
            out.u8(oct[1]);
        }
    }
    if (encoding.waterMask) {
        out.u8(2);
        out.u32(static_cast<std::uint32_t>(tile.waterMask.size()));
        out.append(tile.waterMask);
    }
    if (!encoding.metadataJson.empty()) {
        out.u8(4);
        out.u32(static_cast<std::uint32_t>(encoding.metadataJson.size() + 4));
        out.u32(static_cast<std::uint32_t>(encoding.metadataJson.size()));
        out.append({reinterpret_cast<const std::uint8_t*>(encoding.metadataJson.data()), encoding.metadataJson.size()});
    }
    return encoding.gzipLevel > 0 ? gzipBytes(out.bytes, encoding.gzipLevel) : std::move(out.bytes);
}

// ---- heightmap-1.0 -------------------------------------------------------------------------------

TerrainTileData decodeHeightmapTerrain(std::span<const std::uint8_t> compressed, const TileKey& key,
                                       std::string_view nameForMessages)
{
    const std::vector<std::uint8_t> bytes = gunzipIfCompressed(compressed, nameForMessages);
    const std::string where = prefix(nameForMessages);
    constexpr std::size_t kSamples = kHeightmapSide * kHeightmapSide;
    if (bytes.size() < 2 * kSamples) {
        throw Error(where + "cut short: a heightmap-1.0 tile holds 65 x 65 heights (8450 bytes), these are " +
                    std::to_string(bytes.size()) + " bytes");
    }
    const std::size_t rest = bytes.size() - 2 * kSamples;
    if (rest != 0 && rest != 1 && rest != 2 && rest != 1 + kWaterMaskBytes) {
        throw Error(where + std::to_string(rest) +
                    " bytes after the heights: a heightmap-1.0 tile has a child mask byte and a water mask of 1 or "
                    "65536 bytes");
    }
    TerrainTileData tile;
    tile.key = key;
    tile.size = kHeightmapSide;
    tile.heights.resize(kSamples);
    for (std::size_t i = 0; i < kSamples; ++i) {
        const unsigned value = bytes[2 * i] | (unsigned{bytes[2 * i + 1]} << 8);
        tile.heights[i] = static_cast<float>(value / 5.0 - 1000.0);
    }
    if (rest >= 1) {
        const std::uint8_t mask = bytes[2 * kSamples];
        if (mask > 0x0f) {
            throw Error(where + "child mask " + std::to_string(mask) + " has bits beyond the four children");
        }
        tile.childMask = mask;
    }
    if (rest > 1) {
        tile.waterMask.assign(bytes.begin() + static_cast<std::ptrdiff_t>(2 * kSamples + 1), bytes.end());
        tile.waterMaskSize = rest == 2 ? 1 : 256;
    }
    setHeightRange(tile, tile.heights);
    return tile;
}

float heightmapTerrainQuantize(double height) noexcept
{
    if (!std::isfinite(height)) {
        height = 0.0;
    }
    const double value = std::clamp(std::round((height + 1000.0) * 5.0), 0.0, 65535.0);
    return static_cast<float>(value / 5.0 - 1000.0);
}

std::vector<std::uint8_t> encodeHeightmapTerrain(const TerrainTileData& tile, int gzipLevel)
{
    if (tile.size != kHeightmapSide || tile.heights.size() != std::size_t{kHeightmapSide} * kHeightmapSide) {
        throw Error("heightmap-1.0 tiles are 65 x 65 samples, not " + std::to_string(tile.size));
    }
    ByteWriter out;
    out.bytes.reserve(2 * tile.heights.size() + 2 + tile.waterMask.size());
    for (const float h : tile.heights) {
        const double value = std::isfinite(h) ? std::clamp(std::round((static_cast<double>(h) + 1000.0) * 5.0), 0.0, 65535.0) : 5000.0;
        out.u16(static_cast<std::uint16_t>(value));
    }
    out.u8(tile.childMask & 0x0f);
    if (tile.waterMask.size() == 1 || tile.waterMask.size() == kWaterMaskBytes) {
        out.append(tile.waterMask);
    } else {
        out.u8(0);
    }
    return gzipLevel > 0 ? gzipBytes(out.bytes, gzipLevel) : std::move(out.bytes);
}

// ---- height images -------------------------------------------------------------------------------

HeightGrid decodeHeightImage(std::span<const std::uint8_t> bytes, HeightEncoding encoding, std::string_view nameForMessages)
{
    HeightGrid grid;
    if (encoding == HeightEncoding::Png16) {
        GreyImage16 image;
        try {
            image = decodePng16(bytes, nameForMessages);
        } catch (const Error& error) {
            // An RGB tile given as 16-bit heights is the usual mistake: say what it might be.
            if (detectImageFormat(bytes) != ImageFormat::Unknown && std::string_view(error.what()).find("16-bit") != std::string_view::npos) {
                throw Error(std::string(error.what()) + " (a Terrain-RGB or Terrarium tile? name its format)");
            }
            throw;
        }
        grid.width = image.width;
        grid.height = image.height;
        grid.heights.resize(image.samples.size());
        for (std::size_t i = 0; i < image.samples.size(); ++i) {
            grid.heights[i] = static_cast<float>(static_cast<int>(image.samples[i]) - 32768);
        }
        return grid;
    }
    const Image image = decodeImage(bytes, nameForMessages, 0);
    if (image.channels < 3) {
        throw Error(prefix(nameForMessages) + "a grey image, not " +
                    (encoding == HeightEncoding::TerrainRgb ? "Terrain-RGB" : "Terrarium") + " colours");
    }
    grid.width = image.width;
    grid.height = image.height;
    grid.heights.resize(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height));
    const auto channels = static_cast<std::size_t>(image.channels);
    for (std::size_t i = 0; i < grid.heights.size(); ++i) {
        const std::uint8_t* p = image.pixels.data() + i * channels;
        if (channels == 4 && p[3] == 0) {
            grid.heights[i] = std::numeric_limits<float>::quiet_NaN(); // transparent: no data
        } else if (encoding == HeightEncoding::TerrainRgb) {
            grid.heights[i] = static_cast<float>(-10000.0 + (p[0] * 65536.0 + p[1] * 256.0 + p[2]) * 0.1);
        } else {
            grid.heights[i] = static_cast<float>(p[0] * 256.0 + p[1] + p[2] / 256.0 - 32768.0);
        }
    }
    return grid;
}

std::vector<std::uint8_t> encodeHeightPng16(const HeightGrid& grid, int compressionLevel)
{
    if (grid.width <= 0 || grid.height <= 0 ||
        grid.heights.size() != static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height)) {
        throw Error("a height grid of " + std::to_string(grid.heights.size()) + " samples is not " +
                    std::to_string(grid.width) + " x " + std::to_string(grid.height));
    }
    GreyImage16 image;
    image.width = grid.width;
    image.height = grid.height;
    image.samples.reserve(grid.heights.size());
    for (const float height : grid.heights) {
        const float h = std::isfinite(height) ? height : 0.0f;
        image.samples.push_back(static_cast<std::uint16_t>(std::clamp(std::lround(h) + 32768L, 0L, 65535L)));
    }
    return encodePng16(image, compressionLevel);
}

// ---- SRTM .hgt -----------------------------------------------------------------------------------

HeightGrid decodeHgt(std::span<const std::uint8_t> bytes, std::string_view nameForMessages)
{
    int side = 0;
    for (const int candidate : {1201, 3601}) {
        if (bytes.size() == std::size_t{2} * candidate * candidate) {
            side = candidate;
        }
    }
    if (side == 0) {
        throw Error(prefix(nameForMessages) + std::to_string(bytes.size()) +
                    " bytes: an SRTM .hgt file holds 1201 x 1201 (2,884,802 bytes) or 3601 x 3601 (25,934,402 bytes) "
                    "samples");
    }
    HeightGrid grid;
    grid.width = side;
    grid.height = side;
    grid.heights.resize(static_cast<std::size_t>(side) * side);
    for (std::size_t i = 0; i < grid.heights.size(); ++i) {
        const auto value = static_cast<std::int16_t>((bytes[2 * i] << 8) | bytes[2 * i + 1]);
        grid.heights[i] = value == -32768 ? std::numeric_limits<float>::quiet_NaN() : static_cast<float>(value);
    }
    return grid;
}

std::optional<std::pair<int, int>> hgtCorner(std::string_view fileName) noexcept
{
    const std::size_t slash = fileName.find_last_of('/');
    std::string name(slash == std::string_view::npos ? fileName : fileName.substr(slash + 1));
    std::transform(name.begin(), name.end(), name.begin(),
                   [](char c) { return static_cast<char>(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c); });
    // N37W123.HGT: 11 characters.
    if (name.size() != 11 || name.substr(7) != ".HGT" || (name[0] != 'N' && name[0] != 'S') ||
        (name[3] != 'E' && name[3] != 'W')) {
        return std::nullopt;
    }
    auto digits = [&](std::size_t start, std::size_t count) -> int {
        int value = 0;
        for (std::size_t i = start; i < start + count; ++i) {
            if (name[i] < '0' || name[i] > '9') {
                return -1;
            }
            value = value * 10 + (name[i] - '0');
        }
        return value;
    };
    const int latitude = digits(1, 2);
    const int longitude = digits(4, 3);
    if (latitude < 0 || longitude < 0) {
        return std::nullopt;
    }
    const int south = name[0] == 'N' ? latitude : -latitude;
    const int west = name[3] == 'E' ? longitude : -longitude;
    if (south < -90 || south > 89 || west < -180 || west > 179) {
        return std::nullopt;
    }
    return std::pair(west, south);
}

// ---- geometry ------------------------------------------------------------------------------------

std::optional<glm::dvec3> horizonOcclusionPoint(const Ellipsoid& ellipsoid, std::span<const glm::dvec3> points,
                                                const glm::dvec3& direction) noexcept
{
    // In the scaled space the ellipsoid is the unit sphere. A point q at distance m >= 1 from the
    // centre can be seen only from outside the cone of tangents its horizon makes, which lies at
    // beta = acos(1 / m) from q's direction; a point P along `direction`, at alpha from q, hides
    // q whenever it is hidden itself if |P| >= 1 / cos(alpha + beta).
    const glm::dvec3 d = glm::normalize(direction);
    if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z) || points.empty()) {
        return std::nullopt;
    }
    double magnitude = 1.0;
    for (const glm::dvec3& point : points) {
        const glm::dvec3 q = point * ellipsoid.oneOverRadii();
        const double m = std::max(1.0, glm::length(q));
        const glm::dvec3 unit = glm::normalize(q);
        const double cosAlpha = std::clamp(glm::dot(unit, d), -1.0, 1.0);
        const double sinAlpha = glm::length(glm::cross(unit, d));
        const double cosBeta = 1.0 / m;
        const double sinBeta = std::sqrt(std::max(0.0, m * m - 1.0)) * cosBeta;
        const double denominator = cosAlpha * cosBeta - sinAlpha * sinBeta;
        if (!(denominator > 1e-12)) {
            return std::nullopt;
        }
        magnitude = std::max(magnitude, 1.0 / denominator);
    }
    return d * magnitude;
}

std::array<std::uint8_t, 2> octEncodeNormal(const glm::vec3& normal) noexcept
{
    const float sum = std::abs(normal.x) + std::abs(normal.y) + std::abs(normal.z);
    if (!(sum > 0.0f) || !std::isfinite(sum)) {
        return {128, 128}; // not a direction: straight up in the tile's frame is unknown here, so +z
    }
    float x = normal.x / sum;
    float y = normal.y / sum;
    if (normal.z < 0.0f) {
        const float oldX = x;
        x = (1.0f - std::abs(y)) * (oldX >= 0.0f ? 1.0f : -1.0f);
        y = (1.0f - std::abs(oldX)) * (y >= 0.0f ? 1.0f : -1.0f);
    }
    auto toByte = [](float value) {
        return static_cast<std::uint8_t>(std::clamp(std::lround((std::clamp(value, -1.0f, 1.0f) * 0.5f + 0.5f) * 255.0f), 0L, 255L));
    };
    return {toByte(x), toByte(y)};
}

glm::vec3 octDecodeNormal(std::uint8_t xByte, std::uint8_t yByte) noexcept
{
    const float x = xByte / 255.0f * 2.0f - 1.0f;
    const float y = yByte / 255.0f * 2.0f - 1.0f;
    glm::vec3 n(x, y, 1.0f - std::abs(x) - std::abs(y));
    if (n.z < 0.0f) {
        const float oldX = n.x;
        n.x = (1.0f - std::abs(n.y)) * (oldX >= 0.0f ? 1.0f : -1.0f);
        n.y = (1.0f - std::abs(oldX)) * (n.y >= 0.0f ? 1.0f : -1.0f);
    }
    return glm::normalize(n);
}

} // namespace orbis::world
