#include "orbis/scene/TiledGlobe.h"

#include "orbis/scene/DepthStrategy.h"
#include "orbis/scene/Effect.h"
#include "orbis/scene/ImageryCoverage.h"
#include "orbis/scene/MercatorReprojection.h"

#include <orbis/core/Error.h>
#include <orbis/core/ImageMipmaps.h>
#include <orbis/core/TileMesh.h>
#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>
#include <orbis/renderer/Framebuffer.h>
#include <orbis/renderer/IndexBuffer.h>
#include <orbis/renderer/Sampler.h>
#include <orbis/renderer/ShaderCache.h>
#include <orbis/renderer/ShaderProgram.h>
#include <orbis/renderer/Texture2D.h>
#include <orbis/renderer/VertexArray.h>
#include <orbis/renderer/VertexBuffer.h>
#include <orbis/world/ImageCodec.h>
#include <orbis/world/TileSource.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <deque>
#include <iostream>
#include <map>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace orbis::scene {

namespace {

/// At most this many imagery tiles of one layer on one surface tile: a coarser level is taken
/// when more would be needed (Web Mercator rows near the poles).
constexpr std::size_t kMaximumTexturesPerLayer = 4;
/// GLSL 3.30 guarantees 16 texture units; the renderer keeps one for uploads.
constexpr int kMaximumTextures = 15;

enum class LoadState : std::uint8_t { Unloaded, Loading, Ready, Missing, Failed };

struct MeshContent final : world::TileContent {
    explicit MeshContent(TileMesh mesh_) : mesh(std::move(mesh_)) {}
    std::size_t byteSize() const noexcept override { return mesh.byteSize(); }
    TileMesh mesh;
};

/// A decoded imagery tile, with its mipmap levels made on the worker (empty for Web Mercator tiles,
/// whose levels are made after their reprojection).
struct ImageContent final : world::TileContent {
    ImageContent(Image image_, std::vector<Image> mipmaps_) : image(std::move(image_)), mipmaps(std::move(mipmaps_)) {}
    std::size_t byteSize() const noexcept override
    {
        std::size_t bytes = image.pixels.size();
        for (const Image& level : mipmaps) {
            bytes += level.pixels.size();
        }
        return bytes;
    }
    Image image;
    std::vector<Image> mipmaps;
};

/// One imagery tile of one layer, shared by every surface tile it covers.
struct ImageryTile {
    LoadState state = LoadState::Unloaded;
    std::shared_ptr<renderer::Texture2D> texture;
    std::size_t bytes = 0;
    std::uint64_t lastUsedFrame = 0;
};

/// A surface tile's data: its mesh on the GPU and, per layer, the imagery tiles it wants.
struct SurfaceTile final : TileData {
    LoadState mesh = LoadState::Unloaded;
    std::optional<renderer::VertexBuffer> vertexBuffer;
    std::optional<renderer::VertexArray> vertexArray;
    std::optional<EdgeCoarsening> coarsening; ///< of the index buffer bound to the vertex array
    std::size_t bytes = 0;
    std::vector<std::vector<TileKey>> imagery; ///< per layer, at the level the tile's error asks for
};

SurfaceTile& surfaceOf(QuadtreeTile& tile)
{
    return static_cast<SurfaceTile&>(*tile.data);
}

/// A texture a drawn tile uses.
struct TextureUse {
    ImageryTile* imagery;
    ImageryPlacement placement;
    int layer;
};

/// What a load is for: a surface tile's mesh (layer -1) or a layer's imagery tile.
struct LoadTarget {
    int layer = -1;
    TileKey key;
    QuadtreeTile* tile = nullptr; ///< meshes only
};

/// A loaded tile waiting for its GPU upload.
struct PendingUpload {
    LoadTarget target;
    std::unique_ptr<world::TileContent> content;
};

std::string keyName(const TileKey& key)
{
    return std::to_string(key.level) + "/" + std::to_string(key.x) + "/" + std::to_string(key.y);
}

} // namespace

struct TiledGlobe::Impl {
    struct Layer {
        ImageryLayer layer;
        ImageryTiling tiling;
        std::unordered_map<TileKey, ImageryTile, TileKeyHash> tiles;
    };

    Impl(const Ellipsoid& ellipsoid_, const TiledGlobeOptions& options_)
        : ellipsoid(ellipsoid_)
        , options(&options_)
        , quadtree(ellipsoid_, TilingScheme::geographic(), 64, [this](QuadtreeTile& tile) { created(tile); })
        , loader(options_.loader)
        , effectiveScreenSpaceError(options_.maximumScreenSpaceError)
    {
    }

