#include "orbis/scene/TiledGlobe.h"

#include "orbis/scene/DepthStrategy.h"
#include "orbis/scene/Effect.h"
#include "orbis/scene/ImageryCoverage.h"
#include "orbis/scene/MercatorReprojection.h"

#include "TileMorph.h"
#include "VectorSupport.h"

#include <orbis/core/Error.h>
#include <orbis/core/ImageMipmaps.h>
#include <orbis/core/IntersectionTests.h>
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
#include <orbis/world/TerrainSampler.h>
#include <orbis/world/TerrainSource.h>
#include <orbis/world/TileSource.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <deque>
#include <iostream>
#include <limits>
#include <list>
#include <map>
#include <mutex>
#include <string>
#include <tuple>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace orbis::scene {

namespace {

/// At most this many imagery tiles of one layer on one surface tile: a coarser level is taken
/// when more would be needed (Web Mercator rows near the poles).
constexpr std::size_t kMaximumTexturesPerLayer = 4;
/// How far the cap may raise the screen-space error above the one asked for.
constexpr double kMaximumCoarsening = 1 << 16;
/// GLSL 3.30 guarantees 16 texture units; the renderer keeps one for uploads.
constexpr int kMaximumTextures = 15;

enum class LoadState : std::uint8_t { Unloaded, Loading, Ready, Missing, Failed };

/// A surface tile's mesh, with its heights and normals when the globe has terrain.
struct MeshContent final : world::TileContent {
    MeshContent(TileMesh mesh_, std::vector<float> normals_, bool normalsFromData_, world::TerrainSampler::WaterMask water_,
                std::uint32_t generation_)
        : mesh(std::move(mesh_))
        , normals(std::move(normals_))
        , normalsFromData(normalsFromData_)
        , water(std::move(water_))
        , generation(generation_)
    {
    }
    std::size_t byteSize() const noexcept override
    {
        return mesh.byteSize() + normals.size() * sizeof(float) + water.values.size();
    }
    TileMesh mesh;
    std::vector<float> normals; ///< three per grid and skirt vertex, Earth-fixed, unit; empty without terrain
    bool normalsFromData;       ///< the terrain data's own (world::TerrainSampler::latticeNormals), not the mesh's
    world::TerrainSampler::WaterMask water; ///< with TiledGlobeOptions::water, where the data has a mask
    std::uint32_t generation;   ///< of the exaggeration it was made with
};

/// The terrain tiles the loader's workers cut surface tiles from, shared by all of them: a child
/// beyond the source's deepest level reads its ancestor's data again, so a few are kept.
class TerrainCache {
public:
    explicit TerrainCache(std::shared_ptr<world::TerrainSource> source) : _source(std::move(source)) {}

    const world::TerrainSource& source() const noexcept { return *_source; }

