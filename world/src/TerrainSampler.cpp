#include "orbis/world/TerrainSampler.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace orbis::world {

TerrainSampler::TerrainSampler(std::shared_ptr<const TerrainTileData> data)
    : _data(std::move(data))
{
    if (!_data->isMesh()) {
        return;
    }
    // About two triangles a bucket: a point query looks at a handful.
    const std::size_t triangles = _data->indices.size() / 3;
    _buckets = std::clamp(static_cast<int>(std::sqrt(static_cast<double>(triangles) / 2.0)), 1, 256);
    const auto& vertices = _data->vertices;
    auto bucketOf = [&](float coordinate) {
        return std::clamp(static_cast<int>(coordinate * static_cast<float>(_buckets)), 0, _buckets - 1);
    };
    auto forBuckets = [&](std::size_t t, auto&& visit) {
        const glm::vec3& a = vertices[_data->indices[3 * t]];
        const glm::vec3& b = vertices[_data->indices[3 * t + 1]];
        const glm::vec3& c = vertices[_data->indices[3 * t + 2]];
        const int x0 = bucketOf(std::min({a.x, b.x, c.x}));
        const int x1 = bucketOf(std::max({a.x, b.x, c.x}));
        const int y0 = bucketOf(std::min({a.y, b.y, c.y}));
        const int y1 = bucketOf(std::max({a.y, b.y, c.y}));
        for (int y = y0; y <= y1; ++y) {
            for (int x = x0; x <= x1; ++x) {
                visit(static_cast<std::size_t>(y * _buckets + x));
            }
        }
    };
    // wa = ((b.x - u)(c.y - v) - (c.x - u)(b.y - v)) / area, expanded in u and v; wb likewise.
    _weightPlanes.resize(triangles);
    for (std::size_t t = 0; t < triangles; ++t) {
        const glm::dvec3 a(vertices[_data->indices[3 * t]]);
        const glm::dvec3 b(vertices[_data->indices[3 * t + 1]]);
        const glm::dvec3 c(vertices[_data->indices[3 * t + 2]]);
        const double area = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
        const std::array<float, 3> heights{static_cast<float>(a.z), static_cast<float>(b.z), static_cast<float>(c.z)};
        if (area == 0.0) {
            _weightPlanes[t] = {{}, {}, heights};
            continue;
        }
        _weightPlanes[t] = {{(b.y - c.y) / area, (c.x - b.x) / area, (b.x * c.y - c.x * b.y) / area},
                            {(c.y - a.y) / area, (a.x - c.x) / area, (c.x * a.y - a.x * c.y) / area},
                            heights};
    }
    // Counted first, then filled: one array for all the buckets.
    _bucketStart.assign(static_cast<std::size_t>(_buckets) * static_cast<std::size_t>(_buckets) + 1, 0);
    for (std::size_t t = 0; t < triangles; ++t) {
        forBuckets(t, [&](std::size_t bucket) { ++_bucketStart[bucket + 1]; });
    }
    for (std::size_t b = 1; b < _bucketStart.size(); ++b) {
        _bucketStart[b] += _bucketStart[b - 1];
    }
    _bucketTriangles.resize(_bucketStart.back());
    std::vector<std::uint32_t> next(_bucketStart.begin(), _bucketStart.end() - 1);
    for (std::size_t t = 0; t < triangles; ++t) {
        forBuckets(t, [&](std::size_t bucket) { _bucketTriangles[next[bucket]++] = static_cast<std::uint32_t>(t); });
    }
}

std::size_t TerrainSampler::memoryBytes() const noexcept
{
    return _data->memoryBytes() + (_bucketStart.size() + _bucketTriangles.size()) * sizeof(std::uint32_t) + _weightPlanes.size() * sizeof(WeightPlanes);
}

double TerrainSampler::heightOf(const Weights& weights) const noexcept
{
    const bool mesh = _data->isMesh();
    double height = 0.0;
    for (int k = 0; k < weights.count; ++k) {
        const std::uint32_t at = weights.index[static_cast<std::size_t>(k)];
        height += weights.weight[static_cast<std::size_t>(k)] *
                  static_cast<double>(mesh ? _data->vertices[at].z : _data->heights[at]);
    }
    return height;
}

double TerrainSampler::height(double u, double v) const noexcept
{
    return heightOf(weightsAt(u, v));
}

namespace {
constexpr double kInsideTriangle = 1e-9; // how far outside a triangle a point may be and count as in it
}

