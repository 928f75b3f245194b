#pragma once

#include "orbis/core/Ellipsoid.h"
#include "orbis/core/TileKey.h"
#include "orbis/core/TilingScheme.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace orbis {

/// How many levels coarser the tile drawn across each edge of a tile is (0: the same level or
/// finer). A tile drops the edge vertices its coarser neighbour does not have, so that the two
/// share every edge: no T-junction, no crack, with no skirt.
struct EdgeCoarsening {
    int north = 0;
    int east = 0;
    int south = 0;
    int west = 0;

    friend bool operator==(const EdgeCoarsening&, const EdgeCoarsening&) = default;
};

/// The vertices of one tile of the globe's surface: a grid of (2^k + 1) x (2^k + 1) samples over
/// a geographic tile, lifted by heights along the ellipsoid's normal, with an optional skirt (the
/// edge vertices again, hanging below, hiding cracks where tiles do not stitch).
///
/// Positions are Earth-fixed doubles split into two floats each (EmulatedDVec3), drawn relative
/// to the eye on the GPU (book 5.4): no jitter, and a point shared by two tiles is computed from
/// the same longitude, latitude and height (the longitudes and latitudes of level + k edges of the
/// tiling scheme) into the same floats in both, so both tiles transform it to the same clip
/// position and rasterise without a gap between them.
///
/// Each vertex is kFloatsPerVertex floats: position high (3), position low (3), u and v (0..1
/// west to east and south to north within the tile) and the height in metres. Grid vertex (i, j)
/// (column i from the west, row j from the north) is at index j * size + i; the skirt's follow,
/// one per grid edge vertex: the north edge west to east, the east edge north to south, the
/// south edge east to west and the west edge south to north (corners once per edge).
struct TileMesh {
    static constexpr int kFloatsPerVertex = 9;

    TileKey key;
    int samplesLog2 = 0;        ///< k: 2^k + 1 samples along each side
    bool skirt = false;
    double skirtDepth = 0.0;    ///< metres below its edge vertex each skirt vertex hangs
    std::vector<float> vertices;
    double minimumHeight = 0.0; ///< of the grid, not the skirt
    double maximumHeight = 0.0;

    int size() const noexcept { return (1 << samplesLog2) + 1; }
    std::size_t vertexCount() const noexcept { return vertices.size() / kFloatsPerVertex; }
    std::size_t byteSize() const noexcept { return vertices.size() * sizeof(float); }
    /// The Earth-fixed position of a vertex, as the GPU receives it (high + low).
    glm::dvec3 position(std::size_t vertex) const noexcept;

    /// Builds the mesh of a tile of a geographic scheme. samplesLog2 in 1..8 with key.level +
    /// samplesLog2 <= kMaximumTileLevel (asserted). heights: size() x size() metres, row 0 the
    /// north edge, or empty for the ellipsoid itself. skirtDepth > 0 adds a skirt that deep.
    /// Poles need no special case: a row on a pole puts all its vertices on one point.
    static TileMesh build(const Ellipsoid& ellipsoid, const TilingScheme& scheme, const TileKey& key, int samplesLog2,
                          std::span<const float> heights, double skirtDepth);

    /// The longitude of column i and latitude of row j of a tile's samples (the edges of level +
    /// samplesLog2): the same doubles in every tile that has the point.
    static double latticeLongitude(const TilingScheme& scheme, const TileKey& key, int samplesLog2, int column) noexcept;
    static double latticeLatitude(const TilingScheme& scheme, const TileKey& key, int samplesLog2, int row) noexcept;

    /// Moves grid vertex (i, j) to another height, computed as build() computes it (a tile that
    /// takes its edge from a coarser neighbour gets the neighbour's floats exactly).
    void setVertexHeight(const Ellipsoid& ellipsoid, const TilingScheme& scheme, int i, int j, double height);
    /// Puts grid vertex (i, j) at a position (on a coarser neighbour's edge between its vertices).
    void setVertexPosition(int i, int j, const glm::dvec3& position, double height);
    /// Hangs each skirt vertex skirtDepth below its edge vertex's height again, after edge
    /// vertices moved (computed as build() computes them: the same floats as a mesh built with
    /// the edges' heights). Nothing without a skirt.
    void hangSkirt(const Ellipsoid& ellipsoid, const TilingScheme& scheme);

    /// Unit normals of the surface, three floats per vertex: the cross product of the east-west
    /// and north-south differences of the grid's positions (one-sided at the edges, the axis at a
    /// pole's collapsed row); skirt vertices take their edge vertex's.
    std::vector<float> normals() const;
    /// Normals given for the grid (three floats per grid vertex, row by row from the north),
    /// extended to the skirt vertices as normals() extends its own.
    std::vector<float> normals(std::vector<float> gridNormals) const;

    /// The counter-clockwise triangles (seen from above) of a mesh of 2^samplesLog2 + 1 samples a
    /// side: the inner grid as quads, and a ring of triangles zipping each edge's vertices (every
    /// 2^coarsening-th one; clamped to the side) to the row inside it. One list serves every tile
    /// with the same coarsening (the course's shared index buffer). With a skirt, each edge's
    /// vertices in use are joined to their skirt copies.
    static std::vector<std::uint32_t> indices(int samplesLog2, const EdgeCoarsening& coarsening, bool skirt);

    /// Where indices() puts each part of the tile, so that a part can be drawn alone: first the
    /// inner grid's quads a row at a time, from the north (quad rows 1 .. 2^samplesLog2 - 2, between
    /// vertex rows j and j + 1, their quads from the west), then the ring an edge at a time (north,
    /// east, south, west), each edge with its skirt.
    struct IndexLayout {
        static constexpr std::size_t kQuadIndices = 6; ///< a quad of the inner grid: two triangles
        std::size_t innerRowQuads = 0;   ///< quads in a row of the inner grid, as many rows
        std::size_t ringFirst = 0;       ///< the inner grid's indices: where the ring starts
        std::size_t edgeIndices[4] = {}; ///< the ring's north, east, south and west edges' indices
        /// Every index: indices().size().
        std::size_t indexCount() const noexcept
        {
            return ringFirst + edgeIndices[0] + edgeIndices[1] + edgeIndices[2] + edgeIndices[3];
        }
    };
    static IndexLayout indexLayout(int samplesLog2, const EdgeCoarsening& coarsening, bool skirt) noexcept;
};

} // namespace orbis