    /// The deepest tile at or above `key` that the source has; null where it has none (the
    /// ellipsoid then). Throws orbis::Error with the source's message for a tile that failed.
    std::shared_ptr<const world::TerrainSampler> samplerFor(TileKey key)
    {
        const world::TerrainSourceInfo& info = _source->info();
        if (key.level > info.maximumLevel) {
            key = key.ancestor(info.maximumLevel);
        }
        for (;;) {
            while (key.level > info.minimumLevel && !_source->hasTile(key)) {
                key = key.parent();
            }
            {
                const std::lock_guard lock(_mutex);
                const auto found = _samplers.find(key);
                if (found != _samplers.end()) {
                    _order.splice(_order.begin(), _order, found->second.second);
                    return found->second.first;
                }
            }
            world::TerrainFetch fetched = _source->load(key);
            if (fetched.status == world::TerrainFetch::Status::Failed) {
                throw Error(fetched.message);
            }
            if (fetched.status == world::TerrainFetch::Status::Ok) {
                auto sampler = std::make_shared<const world::TerrainSampler>(
                    std::make_shared<const world::TerrainTileData>(std::move(fetched.tile)));
                const std::lock_guard lock(_mutex);
                if (!_samplers.contains(key)) {
                    _order.push_front(key);
                    _samplers.emplace(key, std::make_pair(sampler, _order.begin()));
                    if (_order.size() > kKept) {
                        _samplers.erase(_order.back());
                        _order.pop_back();
                    }
                }
                return sampler;
            }
            if (key.level <= info.minimumLevel) {
                return nullptr;
            }
            key = key.parent(); // missing: the parent's heights stand for it
        }
    }

private:
    static constexpr std::size_t kKept = 64;
    std::shared_ptr<world::TerrainSource> _source;
    std::mutex _mutex;
    std::list<TileKey> _order; ///< most recently used first
    std::map<TileKey, std::pair<std::shared_ptr<const world::TerrainSampler>, std::list<TileKey>::iterator>> _samplers;
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
    std::optional<renderer::VertexBuffer> normalBuffer; ///< with terrain
    /// Its water mask, when it varies over the tile; otherwise the globe's all-land or all-water one.
    std::optional<renderer::Texture2D> waterMask;
    bool allWater = false;
    bool normalsFromData = false; ///< the data's normals: a new exaggeration loads the tile again
    std::optional<EdgeCoarsening> coarsening; ///< of the index buffer bound to the vertex array
    std::size_t bytes = 0;    ///< on the GPU
    std::size_t cpuBytes = 0; ///< the mesh and heights kept here
    /// The mesh as drawn: its edges facing coarser neighbours moved onto theirs.
    TileMesh drawnMesh;
    std::vector<float> heights; ///< the grid's own heights (exaggerated), to undo those moves
    /// The drawn tiles whose vertices this tile's edges took (north, east, south, west) and its
    /// corners (north-west, north-east, south-east, south-west), with the version of each one's
    /// mesh they were taken from, and the version of its own heights they were put on.
    std::array<std::pair<const QuadtreeTile*, std::uint32_t>, 8> edgesFrom{};
    std::uint32_t edgesOnHeights = ~0u;
    std::uint32_t meshVersion = 0;    ///< counts the changes of `drawnMesh` since it was loaded
    std::uint32_t heightsVersion = 0; ///< counts the changes of its own heights (a load, a morph's step)
    /// On its way from the surface drawn before it to its own (TiledGlobeOptions::morphFrames).
    std::optional<detail::TileMorph> morph;
    double morphFactor = 1.0; ///< how far the morph is: 1 when none
    /// Grid vertex v's height as it is to be drawn before its edges are stitched: its own, morphed.
    double drawnHeight(std::size_t v) const noexcept
    {
        return morph ? morph->height(v, heights, morphFactor) : static_cast<double>(heights[v]);
    }
    /// The lowest and highest heights of its grid's vertices as drawn, and the meshVersion they
    /// were read from (TiledGlobe::drawnHeights reads them when asked).
    mutable std::optional<std::pair<std::uint32_t, std::pair<float, float>>> drawnVertexHeights;
    bool heightsKnown = false;     ///< region bounds from its own heights
    std::uint32_t boundsFromLevel = ~0u; ///< the level of the ancestor whose heights bound it meanwhile
    std::vector<std::vector<TileKey>> imagery; ///< per layer, at the level the tile's error asks for
};

SurfaceTile& surfaceOf(QuadtreeTile& tile)
{
    return static_cast<SurfaceTile&>(*tile.data);
}

const SurfaceTile& surfaceOf(const QuadtreeTile& tile)
{
    return static_cast<const SurfaceTile&>(*tile.data);
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
    /// Whether no frame since the one before last asked for what a load brought (the view moved on).
    bool unwanted(const LoadTarget& target, std::uint64_t frame) const;
    /// Forgets a load's result unuploaded; the view asks for it again if it comes back.
    void drop(PendingUpload pending);
    bool makeRoom(std::size_t bytes, std::uint64_t frame, TileStatistics& statistics);
    /// Drops a surface tile's mesh (GPU and CPU); it is loaded again when the view wants it.
    void evictSurface(QuadtreeTile& tile);
    std::shared_ptr<renderer::Texture2D> reproject(FrameState& frameState, const Layer& layer, const TileKey& key,
                                                   const Image& image);
    renderer::ShaderProgram& program(FrameState& frameState, int textureCount);
    const renderer::IndexBuffer& indexBuffer(FrameState& frameState, const EdgeCoarsening& coarsening);
    std::vector<TextureUse> texturesFor(QuadtreeTile& tile, std::uint64_t frame);
    void warn(const std::string& message) const;
    /// Bounds for a tile without heights of its own: its nearest ancestor's that has them, widened.
    void boundFromAncestor(QuadtreeTile& tile);
    /// Moves the edges of a drawn tile that face coarser drawn neighbours onto theirs (watertight
    /// across levels, with terrain whose levels disagree too), and uploads it when that changed.
    void conformEdges(QuadtreeTile& tile, const EdgeCoarsening& coarsening,
                      const std::unordered_map<TileKey, QuadtreeTile*, TileKeyHash>& drawn);
    /// The drawn tile whose point a corner of a tile takes: the coarsest around it or, among tiles
    /// of its level, the least morphed (givesVerticesTo); none when the tile keeps its own.
    const QuadtreeTile* cornerGiver(const QuadtreeTile& tile, int corner,
                                    const std::unordered_map<TileKey, QuadtreeTile*, TileKeyHash>& drawn) const;
    /// Starts the morphs of tiles drawn in place of others drawn last frame, moves the others a
    /// step, and ends those done or no longer drawn.
    void advanceMorphs(std::uint64_t frame, TileStatistics& statistics);
    /// Starts a morph from the surface drawn last frame over the tile's ground, if any was;
    /// `normalsDrawn` keeps the normals read back from the tiles drawn then, for the frame's other
    /// new tiles (four children start from one parent).
    void beginMorph(QuadtreeTile& tile, std::uint64_t frame,
                    std::unordered_map<const QuadtreeTile*, std::vector<float>>& normalsDrawn);
    /// Puts the tile's grid where its morph is at `factor` (0 to 1, the tile morphing).
    void applyMorph(QuadtreeTile& tile, double factor);
    /// Puts the tile back on its own surface, exactly as it was built, and forgets the morph.
    void endMorph(QuadtreeTile& tile);
    /// Forgets a morph without moving the tile (its mesh is rebuilt or dropped).
    void cancelMorph(SurfaceTile& surface);
    std::size_t residentBytes() const noexcept { return gpuBytes + cpuBytes; }
    /// The level whose meshes sample the terrain's deepest tiles as finely as they are.
    std::uint32_t terrainDeepestLevel() const noexcept
    {
        const world::TerrainSourceInfo& info = options->terrain->info();
        // A grid of 2^k + 1 samples is as fine as 2^(k - samplesLog2) levels of meshes. A mesh
        // tile's (quantized-mesh) triangles cross the lattice's cells, and a lattice follows their
        // creases only as closely as its cells are small: six levels more (cells 64 times finer than
        // the data's spacing) let the selection's error estimate decide, as it does on grids (with
        // two, ETOPO5 drawn 8 km over the Alps was 2.4 pixels off its own tiles at any setting:
        // docs/accuracy-cost.md, "terrain pixel error").
        int finer = 6;
        if (info.gridSize > 1) {
            finer = static_cast<int>(std::lround(std::log2(info.gridSize - 1))) - options->samplesLog2;
        }
        return info.maximumLevel + static_cast<std::uint32_t>(std::max(finer, 0));
    }
    /// The bytes of what the last two frames drew, and of loads waiting to be uploaded.
    std::size_t workingSetBytes(std::uint64_t frame) const noexcept;

    Ellipsoid ellipsoid;
    const TiledGlobeOptions* options = nullptr;
    std::vector<Layer> layers;
    std::shared_ptr<TerrainCache> terrain; ///< with TiledGlobeOptions::terrain
    std::uint32_t meshGeneration = 0;      ///< counts the exaggeration's changes
    TileQuadtree quadtree;
    world::TileLoader loader;
    std::map<std::pair<int, TileKey>, std::uint64_t> tickets;
    std::unordered_map<std::uint64_t, LoadTarget> targets;
    std::uint64_t nextTicket = 1;
    std::deque<PendingUpload> uploads;
    std::vector<QuadtreeTile*> residentTiles; ///< tiles whose mesh is on the GPU
    std::size_t gpuBytes = 0;
    std::size_t cpuBytes = 0;    ///< all the tiles hold here: loads waiting to be uploaded, meshes and heights kept
    std::size_t queuedBytes = 0; ///< of those, the loads waiting to be uploaded
    std::size_t failedCount = 0;
    std::size_t missingCount = 0;
    double effectiveScreenSpaceError;
    std::optional<std::uint64_t> streamedFrame;
    bool rootsLoaded = false;

    TileSelection selection;
    std::unordered_map<TileKey, QuadtreeTile*, TileKeyHash> drawnTiles; ///< the last frame's
    std::vector<std::vector<TextureUse>> drawnTextures; ///< parallel to selection.drawn
    std::map<std::pair<int, DepthStrategy>, std::shared_ptr<renderer::ShaderProgram>> programs;
    std::map<std::array<int, 4>, renderer::IndexBuffer> indexBuffers;
    /// The triangles of each coarsening without skirts, for heights and tests, made on first use.
    mutable std::map<std::array<int, 4>, std::vector<std::uint32_t>> surfaceIndices;
    /// The height (as drawn, exaggeration included) of a tile's mesh at a point inside it, on
    /// the triangle that holds it.
    std::optional<double> meshHeightAt(const QuadtreeTile& tile, const Geodetic2D& position) const;
    const std::vector<std::uint32_t>& surfaceTriangles(const EdgeCoarsening& coarsening) const
    {
        const std::array<int, 4> name{coarsening.north, coarsening.east, coarsening.south, coarsening.west};
        auto found = surfaceIndices.find(name);
        if (found == surfaceIndices.end()) {
            found = surfaceIndices.emplace(name, TileMesh::indices(options->samplesLog2, coarsening, false)).first;
        }
        return found->second;
    }
    /// Whether tiles draw their water masks (TiledGlobeOptions::water needs terrain and lighting).
    bool waterMasks() const noexcept { return options->water && options->lighting && terrain; }
    /// Whether a layer adjusts its colours: then every tile's program has the adjustment.
    bool adjustsColors() const noexcept
    {
        return std::any_of(options->imagery.begin(), options->imagery.end(),
                           [](const ImageryLayer& layer) { return layer.style.adjustsColors(); });
    }
    std::optional<renderer::Sampler> sampler;
    /// With TiledGlobeOptions::water: one texel masks for the tiles all land or all water, and the
    /// masks' sampler (no mipmaps: a coastline stays as sharp as the data has it).
    std::optional<renderer::Texture2D> landMask, waterMask;
    std::optional<renderer::Sampler> maskSampler;
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

glm::vec4 tileLevelColor(std::uint32_t level) noexcept
{
    static constexpr std::array<glm::vec4, 8> kPalette{{{0.90f, 0.30f, 0.25f, 1.0f}, {0.95f, 0.65f, 0.20f, 1.0f},
                                                         {0.90f, 0.90f, 0.30f, 1.0f}, {0.40f, 0.80f, 0.35f, 1.0f},
                                                         {0.30f, 0.75f, 0.85f, 1.0f}, {0.30f, 0.45f, 0.90f, 1.0f},
                                                         {0.65f, 0.40f, 0.85f, 1.0f}, {0.90f, 0.45f, 0.70f, 1.0f}}};
    return kPalette[level % kPalette.size()];
}

namespace {

enum EdgeSide { NorthEdge, EastEdge, SouthEdge, WestEdge };

/// The tile of the same level across an edge (geographic rows count from the south); none at a pole.
std::optional<TileKey> neighbourAcross(const TilingScheme& scheme, const TileKey& key, int edge)
{
    const std::uint32_t columns = scheme.tilesX(key.level);
    switch (edge) {
    case NorthEdge: return key.y + 1 < scheme.tilesY(key.level) ? std::optional<TileKey>({key.level, key.x, key.y + 1}) : std::nullopt;
    case SouthEdge: return key.y > 0 ? std::optional<TileKey>({key.level, key.x, key.y - 1}) : std::nullopt;
    case EastEdge: return TileKey{key.level, (key.x + 1) % columns, key.y};
    default: return TileKey{key.level, (key.x + columns - 1) % columns, key.y};
    }
}

/// Grid vertex k along an edge: the north and south edges west to east, the east and west edges
/// north to south.
std::pair<int, int> edgeVertexAt(int edge, int size, int k)
{
    switch (edge) {
    case NorthEdge: return {k, 0};
    case EastEdge: return {size - 1, k};
    case SouthEdge: return {k, size - 1};
    default: return {0, k};
    }
}

} // namespace

namespace {

/// Whether tile a's edge and corner vertices are drawn by b too where the two (of one level) meet:
/// the less morphed gives (its vertices are where they were drawn last frame), ties by key.
bool givesVerticesTo(const QuadtreeTile& a, const QuadtreeTile& b)
{
    return std::tie(surfaceOf(a).morphFactor, a.key) < std::tie(surfaceOf(b).morphFactor, b.key);
}

/// Each corner's edges (north-west, north-east, south-east, south-west) and its grid vertex.
constexpr std::array<std::array<int, 2>, 4> kCornerEdges{{{NorthEdge, WestEdge}, {NorthEdge, EastEdge},
                                                          {SouthEdge, EastEdge}, {SouthEdge, WestEdge}}};

std::pair<int, int> cornerVertex(int corner, int size)
{
    return {corner == 1 || corner == 2 ? size - 1 : 0, corner >= 2 ? size - 1 : 0};
}

/// Moves grid vertex (i, j) of `mesh` onto `giver`'s drawn surface, where the point lies on one of
/// its vertices (their floats, so both tiles draw the same point) or on one of its grid lines (on
/// the straight edge they draw between two vertices, not on the surface above it).
void takePoint(TileMesh& mesh, int i, int j, const QuadtreeTile& giver, std::uint32_t columns)
{
    const TileMesh& theirs = surfaceOf(giver).drawnMesh;
    const int size = mesh.size();
    const glm::dvec2 at = detail::gridCoordinatesIn(mesh.key, i, j, giver.key, mesh.samplesLog2, columns);
    const int a = std::clamp(static_cast<int>(std::floor(at.x)), 0, size - 1);
    const int b = std::clamp(static_cast<int>(std::floor(at.y)), 0, size - 1);
    const double t = at.x - a;
    const double u = at.y - b;
    auto vertex = [&](int column, int row) { return static_cast<std::size_t>(std::min(row, size - 1) * size + std::min(column, size - 1)); };
    const std::size_t ours = static_cast<std::size_t>(j * size + i) * TileMesh::kFloatsPerVertex;
    if (t == 0.0 && u == 0.0) {
        const std::size_t source = vertex(a, b) * TileMesh::kFloatsPerVertex;
        std::copy_n(&theirs.vertices[source], 6, &mesh.vertices[ours]);
        mesh.vertices[ours + 8] = theirs.vertices[source + 8];
        return;
    }
    if (t != 0.0 && u != 0.0) {
        return; // inside one of its cells: not a point the two tiles share
    }
    const std::size_t from = vertex(a, b);
    const std::size_t to = t != 0.0 ? vertex(a + 1, b) : vertex(a, b + 1);
    const double along = t != 0.0 ? t : u;
    const glm::dvec3 position = glm::mix(theirs.position(from), theirs.position(to), along);
    const double height = (1.0 - along) * static_cast<double>(theirs.vertices[from * TileMesh::kFloatsPerVertex + 8]) +
                          along * static_cast<double>(theirs.vertices[to * TileMesh::kFloatsPerVertex + 8]);
    mesh.setVertexPosition(i, j, position, height);
}

} // namespace

const QuadtreeTile* TiledGlobe::Impl::cornerGiver(const QuadtreeTile& tile, int corner,
                                                  const std::unordered_map<TileKey, QuadtreeTile*, TileKeyHash>& drawn) const
{
    const TilingScheme& scheme = quadtree.scheme();
    const auto [northOrSouth, eastOrWest] = kCornerEdges[static_cast<std::size_t>(corner)];
    const std::optional<TileKey> across = neighbourAcross(scheme, tile.key, northOrSouth);
    const std::array<std::optional<TileKey>, 3> mates{
        across, neighbourAcross(scheme, tile.key, eastOrWest),
        across ? neighbourAcross(scheme, *across, eastOrWest) : std::nullopt};
    const QuadtreeTile* coarsest = nullptr;
    const QuadtreeTile* leastMorphed = &tile;
    for (const std::optional<TileKey>& mate : mates) {
        if (!mate) {
            continue;
        }
        // The drawn tile over the mate, at its level or coarser (none where finer ones cover it).
        for (std::uint32_t level = mate->level + 1; level-- > 0;) {
            const auto found = drawn.find(mate->ancestor(level));
            if (found == drawn.end()) {
                continue;
            }
            const QuadtreeTile* over = found->second;
            if (surfaceOf(*over).drawnMesh.samplesLog2 != surfaceOf(tile).drawnMesh.samplesLog2) {
                break;
            }
            if (level < tile.key.level && (!coarsest || level < coarsest->key.level)) {
                coarsest = over;
            } else if (level == tile.key.level && givesVerticesTo(*over, *leastMorphed)) {
                leastMorphed = over;
            }
            break;
        }
    }
    if (coarsest) {
        return coarsest;
    }
    return leastMorphed != &tile ? leastMorphed : nullptr;
}

void TiledGlobe::Impl::conformEdges(QuadtreeTile& tile, const EdgeCoarsening& coarsening,
                                    const std::unordered_map<TileKey, QuadtreeTile*, TileKeyHash>& drawn)
{
    SurfaceTile& surface = surfaceOf(tile);
    TileMesh& mesh = surface.drawnMesh;
    const TilingScheme& scheme = quadtree.scheme();
    const TileKey& key = tile.key;
    const int size = mesh.size();
    const std::array<int, 4> levels{coarsening.north, coarsening.east, coarsening.south, coarsening.west};
    // Who gives what: per edge a coarser tile (its points for the vertices in use) or a less
    // morphed one of this level (the inner vertices); per corner, cornerGiver.
    std::array<std::pair<const QuadtreeTile*, std::uint32_t>, 8> from{};
    for (int edge = 0; edge < 4; ++edge) {
        const std::optional<TileKey> across = neighbourAcross(scheme, key, edge);
        if (!across) {
            continue;
        }
        const auto found = drawn.find(levels[edge] > 0 ? across->ancestor(key.level - static_cast<std::uint32_t>(levels[edge]))
                                                       : *across);
        if (found != drawn.end() && surfaceOf(*found->second).drawnMesh.samplesLog2 == mesh.samplesLog2 &&
            (levels[edge] > 0 || givesVerticesTo(*found->second, tile))) {
            from[static_cast<std::size_t>(edge)] = {found->second, surfaceOf(*found->second).meshVersion};
        }
    }
    for (int corner = 0; corner < 4; ++corner) {
        if (const QuadtreeTile* giver = cornerGiver(tile, corner, drawn)) {
            from[static_cast<std::size_t>(4 + corner)] = {giver, surfaceOf(*giver).meshVersion};
        }
    }
    if (from == surface.edgesFrom && surface.edgesOnHeights == surface.heightsVersion) {
        return;
    }
    // Back to its own edges (as morphed), then onto the neighbours': those of its level, the
    // coarser ones (the coarsest last), and the corners, which every tile there takes alike.
    for (int edge = 0; edge < 4; ++edge) {
        for (int k = 0; k < size; ++k) {
            const auto [i, j] = edgeVertexAt(edge, size, k);
            mesh.setVertexHeight(ellipsoid, scheme, i, j, surface.drawnHeight(static_cast<std::size_t>(j * size + i)));
        }
    }
    std::array<int, 4> order{NorthEdge, EastEdge, SouthEdge, WestEdge};
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return levels[a] < levels[b]; });
    for (const int edge : order) {
        const QuadtreeTile* giver = from[static_cast<std::size_t>(edge)].first;
        if (!giver) {
            continue;
        }
        const std::uint32_t columns = scheme.tilesX(giver->key.level);
        // Vertices the zipped edge uses: every 2^coarser-th (the corners alone at most), or the
        // inner ones of a tile of this level.
        const int step = std::min(1 << std::min(levels[edge], 30), size - 1);
        for (int k = levels[edge] > 0 ? 0 : 1; k < (levels[edge] > 0 ? size : size - 1); k += step) {
            const auto [i, j] = edgeVertexAt(edge, size, k);
            takePoint(mesh, i, j, *giver, columns);
        }
    }
    for (int corner = 0; corner < 4; ++corner) {
        if (const QuadtreeTile* giver = from[static_cast<std::size_t>(4 + corner)].first) {
            const auto [i, j] = cornerVertex(corner, size);
            takePoint(mesh, i, j, *giver, scheme.tilesX(giver->key.level));
        }
    }
    // The skirt hangs from the edges as they are now drawn, not as they were built.
    mesh.hangSkirt(ellipsoid, scheme);
    surface.edgesFrom = from;
    surface.edgesOnHeights = surface.heightsVersion;
    ++surface.meshVersion;
    surface.vertexBuffer->copyFromSystemMemory(std::as_bytes(std::span(mesh.vertices)));
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
                if (found != layers[l].tiles.end() && found->second.state == LoadState::Loading) {
                    found->second.lastUsedFrame = streamedFrame.value_or(0); // still wanted when it arrives
                }
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
    if (terrain) {
        // The level's estimate (which also keeps the imagery's texels within the limit), or the
        // error the data states where that is larger: a tile is refined for either.
        const double stated = terrain->source().geometricError(tile.key).value_or(0.0);
        tile.geometricError = std::max(quadtree.geometricErrorOf(tile.key.level), stated * options->terrainExaggeration);
        if (!surface.heightsKnown) {
            boundFromAncestor(tile);
        }
    }
}