double TerrainSampler::height(double u, double v, std::array<std::uint32_t, 2>& hints) const noexcept
{
    if (!_data->isMesh()) {
        return heightOf(gridWeights(u, v));
    }
    // The hinted triangles from their planes and corner heights alone; the same arithmetic, in the
    // same order, as triangleWeights and heightOf, so the height does not depend on the hints.
    const std::size_t triangles = _weightPlanes.size();
    std::array<double, 3> w{};
    for (const std::uint32_t t : hints) {
        if (t < triangles && _weightPlanes[t].weights(u, v, w) && std::min({w[0], w[1], w[2]}) >= -kInsideTriangle) {
            hints[0] = t;
            const std::array<float, 3>& h = _weightPlanes[t].heights;
            return 0.0 + w[0] * static_cast<double>(h[0]) + w[1] * static_cast<double>(h[1]) + w[2] * static_cast<double>(h[2]);
        }
    }
    const std::uint32_t t = triangleAt(u, v);
    const Weights weights = t == ~0u ? Weights{} : triangleWeights(t, u, v);
    if (weights.count > 0 && weights.outside <= kInsideTriangle) {
        hints[0] = t;
    }
    return heightOf(weights);
}

std::optional<double> TerrainSampler::heightOnTriangles(double u, double v) const noexcept
{
    const Weights weights = weightsAt(u, v);
    // A rounding: points on an edge of float vertices may come out this far outside both sides.
    constexpr double kRounding = 1e-7;
    if (weights.count == 0 || weights.outside > kRounding) {
        return std::nullopt;
    }
    return heightOf(weights);
}

TerrainSampler::Weights TerrainSampler::weightsAt(double u, double v) const noexcept
{
    return _data->isMesh() ? meshWeights(u, v) : gridWeights(u, v);
}

TerrainSampler::Weights TerrainSampler::gridWeights(double u, double v) const noexcept
{
    const int size = _data->size;
    const double last = size - 1;
    // Exact for lattice points: size - 1 is a power of two, u and v dyadic.
    const double column = std::clamp(u, 0.0, 1.0) * last;
    const double row = (1.0 - std::clamp(v, 0.0, 1.0)) * last;
    const int i = std::min(static_cast<int>(column), size - 2);
    const int j = std::min(static_cast<int>(row), size - 2);
    const double tx = column - i;
    const double ty = row - j;
    auto at = [&](int c, int r) { return static_cast<std::uint32_t>(r * size + c); };
    // (1 - t) a + t b: exactly a at t = 0 and b at t = 1, so tiles sharing an edge agree on it.
    Weights weights;
    weights.count = 4;
    weights.index = {at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)};
    weights.weight = {(1.0 - ty) * (1.0 - tx), (1.0 - ty) * tx, ty * (1.0 - tx), ty * tx};
    return weights;
}

TerrainSampler::Weights TerrainSampler::triangleWeights(std::uint32_t t, double u, double v) const noexcept
{
    Weights weights;
    std::array<double, 3> w{};
    if (!_weightPlanes[t].weights(u, v, w)) {
        return weights; // degenerate
    }
    weights.count = 3;
    weights.index = {_data->indices[3 * t], _data->indices[3 * t + 1], _data->indices[3 * t + 2], 0};
    weights.weight = {w[0], w[1], w[2], 0.0};
    weights.outside = std::max(-std::min({w[0], w[1], w[2]}), 0.0);
    return weights;
}

TerrainSampler::Weights TerrainSampler::meshWeights(double u, double v) const noexcept
{
    const std::uint32_t t = triangleAt(u, v);
    return t == ~0u ? Weights{} : triangleWeights(t, u, v);
}

std::uint32_t TerrainSampler::triangleAt(double u, double v) const noexcept
{
    const int x = std::clamp(static_cast<int>(u * _buckets), 0, _buckets - 1);
    const int y = std::clamp(static_cast<int>(v * _buckets), 0, _buckets - 1);
    std::uint32_t nearest = ~0u;
    double nearestOutside = std::numeric_limits<double>::infinity();
    const std::size_t bucket = static_cast<std::size_t>(y * _buckets + x);
    std::array<double, 3> w{};
    for (std::uint32_t i = _bucketStart[bucket]; i < _bucketStart[bucket + 1]; ++i) {
        const std::uint32_t t = _bucketTriangles[i];
        if (!_weightPlanes[t].weights(u, v, w)) {
            continue;
        }
        const double outside = std::max(-std::min({w[0], w[1], w[2]}), 0.0);
        if (outside <= kInsideTriangle) {
            return t;
        }
        if (outside < nearestOutside) {
            nearestOutside = outside;
            nearest = t;
        }
    }
    return nearest;
}

