#include "TileMorph.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace orbis::scene::detail {

glm::dvec2 gridCoordinatesIn(const TileKey& of, int i, int j, const TileKey& in, int samplesLog2,
                             std::uint32_t columns) noexcept
{
    const int finer = static_cast<int>(of.level - in.level);
    const double steps = std::ldexp(1.0, samplesLog2);
    // Lattice lines of of's level + samplesLog2, counted from the west and from the south.
    const double west = static_cast<double>(of.x) * steps + i;
    const double south = static_cast<double>(of.y + 1) * steps - j;
    double column = std::ldexp(west, -finer) - static_cast<double>(in.x) * steps;
    const double width = static_cast<double>(columns) * steps;
    if (column > steps) {
        column -= width;
    } else if (column < 0.0) {
        column += width;
    }
    const double row = static_cast<double>(in.y + 1) * steps - std::ldexp(south, -finer);
    return {column, row};
}

std::optional<TrianglePoint> drawnTriangleAt(int size, std::span<const std::uint32_t> triangles, double column,
                                             double row)
{
    column = std::clamp(column, 0.0, size - 1.0);
    row = std::clamp(row, 0.0, size - 1.0);
    auto on = [&](std::size_t first) -> std::optional<TrianglePoint> {
        TrianglePoint point;
        std::array<glm::dvec2, 3> corner;
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t vertex = triangles[first + k];
            point.vertices[k] = vertex;
            corner[k] = {static_cast<double>(vertex % static_cast<std::uint32_t>(size)),
                         static_cast<double>(vertex / static_cast<std::uint32_t>(size))};
        }
        const glm::dvec2 e1 = corner[1] - corner[0];
        const glm::dvec2 e2 = corner[2] - corner[0];
        const glm::dvec2 p = glm::dvec2(column, row) - corner[0];
        const double area = e1.x * e2.y - e2.x * e1.y;
        const double w1 = (p.x * e2.y - e2.x * p.y) / area;
        const double w2 = (e1.x * p.y - p.x * e1.y) / area;
        point.weights = {1.0 - w1 - w2, w1, w2};
        if (std::min({point.weights[0], w1, w2}) < -1e-12) {
            return std::nullopt;
        }
        return point;
    };
    // The inner grid's quads come first, two triangles each; the ring around them after.
    const int inner = size - 3;
    const std::size_t ringStart = static_cast<std::size_t>(6 * inner * inner);
    if (column >= 1.0 && column <= size - 2.0 && row >= 1.0 && row <= size - 2.0) {
        const int i = std::min(static_cast<int>(column), size - 3) - 1;
        const int j = std::min(static_cast<int>(row), size - 3) - 1;
        const std::size_t quad = static_cast<std::size_t>(6 * (j * inner + i));
        if (std::optional<TrianglePoint> point = on(quad)) {
            return point;
        }
        if (std::optional<TrianglePoint> point = on(quad + 3)) {
            return point;
        }
    }
    for (std::size_t first = ringStart; first + 2 < triangles.size(); first += 3) {
        if (std::optional<TrianglePoint> point = on(first)) {
            return point;
        }
    }
    return std::nullopt;
}

std::optional<SurfaceSample> sampleDrawnSurface(const TileMesh& mesh, std::span<const std::uint32_t> triangles,
                                                std::span<const float> normals, double column, double row)
{
    const std::optional<TrianglePoint> point = drawnTriangleAt(mesh.size(), triangles, column, row);
    if (!point) {
        return std::nullopt;
    }
    SurfaceSample sample;
    glm::dvec3 normal(0.0);
    for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t v = point->vertices[k];
        sample.height += point->weights[k] * static_cast<double>(mesh.vertices[v * TileMesh::kFloatsPerVertex + 8]);
        if (!normals.empty()) {
            normal += point->weights[k] * glm::dvec3(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]);
        }
    }
    if (glm::length(normal) > 0.0) {
        sample.normal = glm::normalize(normal);
    }
    return sample;
}

