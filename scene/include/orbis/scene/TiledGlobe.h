#pragma once

#include "orbis/scene/FrameState.h"
#include "orbis/scene/TileQuadtree.h"
#include "orbis/scene/TerrainShading.h"
#include "orbis/scene/TileStatistics.h"

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/Geodetic.h>
#include <orbis/core/GeodeticExtent.h>
#include <orbis/world/TileLoader.h>

#include <glm/vec4.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <optional>
#include <vector>

namespace orbis::world {
class TileSource;
class TerrainSource;
} // namespace orbis::world

namespace orbis::scene {

/// How one imagery layer is drawn over the layers below it (course 3.5).
struct ImageryLayerStyle {
    double alpha = 1.0;      ///< 0 transparent .. 1 opaque
    double brightness = 1.0; ///< the colour's scale: 0 black, 1 unchanged
    double contrast = 1.0;   ///< about mid-grey: 0 grey, 1 unchanged
    double gamma = 1.0;      ///< > 0; colours raised to 1 / gamma
    /// Where the layer shows; empty: wherever its source has tiles. May cross the antimeridian.
    std::optional<GeodeticExtent> rectangle;

    /// Whether brightness, contrast or gamma changes the colours: only then do the globe's
    /// shaders compile the adjustment in (Effect::ColorAdjustment).
    bool adjustsColors() const noexcept { return brightness != 1.0 || contrast != 1.0 || gamma != 1.0; }
};

/// An imagery layer: a tile source (TMS folder, URL template, MBTiles, HTTP) and its style.
struct ImageryLayer {
    std::shared_ptr<world::TileSource> source;
    ImageryLayerStyle style;
};

struct TiledGlobeOptions {
    /// Drawn in order, each over the ones before; none: the base colour alone.
    std::vector<ImageryLayer> imagery;
    /// Refine while a tile's screen-space error exceeds this many pixels.
    double maximumScreenSpaceError = 2.0;
    /// The hard cap on what the tiles hold, CPU and GPU together; the selection coarsens rather
    /// than exceed it.
    std::size_t cacheBytes = std::size_t{256} << 20;
    /// GPU uploads per frame stop once this many bytes went up (at least one tile goes each frame).
    std::size_t uploadBytesPerFrame = std::size_t{16} << 20;
    world::TileLoaderOptions loader;
    /// See TileSelectionOptions::loadingDescendantLimit.
    std::size_t loadingDescendantLimit = 20;
    /// Heights for every tile (world::openTerrainSource), finer tiles cut from the deepest tile
    /// the source has; none: the ellipsoid itself.
    std::shared_ptr<world::TerrainSource> terrain;
    /// Terrain heights are multiplied by this; bounds and horizon tests follow.
    double terrainExaggeration = 1.0;
    /// Tile meshes have 2^samplesLog2 + 1 vertices a side; 0: 17 on the ellipsoid (it is
    /// smooth), 65 with terrain.
    int samplesLog2 = 0;
    /// Skirts under the tiles' edges; off by default: tiles stitch to their coarser neighbours.
    bool skirts = false;
    /// With terrain: the frames over which a tile drawn where others were drawn the frame before
    /// (its ancestor, or finer tiles) moves from the surface they drew to its own (book 14.4,
    /// morphing over time); 0: it pops at once.
    int morphFrames = 0;
    /// Lit by the scene's Sun (Scene::setSunDirection). Off by default, as in a scene file that
    /// places no Sun and as CesiumJS's globe: the colours as they are, no lighting computed (no
    /// "lighting" effect in the statistics).
    bool lighting = false;
    glm::vec4 baseColor{0.2f, 0.35f, 0.6f, 1.0f};
    /// Each tile's base colour from its level (a palette of eight), to show the levels of detail
    /// the selection chose (book chapter 12's figures); imagery layers are blended over it.
    bool colorByLevel = false;
    /// Colour by height or slope, contours, hillshade (with or without terrain: the ellipsoid's
    /// tiles are at 0 m).
    TerrainShading shading;
    /// Water where the terrain's water mask says so (quantized-mesh's watermask extension), with
    /// lighting on: level (lit by the ellipsoid's normal, not the sea floor's) and mirroring the
    /// Sun. Tiles whose data has no mask are land.
    bool water = false;
    /// Receives each warning once (a tile that failed, naming its path or URL); empty: they go to
    /// the standard error stream.
    std::function<void(const std::string&)> onWarning;
};

/// Eight colours told apart at a glance, by level (TiledGlobeOptions::colorByLevel), for showing
/// tiles by their level elsewhere too.
glm::vec4 tileLevelColor(std::uint32_t level) noexcept;

/// The globe's surface streamed as tiles (book chapter 12, course chapter 3): each frame selects
/// tiles by screen-space error from a quadtree over the ellipsoid, loads what is missing on worker
/// threads (TileLoader), uploads it under a byte budget, keeps a byte-capped cache, and draws one
/// command per tile with the imagery layers blended in order. Web Mercator layers are reprojected
/// on the GPU to rows linear in latitude when they arrive (course 3.7); beyond their latitude
/// limit the first layer's edge row stretches to the pole, and later layers leave what is below.
///
/// Results enter at frame boundaries in a fixed order, so with deterministic loader timing a
/// camera path gives the same frames whatever the thread count. The roots and their imagery are
/// loaded when the first frame begins, so that no frame has a hole.
class TiledGlobe final : public Primitive {
public:
    TiledGlobe(const Ellipsoid& ellipsoid, TiledGlobeOptions options);
    ~TiledGlobe() override;

