#pragma once

// Meshes of terrain tiles for the terrain tiler: a grid of heights simplified into a triangle mesh
// whose edges depend only on the edge's own samples (so neighbours agree), normals from the grid,
// and the height a mesh or grid gives at a point, for measuring its error. Private to orbis::world.

#include "orbis/world/TerrainSource.h"

#include <orbis/core/Ellipsoid.h>

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace orbis::world::detail {

/// A size x size grid of heights (row 0 north) simplified into a mesh within `tolerance` metres of
/// every grid sample, vertically: each edge's samples are first reduced on their own (a
/// Douglas-Peucker pass over the edge's profile, the same in both tiles that share the edge), then
/// interior samples are inserted greedily, farthest first, into a Delaunay triangulation of
/// those, until none is farther than the tolerance. Vertices are grid samples (u, v from the
/// grid index, v from the south); triangles counter-clockwise, covering the tile once.
struct SimplifiedMesh {
    std::vector<glm::vec3> vertices;     ///< u, v, height
    std::vector<std::uint32_t> indices;
    std::vector<int> gridIndex;          ///< per vertex: row * size + column of its sample
};
SimplifiedMesh simplifyGrid(std::span<const float> heights, int size, double tolerance);

/// The positions of a tile's size x size grid (terrainGridPosition) with a margin of one sample on
/// every side, row by row from the north: (size + 2)^2, the margin's latitudes held at the poles and
/// its longitudes wrapped across the antimeridian.
std::vector<orbis::Geodetic2D> gridPositionsWithMargin(const orbis::TileKey& key, int size);

/// The size x size grid inside heights with a margin of one sample.
std::vector<float> withoutMargin(std::span<const float> heightsWithMargin, int size);

/// Earth-fixed unit normals of a tile's grid samples, from central differences over a grid with a
/// one-sample margin on every side ((size + 2)^2 heights, row 0 one sample north of the tile), so
/// that a sample on an edge gets the same normal in both tiles that share it.
std::vector<glm::vec3> gridNormals(const orbis::TileKey& key, int size, std::span<const float> heightsWithMargin,
                                   const orbis::Ellipsoid& ellipsoid);

/// The vertical distance from h to a grid's surface at u, v (0..1, v from the south), the larger
/// of the two ways of cutting the grid cell into triangles, so that the measure holds whichever
/// diagonal a renderer draws.
double gridDeviation(std::span<const float> heights, int size, double u, double v, double h) noexcept;

} // namespace orbis::world::detail