void TiledGlobe::Impl::boundFromAncestor(QuadtreeTile& tile)
{
    SurfaceTile& surface = surfaceOf(tile);
    const QuadtreeTile* ancestor = tile.parent;
    while (ancestor && !surfaceOf(*ancestor).heightsKnown) {
        ancestor = ancestor->parent;
    }
    const std::uint32_t level = ancestor ? ancestor->key.level : ~0u;
    if (level == surface.boundsFromLevel) {
        return;
    }
    surface.boundsFromLevel = level;
    // A coarser level's heights are smoothed: the finer data may reach past them. Without any,
    // the Earth's range (Challenger Deep to Everest).
    double lowest = -11000.0 * options->terrainExaggeration;
    double highest = 8900.0 * options->terrainExaggeration;
    if (ancestor) {
        const double margin = 0.5 * (ancestor->region.maximumHeight() - ancestor->region.minimumHeight()) + 100.0;
        lowest = std::max(lowest, ancestor->region.minimumHeight() - margin);
        highest = std::min(highest, ancestor->region.maximumHeight() + margin);
    }
    tile.region = quadtree.regionOf(tile.key, lowest, highest);
}

std::uint64_t TiledGlobe::Impl::ticketFor(int layer, const TileKey& key)
{
    const auto [entry, inserted] = tickets.try_emplace({layer, key}, nextTicket);
    if (inserted) {
        ++nextTicket;
    }
    return entry->second;
}

