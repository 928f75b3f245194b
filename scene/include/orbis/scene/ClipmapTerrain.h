#pragma once

#include "orbis/scene/ClipmapStatistics.h"
#include "orbis/scene/FrameState.h"
#include "orbis/scene/TerrainShading.h"
#include "orbis/scene/TiledGlobe.h"

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/Geodetic.h>
#include <orbis/world/TileLoader.h>

#include <glm/vec4.hpp>

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace orbis::renderer {
struct SceneState;
}

namespace orbis::world {
class TerrainSource;
} // namespace orbis::world

namespace orbis::scene {

struct ClipmapTerrainOptions {
    /// Heights (world::openTerrainSource); none: the ellipsoid itself.
    std::shared_ptr<world::TerrainSource> terrain;
    /// Draped on the grids: the first layer (geographic or Web Mercator tiles) colours the posts;
    /// none: baseColor.
    std::vector<ImageryLayer> imagery;
    /// Posts a side of each level: 2^k - 1, 15 .. 1023.
    int posts = 255;
    /// Levels of the pyramid; 0: from the finest data (finestSpacingDegrees) up to the coarsest
    /// level that keeps clear of the grid's poles.
    int levels = 0;
    /// Post spacing of level 0; 0: an eighth of the terrain's finest sample spacing (the levels
    /// below the data's are the four-point filter's), or 1/64 degree without terrain.
    double finestSpacingDegrees = 0.0;
    double exaggeration = 1.0;
    /// Posts written (heights, normals, colour) per frame at most, coarse levels first; a level
    /// with writes left is not drawn. Default: two full levels of 255.
    std::size_t postsPerFrame = 2 * 256 * 256;
    world::TileLoaderOptions loader;
    /// Terrain and imagery tiles kept on the CPU, bytes.
    std::size_t cacheBytes = std::size_t{128} << 20;
    /// Lit by the scene's Sun (Scene::setSunDirection). Off by default, as in a scene file that
    /// places no Sun and as CesiumJS's globe: the colours as they are, no lighting computed (no
    /// "lighting" effect in the statistics).
    bool lighting = false;
    glm::vec4 baseColor{0.2f, 0.35f, 0.6f, 1.0f};
    /// Each level in its own colour (a palette of eight), as the book's figure 13.3.
    bool colorByLevel = false;
    /// Colour by height or slope (under the imagery, which covers it), contours, hillshade: the
    /// tiles' shading (shaders/scene/terrain/terrain_shading.glsl), from the same heights and normals.
    TerrainShading shading;
    /// Receives each warning once (a tile that failed); empty: the standard error stream.
    std::function<void(const std::string&)> onWarning;
};

/// Terrain drawn with geometry clipmaps on the globe (book chapter 13; Losasso and Hoppe 2004;
/// Asirvatham and Hoppe, GPU Gems 2 chapter 2): L nested grids of n x n posts centred on the
/// viewer, level l's posts 2^l times level 0's spacing apart, each moved in steps of two of its
/// posts. All levels share one vertex buffer (the n x n post numbers) and the index ranges of
/// orbis::ClipmapBlockLayout; the vertex shader fetches each post's height from its level's
/// texture, addressed toroidally, and blends height, normal and colour with the next coarser level
/// over each level's outer band (n / 10 posts), so the levels meet without seam or pop.
///
/// The grids lie in latitude-longitude coordinates of one of three parameterisations: geodetic,
/// and two rotations of it whose poles lie on the equator (at 0 and 90 degrees east). The
/// geodetic grid serves while the viewer is within 40 degrees of the equator; beyond, the rotated
/// one whose pole is farther from the viewer (who is then within 32.8 degrees of its equator),
/// until the viewer is back within 30 degrees of the equator. The coarsest level spans no more than 48 degrees from its
/// centre, so no post comes within 2 degrees of the grid's pole: no collapsed or inverted
/// triangle anywhere, the geographic poles included. A switch rewrites every level (coarse
/// first). The grid's longitude is unbounded (followed continuously from frame to frame), so the
/// antimeridian is no edge: post positions are computed from their offsets to the level's centre,
/// whose sines and cosines the CPU gives in double.
///
/// Positions reach the GPU relative to the eye: each level's centre relative to the eye in double
/// on the CPU, each post's offset from that centre in float from small-angle differences, so
/// nothing jitters near the viewer. Each level is drawn with at most two draws (its pieces are
/// in angular order and the view keeps one arc of them); the finest drawn level adds its
/// interior: at most 2L + 1 draws a frame. Pieces outside the view frustum are culled.
///
/// Heights come from the finest terrain tile loaded over each post (loaded on the world layer's
/// TileLoader at the level whose spacing matches the post spacing), or from the next coarser
/// level through the four-point filter where the data are no finer than that level's.
class ClipmapTerrain final : public Primitive {
public:
    /// Throws orbis::Error for posts not 2^k - 1 in 15 .. 1023, levels < 0 or > 24, a spacing or
    /// exaggeration below 0 or not finite, an ellipsoid that is not one of revolution, shading
    /// options out of range.
    ClipmapTerrain(const Ellipsoid& ellipsoid, ClipmapTerrainOptions options);
    ~ClipmapTerrain() override;