    void created(QuadtreeTile& tile);
    void refresh(QuadtreeTile& tile);
    /// The tile to load for a wanted imagery key: the key itself or, where it is missing or failed,
    /// its nearest ancestor not known to be (the parent's imagery stays); empty when none is left.
    std::optional<TileKey> sourceKey(const Layer& layer, const TileKey& key) const;
    /// The texture to draw for an imagery key: its source key's (sourceKey) or the nearest loaded
    /// ancestor's, in `used`; `waiting` when the source key's own is still to come.
    ImageryTile* bestImagery(Layer& layer, const TileKey& key, TileKey& used, bool& waiting);
    std::uint64_t ticketFor(int layer, const TileKey& key);
    void request(const LoadTarget& target, double priority);
    world::TileLoadWork workFor(const LoadTarget& target) const;
    void receive(world::TileLoadResult result, TileStatistics& statistics);
    void upload(FrameState& frameState, PendingUpload pending, TileStatistics& statistics);
    bool makeRoom(std::size_t bytes, std::uint64_t frame, TileStatistics& statistics);
    std::shared_ptr<renderer::Texture2D> reproject(FrameState& frameState, const Layer& layer, const TileKey& key,
                                                   const Image& image);
    renderer::ShaderProgram& program(FrameState& frameState, int textureCount);
    const renderer::IndexBuffer& indexBuffer(FrameState& frameState, const EdgeCoarsening& coarsening);
    std::vector<TextureUse> texturesFor(QuadtreeTile& tile, std::uint64_t frame);
    void warn(const std::string& message) const;
    std::size_t residentBytes() const noexcept { return gpuBytes + cpuBytes; }

    Ellipsoid ellipsoid;
    const TiledGlobeOptions* options = nullptr;
    std::vector<Layer> layers;
    TileQuadtree quadtree;
    world::TileLoader loader;
    std::map<std::pair<int, TileKey>, std::uint64_t> tickets;
    std::unordered_map<std::uint64_t, LoadTarget> targets;
    std::uint64_t nextTicket = 1;
    std::deque<PendingUpload> uploads;
    std::vector<QuadtreeTile*> residentTiles; ///< tiles whose mesh is on the GPU
    std::size_t gpuBytes = 0;
    std::size_t cpuBytes = 0;
    std::size_t failedCount = 0;
    std::size_t missingCount = 0;
    double effectiveScreenSpaceError;
    std::optional<std::uint64_t> streamedFrame;
    bool rootsLoaded = false;

    TileSelection selection;
    std::vector<std::vector<TextureUse>> drawnTextures; ///< parallel to selection.drawn
    std::map<std::pair<int, DepthStrategy>, std::shared_ptr<renderer::ShaderProgram>> programs;
    std::map<std::array<int, 4>, renderer::IndexBuffer> indexBuffers;
    std::optional<renderer::Sampler> sampler;
    std::optional<MercatorReprojection> reprojection;
};

void TiledGlobe::Impl::warn(const std::string& message) const
{
    if (options->onWarning) {
        options->onWarning(message);
    } else {
        std::cerr << "orbis: " << message << "\n";
    }
}

namespace {

/// True for the first layer when it is Web Mercator: beyond its latitude limit its edge rows
/// stretch to the poles, so the globe has no cap of bare base colour.
bool stretchesToPoles(std::size_t layerIndex, const ImageryTiling& tiling)
{
    return layerIndex == 0 && tiling.scheme.projection() == TilingProjection::WebMercator;
}

} // namespace

void TiledGlobe::Impl::created(QuadtreeTile& tile)
{
    auto surface = std::make_unique<SurfaceTile>();
    const GeodeticExtent tileExtent = quadtree.scheme().tileExtent(tile.key);
    for (std::size_t l = 0; l < layers.size(); ++l) {
        const Layer& layer = layers[l];
        GeodeticExtent extent = tileExtent;
        if (stretchesToPoles(l, layer.tiling)) {
            // The edge rows' tiles for what lies beyond the limit: the extent kept within it.
            const GeodeticExtent limit = layer.tiling.scheme.coverage();
            const double band = 1e-9;
            extent.south = std::clamp(extent.south, limit.south, limit.north - band);
            extent.north = std::clamp(extent.north, limit.south + band, limit.north);
            extent.north = std::max(extent.north, extent.south + band);
        }
        std::uint32_t level = imageryLevelFor(layer.tiling, ellipsoid, extent, tile.geometricError);
        std::vector<TileKey> keys = imageryTilesOver(layer.tiling, level, extent);
        while (keys.size() > kMaximumTexturesPerLayer && level > layer.tiling.minimumLevel) {
            keys = imageryTilesOver(layer.tiling, --level, extent);
        }
        if (keys.size() > kMaximumTexturesPerLayer) {
            keys.clear(); // the layer starts deeper than this tile: it shows on finer tiles only
        }
        surface->imagery.push_back(std::move(keys));
    }
    tile.data = std::move(surface);
    tile.renderable = false;
    tile.wantsLoad = true;
    tile.refinable = tile.key.level < kMaximumTileLevel - static_cast<std::uint32_t>(options->samplesLog2);
}

std::optional<TileKey> TiledGlobe::Impl::sourceKey(const Layer& layer, const TileKey& key) const
{
    for (std::uint32_t level = key.level + 1; level-- > layer.tiling.minimumLevel;) {
        const TileKey candidate = key.ancestor(level);
        const auto found = layer.tiles.find(candidate);
        if (found == layer.tiles.end() ||
            (found->second.state != LoadState::Missing && found->second.state != LoadState::Failed)) {
            return candidate;
        }
    }
    return std::nullopt;
}