std::pair<std::vector<double>, std::vector<double>> TerrainSampler::latticeCoordinates(const TileKey& key,
                                                                                     int samplesLog2) const
{
    const TileKey& dataKey = _data->key;
    const int size = (1 << samplesLog2) + 1;
    // Sample (i, j) of key is lattice point (X, Y) of level key.level + samplesLog2 (Y rows from
    // the south); in the data tile it is at (X, Y) / 2^(key.level + samplesLog2 - data level),
    // less the data tile's own origin: powers of two, so exact.
    const double scale = std::ldexp(1.0, static_cast<int>(dataKey.level) - static_cast<int>(key.level) - samplesLog2);
    std::vector<double> us(static_cast<std::size_t>(size));
    std::vector<double> vs(static_cast<std::size_t>(size));
    for (int k = 0; k < size; ++k) {
        us[static_cast<std::size_t>(k)] = (static_cast<double>(key.x << samplesLog2) + k) * scale - dataKey.x;
        vs[static_cast<std::size_t>(k)] = (static_cast<double>((key.y + 1) << samplesLog2) - k) * scale - dataKey.y;
    }
    return {std::move(us), std::move(vs)};
}

std::vector<float> TerrainSampler::latticeHeights(const TileKey& key, int samplesLog2) const
{
    const auto [us, vs] = latticeCoordinates(key, samplesLog2);
    const std::size_t size = us.size();
    std::vector<float> heights(size * size);
    for (std::size_t j = 0; j < size; ++j) {
        for (std::size_t i = 0; i < size; ++i) {
            heights[j * size + i] = static_cast<float>(height(us[i], vs[j]));
        }
    }
    return heights;
}

std::vector<float> TerrainSampler::latticeNormals(const TileKey& key, int samplesLog2) const
{
    const std::vector<glm::vec3>& normals = _data->normals;
    const std::size_t count = _data->isMesh() ? _data->vertices.size() : _data->heights.size();
    if (normals.size() != count || count == 0) {
        return {};
    }
    const auto [us, vs] = latticeCoordinates(key, samplesLog2);
    const std::size_t size = us.size();
    std::vector<float> out(size * size * 3);
    for (std::size_t j = 0; j < size; ++j) {
        for (std::size_t i = 0; i < size; ++i) {
            const Weights weights = weightsAt(us[i], vs[j]);
            glm::dvec3 normal(0.0);
            for (int k = 0; k < weights.count; ++k) {
                normal += weights.weight[static_cast<std::size_t>(k)] *
                          glm::dvec3(normals[weights.index[static_cast<std::size_t>(k)]]);
            }
            const double length = glm::length(normal);
            // Opposite normals cannot cancel on real terrain; should they, the first one stands.
            normal = length > 1e-12 ? normal / length : glm::dvec3(normals[weights.index[0]]);
            const std::size_t at = 3 * (j * size + i);
            out[at] = static_cast<float>(normal.x);
            out[at + 1] = static_cast<float>(normal.y);
            out[at + 2] = static_cast<float>(normal.z);
        }
    }
    return out;
}

TerrainSampler::WaterMask TerrainSampler::waterMask(const TileKey& key) const
{
    const std::vector<std::uint8_t>& mask = _data->waterMask;
    const int maskSize = _data->waterMaskSize;
    if (maskSize <= 0 || mask.size() != static_cast<std::size_t>(maskSize) * static_cast<std::size_t>(maskSize)) {
        return {};
    }
    if (maskSize == 1) {
        return {1, mask};
    }
    // A tile d levels below the data covers maskSize / 2^d of its texels: as many, at least 16,
    // keep the coastline as sharp as the data has it without a full mask per descendant.
    const int levelsBelow = static_cast<int>(key.level) - static_cast<int>(_data->key.level);
    const int size = std::max(maskSize >> std::min(levelsBelow, 4), 1);
    const double scale = std::ldexp(1.0, -levelsBelow);
    const double west = static_cast<double>(key.x) * scale - _data->key.x;
    const double south = static_cast<double>(key.y) * scale - _data->key.y;
    WaterMask out{size, std::vector<std::uint8_t>(static_cast<std::size_t>(size) * static_cast<std::size_t>(size))};
    auto texel = [maskSize](double t) { return std::clamp(static_cast<int>(std::floor(t * maskSize)), 0, maskSize - 1); };
    bool uniform = true;
    for (int j = 0; j < size; ++j) {
        const int row = maskSize - 1 - texel(south + (j + 0.5) / size * scale); // the data's rows run from the north
        for (int i = 0; i < size; ++i) {
            const int column = texel(west + (i + 0.5) / size * scale);
            const std::uint8_t value = mask[static_cast<std::size_t>(row) * static_cast<std::size_t>(maskSize) +
                                            static_cast<std::size_t>(column)];
            out.values[static_cast<std::size_t>(j) * static_cast<std::size_t>(size) + static_cast<std::size_t>(i)] = value;
            uniform = uniform && value == out.values[0];
        }
    }
    if (uniform) {
        out = {1, {out.values[0]}};
    }
    return out;
}

} // namespace orbis::world