    const ClipmapTerrainOptions& options() const noexcept { return _options; }
    int levels() const noexcept;
    /// Radians between level 0's posts.
    double finestSpacing() const noexcept;

    std::optional<BoundingSphere> boundingSphere() const override;
    void update(FrameState& frameState, CommandList& commands) override;
    bool supportsLogarithmicDepth() const override { return true; }
    const ClipmapStatistics* clipmapStatistics() const override { return &_statistics; }
    /// The height (as drawn, exaggeration included) of the finest level drawn in the last frame
    /// over a point: on the triangle of its posts that holds it, the posts blended towards the
    /// coarser level as the vertex shader blends them (interpolated in the grid's angles: the flat
    /// triangle drawn sags below that by (cell / 2)^2 / (2 x radius) at most, centimetres on the
    /// finest levels); empty before the first frame and outside every level drawn.
    std::optional<double> groundHeight(const Geodetic2D& position) const override;
    bool drawsGround() const override { return true; }
    /// Over the levels drawn in this frame's update whose part of the grid meets the extent (a cap
    /// around it, in the grid's angles): the heights each has held, and the coarser level's it
    /// blends towards, the lowest less what its cells sag; and the backdrop's where it is drawn.
    std::optional<HeightInterval> drawnHeights(const GeodeticExtent& extent) const override;

    /// Every level written from the finest data there is, nothing pending.
    bool converged() const noexcept { return _statistics.converged; }

    /// The triangles drawn in the last frame (Earth-fixed, metres, three points each, with the
    /// heights and the blending the vertex shader applies), computed on the CPU from the same
    /// data, for checking orientation and finiteness. Degenerate outer-ring triangles included
    /// when `withDegenerates`.
    std::vector<glm::dvec3> drawnTriangles(bool withDegenerates = false) const;
    /// The same triangles, one call each, without a list of them.
    void forEachDrawnTriangle(bool withDegenerates,
                              const std::function<void(const glm::dvec3&, const glm::dvec3&, const glm::dvec3&)>& visit) const;
    /// What the GPU computed for the same triangles: each vertex's clip position in the last
    /// frame's draws, read back with transform feedback (Context::captureVertexOutputs) under
    /// `sceneState`, in the order and number of forEachDrawnTriangle(true)'s points. For measuring
    /// the positions' precision (jitter) against those, as docs/precision.md measures transforms.
    std::vector<glm::vec4> captureDrawnClipPositions(renderer::Context& context, const renderer::SceneState& sceneState) const;
    /// The distance along the ray (unit direction) to the nearest drawn triangle it meets (exact,
    /// every drawn triangle tested against the ray: milliseconds for a click, not for every frame).
    std::optional<double> pickGround(const Ray& ray) const override;

private:
    struct Impl;
    std::unique_ptr<Impl> _impl;
    ClipmapTerrainOptions _options;
    ClipmapStatistics _statistics;
};

} // namespace orbis::scene
