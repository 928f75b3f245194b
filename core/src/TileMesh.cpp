#include "orbis/core/TileMesh.h"

#include "GeodeticGrid.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace orbis {

namespace {

/// The skirt's source vertices: the grid's edge indices in the order the header gives.
std::vector<std::uint32_t> edgeRing(int columns, int rows)
{
    std::vector<std::uint32_t> ring;
    ring.reserve(static_cast<std::size_t>(2 * (columns + rows)));
    auto at = [columns](int i, int j) { return static_cast<std::uint32_t>(j * columns + i); };
    for (int i = 0; i < columns; ++i) {
        ring.push_back(at(i, 0)); // north, west to east
    }
    for (int j = 0; j < rows; ++j) {
        ring.push_back(at(columns - 1, j)); // east, north to south
    }
    for (int i = columns - 1; i >= 0; --i) {
        ring.push_back(at(i, rows - 1)); // south, east to west
    }
    for (int j = rows - 1; j >= 0; --j) {
        ring.push_back(at(0, j)); // west, south to north
    }
    return ring;
}

} // namespace

TileMesh TileMesh::build(const Ellipsoid& ellipsoid, const GeodeticExtent& extent, int columns, int rows,
                         std::span<const float> heights, double skirtDepth)
{
    assert(columns >= 2 && rows >= 2);
    assert(heights.empty() || heights.size() == static_cast<std::size_t>(columns) * rows);
    TileMesh mesh;
    mesh.columns = columns;
    mesh.rows = rows;
    mesh.skirt = skirtDepth > 0.0;
    mesh.centre = ellipsoid.toCartesian(extent.centre());

    const GeodeticGrid grid(ellipsoid, extent, columns, rows);
    const std::size_t skirtVertices = mesh.skirt ? static_cast<std::size_t>(2 * (columns + rows)) : 0;
    mesh.vertices.resize((static_cast<std::size_t>(columns) * rows + skirtVertices) * kFloatsPerVertex);
    double lowest = std::numeric_limits<double>::infinity();
    double highest = -std::numeric_limits<double>::infinity();
    std::vector<glm::dvec3> normals(static_cast<std::size_t>(columns) * rows);
    for (int j = 0; j < rows; ++j) {
        for (int i = 0; i < columns; ++i) {
            const std::size_t index = static_cast<std::size_t>(j) * columns + i;
            const glm::dvec3 n = grid.normal(i, j);
            const double height = heights.empty() ? 0.0 : static_cast<double>(heights[index]);
            const glm::dvec3 p = grid.surface(n) + height * n - mesh.centre;
            float* v = &mesh.vertices[index * kFloatsPerVertex];
            v[0] = static_cast<float>(p.x);
            v[1] = static_cast<float>(p.y);
            v[2] = static_cast<float>(p.z);
            v[3] = static_cast<float>(static_cast<double>(i) / (columns - 1));
            v[4] = static_cast<float>(1.0 - static_cast<double>(j) / (rows - 1));
            v[5] = static_cast<float>(height);
            normals[index] = n;
            lowest = std::min(lowest, height);
            highest = std::max(highest, height);
        }
    }
    mesh.minimumHeight = lowest;
    mesh.maximumHeight = highest;

    if (mesh.skirt) {
        const std::vector<std::uint32_t> ring = edgeRing(columns, rows);
        float* out = &mesh.vertices[static_cast<std::size_t>(columns) * rows * kFloatsPerVertex];
        for (const std::uint32_t source : ring) {
            const float* v = &mesh.vertices[source * kFloatsPerVertex];
            const glm::dvec3 lowered = glm::dvec3(v[0], v[1], v[2]) - skirtDepth * normals[source];
            out[0] = static_cast<float>(lowered.x);
            out[1] = static_cast<float>(lowered.y);
            out[2] = static_cast<float>(lowered.z);
            out[3] = v[3];
            out[4] = v[4];
            out[5] = static_cast<float>(static_cast<double>(v[5]) - skirtDepth);
            out += kFloatsPerVertex;
        }
    }
    return mesh;
}

std::vector<std::uint32_t> TileMesh::indices(int columns, int rows, bool skirt)
{
    assert(columns >= 2 && rows >= 2);
    std::vector<std::uint32_t> result;
    const std::size_t quads = static_cast<std::size_t>(columns - 1) * (rows - 1) + (skirt ? 2 * (columns + rows) : 0);
    result.reserve(quads * 6);
    // Rows run north to south and columns west to east, so seen from above (x east, y north) the
    // counter-clockwise order of a quad's corners is south-west, south-east, north-east, north-west.
    auto quad = [&result](std::uint32_t northWest, std::uint32_t northEast, std::uint32_t southWest,
                          std::uint32_t southEast) {
        result.insert(result.end(), {southWest, southEast, northEast, southWest, northEast, northWest});
    };
    for (int j = 0; j + 1 < rows; ++j) {
        for (int i = 0; i + 1 < columns; ++i) {
            const auto northWest = static_cast<std::uint32_t>(j * columns + i);
            const auto southWest = static_cast<std::uint32_t>((j + 1) * columns + i);
            quad(northWest, northWest + 1, southWest, southWest + 1);
        }
    }
    if (skirt) {
        // The ring runs clockwise seen from above (north edge eastwards first); each edge vertex and
        // the next, with their skirt copies below, make a wall, counter-clockwise seen from outside.
        const std::vector<std::uint32_t> ring = edgeRing(columns, rows);
        const auto first = static_cast<std::uint32_t>(columns * rows);
        for (std::size_t k = 0; k + 1 < ring.size(); ++k) {
            if (ring[k] == ring[k + 1]) {
                continue; // a corner ends one edge and starts the next: no wall to itself
            }
            const std::uint32_t top0 = ring[k];
            const std::uint32_t top1 = ring[k + 1];
            const auto bottom0 = static_cast<std::uint32_t>(first + k);
            const auto bottom1 = static_cast<std::uint32_t>(first + k + 1);
            result.insert(result.end(), {top0, bottom1, bottom0, top0, top1, bottom1});
        }
    }
    return result;
}

} // namespace orbis