ImageryTile* TiledGlobe::Impl::bestImagery(Layer& layer, const TileKey& key, TileKey& used, bool& waiting)
{
    const std::optional<TileKey> source = sourceKey(layer, key);
    waiting = source.has_value();
    if (!source) {
        return nullptr; // nothing of this layer covers the key: none will come
    }
    for (std::uint32_t level = source->level + 1; level-- > layer.tiling.minimumLevel;) {
        const TileKey candidate = source->ancestor(level);
        const auto found = layer.tiles.find(candidate);
        if (found != layer.tiles.end() && found->second.state == LoadState::Ready) {
            used = candidate;
            waiting = candidate != *source;
            return &found->second;
        }
    }
    return nullptr;
}

void TiledGlobe::Impl::refresh(QuadtreeTile& tile)
{
    SurfaceTile& surface = surfaceOf(tile);
    bool imageryReady = true;
    bool wants = surface.mesh == LoadState::Unloaded;
    for (std::size_t l = 0; l < layers.size(); ++l) {
        for (const TileKey& key : surface.imagery[l]) {
            if (const std::optional<TileKey> source = sourceKey(layers[l], key)) {
                const auto found = layers[l].tiles.find(*source);
                wants = wants || found == layers[l].tiles.end() || found->second.state == LoadState::Unloaded;
            }
            TileKey used;
            bool waiting = false;
            const ImageryTile* texture = bestImagery(layers[l], key, used, waiting);
            // Drawable with an ancestor's imagery meanwhile, or with none once none will come.
            imageryReady = imageryReady && (texture != nullptr || !waiting);
        }
    }
    tile.renderable = surface.mesh == LoadState::Ready && imageryReady;
    tile.wantsLoad = wants;
}

std::uint64_t TiledGlobe::Impl::ticketFor(int layer, const TileKey& key)
{
    const auto [entry, inserted] = tickets.try_emplace({layer, key}, nextTicket);
    if (inserted) {
        ++nextTicket;
    }
    return entry->second;
}

world::TileLoadWork TiledGlobe::Impl::workFor(const LoadTarget& target) const
{
    if (target.layer < 0) {
        const Ellipsoid shape = ellipsoid;
        const TileKey key = target.key;
        const int samplesLog2 = options->samplesLog2;
        // Skirts as deep as the tile's geometric error: enough to hide any crack the level allows.
        const double skirtDepth = options->skirts ? quadtree.geometricErrorOf(key.level) : 0.0;
        return [shape, key, samplesLog2, skirtDepth]() -> std::unique_ptr<world::TileContent> {
            return std::make_unique<MeshContent>(
                TileMesh::build(shape, TilingScheme::geographic(), key, samplesLog2, {}, skirtDepth));
        };
    }
    const Layer& layer = layers[static_cast<std::size_t>(target.layer)];
    std::shared_ptr<world::TileSource> source = layer.layer.source;
    const bool mipmapsHere = layer.tiling.scheme.projection() == TilingProjection::Geographic;
    const TileKey key = target.key;
    return [source, key, mipmapsHere]() -> std::unique_ptr<world::TileContent> {
        world::TileFetch fetched = source->fetch(key);
        if (fetched.status == world::TileFetch::Status::Missing) {
            return nullptr;
        }
        if (fetched.status == world::TileFetch::Status::Failed) {
            throw Error(fetched.message);
        }
        Image image = world::decodeImage(fetched.bytes, source->locate(key), 4);
        std::vector<Image> mipmaps = mipmapsHere ? mipmapChain(image) : std::vector<Image>{};
        return std::make_unique<ImageContent>(std::move(image), std::move(mipmaps));
    };
}

void TiledGlobe::Impl::request(const LoadTarget& target, double priority)
{
    const std::uint64_t ticket = ticketFor(target.layer, target.key);
    targets[ticket] = target;
    loader.request(ticket, priority, workFor(target));
}

void TiledGlobe::Impl::receive(world::TileLoadResult result, TileStatistics& statistics)
{
    const auto found = targets.find(result.ticket);
    if (found == targets.end()) {
        return;
    }
    const LoadTarget target = found->second;
    targets.erase(found);
    tickets.erase({target.layer, target.key});
    LoadState* state = nullptr;
    std::string where;
    if (target.layer < 0) {
        state = &surfaceOf(*target.tile).mesh;
        where = "surface tile " + keyName(target.key);
    } else {
        Layer& layer = layers[static_cast<std::size_t>(target.layer)];
        state = &layer.tiles[target.key].state;
        where = layer.layer.source->locate(target.key);
    }
    switch (result.status) {
    case world::TileLoadResult::Status::Loaded:
        ++statistics.loadedThisFrame;
        cpuBytes += result.content->byteSize();
        uploads.push_back({target, std::move(result.content)});
        break;
    case world::TileLoadResult::Status::Missing:
        *state = LoadState::Missing;
        ++missingCount;
        break;
    case world::TileLoadResult::Status::Failed:
        *state = LoadState::Failed;
        ++failedCount;
        // Named once: a failed tile is never asked for again, and its parent's data stays drawn.
        warn("tile " + where + " failed, its parent's stays drawn: " + result.message);
        break;
    }
}