TileMorph TileMorph::start(const TilingScheme& scheme, const TileMesh& tile, std::span<const float> ownNormals,
                           const std::function<std::optional<SurfaceSample>(int, int)>& drawnBefore,
                           std::uint64_t frame)
{
    TileMorph morph;
    morph.firstFrame = frame;
    const int size = tile.size();
    const std::size_t gridVertices = static_cast<std::size_t>(size * size);
    const bool withNormals = !ownNormals.empty();
    morph.fromHeights.reserve(gridVertices);
    if (withNormals) {
        const std::span<const float> grid = ownNormals.first(3 * gridVertices);
        morph.ownNormals.assign(grid.begin(), grid.end());
        morph.fromNormals.reserve(morph.ownNormals.size());
    }
    morph.fromMinimumHeight = std::numeric_limits<double>::infinity();
    morph.fromMaximumHeight = -std::numeric_limits<double>::infinity();
    morph.up.reserve(3 * gridVertices);
    for (int j = 0; j < size; ++j) {
        for (int i = 0; i < size; ++i) {
            const std::size_t v = static_cast<std::size_t>(j * size + i);
            const glm::dvec3 up = Ellipsoid::geodeticSurfaceNormal(
                Geodetic2D{TileMesh::latticeLongitude(scheme, tile.key, tile.samplesLog2, i),
                           TileMesh::latticeLatitude(scheme, tile.key, tile.samplesLog2, j)});
            morph.up.insert(morph.up.end(), {static_cast<float>(up.x), static_cast<float>(up.y), static_cast<float>(up.z)});
            const std::optional<SurfaceSample> before = drawnBefore(i, j);
            const double height =
                before ? before->height : static_cast<double>(tile.vertices[v * TileMesh::kFloatsPerVertex + 8]);
            morph.fromHeights.push_back(static_cast<float>(height));
            morph.fromMinimumHeight = std::min(morph.fromMinimumHeight, height);
            morph.fromMaximumHeight = std::max(morph.fromMaximumHeight, height);
            if (withNormals) {
                const glm::dvec3 own(ownNormals[3 * v], ownNormals[3 * v + 1], ownNormals[3 * v + 2]);
                const glm::dvec3 normal = before && before->normal ? *before->normal : own;
                morph.fromNormals.insert(morph.fromNormals.end(), {static_cast<float>(normal.x), static_cast<float>(normal.y),
                                                                  static_cast<float>(normal.z)});
            }
        }
    }
    return morph;
}

void TileMorph::moveInnerVertices(TileMesh& mesh, std::span<const float> own, double factor) const
{
    const int size = mesh.size();
    for (int j = 1; j + 1 < size; ++j) {
        for (int i = 1; i + 1 < size; ++i) {
            const std::size_t v = static_cast<std::size_t>(j * size + i);
            const double now = static_cast<double>(mesh.vertices[v * TileMesh::kFloatsPerVertex + 8]);
            const double wanted = height(v, own, factor);
            const glm::dvec3 direction(up[3 * v], up[3 * v + 1], up[3 * v + 2]);
            mesh.setVertexPosition(i, j, mesh.position(v) + (wanted - now) * direction, wanted);
        }
    }
}

double TileMorph::factor(std::uint64_t frame, int frames) const noexcept
{
    if (frames <= 0 || frame < firstFrame) {
        return frames <= 0 ? 1.0 : 0.0;
    }
    return std::min(1.0, static_cast<double>(frame - firstFrame) / frames);
}

double TileMorph::height(std::size_t vertex, std::span<const float> own, double factor) const noexcept
{
    const double from = static_cast<double>(fromHeights[vertex]);
    return from + (static_cast<double>(own[vertex]) - from) * factor;
}

std::vector<float> TileMorph::normals(double factor) const
{
    std::vector<float> normals(ownNormals.size());
    for (std::size_t v = 0; v + 2 < ownNormals.size(); v += 3) {
        const glm::dvec3 from(fromNormals[v], fromNormals[v + 1], fromNormals[v + 2]);
        const glm::dvec3 own(ownNormals[v], ownNormals[v + 1], ownNormals[v + 2]);
        const glm::dvec3 mixed = from + (own - from) * factor;
        // Opposite normals never meet here (both face up); the guard keeps a NaN out regardless.
        const glm::dvec3 unit = glm::length(mixed) > 0.0 ? glm::normalize(mixed) : own;
        normals[v] = static_cast<float>(unit.x);
        normals[v + 1] = static_cast<float>(unit.y);
        normals[v + 2] = static_cast<float>(unit.z);
    }
    return normals;
}

} // namespace orbis::scene::detail
