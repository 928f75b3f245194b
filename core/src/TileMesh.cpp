#include "orbis/core/TileMesh.h"

#include "orbis/core/EmulatedDouble.h"

#include "GeodeticGrid.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cassert>
#include <limits>

namespace orbis {

namespace {

enum Edge { North, East, South, West };

/// Grid index of the vertex at walking position w along an edge (0 at the edge's first corner,
/// edges walked clockwise seen from above), `inset` rows or columns inside the edge.
std::uint32_t edgeVertex(Edge edge, int size, int w, int inset)
{
    int i = 0;
    int j = 0;
    switch (edge) {
    case North: i = w; j = inset; break;
    case East: i = size - 1 - inset; j = w; break;
    case South: i = size - 1 - w; j = size - 1 - inset; break;
    case West: i = inset; j = size - 1 - w; break;
    }
    return static_cast<std::uint32_t>(j * size + i);
}

/// One vertex's floats: position high and low, u, v, height.
void writeVertex(float* v, const glm::dvec3& position, int i, int j, int size, double height)
{
    const EmulatedDVec3 split = EmulatedDVec3::fromDVec3(position);
    v[0] = split.high.x;
    v[1] = split.high.y;
    v[2] = split.high.z;
    v[3] = split.low.x;
    v[4] = split.low.y;
    v[5] = split.low.z;
    v[6] = static_cast<float>(static_cast<double>(i) / (size - 1));
    v[7] = static_cast<float>(1.0 - static_cast<double>(j) / (size - 1));
    v[8] = static_cast<float>(height);
}

} // namespace

// The sample lines are the edges of level + k: the same doubles in every tile that has them.
double TileMesh::latticeLongitude(const TilingScheme& scheme, const TileKey& key, int samplesLog2, int column) noexcept
{
    const std::uint32_t fineLevel = key.level + static_cast<std::uint32_t>(samplesLog2);
    const double longitude = scheme.edgeLongitude(fineLevel, (key.x << samplesLog2) + static_cast<std::uint32_t>(column));
    // 180 degrees east is the same meridian as 180 west, whose sine has the other sign in its last
    // bit: one of them, so tiles on both sides of the antimeridian meet exactly.
    return longitude == kPi ? -kPi : longitude;
}

double TileMesh::latticeLatitude(const TilingScheme& scheme, const TileKey& key, int samplesLog2, int row) noexcept
{
    const std::uint32_t fineLevel = key.level + static_cast<std::uint32_t>(samplesLog2);
    const std::uint32_t northRow = (key.y + 1) << samplesLog2; // geographic rows count from the south
    return scheme.edgeLatitude(fineLevel, northRow - static_cast<std::uint32_t>(row));
}

void TileMesh::setVertexHeight(const Ellipsoid& ellipsoid, const TilingScheme& scheme, int i, int j, double height)
{
    const GeodeticGrid point(ellipsoid, {latticeLongitude(scheme, key, samplesLog2, i)},
                             {latticeLatitude(scheme, key, samplesLog2, j)});
    const glm::dvec3 n = point.normal(0, 0);
    writeVertex(&vertices[static_cast<std::size_t>(j * size() + i) * kFloatsPerVertex], point.surface(n) + height * n, i,
                j, size(), height);
}

void TileMesh::setVertexPosition(int i, int j, const glm::dvec3& position, double height)
{
    writeVertex(&vertices[static_cast<std::size_t>(j * size() + i) * kFloatsPerVertex], position, i, j, size(), height);
}

glm::dvec3 TileMesh::position(std::size_t vertex) const noexcept
{
    const float* v = &vertices[vertex * kFloatsPerVertex];
    return glm::dvec3(v[0], v[1], v[2]) + glm::dvec3(v[3], v[4], v[5]);
}

TileMesh TileMesh::build(const Ellipsoid& ellipsoid, const TilingScheme& scheme, const TileKey& key, int samplesLog2,
                         std::span<const float> heights, double skirtDepth)
{
    assert(scheme.projection() == TilingProjection::Geographic);
    assert(samplesLog2 >= 1 && samplesLog2 <= 8 && key.level + samplesLog2 <= kMaximumTileLevel);
    TileMesh mesh;
    mesh.key = key;
    mesh.samplesLog2 = samplesLog2;
    mesh.skirt = skirtDepth > 0.0;
    const int size = mesh.size();
    assert(heights.empty() || heights.size() == static_cast<std::size_t>(size) * size);

    std::vector<double> longitudes(size);
    std::vector<double> latitudes(size);
    for (int k = 0; k < size; ++k) {
        longitudes[k] = latticeLongitude(scheme, key, samplesLog2, k);
        latitudes[k] = latticeLatitude(scheme, key, samplesLog2, k);
    }
    const GeodeticGrid grid(ellipsoid, longitudes, latitudes);

    const std::size_t gridVertices = static_cast<std::size_t>(size) * size;
    const std::size_t skirtVertices = mesh.skirt ? static_cast<std::size_t>(4 * size) : 0;
    mesh.vertices.resize((gridVertices + skirtVertices) * kFloatsPerVertex);
    double lowest = std::numeric_limits<double>::infinity();
    double highest = -std::numeric_limits<double>::infinity();
    auto write = [&](std::size_t index, const glm::dvec3& p, int i, int j, double height) {
        writeVertex(&mesh.vertices[index * kFloatsPerVertex], p, i, j, size, height);
    };
    for (int j = 0; j < size; ++j) {
        for (int i = 0; i < size; ++i) {
            const std::size_t index = static_cast<std::size_t>(j) * size + i;
            const glm::dvec3 n = grid.normal(i, j);
            const double height = heights.empty() ? 0.0 : static_cast<double>(heights[index]);
            write(index, grid.surface(n) + height * n, i, j, height);
            lowest = std::min(lowest, height);
            highest = std::max(highest, height);
        }
    }
    mesh.minimumHeight = lowest;
    mesh.maximumHeight = highest;

    if (mesh.skirt) {
        mesh.skirtDepth = skirtDepth;
        std::size_t out = gridVertices;
        for (const Edge edge : {North, East, South, West}) {
            for (int w = 0; w < size; ++w, ++out) {
                const std::uint32_t source = edgeVertex(edge, size, w, 0);
                const int i = static_cast<int>(source) % size;
                const int j = static_cast<int>(source) / size;
                const glm::dvec3 n = grid.normal(i, j);
                const double height = (heights.empty() ? 0.0 : static_cast<double>(heights[source])) - skirtDepth;
                write(out, grid.surface(n) + height * n, i, j, height);
            }
        }
    }
    return mesh;
}

void TileMesh::hangSkirt(const Ellipsoid& ellipsoid, const TilingScheme& scheme)
{
    if (!skirt) {
        return;
    }
    const int n = size();
    std::size_t out = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
    for (const Edge edge : {North, East, South, West}) {
        for (int w = 0; w < n; ++w, ++out) {
            const std::uint32_t source = edgeVertex(edge, n, w, 0);
            const int i = static_cast<int>(source) % n;
            const int j = static_cast<int>(source) / n;
            const GeodeticGrid point(ellipsoid, {latticeLongitude(scheme, key, samplesLog2, i)},
                                     {latticeLatitude(scheme, key, samplesLog2, j)});
            const glm::dvec3 normal = point.normal(0, 0);
            const double height = static_cast<double>(vertices[source * kFloatsPerVertex + 8]) - skirtDepth;
            writeVertex(&vertices[out * kFloatsPerVertex], point.surface(normal) + height * normal, i, j, n, height);
        }
    }
}

std::vector<float> TileMesh::normals() const
{
    const TileMesh& mesh = *this;
    const int size = mesh.size();
    const std::size_t grid = static_cast<std::size_t>(size) * size;
    std::vector<float> normals(grid * 3);
    std::vector<glm::dvec3> positions(grid);
    for (std::size_t v = 0; v < grid; ++v) {
        positions[v] = mesh.position(v);
    }
    auto at = [&](int i, int j) -> const glm::dvec3& { return positions[static_cast<std::size_t>(j * size + i)]; };
    for (int j = 0; j < size; ++j) {
        for (int i = 0; i < size; ++i) {
            const glm::dvec3 east = at(std::min(i + 1, size - 1), j) - at(std::max(i - 1, 0), j);
            const glm::dvec3 north = at(i, std::max(j - 1, 0)) - at(i, std::min(j + 1, size - 1));
            glm::dvec3 n = glm::cross(east, north);
            const double length = glm::length(n);
            // A pole's row collapses to a point: its normal is the axis.
            n = length > 0.0 ? n / length : glm::normalize(at(i, j));
            const std::size_t index = static_cast<std::size_t>(j * size + i);
            normals[3 * index] = static_cast<float>(n.x);
            normals[3 * index + 1] = static_cast<float>(n.y);
            normals[3 * index + 2] = static_cast<float>(n.z);
        }
    }
    return this->normals(std::move(normals));
}

std::vector<float> TileMesh::normals(std::vector<float> normals) const
{
    const int size = this->size();
    const std::size_t grid = static_cast<std::size_t>(size) * size;
    assert(normals.size() == grid * 3);
    normals.resize(vertexCount() * 3);
    // Skirt vertices copy the normal of the edge vertex above them, in TileMesh's order: the north
    // edge west to east, the east edge north to south, the south edge east to west, the west edge
    // south to north.
    std::size_t out = grid;
    for (int edge = 0; edge < 4 && out < vertexCount(); ++edge) {
        for (int w = 0; w < size; ++w, ++out) {
            const int i = edge == 0 ? w : edge == 1 ? size - 1 : edge == 2 ? size - 1 - w : 0;
            const int j = edge == 0 ? 0 : edge == 1 ? w : edge == 2 ? size - 1 : size - 1 - w;
            std::copy_n(&normals[3 * static_cast<std::size_t>(j * size + i)], 3, &normals[3 * out]);
        }
    }
    return normals;
}

TileMesh::IndexLayout TileMesh::indexLayout(int samplesLog2, const EdgeCoarsening& coarsening, bool skirt) noexcept
{
    const std::size_t quads = std::size_t{1} << samplesLog2; // a side
    IndexLayout layout;
    layout.innerRowQuads = quads - 2;
    layout.ringFirst = IndexLayout::kQuadIndices * layout.innerRowQuads * layout.innerRowQuads;
    const std::array<int, 4> levels{coarsening.north, coarsening.east, coarsening.south, coarsening.west};
    for (std::size_t edge = 0; edge < 4; ++edge) {
        // As indices() zips them: a triangle for each outer and each inner segment, and a skirt's
        // two for each outer one.
        const std::size_t outerSegments = quads / std::min(std::size_t{1} << std::min(std::max(levels[edge], 0), 30), quads);
        layout.edgeIndices[edge] = 3 * (outerSegments + quads - 2) + (skirt ? 6 * outerSegments : 0);
    }
    return layout;
}

std::vector<std::uint32_t> TileMesh::indices(int samplesLog2, const EdgeCoarsening& coarsening, bool skirt)
{
    assert(samplesLog2 >= 1 && samplesLog2 <= 8);
    const int size = (1 << samplesLog2) + 1;
    std::vector<std::uint32_t> result;
    result.reserve(static_cast<std::size_t>(6 * (size - 1) * (size - 1) + (skirt ? 24 * size : 0)));
    auto at = [size](int i, int j) { return static_cast<std::uint32_t>(j * size + i); };

    // The inner grid: quads between rows and columns 1 .. size - 2, counter-clockwise from above
    // (x east, y north): south-west, south-east, north-east, then north-west.
    for (int j = 1; j + 2 < size; ++j) {
        for (int i = 1; i + 2 < size; ++i) {
            const std::uint32_t northWest = at(i, j);
            const std::uint32_t northEast = at(i + 1, j);
            const std::uint32_t southWest = at(i, j + 1);
            const std::uint32_t southEast = at(i + 1, j + 1);
            result.insert(result.end(), {southWest, southEast, northEast, southWest, northEast, northWest});
        }
    }

    // The ring: each edge's vertices in use (the outer list, every step-th) zipped to the row or
    // column inside it (the inner list, positions 1 .. size - 2), advancing whichever list's next
    // vertex comes first along the edge. Each outer and each inner segment appears once, so the ring
    // meets the inner grid and the neighbouring tile edge to edge.
    const std::array<int, 4> levels{coarsening.north, coarsening.east, coarsening.south, coarsening.west};
    for (const Edge edge : {North, East, South, West}) {
        const int step = std::min(1 << std::min(std::max(levels[edge], 0), 30), size - 1);
        std::vector<int> outer;
        for (int w = 0; w < size; w += step) {
            outer.push_back(w);
        }
        std::vector<int> inner;
        for (int w = 1; w + 1 < size; ++w) {
            inner.push_back(w);
        }
        std::size_t o = 0;
        std::size_t p = 0;
        while (o + 1 < outer.size() || p + 1 < inner.size()) {
            const std::uint32_t outerVertex = edgeVertex(edge, size, outer[o], 0);
            const std::uint32_t innerVertex = edgeVertex(edge, size, inner[p], 1);
            const bool advanceInner = o + 1 == outer.size() || (p + 1 < inner.size() && inner[p + 1] <= outer[o + 1]);
            if (advanceInner) {
                result.insert(result.end(), {outerVertex, innerVertex, edgeVertex(edge, size, inner[p + 1], 1)});
                ++p;
            } else {
                result.insert(result.end(), {outerVertex, innerVertex, edgeVertex(edge, size, outer[o + 1], 0)});
                ++o;
            }
        }
        if (skirt) {
            // Walls between consecutive edge vertices in use and their copies below, facing out.
            const auto first = static_cast<std::uint32_t>(size * size + static_cast<int>(edge) * size);
            for (std::size_t k = 0; k + 1 < outer.size(); ++k) {
                const std::uint32_t top0 = edgeVertex(edge, size, outer[k], 0);
                const std::uint32_t top1 = edgeVertex(edge, size, outer[k + 1], 0);
                const std::uint32_t bottom0 = first + static_cast<std::uint32_t>(outer[k]);
                const std::uint32_t bottom1 = first + static_cast<std::uint32_t>(outer[k + 1]);
                result.insert(result.end(), {top0, bottom1, bottom0, top0, top1, bottom1});
            }
        }
    }
    return result;
}

} // namespace orbis