bool TiledGlobe::Impl::makeRoom(std::size_t bytes, std::uint64_t frame, TileStatistics& statistics)
{
    if (residentBytes() + bytes <= options->cacheBytes) {
        return true;
    }
    // Least recently used first; nothing used in this frame or the last, no root, no layer's
    // coarsest imagery. Ties by level (deepest first) and key, so that eviction is deterministic.
    struct Candidate {
        std::uint64_t lastUsed;
        std::uint32_t level;
        TileKey key;
        int layer; ///< -1: a surface tile's mesh
        QuadtreeTile* tile;
    };
    std::vector<Candidate> candidates;
    const std::uint64_t protectedSince = frame > 0 ? frame - 1 : 0;
    for (QuadtreeTile* tile : residentTiles) {
        if (tile->key.level > 0 && tile->lastVisitedFrame < protectedSince) {
            candidates.push_back({tile->lastVisitedFrame, tile->key.level, tile->key, -1, tile});
        }
    }
    for (std::size_t l = 0; l < layers.size(); ++l) {
        for (auto& [key, imagery] : layers[l].tiles) {
            if (imagery.state == LoadState::Ready && key.level > layers[l].tiling.minimumLevel &&
                imagery.lastUsedFrame < protectedSince) {
                candidates.push_back({imagery.lastUsedFrame, key.level, key, static_cast<int>(l), nullptr});
            }
        }
    }
    std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
        if (a.lastUsed != b.lastUsed) {
            return a.lastUsed < b.lastUsed;
        }
        if (a.level != b.level) {
            return a.level > b.level;
        }
        if (a.layer != b.layer) {
            return a.layer < b.layer;
        }
        return a.key < b.key;
    });
    for (const Candidate& candidate : candidates) {
        if (residentBytes() + bytes <= options->cacheBytes) {
            break;
        }
        if (candidate.layer < 0) {
            SurfaceTile& surface = surfaceOf(*candidate.tile);
            gpuBytes -= surface.bytes;
            surface.vertexArray.reset();
            surface.vertexBuffer.reset();
            surface.coarsening.reset();
            surface.bytes = 0;
            surface.mesh = LoadState::Unloaded;
            candidate.tile->renderable = false;
            residentTiles.erase(std::find(residentTiles.begin(), residentTiles.end(), candidate.tile));
        } else {
            auto& tiles = layers[static_cast<std::size_t>(candidate.layer)].tiles;
            gpuBytes -= tiles[candidate.key].bytes;
            tiles.erase(candidate.key);
        }
        ++statistics.evicted;
    }
    return residentBytes() + bytes <= options->cacheBytes;
}

std::shared_ptr<renderer::Texture2D> TiledGlobe::Impl::reproject(FrameState& frameState, const Layer& layer,
                                                                 const TileKey& key, const Image& image)
{
    if (!reprojection) {
        reprojection.emplace(frameState.context);
    }
    const renderer::Texture2D source = frameState.device.createTexture2D(image, false);
    auto target = std::make_shared<renderer::Texture2D>(frameState.device.createTexture2D(
        renderer::TextureDescription{image.width, image.height, renderer::TextureFormat::RGBA8, true}));
    reprojection->reproject(source, layer.tiling.scheme.tileExtent(key), target);
    target->generateMipmaps();
    return target;
}

