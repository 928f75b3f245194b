#include "orbis/scene/TerrainSampler.h"

#include <algorithm>
#include <cmath>

namespace orbis::scene {

TerrainSampler::TerrainSampler(std::shared_ptr<const world::TerrainTileData> data)
    : _data(std::move(data))
{
    if (!_data->isMesh()) {
        return;
    }
    // About four triangles a bucket: a point query looks at a handful.
    const std::size_t triangles = _data->indices.size() / 3;
    _buckets = std::clamp(static_cast<int>(std::sqrt(static_cast<double>(triangles) / 4.0)), 1, 64);
    _bucketTriangles.resize(static_cast<std::size_t>(_buckets) * _buckets);
    const auto& vertices = _data->vertices;
    auto bucketOf = [&](float coordinate) {
        return std::clamp(static_cast<int>(coordinate * static_cast<float>(_buckets)), 0, _buckets - 1);
    };
    for (std::size_t t = 0; t < triangles; ++t) {
        const glm::vec3& a = vertices[_data->indices[3 * t]];
        const glm::vec3& b = vertices[_data->indices[3 * t + 1]];
        const glm::vec3& c = vertices[_data->indices[3 * t + 2]];
        const int x0 = bucketOf(std::min({a.x, b.x, c.x}));
        const int x1 = bucketOf(std::max({a.x, b.x, c.x}));
        const int y0 = bucketOf(std::min({a.y, b.y, c.y}));
        const int y1 = bucketOf(std::max({a.y, b.y, c.y}));
        for (int y = y0; y <= y1; ++y) {
            for (int x = x0; x <= x1; ++x) {
                _bucketTriangles[static_cast<std::size_t>(y * _buckets + x)].push_back(static_cast<std::uint32_t>(t));
            }
        }
    }
}

double TerrainSampler::height(double u, double v) const noexcept
{
    return _data->isMesh() ? meshHeight(u, v) : gridHeight(u, v);
}

double TerrainSampler::gridHeight(double u, double v) const noexcept
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
    const float* h = _data->heights.data();
    auto at = [&](int c, int r) { return static_cast<double>(h[static_cast<std::size_t>(r) * size + c]); };
    // (1 - t) a + t b: exactly a at t = 0 and b at t = 1, so tiles sharing an edge agree on it.
    const double north = (1.0 - tx) * at(i, j) + tx * at(i + 1, j);
    const double south = (1.0 - tx) * at(i, j + 1) + tx * at(i + 1, j + 1);
    return (1.0 - ty) * north + ty * south;
}

double TerrainSampler::meshHeight(double u, double v) const noexcept
{
    const auto& vertices = _data->vertices;
    const int x = std::clamp(static_cast<int>(u * _buckets), 0, _buckets - 1);
    const int y = std::clamp(static_cast<int>(v * _buckets), 0, _buckets - 1);
    double nearest = 0.0;
    double nearestOutside = std::numeric_limits<double>::infinity();
    for (const std::uint32_t t : _bucketTriangles[static_cast<std::size_t>(y * _buckets + x)]) {
        const glm::dvec3 a(vertices[_data->indices[3 * t]]);
        const glm::dvec3 b(vertices[_data->indices[3 * t + 1]]);
        const glm::dvec3 c(vertices[_data->indices[3 * t + 2]]);
        const double area = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
        if (area == 0.0) {
            continue;
        }
        const double wa = ((b.x - u) * (c.y - v) - (c.x - u) * (b.y - v)) / area;
        const double wb = ((c.x - u) * (a.y - v) - (a.x - u) * (c.y - v)) / area;
        const double wc = 1.0 - wa - wb;
        const double outside = -std::min({wa, wb, wc});
        if (outside <= 1e-9) {
            return wa * a.z + wb * b.z + wc * c.z;
        }
        // A point in no triangle (rounding at an edge): the nearest triangle's plane.
        if (outside < nearestOutside) {
            nearestOutside = outside;
            nearest = wa * a.z + wb * b.z + wc * c.z;
        }
    }
    return nearest;
}

std::vector<float> TerrainSampler::latticeHeights(const TileKey& key, int samplesLog2) const
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
    std::vector<float> heights(static_cast<std::size_t>(size) * size);
    for (int j = 0; j < size; ++j) {
        for (int i = 0; i < size; ++i) {
            heights[static_cast<std::size_t>(j) * size + i] =
                static_cast<float>(height(us[static_cast<std::size_t>(i)], vs[static_cast<std::size_t>(j)]));
        }
    }
    return heights;
}

} // namespace orbis::scene
