#pragma once

#include "orbis/scene/FrameState.h"
#include "orbis/scene/PageRequests.h"
#include "orbis/scene/TileStatistics.h"
#include "orbis/scene/TiledGlobe.h"
#include "orbis/scene/VirtualTextureStatistics.h"

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/Image.h>
#include <orbis/core/VirtualTextureLayout.h>
#include <orbis/world/TileLoader.h>

#include <glm/vec4.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>
#include <optional>
#include <string>

namespace orbis::world {
class TileSource;
} // namespace orbis::world

namespace orbis::scene {

class PageTable;

/// How a virtual texture is cut, stored, fed back and filtered; the defaults are Mayer's base
/// configuration (256-texel pages, quarter-resolution feedback, priorities) with idTech 5's
/// 4-texel border.
struct VirtualTextureOptions {
    int pageSize = 256;  ///< texels a side of a page's content, a power of two 16..1024
    int border = 4;      ///< texels of the neighbours around each page, 0 to pageSize / 4
    /// Slots in the physical texture (at least 4); the texture is that many pages of
    /// (pageSize + 2 border)^2 texels, about square, and must fit the device's maximum size.
    int physicalPages = 256;
    /// The feedback pass's width and height are the frame's divided by this: 1 full, 2 half,
    /// 4 quarter resolution.
    int feedbackDivisor = 4;
    /// Frames between drawing a feedback buffer and reading it back (at least 1). With the
    /// loader's deterministic timing it is read exactly then, waiting if the GPU is not done;
    /// with asynchronous timing at the first frame after that in which its fence has signalled.
    int feedbackLatencyFrames = 1;
    RequestOrder requestOrder = RequestOrder::PixelCount;
    /// Blend the two nearest levels (course 6.1.2); false: the nearest level alone.
    bool trilinear = true;
    /// Anisotropic filtering of the physical texture, 1 (none) to 2 x border (the footprint must
    /// stay inside the border) and the device's limit.
    float maximumAnisotropy = 1.0f;
    double lodBias = 0.0; ///< levels added to every pixel's level of detail (> 0: coarser)
    /// Raise the bias while the view needs more pages than the physical texture holds (Mayer
    /// 4.3.2), instead of evicting pages the frame uses.
    bool dynamicLodBias = true;
    /// Page uploads stop for the frame once this many bytes went up (at least one page a frame).
    std::size_t uploadBytesPerFrame = std::size_t{4} << 20;
    /// Decoded source tiles kept to cut the next pages from (world::VirtualTextureSourceOptions).
    std::size_t tileCacheBytes = std::size_t{64} << 20;
    /// The hardware path (course chapter 5, partially resident textures): one sparse texture the
    /// size of the finest level, with its mip chain, each page committed at its own place when it
    /// arrives and released when evicted (physicalPages then caps the pages committed), read with
    /// the hardware's filtering across pages: no border, no page-table translation. Needs
    /// GL_ARB_sparse_texture, a finest level within the device's sparse texture size and pages of
    /// whole sparse pages wider than 2^(finest level) texels; otherwise the software path, with a
    /// warning saying why. Filters with
    /// textureLod (trilinear or the nearest level): maximumAnisotropy must be 1.
    bool sparse = false;
};

struct VirtualTextureGlobeOptions {
    /// A geographic imagery source: TMS folder, {z}/{x}/{y} template, MBTiles, HTTP.
    std::shared_ptr<world::TileSource> source;
    /// Alpha, brightness, contrast and gamma as for a tiled globe's layer; a rectangle is not
    /// supported (the constructor throws).
    ImageryLayerStyle style;
    VirtualTextureOptions virtualTexture;
    /// The surface's tiles, as a TiledGlobe selects them (the same geometry, so that the two can
    /// be compared pixel for pixel).
    double maximumScreenSpaceError = 2.0;
    int samplesLog2 = 4;
    /// Each tile's rows drawn with the program their pixels need, so that the mip tail's lookup
    /// and the second level's read run only near the horizon or the limb; false: a whole tile with
    /// the program its most demanding rows need. The same picture either way; false is slower.
    bool programsPerRow = true;
    /// Loads pages on worker threads; maximumStartsPerFrame is the loader's budget in pages.
    world::TileLoaderOptions loader;
    /// Surface tiles' meshes kept on the GPU at most (bytes); the least recently drawn go first.
    std::size_t meshCacheBytes = std::size_t{32} << 20;
    /// Lit by the scene's Sun (Scene::setSunDirection). Off by default, as in a scene file that
    /// places no Sun and as CesiumJS's globe: the colours as they are, no lighting computed (no
    /// "lighting" effect in the statistics).
    bool lighting = false;
    glm::vec4 baseColor{0.2f, 0.35f, 0.6f, 1.0f};
    /// Receives each warning once (a page that failed); empty: they go to the standard error.
    std::function<void(const std::string&)> onWarning;
};

/// The globe's surface textured by one virtual texture (Mayer's thesis; course chapter 6): the same
/// tiles on the ellipsoid as a TiledGlobe (TileQuadtree, TileMesh), all reading one virtual texture
/// over the whole Earth through a page table, instead of one texture per tile. Each frame:
///  1. pages loaded on the workers (cut from the source's tiles, world::VirtualTextureSource) go
///     into free or least recently used slots of the physical texture, coarse before fine, under
///     an upload budget; the page table's changed rectangles and the LOD clamp follow;
///  2. the feedback pass, at reduced resolution, casts each pixel's ray at the ellipsoid (one
///     rectangle around the globe's outline, not the tiles' triangles) and writes the page that
///     the frame's own pixel there asks for, into a pixel buffer read a frame or more later (no
///     stall);
///  3. the feedback read back this frame is reduced to pages with pixel counts; the pages and their
///     ancestors not resident are requested, most pixels and coarsest first, requests no longer
///     seen are cancelled, and the LOD bias rises while the view needs more pages than fit.
/// The two level-0 pages are loaded before the first frame and never leave: every pixel always
/// has a page. With deterministic loader timing a camera path gives the same frames every run.
class VirtualTextureGlobe final : public Primitive {
public:
    /// Throws orbis::Error for a source that is not geographic, options out of range, or a style
    /// with a rectangle.
    VirtualTextureGlobe(const Ellipsoid& ellipsoid, VirtualTextureGlobeOptions options);
    ~VirtualTextureGlobe() override;