void TiledGlobe::Impl::upload(FrameState& frameState, PendingUpload pending, TileStatistics& statistics)
{
    const std::size_t cpu = pending.content->byteSize();
    cpuBytes -= cpu;
    const LoadTarget& target = pending.target;
    renderer::Device& device = frameState.device;
    if (target.layer < 0) {
        SurfaceTile& surface = surfaceOf(*target.tile);
        const TileMesh& mesh = static_cast<MeshContent&>(*pending.content).mesh;
        const std::span<const std::byte> bytes = std::as_bytes(std::span(mesh.vertices));
        if (!makeRoom(bytes.size(), frameState.frameNumber, statistics)) {
            surface.mesh = LoadState::Unloaded; // asked for again once there is room
            statistics.memoryLimited = true;
            return;
        }
        surface.vertexBuffer = device.createVertexBuffer(bytes);
        surface.vertexArray = frameState.context.createVertexArray();
        constexpr std::size_t stride = TileMesh::kFloatsPerVertex * sizeof(float);
        using renderer::ComponentType;
        surface.vertexArray->setAttribute(renderer::VertexAttributeLocation::PositionHigh, *surface.vertexBuffer,
                                          {ComponentType::Float, 3, false, false, stride, 0});
        surface.vertexArray->setAttribute(renderer::VertexAttributeLocation::PositionLow, *surface.vertexBuffer,
                                          {ComponentType::Float, 3, false, false, stride, 3 * sizeof(float)});
        surface.vertexArray->setAttribute(renderer::VertexAttributeLocation::TextureCoordinate, *surface.vertexBuffer,
                                          {ComponentType::Float, 3, false, false, stride, 6 * sizeof(float)});
        surface.coarsening.reset();
        surface.mesh = LoadState::Ready;
        surface.bytes = bytes.size();
        gpuBytes += surface.bytes;
        statistics.uploadedBytes += surface.bytes;
        residentTiles.push_back(target.tile);
        return;
    }
    Layer& layer = layers[static_cast<std::size_t>(target.layer)];
    const ImageContent& content = static_cast<ImageContent&>(*pending.content);
    const Image& image = content.image;
    // RGBA with its mipmap chain: a third more.
    const std::size_t bytes = image.pixels.size() * 4 / 3;
    ImageryTile& imagery = layer.tiles[target.key];
    if (!makeRoom(bytes, frameState.frameNumber, statistics)) {
        imagery.state = LoadState::Unloaded;
        statistics.memoryLimited = true;
        return;
    }
    if (layer.tiling.scheme.projection() == TilingProjection::WebMercator) {
        imagery.texture = reproject(frameState, layer, target.key, image);
    } else {
        imagery.texture = std::make_shared<renderer::Texture2D>(device.createTexture2D(image, content.mipmaps));
    }
    imagery.state = LoadState::Ready;
    imagery.bytes = bytes;
    imagery.lastUsedFrame = frameState.frameNumber;
    gpuBytes += bytes;
    statistics.uploadedBytes += bytes;
}

std::vector<TextureUse> TiledGlobe::Impl::texturesFor(QuadtreeTile& tile, std::uint64_t frame)
{
    std::vector<TextureUse> uses;
    SurfaceTile& surface = surfaceOf(tile);
    const GeodeticExtent extent = quadtree.scheme().tileExtent(tile.key);
    for (std::size_t l = 0; l < layers.size(); ++l) {
        Layer& layer = layers[l];
        for (const TileKey& key : surface.imagery[l]) {
            TileKey used;
            bool waiting = false;
            ImageryTile* imagery = bestImagery(layer, key, used, waiting);
            if (!imagery || static_cast<int>(uses.size()) >= kMaximumTextures) {
                continue;
            }
            // The wanted key's part of the tile, drawn from whichever texture stands for it; an edge
            // row of a layer stretched to the poles covers up to the pole, its texture clamped.
            GeodeticExtent keyExtent = layer.tiling.scheme.tileExtent(key);
            if (stretchesToPoles(l, layer.tiling)) {
                if (key.y == 0) {
                    keyExtent.north = kHalfPi;
                }
                if (key.y + 1 == layer.tiling.scheme.tilesY(key.level)) {
                    keyExtent.south = -kHalfPi;
                }
            }
            const auto part = placeImagery(keyExtent, extent, layer.layer.style.rectangle);
            auto placement = placeImagery(layer.tiling.scheme.tileExtent(used), extent, layer.layer.style.rectangle);
            if (!part || !placement) {
                continue;
            }
            placement->tileRectangle = part->tileRectangle;
            imagery->lastUsedFrame = frame;
            uses.push_back({imagery, *placement, static_cast<int>(l)});
        }
    }
    return uses;
}

renderer::ShaderProgram& TiledGlobe::Impl::program(FrameState& frameState, int textureCount)
{
    std::shared_ptr<renderer::ShaderProgram>& program = programs[{textureCount, frameState.depthStrategy}];
    if (program) {
        return *program;
    }
    // One block of uniforms and one blend per texture, written out (see tile.frag.glsl).
    renderer::ShaderSource fragment = renderer::ShaderSource::embedded("scene/tiles/tile.frag.glsl");
    std::string uniforms;
    std::string blends;
    for (int i = 0; i < textureCount; ++i) {
        const std::string n = std::to_string(i);
        uniforms += "uniform sampler2D og_texture" + n + ";\nuniform vec4 u_textureTransform" + n +
                    ";\nuniform vec4 u_textureRectangle" + n + ";\nuniform vec4 u_textureAdjustment" + n + ";\n";
        blends += "color = blendImagery(color, og_texture" + n + ", u_textureTransform" + n + ", u_textureRectangle" +
                  n + ", u_textureAdjustment" + n + ");\n    ";
    }
    auto replace = [&](std::string_view marker, const std::string& text) {
        const std::size_t at = fragment.text.find(marker);
        if (at == std::string::npos) {
            throw Error("scene/tiles/tile.frag.glsl: the marker " + std::string(marker) + " is missing");
        }
        fragment.text.replace(at, marker.size(), text);
    };
    replace("// OG_IMAGERY_UNIFORMS", uniforms);
    replace("// OG_IMAGERY_BLENDS", blends);
    renderer::ShaderProgramDescription description;
    description.name = "globe tile (" + std::to_string(textureCount) + " textures)";
    description.vertex = renderer::ShaderSource::embedded("scene/tiles/tile.vert.glsl");
    description.fragment = std::move(fragment);
    if (options->lighting) {
        description.defines.push_back({"LIGHTING"});
    }
    for (renderer::ShaderDefine& define : depthStrategyDefines(frameState.depthStrategy, Pass::Opaque)) {
        description.defines.push_back(std::move(define));
    }
    if (frameState.device.info().gpuShader5) {
        // Keeps og_emulatedDoubleSubtract's two-sum (built-in functions.glsl).
        description.defines.push_back({"OG_PRECISE"});
        description.extensions.push_back("GL_ARB_gpu_shader5");
    }
    program = frameState.device.shaderCache().get(description);
    return *program;
}

