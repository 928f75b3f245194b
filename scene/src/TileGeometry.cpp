#include "TileGeometry.h"

#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>

#include <algorithm>
#include <span>
#include <vector>

namespace orbis::scene::detail {

TileGpuMesh uploadTileMesh(renderer::Context& context, const TileMesh& mesh)
{
    const std::span<const std::byte> bytes = std::as_bytes(std::span(mesh.vertices));
    TileGpuMesh gpu{context.device().createVertexBuffer(bytes), context.createVertexArray(), std::nullopt, bytes.size()};
    constexpr std::size_t stride = TileMesh::kFloatsPerVertex * sizeof(float);
    using renderer::ComponentType;
    namespace location = renderer::VertexAttributeLocation;
    gpu.array.setAttribute(location::PositionHigh, gpu.vertices, {ComponentType::Float, 3, false, false, stride, 0});
    gpu.array.setAttribute(location::PositionLow, gpu.vertices,
                           {ComponentType::Float, 3, false, false, stride, 3 * sizeof(float)});
    gpu.array.setAttribute(location::TextureCoordinate, gpu.vertices,
                           {ComponentType::Float, 3, false, false, stride, 6 * sizeof(float)});
    return gpu;
}

void TileIndexBuffers::bind(renderer::Device& device, TileGpuMesh& mesh, const EdgeCoarsening& coarsening)
{
    if (mesh.coarsening == coarsening) {
        return;
    }
    const std::array<int, 4> name{coarsening.north, coarsening.east, coarsening.south, coarsening.west};
    auto found = _buffers.find(name);
    if (found == _buffers.end()) {
        const std::vector<std::uint32_t> indices = TileMesh::indices(_samplesLog2, coarsening, _skirts);
        if (*std::max_element(indices.begin(), indices.end()) < 65536) { // 17 x 17 and skirts fit 16 bits
            const std::vector<std::uint16_t> narrow(indices.begin(), indices.end());
            found = _buffers.emplace(name, device.createIndexBuffer(std::span<const std::uint16_t>(narrow))).first;
        } else {
            found = _buffers.emplace(name, device.createIndexBuffer(std::span<const std::uint32_t>(indices))).first;
        }
    }
    mesh.array.setIndexBuffer(&found->second);
    mesh.coarsening = coarsening;
}

} // namespace orbis::scene::detail
