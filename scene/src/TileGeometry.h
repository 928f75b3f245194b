#pragma once

// Surface tiles' meshes on the GPU: a TileMesh's vertices in a vertex array, and the index buffers
// shared by every tile of a grid size, one per edge coarsening (the course's shared index buffer).

#include <orbis/core/TileMesh.h>
#include <orbis/renderer/IndexBuffer.h>
#include <orbis/renderer/VertexArray.h>
#include <orbis/renderer/VertexBuffer.h>

#include <array>
#include <cstddef>
#include <map>
#include <optional>

namespace orbis::renderer {
class Context;
class Device;
} // namespace orbis::renderer

namespace orbis::scene::detail {

/// One tile's vertices on the GPU, read by shaders/scene/tiles/tile.vert.glsl.
struct TileGpuMesh {
    renderer::VertexBuffer vertices;
    renderer::VertexArray array;
    std::optional<EdgeCoarsening> coarsening; ///< of the index buffer bound to the array
    std::size_t bytes = 0;
};

/// Uploads the mesh's vertices (positionHigh, positionLow, textureCoordinate); no index buffer yet.
TileGpuMesh uploadTileMesh(renderer::Context& context, const TileMesh& mesh);

/// The index buffers of meshes with 2^samplesLog2 + 1 samples a side, made on first use.
class TileIndexBuffers {
public:
    TileIndexBuffers(int samplesLog2, bool skirts) : _samplesLog2(samplesLog2), _skirts(skirts) {}

    /// Binds the index buffer stitching the mesh to coarser neighbours, when it changed.
    void bind(renderer::Device& device, TileGpuMesh& mesh, const EdgeCoarsening& coarsening);

private:
    int _samplesLog2;
    bool _skirts;
    std::map<std::array<int, 4>, renderer::IndexBuffer> _buffers;
};

} // namespace orbis::scene::detail