const renderer::IndexBuffer& TiledGlobe::Impl::indexBuffer(FrameState& frameState, const EdgeCoarsening& coarsening)
{
    const std::array<int, 4> name{coarsening.north, coarsening.east, coarsening.south, coarsening.west};
    const auto found = indexBuffers.find(name);
    if (found != indexBuffers.end()) {
        return found->second;
    }
    const std::vector<std::uint32_t> indices = TileMesh::indices(options->samplesLog2, coarsening, options->skirts);
    std::vector<std::uint16_t> narrow(indices.begin(), indices.end()); // 17 x 17 and skirts fit
    auto [entry, inserted] = indexBuffers.emplace(name, frameState.device.createIndexBuffer(std::span<const std::uint16_t>(narrow)));
    return entry->second;
}

TiledGlobe::TiledGlobe(const Ellipsoid& ellipsoid, TiledGlobeOptions options)
    : _options(std::move(options))
{
    if (_options.samplesLog2 < 1 || _options.samplesLog2 > 7) {
        throw Error("TiledGlobe: samplesLog2 must be 1 to 7 (3 to 129 vertices a side), not " +
                    std::to_string(_options.samplesLog2));
    }
    if (!(_options.maximumScreenSpaceError > 0.0)) {
        throw Error("TiledGlobe: maximumScreenSpaceError must be above 0 pixels");
    }
    _impl = std::make_unique<Impl>(ellipsoid, _options);
    for (const ImageryLayer& layer : _options.imagery) {
        if (!layer.source) {
            throw Error("TiledGlobe: an imagery layer has no source");
        }
        const world::TileSourceInfo& info = layer.source->info();
        ImageryTiling tiling{info.scheme, info.minimumLevel, info.maximumLevel, info.tileWidth, info.tileHeight,
                             info.extent};
        _impl->layers.push_back({layer, tiling, {}});
    }
    // The roots were made before the layers existed: give them their imagery now.
    for (auto& root : _impl->quadtree.roots()) {
        _impl->created(*root);
    }
    _statistics.maximumScreenSpaceError = _options.maximumScreenSpaceError;
}

TiledGlobe::~TiledGlobe() = default;

std::optional<BoundingSphere> TiledGlobe::boundingSphere() const
{
    return BoundingSphere{glm::dvec3(0.0), _impl->ellipsoid.maximumRadius()};
}