    const VirtualTextureGlobeOptions& options() const noexcept { return _options; }
    const VirtualTextureLayout& layout() const noexcept;

    std::optional<BoundingSphere> boundingSphere() const override;
    void update(FrameState& frameState, CommandList& commands) override;
    bool supportsLogarithmicDepth() const override { return true; }
    const TileStatistics* tileStatistics() const override { return &_tileStatistics; }
    const VirtualTextureStatistics* virtualTextureStatistics() const override { return &_statistics; }

    bool converged() const noexcept { return _statistics.converged; }

    /// The CPU copy of the page table.
    const PageTable& pageTable() const noexcept;

    /// Pictures of the machinery, for the example and for debugging (each reads the GPU, slowly):
    /// the physical texture as it is (empty on the sparse path, which has none);
    Image physicalTextureImage() const;
    /// the finest level of the page table, a pixel per page, coloured by the level it shows;
    Image pageTableImage() const;
    /// the latest feedback buffer read back, coloured by the level asked for, fallbacks in white,
    /// top row first. Empty before the first read-back.
    Image feedbackImage() const;
    /// The latest feedback buffer read back, a sample a pixel, rows from the bottom; empty before
    /// the first read-back.
    struct Feedback {
        int width = 0;
        int height = 0;
        std::vector<FeedbackSample> samples;
    };
    Feedback feedback() const;
    /// The colour (RGBA) pageTableImage and feedbackImage give a level.
    static std::array<std::uint8_t, 4> levelColor(std::uint32_t level) noexcept;

private:
    struct Impl;
    std::unique_ptr<Impl> _impl;
    VirtualTextureGlobeOptions _options;
    VirtualTextureStatistics _statistics;
    TileStatistics _tileStatistics;
};

} // namespace orbis::scene