namespace {

/// Normals of the data's heights made those of heights times `exaggeration`: the slope's tangent
/// scales with it, so the part along the ellipsoid's normal stays and the rest is multiplied.
void exaggerateNormals(const Ellipsoid& ellipsoid, const TileMesh& mesh, double exaggeration, std::vector<float>& normals)
{
    if (exaggeration == 1.0) {
        return;
    }
    for (std::size_t v = 0; 3 * v < normals.size(); ++v) {
        const glm::dvec3 up = ellipsoid.geodeticSurfaceNormal(mesh.position(v));
        const glm::dvec3 n(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]);
        const double along = glm::dot(n, up);
        const glm::dvec3 scaled = up * along + (n - up * along) * exaggeration;
        const double length = glm::length(scaled);
        const glm::dvec3 unit = length > 1e-12 ? scaled / length : up;
        normals[3 * v] = static_cast<float>(unit.x);
        normals[3 * v + 1] = static_cast<float>(unit.y);
        normals[3 * v + 2] = static_cast<float>(unit.z);
    }
}

} // namespace

world::TileLoadWork TiledGlobe::Impl::workFor(const LoadTarget& target) const
{
    if (target.layer < 0) {
        const Ellipsoid shape = ellipsoid;
        const TileKey key = target.key;
        const int samplesLog2 = options->samplesLog2;
        // Skirts as deep as the tile's geometric error: enough to hide any crack the level allows.
        const double skirtDepth = options->skirts ? quadtree.geometricErrorOf(key.level) : 0.0;
        const std::shared_ptr<TerrainCache> heightsFrom = terrain;
        const double exaggeration = options->terrainExaggeration;
        const bool water = waterMasks();
        const std::uint32_t generation = meshGeneration;
        return [shape, key, samplesLog2, skirtDepth, heightsFrom, exaggeration, water,
                generation]() -> std::unique_ptr<world::TileContent> {
            std::vector<float> heights;
            std::vector<float> dataNormals;
            world::TerrainSampler::WaterMask mask;
            if (heightsFrom) {
                if (const std::shared_ptr<const world::TerrainSampler> data = heightsFrom->samplerFor(key)) {
                    if (water) {
                        mask = data->waterMask(key);
                    }
                    heights = data->latticeHeights(key, samplesLog2);
                    for (float& height : heights) {
                        height = static_cast<float>(static_cast<double>(height) * exaggeration);
                    }
                    dataNormals = data->latticeNormals(key, samplesLog2);
                } else {
                    heights.assign(static_cast<std::size_t>(((1 << samplesLog2) + 1) * ((1 << samplesLog2) + 1)), 0.0f);
                }
            }
            TileMesh mesh = TileMesh::build(shape, TilingScheme::geographic(), key, samplesLog2, heights, skirtDepth);
            const bool fromData = !dataNormals.empty();
            std::vector<float> normals;
            if (fromData) {
                exaggerateNormals(shape, mesh, exaggeration, dataNormals);
                normals = mesh.normals(std::move(dataNormals));
            } else if (heightsFrom) {
                normals = mesh.normals();
            }
            return std::make_unique<MeshContent>(std::move(mesh), std::move(normals), fromData, std::move(mask),
                                                 generation);
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
        queuedBytes += result.content->byteSize();
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

std::size_t TiledGlobe::Impl::workingSetBytes(std::uint64_t frame) const noexcept
{
    const std::uint64_t since = frame > 0 ? frame - 1 : 0;
    std::size_t bytes = queuedBytes;
    for (const QuadtreeTile* tile : residentTiles) {
        bytes += tile->lastVisitedFrame >= since ? surfaceOf(*tile).bytes + surfaceOf(*tile).cpuBytes : 0;
    }
    for (const Layer& layer : layers) {
        for (const auto& [key, imagery] : layer.tiles) {
            bytes += imagery.state == LoadState::Ready && imagery.lastUsedFrame >= since ? imagery.bytes : 0;
        }
    }
    return bytes;
}

void TiledGlobe::Impl::advanceMorphs(std::uint64_t frame, TileStatistics& statistics)
{
    if (!terrain || options->morphFrames == 0) {
        return;
    }
    // New tiles start from what was drawn over their ground last frame (an ancestor, or finer
    // tiles), before any of those moves on.
    std::unordered_map<const QuadtreeTile*, std::vector<float>> normalsDrawn;
    for (QuadtreeTile* tile : selection.drawn) {
        if (!surfaceOf(*tile).morph && !drawnTiles.contains(tile->key)) {
            beginMorph(*tile, frame, normalsDrawn);
        }
    }
    const std::unordered_set<const QuadtreeTile*> drawnNow(selection.drawn.begin(), selection.drawn.end());
    for (QuadtreeTile* tile : residentTiles) {
        SurfaceTile& surface = surfaceOf(*tile);
        if (!surface.morph) {
            continue;
        }
        const double factor = surface.morph->factor(frame, options->morphFrames);
        if (factor >= 1.0 || !drawnNow.contains(tile)) {
            endMorph(*tile);
        } else {
            applyMorph(*tile, factor);
            ++statistics.morphing;
        }
    }
}

namespace {

/// The grid's normals (three floats per grid vertex) of a tile's normal buffer; none without one.
std::vector<float> gridNormals(const SurfaceTile& surface)
{
    if (!surface.normalBuffer) {
        return {};
    }
    const std::size_t count = static_cast<std::size_t>(surface.drawnMesh.size() * surface.drawnMesh.size()) * 3;
    const std::vector<std::byte> bytes = surface.normalBuffer->copyToSystemMemory(0, count * sizeof(float));
    std::vector<float> normals(count);
    std::memcpy(normals.data(), bytes.data(), bytes.size());
    return normals;
}

/// The drawn tile holding a point (the first level's where it is on an edge), if any.
const QuadtreeTile* drawnTileAt(const TileQuadtree& quadtree,
                                const std::unordered_map<TileKey, QuadtreeTile*, TileKeyHash>& drawn,
                                const Geodetic2D& position)
{
    for (std::uint32_t level = 0; level <= kMaximumTileLevel; ++level) {
        const std::optional<TileKey> key = quadtree.scheme().tileAt(position, level);
        if (!key) {
            return nullptr;
        }
        const auto found = drawn.find(*key);
        if (found != drawn.end()) {
            return found->second;
        }
    }
    return nullptr;
}

} // namespace

void TiledGlobe::Impl::beginMorph(QuadtreeTile& tile, std::uint64_t frame,
                                  std::unordered_map<const QuadtreeTile*, std::vector<float>>& normalsDrawn)
{
    SurfaceTile& surface = surfaceOf(tile);
    const TilingScheme& scheme = quadtree.scheme();
    const int samplesLog2 = surface.drawnMesh.samplesLog2;
    // The tile drawn last frame at each grid vertex: one ancestor for all, or the finer tiles in
    // turn (the last one found holds the next vertex, mostly), with their normals read back once.
    const QuadtreeTile* giver = nullptr;
    bool covered = false;
    auto drawnBefore = [&](int i, int j) -> std::optional<detail::SurfaceSample> {
        auto inside = [&](const QuadtreeTile& candidate) {
            const int size = surfaceOf(candidate).drawnMesh.size();
            const glm::dvec2 at = detail::gridCoordinatesIn(tile.key, i, j, candidate.key, samplesLog2,
                                                            scheme.tilesX(candidate.key.level));
            return at.x >= 0.0 && at.x <= size - 1.0 && at.y >= 0.0 && at.y <= size - 1.0;
        };
        if (!giver || !inside(*giver)) {
            const Geodetic2D position{TileMesh::latticeLongitude(scheme, tile.key, samplesLog2, i),
                                      TileMesh::latticeLatitude(scheme, tile.key, samplesLog2, j)};
            const QuadtreeTile* found = drawnTileAt(quadtree, drawnTiles, position);
            if (!found || found == &tile || surfaceOf(*found).mesh != LoadState::Ready ||
                surfaceOf(*found).drawnMesh.samplesLog2 != samplesLog2 || !inside(*found)) {
                return std::nullopt;
            }
            giver = found;
            if (!normalsDrawn.contains(giver)) {
                normalsDrawn.emplace(giver, gridNormals(surfaceOf(*giver)));
            }
        }
        const SurfaceTile& from = surfaceOf(*giver);
        const glm::dvec2 at = detail::gridCoordinatesIn(tile.key, i, j, giver->key, samplesLog2,
                                                        scheme.tilesX(giver->key.level));
        covered = true;
        return detail::sampleDrawnSurface(from.drawnMesh, surfaceTriangles(from.coarsening.value_or(EdgeCoarsening{})),
                                          normalsDrawn.at(giver), at.x, at.y);
    };
    detail::TileMorph morph = detail::TileMorph::start(scheme, surface.drawnMesh, gridNormals(surface), drawnBefore, frame);
    if (!covered) {
        return; // new ground: nothing was drawn there to move from
    }
    surface.morph = std::move(morph);
    surface.cpuBytes += surface.morph->byteSize();
    cpuBytes += surface.morph->byteSize();
    // Bounds that hold all the way: the surface before may stand above or below its own.
    const TileMesh& mesh = surface.drawnMesh;
    tile.region = quadtree.regionOf(tile.key, std::min(mesh.minimumHeight, surface.morph->fromMinimumHeight),
                                    std::max(mesh.maximumHeight, surface.morph->fromMaximumHeight));
}

void TiledGlobe::Impl::applyMorph(QuadtreeTile& tile, double factor)
{
    SurfaceTile& surface = surfaceOf(tile);
    TileMesh& mesh = surface.drawnMesh;
    surface.morphFactor = factor;
    surface.morph->moveInnerVertices(mesh, surface.heights, factor);
    if (surface.normalBuffer && !surface.morph->ownNormals.empty()) {
        const std::vector<float> normals = mesh.normals(surface.morph->normals(factor));
        surface.normalBuffer->copyFromSystemMemory(std::as_bytes(std::span(normals)));
    }
    ++surface.heightsVersion; // conformEdges stitches and uploads it
}

void TiledGlobe::Impl::endMorph(QuadtreeTile& tile)
{
    SurfaceTile& surface = surfaceOf(tile);
    TileMesh& mesh = surface.drawnMesh;
    // Its own normals and heights, exactly as loaded and built.
    if (surface.normalBuffer && !surface.morph->ownNormals.empty()) {
        const std::vector<float> normals = mesh.normals(surface.morph->ownNormals);
        surface.normalBuffer->copyFromSystemMemory(std::as_bytes(std::span(normals)));
    }
    cancelMorph(surface);
    const int size = mesh.size();
    for (int j = 0; j < size; ++j) {
        for (int i = 0; i < size; ++i) {
            mesh.setVertexHeight(ellipsoid, quadtree.scheme(), i, j,
                                 static_cast<double>(surface.heights[static_cast<std::size_t>(j * size + i)]));
        }
    }
    ++surface.heightsVersion; // conformEdges stitches and uploads it
    tile.region = quadtree.regionOf(tile.key, mesh.minimumHeight, mesh.maximumHeight);
}

void TiledGlobe::Impl::cancelMorph(SurfaceTile& surface)
{
    if (surface.morph) {
        surface.cpuBytes -= surface.morph->byteSize();
        cpuBytes -= surface.morph->byteSize();
        surface.morph.reset();
    }
    surface.morphFactor = 1.0;
}

void TiledGlobe::Impl::evictSurface(QuadtreeTile& tile)
{
    SurfaceTile& surface = surfaceOf(tile);
    cancelMorph(surface);
    gpuBytes -= surface.bytes;
    cpuBytes -= surface.cpuBytes;
    surface.vertexArray.reset();
    surface.vertexBuffer.reset();
    surface.normalBuffer.reset();
    surface.waterMask.reset();
    surface.coarsening.reset();
    surface.drawnMesh = TileMesh{};
    surface.heights = {};
    surface.bytes = 0;
    surface.cpuBytes = 0; // its bounds stay: they still hold
    surface.mesh = LoadState::Unloaded;
    tile.renderable = false;
    residentTiles.erase(std::find(residentTiles.begin(), residentTiles.end(), &tile));
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
            evictSurface(*candidate.tile);
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

bool TiledGlobe::Impl::unwanted(const LoadTarget& target, std::uint64_t frame) const
{
    std::uint64_t wanted = 0;
    if (target.layer < 0) {
        wanted = target.tile->lastVisitedFrame;
    } else {
        const auto& tiles = layers[static_cast<std::size_t>(target.layer)].tiles;
        const auto found = tiles.find(target.key);
        wanted = found == tiles.end() ? 0 : found->second.lastUsedFrame;
    }
    return target.key.level > 0 && wanted + 2 < frame;
}

void TiledGlobe::Impl::drop(PendingUpload pending)
{
    cpuBytes -= pending.content->byteSize();
    queuedBytes -= pending.content->byteSize();
    const LoadTarget& target = pending.target;
    if (target.layer < 0) {
        surfaceOf(*target.tile).mesh = LoadState::Unloaded;
    } else {
        layers[static_cast<std::size_t>(target.layer)].tiles[target.key].state = LoadState::Unloaded;
    }
}

void TiledGlobe::Impl::upload(FrameState& frameState, PendingUpload pending, TileStatistics& statistics)
{
    const std::size_t cpu = pending.content->byteSize();
    cpuBytes -= cpu;
    queuedBytes -= cpu;
    const LoadTarget& target = pending.target;
    renderer::Device& device = frameState.device;
    if (target.layer < 0) {
        SurfaceTile& surface = surfaceOf(*target.tile);
        MeshContent& content = static_cast<MeshContent&>(*pending.content);
        if (content.generation != meshGeneration) {
            surface.mesh = LoadState::Unloaded; // made with another exaggeration: asked for again
            return;
        }
        const TileMesh& mesh = content.mesh;
        const std::span<const std::byte> bytes = std::as_bytes(std::span(mesh.vertices));
        const std::span<const std::byte> normalBytes = std::as_bytes(std::span(content.normals));
        // The GPU's copy, and the one kept here for stitching and heights.
        const std::size_t kept = bytes.size() + static_cast<std::size_t>(mesh.size() * mesh.size()) * sizeof(float);
        const std::size_t maskBytes = content.water.size > 1 ? content.water.values.size() : 0;
        if (!makeRoom(bytes.size() + normalBytes.size() + maskBytes + kept, frameState.frameNumber, statistics)) {
            surface.mesh = LoadState::Unloaded; // asked for again once there is room
            statistics.memoryLimited = true;
            return;
        }
        surface.vertexBuffer = device.createVertexBuffer(bytes);
        surface.vertexArray = frameState.context.createVertexArray();
        surface.normalsFromData = content.normalsFromData;
        surface.allWater = content.water.size == 1 && content.water.values[0] >= 128;
        if (maskBytes > 0) {
            const int size = content.water.size;
            surface.waterMask = device.createTexture2D({size, size, renderer::TextureFormat::R8});
            surface.waterMask->copyFromSystemMemory(std::as_bytes(std::span(content.water.values)));
        }
        if (!content.normals.empty()) {
            surface.normalBuffer = device.createVertexBuffer(normalBytes);
            surface.vertexArray->setAttribute(renderer::VertexAttributeLocation::Normal, *surface.normalBuffer,
                                              {renderer::ComponentType::Float, 3, false, false, 3 * sizeof(float), 0});
        }
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
        surface.bytes = bytes.size() + normalBytes.size() + maskBytes;
        gpuBytes += surface.bytes;
        statistics.uploadedBytes += surface.bytes;
        surface.heights.resize(static_cast<std::size_t>(mesh.size()) * mesh.size());
        for (std::size_t v = 0; v < surface.heights.size(); ++v) {
            surface.heights[v] = mesh.vertices[v * TileMesh::kFloatsPerVertex + 8];
        }
        surface.cpuBytes = kept;
        cpuBytes += kept;
        if (terrain) {
            target.tile->region = quadtree.regionOf(target.key, mesh.minimumHeight, mesh.maximumHeight);
            surface.heightsKnown = true;
        }
        surface.drawnMesh = std::move(content.mesh);
        ++surface.heightsVersion;
        ++surface.meshVersion;
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
    const bool water = waterMasks();
    if (water) { // the mask reads the unit after the imagery's
        const std::string unit = "og_texture" + std::to_string(textureCount);
        uniforms += "uniform sampler2D " + unit + ";\n#define WATER_MASK_TEXTURE " + unit + "\n";
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
    fragment.text.insert(0, renderer::ShaderSource::embedded("scene/tiles/imagery_over.glsl").text);
    if (options->shading.any()) {
        fragment.text.insert(0, terrainShadingSource());
        addTerrainShadingDefines(options->shading, description.defines);
    }
    description.name = "globe tile (" + std::to_string(textureCount) + " textures)";
    description.vertex = renderer::ShaderSource::embedded("scene/tiles/tile.vert.glsl");
    description.fragment = std::move(fragment);
    if (options->lighting) {
        description.defines.push_back({"LIGHTING"});
    }
    if (terrain) {
        description.defines.push_back({"TERRAIN"});
    }
    if (water) {
        description.defines.push_back({"WATER_MASK"});
    }
    if (adjustsColors()) {
        description.defines.push_back({"COLOR_ADJUSTMENT"});
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
    if (_options.samplesLog2 == 0) {
        _options.samplesLog2 = _options.terrain ? 6 : 4;
    }
    if (_options.samplesLog2 < 1 || _options.samplesLog2 > 7) {
        throw Error("TiledGlobe: samplesLog2 must be 1 to 7 (3 to 129 vertices a side), not " +
                    std::to_string(_options.samplesLog2));
    }
    if (!(_options.maximumScreenSpaceError > 0.0)) {
        throw Error("TiledGlobe: maximumScreenSpaceError must be above 0 pixels");
    }
    if (!(std::isfinite(_options.terrainExaggeration) && _options.terrainExaggeration >= 0.0)) {
        throw Error("TiledGlobe: the terrain exaggeration must be a number of 0 or more");
    }
    if (_options.morphFrames < 0) {
        throw Error("TiledGlobe: morphFrames must be 0 or more, not " + std::to_string(_options.morphFrames));
    }
    validateTerrainShading(_options.shading, "TiledGlobe");
    _impl = std::make_unique<Impl>(ellipsoid, _options);
    if (_options.terrain) {
        _impl->terrain = std::make_shared<TerrainCache>(_options.terrain);
    }
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
            if (impl.unwanted(pending.target, frame)) {
                impl.drop(std::move(pending));
                continue;
            }
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
        // Finer tiles than the deepest imagery and terrain show nothing new.
        selectionOptions.maximumLevel = impl.layers.empty() ? 0 : deepest;
        if (impl.terrain) {
            selectionOptions.maximumLevel = std::max(selectionOptions.maximumLevel, impl.terrainDeepestLevel());
        }
        impl.quadtree.select(view, selectionOptions, frame, impl.selection,
                             [&impl](QuadtreeTile& tile) { impl.refresh(tile); });

        // No new loads while more arrived than four frames' uploads: what the view asks for later
        // is more useful than what it asked for while the queue was long.
        const bool mayStart = impl.queuedBytes < 4 * _options.uploadBytesPerFrame;
        for (const TileLoadCandidate& candidate : impl.selection.loads) {
            SurfaceTile& surface = surfaceOf(*candidate.tile);
            if (surface.mesh == LoadState::Unloaded && mayStart) {
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
                    // Kept (or, still loading, uploaded) while the tile waits for what it lacks.
                    imagery.lastUsedFrame = frame;
                    if (imagery.state == LoadState::Unloaded && mayStart) {
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
        statistics.residentTiles = impl.residentTiles.size();
        statistics.residentImageryTiles = 0;
        for (const auto& layer : impl.layers) {
            for (const auto& [key, imagery] : layer.tiles) {
                statistics.residentImageryTiles += imagery.state == LoadState::Ready;
            }
        }
        statistics.maximumScreenSpaceError = impl.effectiveScreenSpaceError;
        const bool refusedForRoom = statistics.memoryLimited; // set by an upload the cap refused
        statistics.memoryLimited = refusedForRoom || impl.effectiveScreenSpaceError > _options.maximumScreenSpaceError;
        impl.advanceMorphs(frame, statistics);
        statistics.converged = selection.standIns == 0 && selection.loads.empty() && statistics.pending == 0 &&
                               statistics.fallbackImagery == 0 && statistics.morphing == 0;
        // The cap binds when an upload finds no room after everything evictable went (a full
        // cache of tiles the view no longer uses is no reason: those are evicted as needed).
        // Coarser while uploads are refused; back towards the error asked for once the view's own
        // tiles leave room.
        const std::size_t working = impl.workingSetBytes(frame);
        if (refusedForRoom) {
            impl.effectiveScreenSpaceError = std::min(impl.effectiveScreenSpaceError * 1.25,
                                                      _options.maximumScreenSpaceError * kMaximumCoarsening);
        } else if (impl.effectiveScreenSpaceError > _options.maximumScreenSpaceError &&
                   working < _options.cacheBytes * 7 / 10) {
            impl.effectiveScreenSpaceError = std::max(_options.maximumScreenSpaceError, impl.effectiveScreenSpaceError / 1.25);
            statistics.converged = false; // the next frame refines
        }
        _statistics = statistics;
    }

    // The commands: one per drawn tile, stitched to its coarser and less morphed neighbours (those
    // first, so that the others take their edges as they are drawn).
    DrawnTileSet drawn;
    std::unordered_map<TileKey, QuadtreeTile*, TileKeyHash>& drawnTiles = impl.drawnTiles;
    drawnTiles.clear();
    for (QuadtreeTile* tile : impl.selection.drawn) {
        drawn.insert(tile->key);
        drawnTiles.emplace(tile->key, tile);
    }
    std::vector<QuadtreeTile*> coarseFirst = impl.selection.drawn;
    std::sort(coarseFirst.begin(), coarseFirst.end(), [](const QuadtreeTile* a, const QuadtreeTile* b) {
        return a->key.level != b->key.level ? a->key.level < b->key.level : givesVerticesTo(*a, *b);
    });
    for (QuadtreeTile* tile : coarseFirst) {
        impl.conformEdges(*tile, edgeCoarsening(impl.quadtree.scheme(), tile->key, drawn), drawnTiles);
    }
    if (!impl.sampler) {
        SamplerDescription sampler;
        sampler.minificationFilter = TextureMinificationFilter::LinearMipmapLinear;
        impl.sampler = frameState.device.createSampler(sampler);
    }
    if (impl.waterMasks() && !impl.maskSampler) {
        impl.maskSampler = frameState.device.createSampler(SamplerDescription{});
        for (const auto& [mask, value] : {std::pair{&impl.landMask, std::byte{0}}, std::pair{&impl.waterMask, std::byte{255}}}) {
            *mask = frameState.device.createTexture2D({1, 1, renderer::TextureFormat::R8});
            (*mask)->copyFromSystemMemory(std::span(&value, 1));
        }
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
        if (program.hasUniform("u_baseColor")) { // not with a colour ramp in its place
            command.draw.uniforms.set("u_baseColor", _options.colorByLevel ? tileLevelColor(tile.key.level) : _options.baseColor);
        }
        if (program.hasUniform("u_oneOverRadiiSquared")) { // for the ellipsoid's normals
            command.draw.uniforms.set("u_oneOverRadiiSquared", glm::vec3(impl.ellipsoid.oneOverRadiiSquared()));
        }
        if (_options.shading.any()) {
            setTerrainShadingUniforms(_options.shading, command.draw.uniforms);
            const double exaggeration = _options.terrainExaggeration;
            if (program.hasUniform("u_heightScale")) { // not for a hillshade alone
                command.draw.uniforms.set("u_heightScale",
                                          static_cast<float>(exaggeration > 0.0 ? 1.0 / exaggeration : 0.0));
            }
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
        if (impl.waterMasks()) {
            const renderer::Texture2D& mask = surface.waterMask ? *surface.waterMask
                                              : surface.allWater ? *impl.waterMask
                                                                 : *impl.landMask;
            command.draw.textures.push_back({static_cast<int>(uses.size()), &mask, &*impl.maskSampler});
        }
        command.boundingSphere = tile.region.boundingSphere();
        command.nearestDistance = std::max(tile.region.distanceTo(eye), eyeHeight - tile.region.maximumHeight());
        command.tags = Effect::Globe | Effect::TiledImagery;
        command.ground = true;
        if (impl.terrain) {
            command.tags = command.tags | Effect::Terrain;
        }
        if (_options.lighting) {
            command.tags = command.tags | Effect::Lighting;
        }
        if (_options.shading.any()) {
            command.tags = command.tags | Effect::TerrainShading;
        }
        if (impl.waterMasks()) {
            command.tags = command.tags | Effect::Water;
        }
        if (impl.adjustsColors()) {
            command.tags = command.tags | Effect::ColorAdjustment;
        }
        commands.push_back(std::move(command));
    }
}

void TiledGlobe::setTerrainExaggeration(double exaggeration)
{
    if (!(std::isfinite(exaggeration) && exaggeration >= 0.0)) {
        throw Error("TiledGlobe: the terrain exaggeration must be a number of 0 or more");
    }
    Impl& impl = *_impl;
    const double before = _options.terrainExaggeration;
    if (!impl.terrain || exaggeration == before) {
        _options.terrainExaggeration = exaggeration;
        return;
    }
    _options.terrainExaggeration = exaggeration;
    ++impl.meshGeneration; // loads under way were made with the old one
    const TilingScheme& scheme = impl.quadtree.scheme();
    std::vector<QuadtreeTile*> resident = impl.residentTiles;
    for (QuadtreeTile* tile : resident) {
        SurfaceTile& surface = surfaceOf(*tile);
        if (before == 0.0 || surface.normalsFromData) {
            // Flat tiles keep no heights to scale, and the data's normals are not kept: loaded
            // again (the roots at once).
            impl.evictSurface(*tile);
            continue;
        }
        impl.cancelMorph(surface); // the tile shows its own surface at the new exaggeration
        for (float& height : surface.heights) {
            height = static_cast<float>(static_cast<double>(height) * (exaggeration / before));
        }
        const double skirtDepth = _options.skirts ? impl.quadtree.geometricErrorOf(tile->key.level) : 0.0;
        surface.drawnMesh = TileMesh::build(impl.ellipsoid, scheme, tile->key, surface.drawnMesh.samplesLog2,
                                            surface.heights, skirtDepth);
        const std::vector<float> normals = surface.drawnMesh.normals();
        surface.vertexBuffer->copyFromSystemMemory(std::as_bytes(std::span(surface.drawnMesh.vertices)));
        surface.normalBuffer->copyFromSystemMemory(std::as_bytes(std::span(normals)));
        tile->region = impl.quadtree.regionOf(tile->key, surface.drawnMesh.minimumHeight, surface.drawnMesh.maximumHeight);
        ++surface.heightsVersion;
        ++surface.meshVersion;
    }
    // Tiles bounded by an ancestor's heights take the new ones at their next visit.
    std::vector<QuadtreeTile*> stack;
    for (auto& root : impl.quadtree.roots()) {
        stack.push_back(root.get());
    }
    while (!stack.empty()) {
        QuadtreeTile* tile = stack.back();
        stack.pop_back();
        SurfaceTile& surface = surfaceOf(*tile);
        surface.boundsFromLevel = ~0u;
        surface.heightsKnown = surface.heightsKnown && surface.mesh == LoadState::Ready;
        for (auto& child : tile->children) {
            if (child) {
                stack.push_back(child.get());
            }
        }
    }
    if (before == 0.0) {
        impl.rootsLoaded = false;
    }
}

std::optional<double> TiledGlobe::Impl::meshHeightAt(const QuadtreeTile& tile, const Geodetic2D& position) const
{
    const SurfaceTile& surface = surfaceOf(tile);
    const TileMesh& mesh = surface.drawnMesh;
    const int size = mesh.size();
    const glm::dvec2 uv = glm::clamp(quadtree.scheme().positionInTile(tile.key, position), 0.0, 1.0);
    const std::optional<detail::SurfaceSample> sample =
        detail::sampleDrawnSurface(mesh, surfaceTriangles(surface.coarsening.value_or(EdgeCoarsening{})), {},
                                   uv.x * (size - 1), (1.0 - uv.y) * (size - 1));
    return sample ? std::optional(sample->height) : std::nullopt;
}

std::optional<double> TiledGlobe::heightAt(const Geodetic2D& position) const
{
    const QuadtreeTile* tile = drawnTileAt(_impl->quadtree, _impl->drawnTiles, position);
    const std::optional<double> height = tile ? _impl->meshHeightAt(*tile, position) : std::nullopt;
    if (!height) {
        return std::nullopt;
    }
    const double exaggeration = _options.terrainExaggeration;
    return exaggeration > 0.0 ? *height / exaggeration : 0.0;
}

std::optional<double> TiledGlobe::pickGround(const Ray& ray) const
{
    const Impl& impl = *_impl;
    // The tiles whose bounds the ray enters, nearest first: a hit nearer than the next tile's
    // bounds ends the search.
    std::vector<std::pair<double, const QuadtreeTile*>> candidates;
    for (const QuadtreeTile* tile : impl.selection.drawn) {
        if (const std::optional<RayInterval> inside = intersectRaySphere(ray, tile->region.boundingSphere())) {
            candidates.emplace_back(inside->nearDistance, tile);
        }
    }
    std::sort(candidates.begin(), candidates.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    std::optional<double> nearest;
    for (const auto& [entry, tile] : candidates) {
        if (nearest && entry > *nearest) {
            break;
        }
        const SurfaceTile& surface = surfaceOf(*tile);
        const TileMesh& mesh = surface.drawnMesh;
        const std::vector<std::uint32_t>& indices = impl.surfaceTriangles(surface.coarsening.value_or(EdgeCoarsening{}));
        for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
            const std::optional<RayTriangleHit> hit = intersectRayTriangle(
                ray, mesh.position(indices[t]), mesh.position(indices[t + 1]), mesh.position(indices[t + 2]));
            if (hit && (!nearest || hit->distance < *nearest)) {
                nearest = hit->distance;
            }
        }
    }
    return nearest;
}

std::optional<double> TiledGlobe::groundHeight(const Geodetic2D& position) const
{
    const Impl& impl = *_impl;
    if (const QuadtreeTile* drawn = drawnTileAt(impl.quadtree, impl.drawnTiles, position)) {
        return impl.meshHeightAt(*drawn, position);
    }
    // Not in view (under the eye of a camera looking at the horizon, say): the deepest tile
    // loaded there, down from the root that holds the point.
    const TilingScheme& scheme = impl.quadtree.scheme();
    const QuadtreeTile* tile = nullptr;
    for (const auto& root : impl.quadtree.roots()) {
        if (scheme.tileAt(position, 0) == root->key) {
            tile = root.get();
        }
    }
    if (!tile || surfaceOf(*tile).mesh != LoadState::Ready) {
        return std::nullopt;
    }
    for (bool deeper = true; deeper;) {
        deeper = false;
        const std::optional<TileKey> next = scheme.tileAt(position, tile->key.level + 1);
        for (const auto& child : tile->children) {
            if (child && next && child->key == *next && surfaceOf(*child).mesh == LoadState::Ready) {
                tile = child.get();
                deeper = true;
                break;
            }
        }
    }
    return impl.meshHeightAt(*tile, position);
}

std::optional<HeightInterval> TiledGlobe::drawnHeights(const GeodeticExtent& extent) const
{
    const Impl& impl = *_impl;
    const TilingScheme& scheme = impl.quadtree.scheme();
    std::optional<HeightInterval> heights;
    std::vector<const QuadtreeTile*> stack;
    for (const auto& root : impl.quadtree.roots()) {
        stack.push_back(root.get());
    }
    while (!stack.empty()) {
        const QuadtreeTile& tile = *stack.back();
        stack.pop_back();
        const GeodeticExtent tileExtent = scheme.tileExtent(tile.key);
        if (!tileExtent.intersects(extent)) {
            continue;
        }
        if (!impl.drawnTiles.contains(tile.key)) {
            if (tile.hasChildren()) {
                for (const auto& child : tile.children) {
                    stack.push_back(child.get());
                }
            }
            continue;
        }
        const SurfaceTile& surface = surfaceOf(tile);
        const TileMesh& mesh = surface.drawnMesh;
        if (!surface.drawnVertexHeights || surface.drawnVertexHeights->first != surface.meshVersion) {
            // The grid's vertices only: a skirt hangs where no crack lets it show.
            const std::size_t count = static_cast<std::size_t>(mesh.size()) * static_cast<std::size_t>(mesh.size());
            float lowest = std::numeric_limits<float>::infinity();
            float highest = -lowest;
            for (std::size_t v = 0; v < count; ++v) {
                const float height = mesh.vertices[v * TileMesh::kFloatsPerVertex + 8];
                lowest = std::min(lowest, height);
                highest = std::max(highest, height);
            }
            surface.drawnVertexHeights = {surface.meshVersion, {lowest, highest}};
        }
        // Between its vertices a flat triangle sags below them, by what its widest edge allows: a
        // cell's diagonal, or beside a coarser neighbour a zipped triangle 2^c cells long, whose
        // edge vertices lie on that neighbour's chords (sagging as much again, at most).
        const EdgeCoarsening coarsening = surface.coarsening.value_or(EdgeCoarsening{});
        const int coarser = std::max({coarsening.north, coarsening.east, coarsening.south, coarsening.west});
        const double cell = (tileExtent.width() + tileExtent.height()) / (mesh.size() - 1);
        const double sag = detail::triangleSagBound(impl.ellipsoid, coarser > 0 ? std::ldexp(cell, std::min(coarser + 1, 30)) : cell);
        const auto [lowest, highest] = surface.drawnVertexHeights->second;
        heights = enclose(heights, {static_cast<double>(lowest) - sag, static_cast<double>(highest)});
    }
    return heights;
}

std::vector<TiledGlobe::DrawnTile> TiledGlobe::drawnTiles() const
{
    std::vector<DrawnTile> tiles;
    for (const QuadtreeTile* tile : _impl->selection.drawn) {
        tiles.push_back({tile->key, tile->region});
    }
    return tiles;
}

std::vector<glm::dvec3> TiledGlobe::drawnTriangles() const
{
    std::vector<glm::dvec3> points;
    for (const QuadtreeTile* tile : _impl->selection.drawn) {
        const SurfaceTile& surface = surfaceOf(*tile);
        for (const std::uint32_t vertex : _impl->surfaceTriangles(surface.coarsening.value_or(EdgeCoarsening{}))) {
            points.push_back(surface.drawnMesh.position(vertex));
        }
    }
    return points;
}

} // namespace orbis::scene