void TiledGlobe::update(FrameState& frameState, CommandList& commands)
{
    Impl& impl = *_impl;
    const std::uint64_t frame = frameState.frameNumber;
    if (impl.streamedFrame != frame) {
        // Once per frame, however many times the scene updates its primitives (a second depth
        // strategy): loads, uploads and the selection.
        impl.streamedFrame = frame;
        TileStatistics statistics;
        if (!impl.rootsLoaded) {
            // The roots and their imagery, here and now: the first frame shows the whole globe.
            impl.rootsLoaded = true;
            std::vector<LoadTarget> first;
            for (auto& root : impl.quadtree.roots()) {
                first.push_back({-1, root->key, root.get()});
                for (std::size_t l = 0; l < impl.layers.size(); ++l) {
                    for (const TileKey& key : surfaceOf(*root).imagery[l]) {
                        if (!impl.layers[l].tiles.contains(key)) {
                            impl.layers[l].tiles[key].state = LoadState::Loading;
                            first.push_back({static_cast<int>(l), key, nullptr});
                        }
                    }
                }
            }
            for (const LoadTarget& target : first) {
                world::TileLoadResult result;
                result.ticket = impl.ticketFor(target.layer, target.key);
                impl.targets[result.ticket] = target;
                try {
                    result.content = impl.workFor(target)();
                    result.status = result.content ? world::TileLoadResult::Status::Loaded
                                                   : world::TileLoadResult::Status::Missing;
                } catch (const std::exception& error) {
                    result.status = world::TileLoadResult::Status::Failed;
                    result.message = error.what();
                }
                impl.receive(std::move(result), statistics);
            }
            while (!impl.uploads.empty()) {
                PendingUpload pending = std::move(impl.uploads.front());
                impl.uploads.pop_front();
                impl.upload(frameState, std::move(pending), statistics);
            }
        }

        for (world::TileLoadResult& result : impl.loader.beginFrame(frame)) {
            impl.receive(std::move(result), statistics);
        }
        // Uploads in arrival order, up to the byte budget (at least one per frame).
        std::size_t uploaded = 0;
        while (!impl.uploads.empty() && (uploaded == 0 || statistics.uploadedBytes < _options.uploadBytesPerFrame)) {
            PendingUpload pending = std::move(impl.uploads.front());
            impl.uploads.pop_front();
            impl.upload(frameState, std::move(pending), statistics);
            ++uploaded;
        }

        const Camera& camera = frameState.camera;
        TileView view;
        view.eye = camera.eye();
        view.direction = camera.direction();
        view.frustum = frameState.cullingVolume;
        view.viewportHeightPixels = frameState.height;
        view.fieldOfViewY = camera.fieldOfViewY();
        TileSelectionOptions selectionOptions;
        selectionOptions.maximumScreenSpaceError = impl.effectiveScreenSpaceError;
        selectionOptions.loadingDescendantLimit = _options.loadingDescendantLimit;
        std::uint32_t deepest = 0;
        for (const auto& layer : impl.layers) {
            deepest = std::max(deepest, layer.tiling.maximumLevel);
        }
        // Finer tiles than the deepest imagery show nothing new.
        selectionOptions.maximumLevel = impl.layers.empty() ? 0 : deepest;
        impl.quadtree.select(view, selectionOptions, frame, impl.selection,
                             [&impl](QuadtreeTile& tile) { impl.refresh(tile); });

        for (const TileLoadCandidate& candidate : impl.selection.loads) {
            SurfaceTile& surface = surfaceOf(*candidate.tile);
            if (surface.mesh == LoadState::Unloaded) {
                surface.mesh = LoadState::Loading;
                impl.request({-1, candidate.tile->key, candidate.tile}, candidate.priority);
            }
            for (std::size_t l = 0; l < impl.layers.size(); ++l) {
                for (const TileKey& key : surface.imagery[l]) {
                    const std::optional<TileKey> source = impl.sourceKey(impl.layers[l], key);
                    if (!source) {
                        continue;
                    }
                    ImageryTile& imagery = impl.layers[l].tiles[*source];
                    if (imagery.state == LoadState::Unloaded) {
                        imagery.state = LoadState::Loading;
                        impl.request({static_cast<int>(l), *source, nullptr}, candidate.priority);
                    }
                }
            }
        }
        // Candidates the loader does not start this frame go back to Unloaded: they are asked for
        // again next frame if the view still wants them.
        impl.loader.endFrame();
        _loadsStarted.clear();
        for (const std::uint64_t ticket : impl.loader.startedTickets()) {
            const LoadTarget& target = impl.targets.at(ticket);
            _loadsStarted.push_back({target.layer, target.key});
        }
        for (auto entry = impl.targets.begin(); entry != impl.targets.end();) {
            if (impl.loader.isLoading(entry->first)) {
                ++entry;
                continue;
            }
            const LoadTarget& target = entry->second;
            if (target.layer < 0) {
                surfaceOf(*target.tile).mesh = LoadState::Unloaded;
            } else {
                impl.layers[static_cast<std::size_t>(target.layer)].tiles[target.key].state = LoadState::Unloaded;
            }
            impl.tickets.erase({target.layer, target.key});
            entry = impl.targets.erase(entry);
        }

        // The textures each drawn tile uses, and what the frame leaves undone.
        impl.drawnTextures.clear();
        std::unordered_set<const ImageryTile*> imageryRead;
        for (std::size_t i = 0; i < impl.selection.drawn.size(); ++i) {
            QuadtreeTile& tile = *impl.selection.drawn[i];
            impl.drawnTextures.push_back(impl.texturesFor(tile, frame));
            for (const TextureUse& use : impl.drawnTextures.back()) {
                imageryRead.insert(use.imagery);
            }
            bool fallback = false;
            for (std::size_t l = 0; l < impl.layers.size(); ++l) {
                for (const TileKey& key : surfaceOf(tile).imagery[l]) {
                    TileKey used;
                    bool waiting = false;
                    impl.bestImagery(impl.layers[l], key, used, waiting);
                    fallback = fallback || waiting;
                }
            }
            statistics.fallbackImagery += fallback ? 1 : 0;
            statistics.deepestLevelDrawn = std::max(statistics.deepestLevelDrawn, tile.key.level);
            statistics.largestScreenSpaceErrorDrawn =
                std::max(statistics.largestScreenSpaceErrorDrawn, impl.selection.drawnScreenSpaceErrors[i]);
        }
        const TileSelection& selection = impl.selection;
        statistics.imageryDrawn = imageryRead.size();
        statistics.visited = selection.visited;
        statistics.culledByFrustum = selection.culledByFrustum;
        statistics.culledByHorizon = selection.culledByHorizon;
        statistics.selected = selection.selected;
        statistics.drawn = selection.drawn.size();
        statistics.standIns = selection.standIns;
        statistics.requested = impl.loader.startedLastFrame();
        statistics.pending = impl.loader.inFlight() + impl.uploads.size() + impl.loader.deferred();
        statistics.failed = impl.failedCount;
        statistics.missing = impl.missingCount;
        statistics.residentBytesCpu = impl.cpuBytes;
        statistics.residentBytesGpu = impl.gpuBytes;
        statistics.maximumScreenSpaceError = impl.effectiveScreenSpaceError;
        statistics.memoryLimited = statistics.memoryLimited || impl.effectiveScreenSpaceError > _options.maximumScreenSpaceError;
        statistics.converged = selection.standIns == 0 && selection.loads.empty() && statistics.pending == 0 &&
                               statistics.fallbackImagery == 0;
        // The cap: coarser while it binds, back towards the error asked for once there is room.
        if (statistics.evicted > 0 && impl.residentBytes() > _options.cacheBytes * 9 / 10) {
            impl.effectiveScreenSpaceError *= 1.25;
        } else if (statistics.memoryLimited && impl.residentBytes() + _options.cacheBytes / 10 > _options.cacheBytes) {
            impl.effectiveScreenSpaceError *= 1.25;
        } else if (impl.effectiveScreenSpaceError > _options.maximumScreenSpaceError &&
                   impl.residentBytes() < _options.cacheBytes * 7 / 10) {
            impl.effectiveScreenSpaceError = std::max(_options.maximumScreenSpaceError, impl.effectiveScreenSpaceError / 1.1);
        }
        _statistics = statistics;
    }

    // The commands: one per drawn tile, stitched to its coarser neighbours.
    DrawnTileSet drawn;
    for (const QuadtreeTile* tile : impl.selection.drawn) {
        drawn.insert(tile->key);
    }
    if (!impl.sampler) {
        SamplerDescription sampler;
        sampler.minificationFilter = TextureMinificationFilter::LinearMipmapLinear;
        impl.sampler = frameState.device.createSampler(sampler);
    }
    const glm::dvec3& eye = frameState.camera.eye();
    // Nothing of a tile is nearer than the eye's height above its highest point: far tighter than
    // the box of a large tile, which a low eye is inside of.
    const double eyeHeight = impl.ellipsoid.toGeodetic3D(eye).height;
    for (std::size_t i = 0; i < impl.selection.drawn.size(); ++i) {
        QuadtreeTile& tile = *impl.selection.drawn[i];
        SurfaceTile& surface = surfaceOf(tile);
        const EdgeCoarsening coarsening = edgeCoarsening(impl.quadtree.scheme(), tile.key, drawn);
        if (surface.coarsening != coarsening) {
            surface.vertexArray->setIndexBuffer(&impl.indexBuffer(frameState, coarsening));
            surface.coarsening = coarsening;
        }
        const std::vector<TextureUse>& uses = impl.drawnTextures[i];
        renderer::ShaderProgram& program = impl.program(frameState, static_cast<int>(uses.size()));
        SceneCommand command;
        command.draw.debugName = "globe tile " + keyName(tile.key);
        command.draw.vertexArray = &*surface.vertexArray;
        command.draw.shaderProgram = &program;
        command.draw.renderState.facetCulling.enabled = false;
        command.draw.uniforms.set("u_baseColor", _options.baseColor);
        if (program.hasUniform("u_oneOverRadiiSquared")) { // for the lighting's normals only
            command.draw.uniforms.set("u_oneOverRadiiSquared", glm::vec3(impl.ellipsoid.oneOverRadiiSquared()));
        }
        for (std::size_t t = 0; t < uses.size(); ++t) {
            const TextureUse& use = uses[t];
            const ImageryLayerStyle& style = impl.layers[static_cast<std::size_t>(use.layer)].layer.style;
            const std::string n = std::to_string(t);
            command.draw.uniforms.set("u_textureTransform" + n,
                                      glm::vec4(glm::dvec4(use.placement.translation, use.placement.scale)));
            // A side on the tile's own edge is left open: texture coordinates interpolated across a
            // triangle overshoot 0 and 1 by a rounding at the edges, which must not drop the texture.
            glm::dvec4 rectangle = use.placement.tileRectangle;
            rectangle.x = rectangle.x <= 0.0 ? -1.0 : rectangle.x;
            rectangle.y = rectangle.y <= 0.0 ? -1.0 : rectangle.y;
            rectangle.z = rectangle.z >= 1.0 ? 2.0 : rectangle.z;
            rectangle.w = rectangle.w >= 1.0 ? 2.0 : rectangle.w;
            command.draw.uniforms.set("u_textureRectangle" + n, glm::vec4(rectangle));
            command.draw.uniforms.set("u_textureAdjustment" + n,
                                      glm::vec4(static_cast<float>(style.alpha), static_cast<float>(style.brightness),
                                                static_cast<float>(style.contrast), static_cast<float>(1.0 / style.gamma)));
            command.draw.textures.push_back({static_cast<int>(t), use.imagery->texture.get(), &*impl.sampler});
        }
        command.boundingSphere = tile.region.boundingSphere();
        command.nearestDistance = std::max(tile.region.distanceTo(eye), eyeHeight - tile.region.maximumHeight());
        command.tags = Effect::Globe | Effect::TiledImagery;
        if (_options.lighting) {
            command.tags = command.tags | Effect::Lighting;
        }
        commands.push_back(std::move(command));
    }
}

} // namespace orbis::scene