    const TiledGlobeOptions& options() const noexcept { return _options; }

    std::optional<BoundingSphere> boundingSphere() const override;
    void update(FrameState& frameState, CommandList& commands) override;
    bool supportsLogarithmicDepth() const override { return true; }
    const TileStatistics* tileStatistics() const override { return &_statistics; }

    /// Every drawn tile at the level its error asks for with its own imagery, nothing pending.
    bool converged() const noexcept { return _statistics.converged; }

    /// Changes the terrain's exaggeration: the resident tiles are rebuilt from their heights at
    /// once (their bounds and horizon points follow), loads under way are made again. From 0, the
    /// tiles are loaded again. Throws orbis::Error for a value below 0 or not finite.
    void setTerrainExaggeration(double exaggeration);

    /// The terrain's height (metres, exaggeration taken out) of the surface drawn at a point in
    /// the last frame: on the triangle drawn there, so that a point on an edge or a corner shared
    /// by tiles gets the same height from each. Empty before the first frame, and where no tile
    /// was drawn (a point behind the horizon is covered by the coarser tiles drawn there).
    std::optional<double> heightAt(const Geodetic2D& position) const;

    /// The first hit of a ray on the triangles drawn in the last frame (their double positions):
    /// what a click on the terrain picks.
    std::optional<double> pickGround(const Ray& ray) const override;
    /// heightAt times the exaggeration: the drawn surface's height above the ellipsoid.
    std::optional<double> groundHeight(const Geodetic2D& position) const override;
    bool drawsGround() const override { return true; }
    /// Over the tiles drawn in this frame's update that meet the extent: their vertices' heights as
    /// drawn (stitched, morphing), the lowest less what the flat triangles sag; skirts left out.
    std::optional<HeightInterval> drawnHeights(const GeodeticExtent& extent) const override;

    /// A tile drawn in the last frame and the region that bounds it (its oriented box is what the
    /// frustum culls, its horizon point what the horizon culls), for showing the selection.
    struct DrawnTile {
        TileKey key;
        BoundingRegion region;
    };
    std::vector<DrawnTile> drawnTiles() const;

    /// The triangles of the surface drawn in the last frame (Earth-fixed, three points each, as
    /// the GPU receives them), for checking that it is watertight.
    std::vector<glm::dvec3> drawnTriangles() const;

    /// A load this globe started: a surface tile's mesh (layer -1) or an imagery layer's tile.
    struct Load {
        int layer;
        TileKey key;
        friend bool operator==(const Load&, const Load&) = default;
    };
    /// The loads started in the last frame, in the order they started.
    const std::vector<Load>& loadsStarted() const noexcept { return _loadsStarted; }

private:
    struct Impl;
    std::unique_ptr<Impl> _impl;
    TiledGlobeOptions _options;
    TileStatistics _statistics;
    std::vector<Load> _loadsStarted;
};

} // namespace orbis::scene
