#pragma once

#include <orbis/core/TileKey.h>
#include "orbis/world/TerrainSource.h"

#include <array>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

namespace orbis::world {

/// Heights (and the data's normals, where it has them) anywhere in one terrain tile of the
/// geographic scheme: bilinear between a grid's samples, or on the triangle of a mesh
/// (quantized-mesh) that holds the point.
///
/// Positions are given as a sample of a finer (or equal) lattice, so that a point that two tiles
/// share, or a child and the data tile it is cut from, is the same pair of doubles and gets the
/// same height: exactly the data's sample where the lattices meet.
class TerrainSampler {
public:
    explicit TerrainSampler(std::shared_ptr<const TerrainTileData> data);

    const TerrainTileData& data() const noexcept { return *_data; }
    /// What it holds in memory: the data and its index over the triangles.
    std::size_t memoryBytes() const noexcept;

    /// The height at u (0 west .. 1 east) and v (0 south .. 1 north) of the data tile; a point of
    /// a mesh in no triangle (a rounding at an edge) takes the plane of the nearest.
    double height(double u, double v) const noexcept;
    /// The same, trying first the triangles `hints` name (~0u: none), in order, and leaving the
    /// one found in hints[0]: a point asked for in order along a row mostly shares a triangle with
    /// the last one, or with the one a row before (clipmap posts).
    double height(double u, double v, std::array<std::uint32_t, 2>& hints) const noexcept;
    /// The same, but none for a mesh point farther than a rounding outside every triangle (a mesh
    /// that does not cover its tile).
    std::optional<double> heightOnTriangles(double u, double v) const noexcept;

    /// The heights of sample (i, j) (column from the west, row from the north) of the
    /// (2^samplesLog2 + 1)^2 lattice of `key`, a descendant of (or the same as) the data's tile.
    std::vector<float> latticeHeights(const TileKey& key, int samplesLog2) const;

    /// The data's unit normals (Earth-fixed) interpolated to the same lattice, three floats a
    /// sample; empty when the data has none. Tiles sharing an edge interpolate the same data there,
    /// so their shading meets without a seam (a tile's own height differences cannot see across
    /// its edge).
    std::vector<float> latticeNormals(const TileKey& key, int samplesLog2) const;

    /// The data's water mask (quantized-mesh's extension) over `key`, a descendant of (or the same
    /// as) the data's tile: size x size values, 0 land to 255 water, rows from the south (as a
    /// texture's rows go), nearest texel of the data's mask at each value's centre. Size 0 when the
    /// data has no mask; 1 when the mask is the same over the whole of `key`.
    struct WaterMask {
        int size = 0;
        std::vector<std::uint8_t> values;
    };
    WaterMask waterMask(const TileKey& key) const;

private:
    /// The data samples or vertices around a point and their weights (summing to 1).
    struct Weights {
        std::array<std::uint32_t, 4> index{};
        std::array<double, 4> weight{};
        int count = 0;
        double outside = 0.0; ///< how far outside its triangle (the most negative weight, negated)
    };
    double heightOf(const Weights& weights) const noexcept;
    Weights weightsAt(double u, double v) const noexcept;
    Weights gridWeights(double u, double v) const noexcept;
    Weights meshWeights(double u, double v) const noexcept;
    /// Through the buckets: the triangle holding (u, v), or for a point in none (a rounding at an
    /// edge) the nearest; ~0u when the bucket has no triangle that is not degenerate.
    std::uint32_t triangleAt(double u, double v) const noexcept;
    /// Triangle t's weights at (u, v); count 0 for a degenerate triangle.
    Weights triangleWeights(std::uint32_t t, double u, double v) const noexcept;
    /// The lattice's u (west to east) and v (north to south) coordinates within the data tile.
    std::pair<std::vector<double>, std::vector<double>> latticeCoordinates(const TileKey& key, int samplesLog2) const;

    std::shared_ptr<const TerrainTileData> _data;
    /// Meshes: the triangles over each bucket of a buckets x buckets grid over the tile, bucket
    /// b's at [_bucketStart[b], _bucketStart[b + 1]) of _bucketTriangles.
    int _buckets = 0;
    std::vector<std::uint32_t> _bucketStart;
    std::vector<std::uint32_t> _bucketTriangles;
    /// Meshes: each triangle's first two barycentric weights as planes in (u, v), w = a u + b v + c
    /// (the third is 1 minus both): a point's weights without a division (clipmap posts ask for
    /// many). A degenerate triangle's are all zero. With its corners' heights, so that a height in
    /// a hinted triangle reads one cache line.
    struct WeightPlanes {
        std::array<double, 3> first, second;
        std::array<float, 3> heights;

        /// The three weights at (u, v); false for a degenerate triangle.
        bool weights(double u, double v, std::array<double, 3>& w) const noexcept
        {
            if (first[0] == 0.0 && first[1] == 0.0 && first[2] == 0.0) {
                return false;
            }
            w[0] = first[0] * u + first[1] * v + first[2];
            w[1] = second[0] * u + second[1] * v + second[2];
            w[2] = 1.0 - w[0] - w[1];
            return true;
        }
    };
    std::vector<WeightPlanes> _weightPlanes;
};

} // namespace orbis::world
