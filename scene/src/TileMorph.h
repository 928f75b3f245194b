#pragma once

// Where a point of one tile's grid lies on another tile's drawn surface, and the morph that moves a
// tile from the surface drawn before it (an ancestor's or finer tiles') to its own over frames (book 14.4).

#include <orbis/core/TileKey.h>
#include <orbis/core/TileMesh.h>
#include <orbis/core/TilingScheme.h>

#include <glm/vec2.hpp>

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

namespace orbis::scene::detail {

/// Grid coordinates (column from the west, row from the north, in grid steps) in tile `in` of
/// grid vertex (i, j) of tile `of`, at the same level or finer: exact, all steps being powers of
/// two. Columns wrap at the antimeridian (`columns`: the tiles of in's level along it), so a
/// neighbour across it gets coordinates on its own edge.
glm::dvec2 gridCoordinatesIn(const TileKey& of, int i, int j, const TileKey& in, int samplesLog2,
                             std::uint32_t columns) noexcept;

/// A point of a tile's grid on one of its drawn triangles: the triangle's vertices (grid indices)
/// and the point's barycentric weights.
struct TrianglePoint {
    std::array<std::uint32_t, 3> vertices{};
    std::array<double, 3> weights{};
};

/// The triangle of `triangles` (TileMesh::indices without a skirt, for a grid of size x size)
/// that holds grid coordinates (column, row), clamped into the tile; none only for a malformed list.
std::optional<TrianglePoint> drawnTriangleAt(int size, std::span<const std::uint32_t> triangles, double column,
                                             double row);

/// The surface a tile drew at a point: its height and, where the tile has them, its normal.
struct SurfaceSample {
    double height = 0.0;
    std::optional<glm::dvec3> normal;
};

/// The sample of `mesh`'s drawn triangles (`triangles`, as for drawnTriangleAt; `normals`: three
/// floats per grid vertex, or none) at grid coordinates (column, row).
std::optional<SurfaceSample> sampleDrawnSurface(const TileMesh& mesh, std::span<const std::uint32_t> triangles,
                                                std::span<const float> normals, double column, double row);

/// A tile on its way from the surface drawn before it over its ground (factor 0: an ancestor's,
/// or finer tiles') to its own (factor 1).
struct TileMorph {
    std::uint64_t firstFrame = 0;
    std::vector<float> fromHeights; ///< per grid vertex, row by row from the north
    std::vector<float> fromNormals; ///< three per grid vertex; both empty without normals
    std::vector<float> ownNormals;
    /// Three per grid vertex: the ellipsoid's normal at its longitude and latitude, the line a
    /// vertex moves along as its height changes.
    std::vector<float> up;
    double fromMinimumHeight = 0.0;
    double fromMaximumHeight = 0.0;

    /// Starts at `frame` from the surface `drawnBefore` gives at each of `tile`'s grid vertices
    /// (column, row); where it gives none, the vertex starts where it is to end.
    static TileMorph start(const TilingScheme& scheme, const TileMesh& tile, std::span<const float> ownNormals,
                           const std::function<std::optional<SurfaceSample>(int, int)>& drawnBefore,
                           std::uint64_t frame);
    /// Moves the tile's inner grid vertices (not its edges, which the stitching puts back) to
    /// their heights at a factor, along `up` from where they are: no trigonometry a frame.
    void moveInnerVertices(TileMesh& mesh, std::span<const float> own, double factor) const;

    /// 0 on its first frame, rising linearly to 1 `frames` frames later.
    double factor(std::uint64_t frame, int frames) const noexcept;
    /// Grid vertex v's height at a factor, between the surface before and `own`.
    double height(std::size_t vertex, std::span<const float> own, double factor) const noexcept;
    /// The grid's unit normals at a factor (empty without normals).
    std::vector<float> normals(double factor) const;
    std::size_t byteSize() const noexcept
    {
        return (fromHeights.size() + fromNormals.size() + ownNormals.size() + up.size()) * sizeof(float);
    }
};

} // namespace orbis::scene::detail
