#include "orbis/scene/VirtualTextureGlobe.h"

#include "TileGeometry.h"
#include "VectorSupport.h"

#include "orbis/scene/DepthStrategy.h"
#include "orbis/scene/Effect.h"
#include "orbis/scene/PageTable.h"
#include "orbis/scene/PhysicalPageCache.h"
#include "orbis/scene/TileQuadtree.h"

#include <orbis/core/Error.h>
#include <orbis/core/ImageMipmaps.h>
#include <orbis/core/IntersectionTests.h>
#include <orbis/core/TileMesh.h>
#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>
#include <orbis/renderer/Fence.h>
#include <orbis/renderer/Framebuffer.h>
#include <orbis/renderer/PixelBuffer.h>
#include <orbis/renderer/Sampler.h>
#include <orbis/renderer/ShaderCache.h>
#include <orbis/renderer/ShaderProgram.h>
#include <orbis/renderer/Texture2D.h>
#include <orbis/world/TileSource.h>
#include <orbis/world/VirtualTextureSource.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <deque>
#include <iostream>
#include <limits>
#include <map>
#include <set>
#include <tuple>
#include <string>
#include <unordered_set>
#include <utility>

namespace orbis::scene {

namespace {

/// A surface tile's mesh on the GPU, made when the tile is first drawn.
struct SurfaceTile final : TileData {
    std::optional<detail::TileGpuMesh> mesh;
    std::uint64_t lastDrawnFrame = 0;
};

SurfaceTile& surfaceOf(QuadtreeTile& tile)
{
    return static_cast<SurfaceTile&>(*tile.data);
}

/// A page cut on a worker: its slot's texels, rows from the north.
struct PageContent final : world::TileContent {
    explicit PageContent(Image image_) : image(std::move(image_)) {}
    std::size_t byteSize() const noexcept override { return image.pixels.size(); }
    Image image;
};

/// What a feedback buffer was drawn from: the view and the bias. A feedback describes the present
/// picture only while these are the same.
struct FeedbackView {
    glm::dvec3 eye{0.0};
    glm::dvec3 target{0.0};
    glm::dvec3 up{0.0};
    double fieldOfViewY = 0.0;
    int width = 0;
    int height = 0;
    double lodBias = 0.0;
    friend bool operator==(const FeedbackView&, const FeedbackView&) = default;
};

/// What a feedback pass draws from: the view and the page table's and LOD clamp's contents
/// (their version). A frame with the same inputs would draw the same feedback.
struct FeedbackInputs {
    FeedbackView view;
    std::uint64_t tablesVersion = 0;
    friend bool operator==(const FeedbackInputs&, const FeedbackInputs&) = default;
};

/// A feedback buffer on its way back from the GPU.
struct FeedbackRead {
    std::uint64_t frame = 0;
    renderer::PixelBuffer buffer;
    renderer::Fence fence;
    int width = 0;
    int height = 0;
    FeedbackView view;
};

/// The LOD clamp's "no page waits here" (vtLodClamp): far below any level of detail.
constexpr float kNoClamp = -1000.0f;

std::uint64_t ticketOf(const PageKey& page)
{
    return VirtualTextureLayout::linearIndex(page) + 1;
}

std::string pageName(const PageKey& page)
{
    return std::to_string(page.level) + "/" + std::to_string(page.x) + "/" + std::to_string(page.y);
}

/// The physical texture's slots: about square.
std::pair<int, int> slotGrid(int pages)
{
    const int across = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(pages))));
    return {across, (pages + across - 1) / across};
}

void validate(const VirtualTextureGlobeOptions& options)
{
    const VirtualTextureOptions& vt = options.virtualTexture;
    if (!options.source) {
        throw Error("VirtualTextureGlobe: no imagery source");
    }
    if (options.style.rectangle) {
        throw Error("VirtualTextureGlobe: a virtual texture covers the whole globe; an imagery rectangle is not "
                    "supported with it");
    }
    if (vt.physicalPages < 4) {
        throw Error("VirtualTextureGlobe: physicalPages must be at least 4 (the two coarsest pages never leave), not " +
                    std::to_string(vt.physicalPages));
    }
    if (vt.feedbackDivisor < 1 || vt.feedbackDivisor > 16) {
        throw Error("VirtualTextureGlobe: feedbackDivisor must be 1 to 16, not " + std::to_string(vt.feedbackDivisor));
    }
    if (vt.feedbackLatencyFrames < 1 || vt.feedbackLatencyFrames > 8) {
        throw Error("VirtualTextureGlobe: feedbackLatencyFrames must be 1 to 8, not " +
                    std::to_string(vt.feedbackLatencyFrames));
    }
    if (!(vt.maximumAnisotropy >= 1.0f) || vt.maximumAnisotropy > std::max(1.0f, 2.0f * static_cast<float>(vt.border))) {
        throw Error("VirtualTextureGlobe: maximumAnisotropy must be 1 to twice the border (" +
                    std::to_string(2 * vt.border) + "), so that the filter stays inside the page's border");
    }
    if (vt.sparse && vt.maximumAnisotropy > 1.0f) {
        throw Error("VirtualTextureGlobe: the sparse path filters with textureLod, trilinearly or the nearest level: "
                    "maximumAnisotropy must be 1 with it");
    }
    if (!std::isfinite(vt.lodBias)) {
        throw Error("VirtualTextureGlobe: lodBias must be a finite number of levels");
    }
    if (!(options.maximumScreenSpaceError > 0.0)) {
        throw Error("VirtualTextureGlobe: maximumScreenSpaceError must be above 0 pixels");
    }
    if (options.samplesLog2 < 1 || options.samplesLog2 > 7) {
        throw Error("VirtualTextureGlobe: samplesLog2 must be 1 to 7, not " + std::to_string(options.samplesLog2));
    }
}

/// The levels a tile's pixels may show (Impl::pixelLevels); its program reads only those.
enum class PixelLevels {
    Finest,      ///< every pixel magnifies the finest level, which is read alone
    Blended,     ///< two levels blended (trilinear filtering): two reads a pixel
    WithMipTail, ///< blended, and some pixels coarser than level 0: the mip tail's lookup too
};

} // namespace

struct VirtualTextureGlobe::Impl {
    Impl(const Ellipsoid& ellipsoid_, const VirtualTextureGlobeOptions& options_)
        : ellipsoid(ellipsoid_)
        , options(&options_)
        , pages(std::make_shared<world::VirtualTextureSource>(
              options_.source,
              world::VirtualTextureSourceOptions{options_.virtualTexture.pageSize, options_.virtualTexture.border,
                                                 options_.virtualTexture.tileCacheBytes}))
        , layout(pages->layout())
        , quadtree(ellipsoid_, TilingScheme::geographic(), 64,
                   [](QuadtreeTile& tile) {
                       tile.data = std::make_unique<SurfaceTile>();
                       tile.wantsLoad = false; // meshes are made when drawn: nothing to wait for
                   })
        , loader(options_.loader)
        , pageTable(layout.finestLevel)
        , indexBuffers(options_.samplesLog2, false)
    {
        const auto [across, up] = slotGrid(options_.virtualTexture.physicalPages);
        cache.emplace(across, up);
    }

    void start(FrameState& frameState);
    /// The slots and the mip tail's strip in one texture (the software path).
    void createPhysicalTexture(FrameState& frameState);
    /// The sparse texture (VirtualTextureOptions::sparse), level 0 and the mip tail committed for
    /// good; false, with a warning saying why, where the device cannot have it.
    bool createSparseTexture(renderer::Device& device);
    /// A page's texels in the sparse texture, at its level's mipmap level.
    renderer::PixelRectangle sparseRegion(const PageKey& page) const noexcept
    {
        const int size = layout.pageSize;
        return {static_cast<int>(page.x) * size, static_cast<int>(page.y) * size, size, size};
    }
    int sparseMipmapLevel(const PageKey& page) const noexcept { return static_cast<int>(layout.finestLevel - page.level); }
    void receive(world::TileLoadResult result);
    bool uploadPage(FrameState& frameState, const PageKey& page, const Image& image);
    /// Sends the page table's changed rectangles, and the LOD clamp's, to the GPU.
    void uploadTables();
    /// Level 0 halved down to 1 x 1 (level 0: its two pages side by side, rows from the north),
    /// into the strip below the slots (VirtualTextureLayout::tailOffset), or the sparse texture's
    /// mipmap levels below level 0's.
    void uploadTail(const Image& level0);
    /// Whether it uploaded anything.
    bool updateLodClamp();
    void readFeedback(FrameState& frameState);
    /// Marks the pages the latest feedback asks for (their ancestors with them) used in `frame`.
    void touchNeeded(std::uint64_t frame);
    /// Where the mip tail's strip starts up the physical texture: above the slots.
    int tailStripY() const noexcept { return cache->slotsY() * layout.slotSize(); }
    void adjustBias();
    void requestPages();
    void drawFeedback(FrameState& frameState, const FeedbackView& drawnFrom);
    /// The rectangle of a width x height view, in clip coordinates (x and y of its lower left and
    /// upper right corners), holding the globe's outline with a margin of `margin` pixels; the
    /// whole view where the outline reaches behind the eye.
    glm::vec4 globeBounds(const Camera& camera, int width, int height, double margin) const;
    void ensureMeshes(FrameState& frameState);
    /// The program of a pass: for the main pass, reading the levels a tile's pixels may show;
    /// with the LOD clamp's ramp while a page the view asks for is loading. Variants rather than
    /// branches: llvmpipe runs both sides of every branch for every pixel.
    renderer::ShaderProgram& program(FrameState& frameState, bool feedback, PixelLevels levels);
    /// How far from the point under the eye the view's pixels reach, and how large a pixel's
    /// footprint on the ground is at most in the view (pixelLevels).
    struct ViewReach {
        double angle = 0.0;      ///< radians at the centre; the horizon's where the view reaches it
        double footprint = 0.0;  ///< metres, the long axis; infinite where the view reaches the horizon
        double pixelAngle = 0.0; ///< radians across the pixel at the view's centre, the widest
        glm::dvec3 down{0.0};    ///< the unit vector from the Earth's centre towards the eye
        double opposite = 0.0;   ///< the meridian opposite the eye's (radians)
    };
    ViewReach viewReach(const FrameState& frameState) const;
    /// The largest angle at the Earth's centre between the point under the eye and a point of a
    /// latitude between two longitudes.
    double farthestAlong(const ViewReach& reach, double latitude, double west, double east) const;
    /// The levels the pixels of a part of the surface may show, within the view's reach; farthest:
    /// the part's largest angle from the point under the eye (farthestAlong its north and south edges).
    PixelLevels pixelLevels(const FrameState& frameState, const GeodeticExtent& extent, double farthest,
                            const ViewReach& reach) const;
    /// A run of a tile's triangles drawn with one program (TileMesh::indexLayout).
    struct TilePart {
        std::size_t first = 0;
        std::size_t count = 0;
        PixelLevels levels = PixelLevels::Finest;
    };
    /// A tile's triangles in runs whose pixels show the same levels: the inner grid's quads a row
    /// at a time, the ring an edge at a time. The programs that read more (the mip
    /// tail's lookup, the second level) then run only where the view needs them, near the horizon
    /// or the limb, rather than over every tile reaching there: llvmpipe runs a program's every
    /// instruction for every pixel.
    std::vector<TilePart> tileParts(const FrameState& frameState, const QuadtreeTile& tile, const ViewReach& reach) const;
    /// Whether the main pass blends two levels for a tile's pixels: with trilinear filtering,
    /// unless every pixel magnifies the finest level and no page waits (the LOD clamp's ramp can
    /// make any pixel coarser).
    bool blendsLevels(PixelLevels levels) const
    {
        return options->virtualTexture.trilinear && (levels != PixelLevels::Finest || !waitingFootprints.empty());
    }
    /// The uniforms both passes share.
    void setUniforms(renderer::DrawCommand& draw, double bias) const;
    bool evictable(const PageKey& page) const;
    double bias() const noexcept { return options->virtualTexture.lodBias + dynamicBias; }
    void warn(const std::string& message) const;
    std::size_t gpuBytes() const noexcept;

    Ellipsoid ellipsoid;
    const VirtualTextureGlobeOptions* options;
    std::shared_ptr<world::VirtualTextureSource> pages; ///< shared with the workers' loads
    VirtualTextureLayout layout;
    TileQuadtree quadtree;
    world::TileLoader loader;
    PageTable pageTable;
    std::optional<PhysicalPageCache> cache;
    detail::TileIndexBuffers indexBuffers;
    bool started = false;
    bool sparse = false; ///< the sparse texture is the physical texture (createSparseTexture)
    std::optional<std::uint64_t> streamedFrame;
    VirtualTextureStatistics statistics; ///< this frame's, being filled
    std::size_t missingCount = 0;
    bool warnedOutside = false; ///< a feedback naming pages beyond the texture was reported
    std::size_t failedCount = 0;

    // Pages on their way: loads started, and pages loaded and waiting for their upload.
    std::set<PageKey> inFlight;
    std::map<PageKey, Image> arrived;

    // The latest feedback read back, and what the view needs from it.
    std::optional<FeedbackView> feedbackView;
    std::optional<FeedbackInputs> lastFeedbackInputs; ///< of the last feedback pass drawn
    std::uint64_t tablesVersion = 0;                  ///< counts the frames the tables changed in
    FeedbackSummary summary;
    std::vector<PageCount> needed;
    std::unordered_set<PageKey, TileKeyHash> neededSet;
    std::vector<std::uint32_t> feedbackSamples; ///< rows bottom to top
    int feedbackSamplesWidth = 0;
    int feedbackSamplesHeight = 0;
    double dynamicBias = 0.0;
    bool requestsOutstanding = false;

    // GPU resources, made on the first frame.
    std::shared_ptr<renderer::Texture2D> physical; ///< the slots, or the sparse texture
    std::optional<renderer::Texture2D> pageTableTexture;
    std::optional<renderer::Texture2D> lodClamp;
    /// Per page of the finest level: the coarsest level of detail its resident pages allow, and the
    /// same where a page the view asks for is still missing there (else none): see vtLodClamp. On
    /// the sparse path also its eight neighbours' reds, packed (packResidencyNeighbours).
    std::vector<glm::vec4> clampValues;
    /// Channels of the LOD clamp texture: RG32F, RGBA32F on the sparse path.
    int clampChannels() const noexcept { return sparse ? 4 : 2; }
    std::vector<std::uint8_t> waiting;               ///< finest pages under a page asked for, not resident
    std::vector<PageRectangle> waitingFootprints;    ///< those pages' extents at the finest level
    std::optional<renderer::Sampler> physicalSampler;
    std::optional<renderer::Sampler> pointSampler;
    std::unique_ptr<renderer::Framebuffer> feedbackTarget;
    std::optional<renderer::VertexBuffer> feedbackRectangleVertices; ///< two triangles, corners 0..1
    std::optional<renderer::VertexArray> feedbackRectangle;
    std::deque<FeedbackRead> feedbackReads; ///< oldest first
    std::vector<renderer::PixelBuffer> spareBuffers;
    std::map<std::tuple<bool, DepthStrategy, bool, bool, bool>, std::shared_ptr<renderer::ShaderProgram>> programs;

    // The surface.
    TileSelection selection;
    std::vector<QuadtreeTile*> meshTiles; ///< tiles with a mesh on the GPU
    std::size_t meshBytes = 0;
    std::size_t meshUploadedBytes = 0;
    std::vector<std::uint8_t> staging;
    std::vector<float> tableTexels; ///< uploadTables', kept for its memory
};

void VirtualTextureGlobe::Impl::warn(const std::string& message) const
{
    if (options->onWarning) {
        options->onWarning(message);
    } else {
        std::cerr << "orbis: " << message << "\n";
    }
}

std::size_t VirtualTextureGlobe::Impl::gpuBytes() const noexcept
{
    std::size_t bytes = 0;
    if (sparse) {
        // The pages committed, and level 0's mipmap levels below it, counted in texels (the
        // driver rounds the smallest up to a whole sparse page).
        const std::size_t page = static_cast<std::size_t>(layout.pageSize) * layout.pageSize * 4;
        bytes += cache->size() * page;
        for (int t = 1; t <= layout.tailLevels(); ++t) {
            bytes += static_cast<std::size_t>(layout.tailSize(t).x) * layout.tailSize(t).y * 4;
        }
    } else if (physical) {
        bytes += static_cast<std::size_t>(physical->width()) * physical->height() * 4;
    }
    if (pageTableTexture) {
        bytes += static_cast<std::size_t>(pageTableTexture->width()) * pageTableTexture->height() * 8;
    }
    bytes += clampValues.size() * sizeof(float) * static_cast<std::size_t>(clampChannels());
    if (feedbackTarget) {
        // Colour alone (the pass casts rays: no depth), and the pixel buffers in flight or spare.
        bytes += static_cast<std::size_t>(feedbackTarget->width()) * feedbackTarget->height() * 4;
    }
    for (const FeedbackRead& read : feedbackReads) {
        bytes += read.buffer.sizeInBytes();
    }
    for (const renderer::PixelBuffer& buffer : spareBuffers) {
        bytes += buffer.sizeInBytes();
    }
    return bytes;
}

bool VirtualTextureGlobe::Impl::evictable(const PageKey& page) const
{
    if (page.level == 0) {
        return false; // the coarsest pages are every pixel's last fallback
    }
    if (page.level < layout.finestLevel) {
        for (int c = 0; c < 4; ++c) {
            if (pageTable.isMapped(page.child(c))) {
                return false; // a mapped page's ancestors stay: they are its fallbacks
            }
        }
    }
    return true;
}

void VirtualTextureGlobe::Impl::createPhysicalTexture(FrameState& frameState)
{
    renderer::Device& device = frameState.device;
    const int maximum = device.info().maxTextureSize;
    const int slot = layout.slotSize();
    // The slots, and the mip tail's strip below them.
    const int physicalWidth = std::max(cache->slotsX() * slot, layout.tailStripSize().x);
    const int physicalHeight = tailStripY() + layout.tailStripSize().y;
    if (physicalWidth > maximum || physicalHeight > maximum) {
        throw Error("VirtualTextureGlobe: a physical texture of " + std::to_string(cache->capacity()) + " pages of " +
                    std::to_string(slot) + " texels is " + std::to_string(physicalWidth) + " x " +
                    std::to_string(physicalHeight) + " texels, beyond this device's " + std::to_string(maximum) +
                    "; ask for fewer physicalPages or a smaller pageSize");
    }
    physical = std::make_shared<renderer::Texture2D>(device.createTexture2D(
        {physicalWidth, physicalHeight, renderer::TextureFormat::RGBA8, false}));
    // Defined texels in the empty slots, dark grey in pictures of the physical texture; no pixel
    // ever reads them.
    renderer::Framebuffer target = frameState.context.createFramebuffer();
    target.setColorAttachment(0, physical);
    renderer::ClearState clear;
    clear.color = glm::vec4(0.1f, 0.1f, 0.1f, 1.0f);
    frameState.context.clear(clear, &target);
}

bool VirtualTextureGlobe::Impl::createSparseTexture(renderer::Device& device)
{
    const renderer::DeviceInfo& info = device.info();
    const int width = static_cast<int>(layout.texelsX(layout.finestLevel));
    const int height = static_cast<int>(layout.texelsY(layout.finestLevel));
    const int finest = static_cast<int>(layout.finestLevel);
    std::string why;
    if (!info.sparseTexture) {
        why = "the device lacks GL_ARB_sparse_texture";
    } else if ((1 << finest) >= layout.pageSize) {
        // vtSparseLod: the square the taps reach (up to 2^finest texels of the finest level from
        // the point) must stay within a page's neighbours.
        why = "pages of " + std::to_string(layout.pageSize) + " texels are too small for a finest level " +
              std::to_string(finest) + " deep (more than 2^" + std::to_string(finest) + " texels are needed)";
    } else if (width > info.maxSparseTextureSize) {
        why = "its finest level, " + std::to_string(width) + " x " + std::to_string(height) +
              " texels, is beyond the device's " + std::to_string(info.maxSparseTextureSize) + " for a sparse texture";
    } else {
        const renderer::SparsePageSize page = device.sparsePageSize(renderer::TextureFormat::RGBA8);
        if (page.width < 1 || page.height < 1 || layout.pageSize % page.width != 0 || layout.pageSize % page.height != 0) {
            why = "pages of " + std::to_string(layout.pageSize) + " texels are not whole sparse pages of " +
                  std::to_string(page.width) + " x " + std::to_string(page.height);
        }
    }
    if (why.empty()) {
        renderer::TextureDescription description{width, height, renderer::TextureFormat::RGBA8, true};
        description.sparse = true;
        physical = std::make_shared<renderer::Texture2D>(device.createTexture2D(description));
        if (physical->sparseLevelCount() < finest) {
            why = "the device commits only " + std::to_string(physical->sparseLevelCount()) + " of its " +
                  std::to_string(finest) + " finest levels a page at a time";
            physical.reset();
        }
    }
    if (!why.empty()) {
        warn("virtual texture: the software path, not the sparse texture asked for: " + why);
        return false;
    }
    // Level 0 and the levels below it never leave.
    for (int level = finest; level < physical->levelCount(); ++level) {
        physical->commit({0, 0, std::max(1, width >> level), std::max(1, height >> level)}, level, true);
    }
    return true;
}

void VirtualTextureGlobe::Impl::start(FrameState& frameState)
{
    renderer::Device& device = frameState.device;
    const int maximum = device.info().maxTextureSize;
    const int slot = layout.slotSize();
    const std::uint32_t pagesX = VirtualTextureLayout::pagesX(layout.finestLevel);
    const std::uint32_t pagesY = VirtualTextureLayout::pagesY(layout.finestLevel);
    const glm::uvec2 tableSize = VirtualTextureLayout::pageTableSize(layout.finestLevel);
    if (static_cast<int>(pagesX) + 1 > maximum) {
        throw Error("VirtualTextureGlobe: the page table of " + pages->tileSource().info().name + " needs " +
                    std::to_string(pagesX + 1) + " texels across, beyond this device's " + std::to_string(maximum) +
                    "; use larger pages");
    }
    sparse = options->virtualTexture.sparse && createSparseTexture(device);
    if (!sparse) {
        createPhysicalTexture(frameState);
    }
    pageTableTexture = device.createTexture2D(
        {static_cast<int>(tableSize.x), static_cast<int>(tableSize.y), renderer::TextureFormat::RG32F, false});
    lodClamp = device.createTexture2D({static_cast<int>(pagesX), static_cast<int>(pagesY),
                                       sparse ? renderer::TextureFormat::RGBA32F : renderer::TextureFormat::RG32F, false});
    clampValues.assign(static_cast<std::size_t>(pagesX) * pagesY,
                       glm::vec4(static_cast<float>(layout.finestLevel), kNoClamp, 0.0f, 0.0f));
    waiting.assign(static_cast<std::size_t>(pagesX) * pagesY, 0);
    SamplerDescription linear;
    linear.maximumAnisotropy = options->virtualTexture.maximumAnisotropy;
    if (sparse) {
        // The hardware's own filtering across pages and levels; the antimeridian wraps.
        linear.minificationFilter = options->virtualTexture.trilinear ? TextureMinificationFilter::LinearMipmapLinear
                                                                      : TextureMinificationFilter::LinearMipmapNearest;
        linear.wrapS = TextureWrap::Repeat;
    }
    physicalSampler = device.createSampler(linear);
    SamplerDescription point;
    point.minificationFilter = TextureMinificationFilter::NearestMipmapNearest;
    point.magnificationFilter = TextureMagnificationFilter::Nearest;
    pointSampler = device.createSampler(point);

    // The coarsest level, here and now: every pixel of the first frame has a page; and the mip
    // tail made from it.
    Image level0(2 * layout.pageSize, layout.pageSize, 4);
    for (std::uint32_t x = 0; x < VirtualTextureLayout::pagesX(0); ++x) {
        const PageKey root{0, x, 0};
        std::optional<Image> image;
        try {
            image = pages->cutPage(root);
        } catch (const std::exception& error) {
            ++failedCount;
            warn("virtual texture: " + pages->describe(root) + " failed, drawn transparent: " + error.what());
        }
        if (!image) {
            image = Image(slot, slot, 4); // transparent: the base colour shows
        }
        uploadPage(frameState, root, *image);
        for (int row = 0; row < layout.pageSize; ++row) {
            std::memcpy(level0.pixel(static_cast<int>(x) * layout.pageSize, row),
                        image->pixel(layout.border, layout.border + row), static_cast<std::size_t>(layout.pageSize) * 4);
        }
    }
    uploadTail(level0);
    uploadTables();
}

bool VirtualTextureGlobe::Impl::uploadPage(FrameState& frameState, const PageKey& page, const Image& image)
{
    const std::optional<PhysicalPageCache::Placement> placement =
        cache->insert(page, frameState.frameNumber, [this](const PageKey& key) { return evictable(key); });
    if (!placement) {
        return false;
    }
    if (placement->evicted) {
        pageTable.unmap(*placement->evicted);
        ++statistics.pagesEvicted;
        if (sparse) {
            physical->commit(sparseRegion(*placement->evicted), sparseMipmapLevel(*placement->evicted), false);
        }
    }
    // Rows from the north in the image, from the south in GL. The sparse path takes the page's own
    // texels alone, to their place: the hardware filters across pages, so the border stays behind.
    const int skip = sparse ? layout.border : 0;
    const int size = sparse ? layout.pageSize : layout.slotSize();
    const std::size_t rowBytes = static_cast<std::size_t>(size) * 4;
    staging.resize(rowBytes * size);
    for (int row = 0; row < size; ++row) {
        std::memcpy(staging.data() + static_cast<std::size_t>(row) * rowBytes, image.pixel(skip, skip + size - 1 - row),
                    rowBytes);
    }
    const std::span<const std::byte> texels = std::as_bytes(std::span(staging));
    if (sparse) {
        if (page.level > 0) {
            physical->commit(sparseRegion(page), sparseMipmapLevel(page), true); // level 0's is for good
        }
        physical->copyFromSystemMemory(texels, sparseRegion(page), sparseMipmapLevel(page));
    } else {
        physical->copyFromSystemMemory(texels, {placement->slot.x * size, placement->slot.y * size, size, size});
    }
    pageTable.map(page, placement->slot.x, placement->slot.y);
    statistics.uploadedBytes += staging.size();
    ++statistics.pagesLoaded;
    return true;
}

void VirtualTextureGlobe::Impl::uploadTail(const Image& level0)
{
    const int border = layout.border;
    const std::vector<Image> chain = mipmapChain(level0);
    for (int t = 1; t <= layout.tailLevels(); ++t) {
        const Image& level = chain[static_cast<std::size_t>(t) - 1];
        if (sparse) {
            physical->copyFromImage(level, static_cast<int>(layout.finestLevel) + t);
            continue;
        }
        const int width = level.width + 2 * border, height = level.height + 2 * border;
        // Rows from the south, as GL has them; the border as a page's: the antimeridian wraps,
        // beyond a pole the edge row repeats.
        staging.resize(static_cast<std::size_t>(width) * height * 4);
        for (int y = 0; y < height; ++y) {
            const int row = std::clamp(level.height - 1 - (y - border), 0, level.height - 1);
            for (int x = 0; x < width; ++x) {
                const int column = ((x - border) % level.width + level.width) % level.width;
                std::memcpy(staging.data() + (static_cast<std::size_t>(y) * width + x) * 4, level.pixel(column, row), 4);
            }
        }
        physical->copyFromSystemMemory(std::as_bytes(std::span(staging)), {layout.tailOffset(t), tailStripY(), width, height});
    }
}

void VirtualTextureGlobe::Impl::uploadTables()
{
    const std::uint32_t finest = layout.finestLevel;
    bool changed = false;
    for (std::uint32_t level = 0; level <= finest; ++level) {
        const std::optional<PageRectangle>& dirty = pageTable.dirty(level);
        if (!dirty) {
            continue;
        }
        changed = true;
        pageTable.texels(level, *dirty, tableTexels);
        const glm::uvec2 origin = VirtualTextureLayout::pageTableOrigin(level, finest);
        pageTableTexture->copyFromSystemMemory(
            std::as_bytes(std::span(tableTexels)),
            {static_cast<int>(origin.x + dirty->x0), static_cast<int>(origin.y + dirty->y0),
             static_cast<int>(dirty->x1 - dirty->x0), static_cast<int>(dirty->y1 - dirty->y0)});
        statistics.uploadedBytes += tableTexels.size() * sizeof(float);
    }
    changed = updateLodClamp() || changed;
    pageTable.clearDirty();
    tablesVersion += changed ? 1 : 0;
}

namespace {

PageRectangle unite(const std::optional<PageRectangle>& a, const PageRectangle& b)
{
    if (!a) {
        return b;
    }
    return {std::min(a->x0, b.x0), std::min(a->y0, b.y0), std::max(a->x1, b.x1), std::max(a->y1, b.y1)};
}

} // namespace

bool VirtualTextureGlobe::Impl::updateLodClamp()
{
    // Where the view asks for pages that are not resident yet: their extents at the finest level.
    const std::uint32_t finest = layout.finestLevel;
    std::vector<PageRectangle> footprints;
    for (const PageCount& asked : summary.pages) {
        if (asked.page.level > finest || pageTable.isMapped(asked.page) || pageTable.isMissing(asked.page)) {
            continue;
        }
        const std::uint32_t shift = finest - asked.page.level;
        footprints.push_back({asked.page.x << shift, asked.page.y << shift, (asked.page.x + 1) << shift,
                              (asked.page.y + 1) << shift});
    }
    std::sort(footprints.begin(), footprints.end(), [](const PageRectangle& a, const PageRectangle& b) {
        return std::tie(a.y0, a.x0, a.y1, a.x1) < std::tie(b.y0, b.x0, b.y1, b.x1);
    });
    std::optional<PageRectangle> dirty = pageTable.dirty(finest);
    if (footprints != waitingFootprints) {
        for (const PageRectangle& footprint : footprints) {
            if (!std::binary_search(waitingFootprints.begin(), waitingFootprints.end(), footprint,
                                    [](const PageRectangle& a, const PageRectangle& b) {
                                        return std::tie(a.y0, a.x0, a.y1, a.x1) < std::tie(b.y0, b.x0, b.y1, b.x1);
                                    })) {
                dirty = unite(dirty, footprint);
            }
        }
        for (const PageRectangle& footprint : waitingFootprints) {
            if (!std::binary_search(footprints.begin(), footprints.end(), footprint,
                                    [](const PageRectangle& a, const PageRectangle& b) {
                                        return std::tie(a.y0, a.x0, a.y1, a.x1) < std::tie(b.y0, b.x0, b.y1, b.x1);
                                    })) {
                dirty = unite(dirty, footprint);
            }
        }
        waitingFootprints = std::move(footprints);
    }
    if (!dirty) {
        return false;
    }
    const std::uint32_t pagesX = VirtualTextureLayout::pagesX(finest);
    for (std::uint32_t y = dirty->y0; y < dirty->y1; ++y) {
        std::fill_n(waiting.begin() + static_cast<std::ptrdiff_t>(y) * pagesX + dirty->x0, dirty->x1 - dirty->x0, 0);
    }
    for (const PageRectangle& footprint : waitingFootprints) {
        const PageRectangle overlap{std::max(footprint.x0, dirty->x0), std::max(footprint.y0, dirty->y0),
                                    std::min(footprint.x1, dirty->x1), std::min(footprint.y1, dirty->y1)};
        for (std::uint32_t y = overlap.y0; y < overlap.y1; ++y) {
            for (std::uint32_t x = overlap.x0; x < overlap.x1; ++x) {
                waiting[static_cast<std::size_t>(y) * pagesX + x] = 1;
            }
        }
    }
    const std::span<const PageTableEntry> entries = pageTable.level(finest);
    for (std::uint32_t y = dirty->y0; y < dirty->y1; ++y) {
        for (std::uint32_t x = dirty->x0; x < dirty->x1; ++x) {
            const std::size_t at = static_cast<std::size_t>(y) * pagesX + x;
            const PageTableEntry& entry = entries[at];
            const float own = (entry.flags & PageTableEntry::kValid) ? static_cast<float>(finest - entry.level)
                                                                      : static_cast<float>(finest);
            clampValues[at].r = own;
            clampValues[at].g = waiting[at] ? own : kNoClamp;
        }
    }
    PageRectangle sent = *dirty;
    if (sparse) {
        sent = packResidencyNeighbours(clampValues, pagesX, VirtualTextureLayout::pagesY(finest), sent);
    }
    std::vector<float> region;
    const int channels = clampChannels();
    region.reserve(static_cast<std::size_t>(sent.x1 - sent.x0) * (sent.y1 - sent.y0) * channels);
    for (std::uint32_t y = sent.y0; y < sent.y1; ++y) {
        for (std::uint32_t x = sent.x0; x < sent.x1; ++x) {
            const glm::vec4& value = clampValues[static_cast<std::size_t>(y) * pagesX + x];
            region.insert(region.end(), &value.r, &value.r + channels);
        }
    }
    lodClamp->copyFromSystemMemory(std::as_bytes(std::span(region)),
                                   {static_cast<int>(sent.x0), static_cast<int>(sent.y0), static_cast<int>(sent.x1 - sent.x0),
                                    static_cast<int>(sent.y1 - sent.y0)});
    statistics.uploadedBytes += region.size() * sizeof(float);
    return true;
}

void VirtualTextureGlobe::Impl::receive(world::TileLoadResult result)
{
    const PageKey page = VirtualTextureLayout::pageOfIndex(result.ticket - 1);
    inFlight.erase(page);
    switch (result.status) {
    case world::TileLoadResult::Status::Loaded:
        arrived.emplace(page, std::move(static_cast<PageContent&>(*result.content).image));
        break;
    case world::TileLoadResult::Status::Missing:
        pageTable.markMissing(page);
        ++missingCount;
        break;
    case world::TileLoadResult::Status::Failed:
        // Named once: the page is never asked for again, and its ancestor stays drawn there.
        pageTable.markMissing(page);
        ++failedCount;
        warn("virtual texture: " + pages->describe(page) + " failed, its ancestor stays drawn: " + result.message);
        break;
    }
}

void VirtualTextureGlobe::Impl::touchNeeded(std::uint64_t frame)
{
    // Pages the view uses are the most recently used.
    for (const PageCount& count : needed) {
        cache->touch(count.page, frame);
    }
}

void VirtualTextureGlobe::Impl::readFeedback(FrameState& frameState)
{
    const VirtualTextureOptions& vt = options->virtualTexture;
    const bool deterministic = options->loader.latencyFrames > 0;
    std::optional<FeedbackRead> ready;
    // The newest buffer that is due (and, with asynchronous timing, done); older ones are dropped.
    while (!feedbackReads.empty()) {
        FeedbackRead& oldest = feedbackReads.front();
        if (oldest.frame + static_cast<std::uint64_t>(vt.feedbackLatencyFrames) > frameState.frameNumber) {
            break;
        }
        if (!deterministic && !oldest.fence.signaled()) {
            break;
        }
        if (ready) {
            spareBuffers.push_back(std::move(ready->buffer));
        }
        ready = std::move(oldest);
        feedbackReads.pop_front();
    }
    if (!ready) {
        return;
    }
    // Deterministic timing waits here if the GPU is behind; the buffer is then read without a stall.
    if (ready->fence.clientWait() != renderer::Fence::Status::Signaled) {
        throw Error("VirtualTextureGlobe: the feedback read-back did not finish within 10 s");
    }
    const std::vector<std::byte> bytes = ready->buffer.copyToSystemMemory(
        0, static_cast<std::size_t>(ready->width) * ready->height * 4);
    feedbackSamples.resize(bytes.size() / 4);
    std::memcpy(feedbackSamples.data(), bytes.data(), bytes.size());
    feedbackSamplesWidth = ready->width;
    feedbackSamplesHeight = ready->height;
    spareBuffers.push_back(std::move(ready->buffer));
    statistics.feedbackLatencyFrames = frameState.frameNumber - ready->frame;

    summary = reduceFeedback(feedbackSamples, layout.finestLevel);
    if (summary.outside > 0 && !warnedOutside) {
        warnedOutside = true; // named once
        warn("virtual texture: " + std::to_string(summary.outside) +
             " feedback pixels name no page of the texture (a read-back gone wrong); they are left out");
    }
    needed = withAncestors(summary);
    neededSet.clear();
    for (const PageCount& count : needed) {
        neededSet.insert(count.page);
    }
    feedbackView = ready->view;
    touchNeeded(frameState.frameNumber);
    // Requests the view no longer makes are dropped (Mayer 4.2): loads in flight, pages not uploaded.
    for (auto page = inFlight.begin(); page != inFlight.end();) {
        if (neededSet.contains(*page)) {
            ++page;
            continue;
        }
        loader.cancel(ticketOf(*page));
        page = inFlight.erase(page);
    }
    std::erase_if(arrived, [&](const auto& entry) { return !neededSet.contains(entry.first); });
    adjustBias();
}

void VirtualTextureGlobe::Impl::adjustBias()
{
    if (!options->virtualTexture.dynamicLodBias || !feedbackView || feedbackView->lodBias != bias()) {
        return; // only a feedback drawn with the present bias says what it asks for
    }
    const double capacity = static_cast<double>(cache->capacity());
    // What the slots must hold: the pages asked for and their ancestors, and the level-0 pages,
    // which never leave.
    std::size_t slotsNeeded = needed.size();
    for (std::uint32_t x = 0; x < VirtualTextureLayout::pagesX(0); ++x) {
        slotsNeeded += neededSet.contains(PageKey{0, x, 0}) ? 0 : 1;
    }
    const double wanted = static_cast<double>(slotsNeeded);
    // A quarter of a level coarser while more than 90% of the slots are asked for; back an eighth
    // (at most 19% more pages) while under 45%, so the two never chase each other. A close view
    // magnifies the finest level: the bias may have to exceed the levels there are.
    if (wanted > 0.9 * capacity && dynamicBias < static_cast<double>(kMaximumTileLevel)) {
        dynamicBias += 0.25;
    } else if (wanted < 0.45 * capacity && dynamicBias > 0.0) {
        dynamicBias = std::max(0.0, dynamicBias - 0.125);
    }
}

void VirtualTextureGlobe::Impl::requestPages()
{
    const std::vector<PageCount> requests =
        sortRequests(needed,
                     [this](const PageKey& page) {
                         return !pageTable.isMapped(page) && !pageTable.isMissing(page) && !inFlight.contains(page) &&
                                !arrived.contains(page);
                     },
                     options->virtualTexture.requestOrder);
    requestsOutstanding = !requests.empty();
    // The loader starts the first ones within its budget (equal priorities by ticket); those it
    // does not start are offered again next frame if the view still asks for them.
    double rank = 0.0;
    for (const PageCount& request : requests) {
        const PageKey page = request.page;
        std::shared_ptr<world::VirtualTextureSource> source = pages;
        loader.request(ticketOf(page), rank, [source, page]() -> std::unique_ptr<world::TileContent> {
            std::optional<Image> image = source->cutPage(page);
            if (!image) {
                return nullptr;
            }
            return std::make_unique<PageContent>(std::move(*image));
        });
        rank += 1.0;
    }
    loader.endFrame();
    for (const std::uint64_t ticket : loader.startedTickets()) {
        inFlight.insert(VirtualTextureLayout::pageOfIndex(ticket - 1));
    }
    statistics.pagesRequested = loader.startedLastFrame();
}

renderer::ShaderProgram& VirtualTextureGlobe::Impl::program(FrameState& frameState, bool feedback, PixelLevels levels)
{
    // The feedback pass casts its pixels' rays, with no depth, whatever the frame's depth strategy,
    // and reads no texels: the mip tail is the main pass's only, and the level it asks for is
    // the one trilinear filtering would blend from.
    const DepthStrategy strategy = feedback ? DepthStrategy::MultiFrustum : frameState.depthStrategy;
    const bool mipTail = !feedback && levels == PixelLevels::WithMipTail;
    const bool ramp = !waitingFootprints.empty();
    const bool trilinear = feedback ? options->virtualTexture.trilinear : blendsLevels(levels);
    std::shared_ptr<renderer::ShaderProgram>& program = programs[{feedback, strategy, mipTail, ramp, trilinear}];
    if (program) {
        return *program;
    }
    renderer::ShaderProgramDescription description;
    description.name = feedback ? "virtual texture feedback" : "virtual texture";
    description.vertex = renderer::ShaderSource::embedded(feedback ? "scene/virtual/feedback.vert.glsl" : "scene/tiles/tile.vert.glsl");
    description.fragment = renderer::ShaderSource::embedded("scene/virtual/virtual_texture.frag.glsl");
    if (feedback) {
        description.defines.push_back({"VT_FEEDBACK"});
        description.fragment.text.insert(0, renderer::ShaderSource::embedded("scene/globe/ray_cast_ellipsoid.glsl").text);
    } else {
        description.fragment.text.insert(0, renderer::ShaderSource::embedded("scene/tiles/imagery_over.glsl").text);
        if (options->lighting) {
            description.defines.push_back({"LIGHTING"});
        }
    }
    if (trilinear) {
        description.defines.push_back({"VT_TRILINEAR"});
    }
    if (options->virtualTexture.maximumAnisotropy > 1.0f) {
        description.defines.push_back({"VT_ANISOTROPIC"});
    }
    if (mipTail) {
        description.defines.push_back({"VT_MIP_TAIL"});
    }
    if (sparse) {
        description.defines.push_back({"VT_SPARSE"});
    }
    if (!feedback && options->style.adjustsColors()) {
        description.defines.push_back({"COLOR_ADJUSTMENT"});
    }
    if (ramp) {
        description.defines.push_back({"VT_LOD_RAMP"});
    }
    for (renderer::ShaderDefine& define : depthStrategyDefines(strategy, Pass::Opaque)) {
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

void VirtualTextureGlobe::Impl::setUniforms(renderer::DrawCommand& draw, double lodBias) const
{
    // Each variant (feedback, filtering, lighting) reads its own subset.
    const renderer::ShaderProgram& program = *draw.shaderProgram;
    auto set = [&](std::string_view name, const renderer::UniformValue& value) {
        if (program.hasUniform(name)) {
            draw.uniforms.set(name, value);
        }
    };
    set("u_layout", glm::ivec4(static_cast<int>(layout.finestLevel), layout.pageSize, layout.border, layout.slotSize()));
    set("u_physicalTexelSize",
        glm::vec2(1.0f / static_cast<float>(physical->width()), 1.0f / static_cast<float>(physical->height())));
    set("u_lodBias", static_cast<float>(lodBias));
    set("u_tailOrigin", glm::vec2(0.0f, static_cast<float>(tailStripY())));
    set("u_tailLevels", layout.tailLevels());
    set("u_maximumAnisotropyLog2", std::log2(options->virtualTexture.maximumAnisotropy));
}

VirtualTextureGlobe::Impl::ViewReach VirtualTextureGlobe::Impl::viewReach(const FrameState& frameState) const
{
    // Rays through a 9 x 9 grid of the view's pixels, corners and edges included; one that misses
    // the globe means the view reaches the horizon. A pixel's footprint along its ray's ground
    // track is d rho cos(theta) / sin(a): d the distance to the ground, rho cos(theta) the pixel's
    // angle across at theta from the view's axis (the larger of its two: cos^2 theta along the
    // radius), a the angle between the ray and the ground.
    const Camera& camera = frameState.camera;
    const double radius = ellipsoid.minimumRadius();
    ViewReach reach;
    reach.down = glm::normalize(camera.eye());
    reach.opposite = std::remainder(std::atan2(reach.down.y, reach.down.x) + kPi, kTwoPi);
    const glm::dvec3& down = reach.down;
    reach.pixelAngle = frameState.metersPerPixel(1.0); // a pixel's size at unit distance: its angle
    const double rho = reach.pixelAngle;
    const glm::dvec3 axis = camera.direction();
    constexpr int kSamples = 9;
    for (int j = 0; j < kSamples; ++j) {
        for (int i = 0; i < kSamples; ++i) {
            const glm::dvec2 pixel(frameState.width * i / (kSamples - 1.0), frameState.height * j / (kSamples - 1.0));
            const Ray ray = camera.pickRay(pixel, frameState.width, frameState.height);
            const std::optional<RayInterval> hit = intersectRayEllipsoid(ray, ellipsoid);
            if (!hit) {
                reach.angle = std::acos(std::min(1.0, radius / glm::length(camera.eye())));
                reach.footprint = std::numeric_limits<double>::infinity();
                return reach;
            }
            const glm::dvec3 ground = ray.pointAt(hit->nearDistance);
            reach.angle = std::max(reach.angle, detail::centralAngle(down, ground));
            const glm::dvec3 direction = glm::normalize(ray.direction);
            const double grazing = std::abs(glm::dot(direction, ellipsoid.geodeticSurfaceNormal(ground)));
            const double across = rho * glm::dot(direction, axis) * glm::length(ground - ray.origin);
            reach.footprint = std::max(reach.footprint, grazing > 0.0 ? across / grazing : std::numeric_limits<double>::infinity());
        }
    }
    return reach;
}

double VirtualTextureGlobe::Impl::farthestAlong(const ViewReach& reach, double latitude, double west, double east) const
{
    // Along a latitude the angle grows with the longitude's distance from the eye's: it is largest
    // at the end farther from it, or on the opposite meridian where the run crosses that.
    double farthest = 0.0;
    for (const double longitude : {west, east, std::clamp(reach.opposite, west, east)}) {
        farthest = std::max(farthest, detail::centralAngle(reach.down, ellipsoid.geodeticSurfaceNormal(Geodetic2D{longitude, latitude})));
    }
    return farthest;
}

PixelLevels VirtualTextureGlobe::Impl::pixelLevels(const FrameState& frameState, const GeodeticExtent& extent, double farthest,
                                                   const ViewReach& reach) const
{
    // A pixel asks for a level coarser than l where its footprint's long axis spans more than a
    // texel of level l (pi / (P 2^l) radians of longitude: a cos(latitude) metres, narrowest nearest
    // the pole): coarser than the finest level it blends two, coarser than level 0 it reads the
    // mip tail. On a sphere of radius R seen from D, the footprint at an angle t from the point under
    // the eye is d rho / sin(a) = rho d^2 / (D cos t - R) (d its distance, a the grazing angle,
    // rho a pixel's angle at the centre of the view, the largest): it grows with t, so a part's
    // largest is at the farthest of its points that the view reaches (a margin of two); a part
    // wider than 45 degrees, or reaching within a degree of the horizon, may ask for any level.
    const glm::dvec3& eye = frameState.camera.eye();
    const double eyeDistance = glm::length(eye);
    const double radius = ellipsoid.minimumRadius();
    const double horizon = std::acos(std::min(1.0, radius / eyeDistance));
    if (extent.width() > toRadians(45.0)) {
        return PixelLevels::WithMipTail;
    }
    const double t = std::min(farthest, reach.angle);
    if (t > horizon - toRadians(1.0)) {
        return PixelLevels::WithMipTail;
    }
    const double rho = reach.pixelAngle;
    const double d2 = eyeDistance * eyeDistance + radius * radius - 2.0 * eyeDistance * radius * std::cos(t);
    const double footprint = rho * d2 / (eyeDistance * std::cos(t) - radius);
    const double poleward = std::max(std::abs(extent.south), std::abs(extent.north));
    const double texel0 = ellipsoid.maximumRadius() * std::cos(poleward) * kPi / layout.pageSize * std::exp2(-bias());
    if (2.0 * footprint > texel0) {
        return PixelLevels::WithMipTail;
    }
    // The largest footprint in the view, from its rays, bounds every tile's too; it is tighter where
    // the view's edge limits the tile (the footprint above takes the centre pixel's angle for every
    // pixel), with a margin of 1.5 for the footprints between the rays.
    const double finestTexel = texel0 * std::exp2(-static_cast<double>(layout.finestLevel));
    return std::min(2.0 * footprint, 1.5 * reach.footprint) > finestTexel ? PixelLevels::Blended : PixelLevels::Finest;
}

std::vector<VirtualTextureGlobe::Impl::TilePart> VirtualTextureGlobe::Impl::tileParts(const FrameState& frameState,
                                                                                     const QuadtreeTile& tile,
                                                                                     const ViewReach& reach) const
{
    const SurfaceTile& surface = static_cast<const SurfaceTile&>(*tile.data);
    const TileMesh::IndexLayout indices = TileMesh::indexLayout(options->samplesLog2, *surface.mesh->coarsening, false);
    if (sparse) {
        // The hardware filters every pixel, at any level: one program for the whole tile.
        return {{0, indices.indexCount(), PixelLevels::Blended}};
    }
    const GeodeticExtent extent = quadtree.scheme().tileExtent(tile.key);
    // The farthest angle along each row of vertices, from the north: a run of rows reaches its
    // largest on its northern or southern row (along a meridian the angle has its one extreme
    // between the poles at the nearest point, so the farthest is at an end).
    const int quads = 1 << options->samplesLog2;
    std::array<double, (1 << 7) + 1> latitude{}; // samplesLog2 is at most 7 (validate)
    std::array<double, (1 << 7) + 1> farthest{};
    for (std::size_t row = 0; row <= static_cast<std::size_t>(quads); ++row) {
        latitude[row] = TileMesh::latticeLatitude(quadtree.scheme(), tile.key, options->samplesLog2, static_cast<int>(row));
        farthest[row] = farthestAlong(reach, latitude[row], extent.west, extent.east);
    }
    // Quad rows first .. last - 1 (from the north).
    auto rows = [&](int first, int last) {
        const auto north = static_cast<std::size_t>(first), south = static_cast<std::size_t>(last);
        const GeodeticExtent band{extent.west, latitude[south], extent.east, latitude[north]};
        return pixelLevels(frameState, band, std::max(farthest[north], farthest[south]), reach);
    };
    if (!options->programsPerRow) {
        return {{0, indices.indexCount(), rows(0, quads)}};
    }
    // Each quad row's band spans the tile's width: its levels hold for the ring's quads in it too.
    std::array<PixelLevels, 1 << 7> rowLevels{};
    PixelLevels demanding = PixelLevels::Finest;
    for (int row = 0; row < quads; ++row) {
        rowLevels[static_cast<std::size_t>(row)] = rows(row, row + 1);
        demanding = std::max(demanding, rowLevels[static_cast<std::size_t>(row)]);
    }
    std::vector<TilePart> parts;
    auto add = [&](std::size_t count, PixelLevels levels) {
        if (!parts.empty() && parts.back().levels == levels) {
            parts.back().count += count;
        } else {
            parts.push_back({parts.empty() ? 0 : parts.back().first + parts.back().count, count, levels});
        }
    };
    for (int row = 1; row + 1 < quads; ++row) {
        add(TileMesh::IndexLayout::kQuadIndices * indices.innerRowQuads, rowLevels[static_cast<std::size_t>(row)]);
    }
    // The ring: its north and south edges in the first and last rows, its east and west edges in
    // every row.
    add(indices.edgeIndices[0], rowLevels.front());
    add(indices.edgeIndices[1], demanding);
    add(indices.edgeIndices[2], rowLevels[static_cast<std::size_t>(quads) - 1]);
    add(indices.edgeIndices[3], demanding);
    return parts;
}

glm::vec4 VirtualTextureGlobe::Impl::globeBounds(const Camera& camera, int width, int height, double margin) const
{
    // Where the rays from the eye graze the ellipsoid: in its radii's units (a unit sphere) the
    // circle of points q with q . e = 1, e the eye there; its picture on the screen is the
    // globe's outline, sampled at kSamples points.
    const glm::vec4 wholeView(-1.0f, -1.0f, 1.0f, 1.0f);
    const glm::dvec3 eyeScaled = camera.eye() * ellipsoid.oneOverRadii();
    const double distanceSquared = glm::dot(eyeScaled, eyeScaled);
    if (distanceSquared <= 1.0) {
        return wholeView;
    }
    const glm::dvec3 centre = eyeScaled / distanceSquared;
    const double radius = std::sqrt(1.0 - 1.0 / distanceSquared);
    const glm::dvec3 axis = glm::normalize(eyeScaled);
    const glm::dvec3 other = std::abs(axis.z) < 0.9 ? glm::dvec3(0.0, 0.0, 1.0) : glm::dvec3(1.0, 0.0, 0.0);
    const glm::dvec3 u = glm::normalize(glm::cross(axis, other));
    const glm::dvec3 v = glm::cross(axis, u);
    constexpr int kSamples = 64;
    glm::dvec2 low(std::numeric_limits<double>::infinity()), high(-std::numeric_limits<double>::infinity());
    for (int k = 0; k < kSamples; ++k) {
        const double angle = kTwoPi * k / kSamples;
        const glm::dvec3 onOutline = (centre + radius * (std::cos(angle) * u + std::sin(angle) * v)) * ellipsoid.radii();
        const std::optional<glm::dvec2> window = camera.worldToWindow(onOutline, width, height);
        if (!window) {
            return wholeView; // the outline reaches behind the eye
        }
        low = glm::min(low, *window);
        high = glm::max(high, *window);
    }
    // Between two samples the outline bulges out by less than 1 - cos(pi / kSamples) of its size
    // (0.12 %): 1 % of the size, and the margin, more.
    const glm::dvec2 extra = 0.01 * (high - low) + glm::dvec2(margin);
    const glm::dvec2 size(width, height);
    // Window positions count y down; clip coordinates up.
    low = glm::max(glm::dvec2(2.0 * (low.x - extra.x) / size.x - 1.0, 1.0 - 2.0 * (high.y + extra.y) / size.y), glm::dvec2(-1.0));
    high = glm::min(glm::dvec2(2.0 * (high.x + extra.x) / size.x - 1.0, 1.0 - 2.0 * (low.y - extra.y) / size.y), glm::dvec2(1.0));
    if (low.x >= high.x || low.y >= high.y) {
        return glm::vec4(0.0f); // the globe is out of view: an empty rectangle
    }
    return glm::vec4(glm::vec2(low), glm::vec2(high));
}

void VirtualTextureGlobe::Impl::drawFeedback(FrameState& frameState, const FeedbackView& drawnFrom)
{
    renderer::Context& context = frameState.context;
    renderer::Device& device = frameState.device;
    const int divisor = options->virtualTexture.feedbackDivisor;
    const int width = std::max(1, (frameState.width + divisor - 1) / divisor);
    const int height = std::max(1, (frameState.height + divisor - 1) / divisor);
    if (!feedbackTarget || feedbackTarget->width() != width || feedbackTarget->height() != height) {
        renderer::FramebufferOptions colourOnly;
        colourOnly.hasDepth = false; // one rectangle, its pixels' rays: nothing to order
        feedbackTarget = std::make_unique<renderer::Framebuffer>(context.createFramebuffer(width, height, colourOnly));
        spareBuffers.clear();
        feedbackReads.clear();
    }
    const std::size_t bytes = static_cast<std::size_t>(width) * height * 4;
    renderer::PixelBuffer buffer;
    if (!spareBuffers.empty()) {
        buffer = std::move(spareBuffers.back());
        spareBuffers.pop_back();
    } else {
        buffer = device.createPixelBuffer(bytes);
    }

    if (!feedbackRectangle) {
        const std::array<glm::vec3, 6> corners{glm::vec3(0.0f, 0.0f, 0.0f), glm::vec3(1.0f, 0.0f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f),
                                               glm::vec3(1.0f, 0.0f, 0.0f), glm::vec3(1.0f, 1.0f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f)};
        feedbackRectangleVertices = device.createVertexBuffer(std::as_bytes(std::span(corners)));
        feedbackRectangle = context.createVertexArray();
        feedbackRectangle->setAttribute(renderer::VertexAttributeLocation::Position, *feedbackRectangleVertices,
                                        {renderer::ComponentType::Float, 3, false, false, 0, 0});
    }
    const Camera& camera = frameState.camera;
    const Camera::Axes axes = camera.axes();
    const glm::dvec2 extent = camera.halfExtent(frameState.width, frameState.height);
    const double pixel = frameState.metersPerPixel(1.0); // the frame's own pixels' angle
    const glm::dvec3 eyeScaled = camera.eye() * ellipsoid.oneOverRadii();
    const double flattening = ellipsoid.radii().z / ellipsoid.radii().x;
    renderer::ClearState clear;
    clear.color = glm::vec4(0.0f); // a pixel outside the rectangle packs to 0, as one whose ray misses the globe
    context.clear(clear, feedbackTarget.get());
    renderer::SceneState sceneState;
    sceneState.cameraEye = camera.eye();
    sceneState.viewport = {0, 0, width, height};
    renderer::DrawCommand draw;
    draw.debugName = "virtual texture feedback";
    draw.shaderProgram = &program(frameState, true, PixelLevels::Blended);
    draw.framebuffer = feedbackTarget.get();
    draw.vertexArray = &*feedbackRectangle;
    draw.renderState.depthTest.enabled = false;
    draw.textures = {{0, &*pageTableTexture, &*pointSampler}, {2, &*lodClamp, &*pointSampler}};
    setUniforms(draw, bias());
    // Two of the feedback's pixels, in the frame's.
    draw.uniforms.set("u_bounds", globeBounds(camera, frameState.width, frameState.height, 2.0 * divisor));
    draw.uniforms.set("u_rayCentre", glm::vec3(axes.direction));
    draw.uniforms.set("u_rayRight", glm::vec3(axes.right * extent.x));
    draw.uniforms.set("u_rayUp", glm::vec3(axes.up * extent.y));
    draw.uniforms.set("u_pixelRight", glm::vec3(axes.right * pixel));
    draw.uniforms.set("u_pixelUp", glm::vec3(axes.up * pixel));
    draw.uniforms.set("u_cameraScaled", glm::vec3(eyeScaled));
    draw.uniforms.set("u_cameraScaledLengthSquaredMinusOne", static_cast<float>(glm::dot(eyeScaled, eyeScaled) - 1.0));
    draw.uniforms.set("u_oneOverRadii", glm::vec3(ellipsoid.oneOverRadii()));
    draw.uniforms.set("u_polarOverEquatorialSquared", static_cast<float>(flattening * flattening));
    draw.uniforms.set("u_texelsPerMetre", static_cast<float>(layout.pageSize * std::exp2(layout.finestLevel) /
                                                           (kPi * ellipsoid.radii().x)));
    context.draw(draw, sceneState);
    context.readPixels(buffer, feedbackTarget.get());
    feedbackReads.push_back({frameState.frameNumber, std::move(buffer), device.createFence(), width, height, drawnFrom});
    statistics.feedbackWidth = width;
    statistics.feedbackHeight = height;
}

void VirtualTextureGlobe::Impl::ensureMeshes(FrameState& frameState)
{
    const std::uint64_t frame = frameState.frameNumber;
    DrawnTileSet drawn;
    for (const QuadtreeTile* tile : selection.drawn) {
        drawn.insert(tile->key);
    }
    for (QuadtreeTile* tile : selection.drawn) {
        SurfaceTile& surface = surfaceOf(*tile);
        if (!surface.mesh) {
            const TileMesh mesh =
                TileMesh::build(ellipsoid, TilingScheme::geographic(), tile->key, options->samplesLog2, {}, 0.0);
            surface.mesh = detail::uploadTileMesh(frameState.context, mesh);
            meshBytes += surface.mesh->bytes;
            meshUploadedBytes += surface.mesh->bytes;
            meshTiles.push_back(tile);
        }
        surface.lastDrawnFrame = frame;
        indexBuffers.bind(frameState.device, *surface.mesh, edgeCoarsening(quadtree.scheme(), tile->key, drawn));
    }
    if (meshBytes <= options->meshCacheBytes) {
        return;
    }
    // Over the cap: the least recently drawn go, never one drawn in this frame.
    std::sort(meshTiles.begin(), meshTiles.end(), [](QuadtreeTile* a, QuadtreeTile* b) {
        const std::uint64_t da = surfaceOf(*a).lastDrawnFrame;
        const std::uint64_t db = surfaceOf(*b).lastDrawnFrame;
        return da != db ? da > db : a->key < b->key;
    });
    while (meshBytes > options->meshCacheBytes && !meshTiles.empty() &&
           surfaceOf(*meshTiles.back()).lastDrawnFrame < frame) {
        SurfaceTile& surface = surfaceOf(*meshTiles.back());
        meshBytes -= surface.mesh->bytes;
        surface.mesh.reset();
        meshTiles.pop_back();
    }
}

VirtualTextureGlobe::VirtualTextureGlobe(const Ellipsoid& ellipsoid, VirtualTextureGlobeOptions options)
    : _options(std::move(options))
{
    validate(_options);
    _impl = std::make_unique<Impl>(ellipsoid, _options);
    _statistics.physicalPages = _impl->cache->capacity();
}

VirtualTextureGlobe::~VirtualTextureGlobe() = default;

const VirtualTextureLayout& VirtualTextureGlobe::layout() const noexcept
{
    return _impl->layout;
}

const PageTable& VirtualTextureGlobe::pageTable() const noexcept
{
    return _impl->pageTable;
}

std::optional<BoundingSphere> VirtualTextureGlobe::boundingSphere() const
{
    return BoundingSphere{glm::dvec3(0.0), _impl->ellipsoid.maximumRadius()};
}

void VirtualTextureGlobe::update(FrameState& frameState, CommandList& commands)
{
    Impl& impl = *_impl;
    const std::uint64_t frame = frameState.frameNumber;
    if (impl.streamedFrame != frame) {
        // Once per frame, however many times the scene updates its primitives.
        impl.streamedFrame = frame;
        impl.statistics = VirtualTextureStatistics{};
        impl.meshUploadedBytes = 0;
        if (!impl.started) {
            impl.started = true;
            impl.start(frameState);
        }
        for (world::TileLoadResult& result : impl.loader.beginFrame(frame)) {
            impl.receive(std::move(result));
        }
        impl.readFeedback(frameState);

        // Uploads, coarse before fine (a page goes in once its parent is in), until the budget is
        // spent; at least one a frame.
        const std::size_t budget = _options.virtualTexture.uploadBytesPerFrame;
        for (auto entry = impl.arrived.begin(); entry != impl.arrived.end();) {
            if (impl.statistics.pagesLoaded > 0 && impl.statistics.uploadedBytes >= budget) {
                break;
            }
            const PageKey page = entry->first;
            if (impl.pageTable.isMissing(page)) {
                entry = impl.arrived.erase(entry); // under a page that failed: it can never be shown
                continue;
            }
            if (page.level > 0 && !impl.pageTable.isMapped(page.parent())) {
                ++entry; // waits for its parent
                continue;
            }
            if (!impl.uploadPage(frameState, page, entry->second)) {
                break; // every slot holds a page this frame uses: the bias will rise
            }
            entry = impl.arrived.erase(entry);
        }
        impl.uploadTables();
        impl.requestPages();

        // The surface's tiles, as a TiledGlobe of the same source would select them.
        const Camera& camera = frameState.camera;
        TileView view;
        view.eye = camera.eye();
        view.direction = camera.direction();
        view.frustum = frameState.cullingVolume;
        view.viewportHeightPixels = frameState.height;
        view.fieldOfViewY = camera.fieldOfViewY();
        TileSelectionOptions selectionOptions;
        selectionOptions.maximumScreenSpaceError = _options.maximumScreenSpaceError;
        selectionOptions.maximumLevel = impl.pages->tileSource().info().maximumLevel;
        const std::uint32_t deepest = kMaximumTileLevel - static_cast<std::uint32_t>(_options.samplesLog2);
        impl.quadtree.select(view, selectionOptions, frame, impl.selection, [deepest](QuadtreeTile& tile) {
            tile.renderable = true;
            tile.wantsLoad = false;
            tile.refinable = tile.key.level < deepest;
        });
        impl.ensureMeshes(frameState);

        const FeedbackView current{camera.eye(), camera.target(), camera.up(), camera.fieldOfViewY(),
                                   frameState.width, frameState.height, impl.bias()};
        FeedbackInputs inputs{current, impl.tablesVersion};
        if (inputs != impl.lastFeedbackInputs) {
            impl.drawFeedback(frameState, current);
            impl.lastFeedbackInputs = std::move(inputs);
        } else {
            // The last feedback drawn is this frame's: no pass (a still view costs no more than
            // its draws); its pages are used this frame as it read them.
            impl.touchNeeded(frame);
        }

        VirtualTextureStatistics& s = impl.statistics;
        s.pagesWanted = impl.needed.size();
        s.pagesResident = impl.cache->size();
        s.physicalPages = impl.cache->capacity();
        s.pagesPending = impl.inFlight.size() + impl.arrived.size();
        s.pagesMissing = impl.missingCount;
        s.pagesFailed = impl.failedCount;
        s.fallbackPixels = impl.summary.fallback;
        s.feedbackPixels = impl.summary.pixels;
        s.fallbackFraction = impl.summary.fallbackFraction();
        s.lodBias = impl.bias();
        s.lodBiasRaised = impl.dynamicBias > 0.0;
        s.gpuBytes = impl.gpuBytes();
        s.sparse = impl.sparse;
        s.converged = impl.feedbackView && *impl.feedbackView == current && impl.summary.fallback == 0 &&
                      s.pagesPending == 0 && !impl.requestsOutstanding;
        _statistics = s;

        TileStatistics tiles;
        const TileSelection& selection = impl.selection;
        tiles.visited = selection.visited;
        tiles.culledByFrustum = selection.culledByFrustum;
        tiles.culledByHorizon = selection.culledByHorizon;
        tiles.selected = selection.selected;
        tiles.drawn = selection.drawn.size();
        for (std::size_t i = 0; i < selection.drawn.size(); ++i) {
            tiles.deepestLevelDrawn = std::max(tiles.deepestLevelDrawn, selection.drawn[i]->key.level);
            tiles.largestScreenSpaceErrorDrawn =
                std::max(tiles.largestScreenSpaceErrorDrawn, selection.drawnScreenSpaceErrors[i]);
        }
        // The pages stand for the tiles' imagery: what is loading, what went up, what is held.
        tiles.requested = s.pagesRequested;
        tiles.loadedThisFrame = s.pagesLoaded;
        tiles.pending = s.pagesPending;
        tiles.failed = s.pagesFailed;
        tiles.missing = s.pagesMissing;
        tiles.evicted = s.pagesEvicted;
        tiles.residentBytesGpu = impl.meshBytes + s.gpuBytes;
        tiles.residentTiles = impl.meshTiles.size();
        tiles.residentImageryTiles = s.pagesResident;
        tiles.uploadedBytes = impl.meshUploadedBytes + s.uploadedBytes;
        tiles.maximumScreenSpaceError = _options.maximumScreenSpaceError;
        tiles.converged = s.converged;
        _tileStatistics = tiles;
    }

    // The commands: a drawn tile's parts (tileParts), all reading the one virtual texture.
    const auto reach = impl.viewReach(frameState);
    _statistics.tilesWithMipTail = 0;
    _statistics.tilesBlendingLevels = 0;
    const glm::dvec3& eye = frameState.camera.eye();
    const double eyeHeight = impl.ellipsoid.toGeodetic3D(eye).height;
    const ImageryLayerStyle& style = _options.style;
    for (QuadtreeTile* tile : impl.selection.drawn) {
        SurfaceTile& surface = surfaceOf(*tile);
        const std::vector<Impl::TilePart> parts = impl.tileParts(frameState, *tile, reach);
        bool withMipTail = false, blending = false;
        for (const Impl::TilePart& part : parts) {
            withMipTail = withMipTail || part.levels == PixelLevels::WithMipTail;
            blending = blending || impl.blendsLevels(part.levels);
        }
        _statistics.tilesWithMipTail += withMipTail ? 1 : 0;
        _statistics.tilesBlendingLevels += blending ? 1 : 0;
        // What the tile's parts share.
        SceneCommand command;
        command.draw.debugName = "virtual texture tile " + pageName(tile->key);
        command.draw.vertexArray = &surface.mesh->array;
        command.draw.textures = {{0, &*impl.pageTableTexture, &*impl.pointSampler},
                                 {1, impl.physical.get(), &*impl.physicalSampler},
                                 {2, &*impl.lodClamp, &*impl.pointSampler}};
        command.boundingSphere = tile->region.boundingSphere();
        command.nearestDistance = std::max(tile->region.distanceTo(eye), eyeHeight - tile->region.maximumHeight());
        command.tags = Effect::Globe | Effect::VirtualTexture;
        command.ground = true;
        if (_options.lighting) {
            command.tags = command.tags | Effect::Lighting;
        }
        if (_options.style.adjustsColors()) {
            command.tags = command.tags | Effect::ColorAdjustment;
        }
        for (const Impl::TilePart& part : parts) {
            SceneCommand partCommand = command;
            partCommand.draw.first = part.first;
            partCommand.draw.count = part.count;
            renderer::ShaderProgram& program = impl.program(frameState, false, part.levels);
            partCommand.draw.shaderProgram = &program;
            impl.setUniforms(partCommand.draw, impl.bias());
            partCommand.draw.uniforms.set(
                "u_tileKey", glm::ivec3(static_cast<int>(tile->key.level), static_cast<int>(tile->key.x), static_cast<int>(tile->key.y)));
            partCommand.draw.uniforms.set("u_baseColor", _options.baseColor);
            partCommand.draw.uniforms.set("u_textureAdjustment",
                                          glm::vec4(static_cast<float>(style.alpha), static_cast<float>(style.brightness),
                                                    static_cast<float>(style.contrast), static_cast<float>(1.0 / style.gamma)));
            if (program.hasUniform("u_oneOverRadiiSquared")) { // for the lighting's normals only
                partCommand.draw.uniforms.set("u_oneOverRadiiSquared", glm::vec3(impl.ellipsoid.oneOverRadiiSquared()));
            }
            commands.push_back(std::move(partCommand));
        }
    }
}

std::array<std::uint8_t, 4> VirtualTextureGlobe::levelColor(std::uint32_t level) noexcept
{
    // Cold to warm, coarse to fine, cycling after twelve levels.
    static constexpr std::uint8_t kColors[12][3] = {
        {48, 18, 59},   {67, 87, 201},  {57, 154, 246}, {24, 214, 203}, {70, 247, 131}, {164, 252, 60},
        {225, 221, 55}, {254, 164, 49}, {244, 98, 23},  {206, 43, 6},   {148, 12, 2},   {122, 4, 3}};
    const std::uint8_t* c = kColors[level % 12];
    return {c[0], c[1], c[2], 255};
}

Image VirtualTextureGlobe::physicalTextureImage() const
{
    return _impl->physical && !_impl->sparse ? _impl->physical->copyToImage() : Image();
}

Image VirtualTextureGlobe::pageTableImage() const
{
    const PageTable& table = _impl->pageTable;
    const std::uint32_t finest = table.finestLevel();
    const int width = static_cast<int>(VirtualTextureLayout::pagesX(finest));
    const int height = static_cast<int>(VirtualTextureLayout::pagesY(finest));
    Image image(width, height, 4);
    const std::span<const PageTableEntry> entries = table.level(finest);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const PageTableEntry& entry = entries[static_cast<std::size_t>(y) * width + x];
            const auto color = (entry.flags & PageTableEntry::kValid) ? levelColor(entry.level)
                                                                      : std::array<std::uint8_t, 4>{0, 0, 0, 255};
            std::memcpy(image.pixel(x, height - 1 - y), color.data(), 4);
        }
    }
    return image;
}

VirtualTextureGlobe::Feedback VirtualTextureGlobe::feedback() const
{
    const Impl& impl = *_impl;
    Feedback feedback{impl.feedbackSamplesWidth, impl.feedbackSamplesHeight, {}};
    feedback.samples.reserve(impl.feedbackSamples.size());
    for (const std::uint32_t bits : impl.feedbackSamples) {
        feedback.samples.push_back(unpackFeedback(bits));
    }
    return feedback;
}

Image VirtualTextureGlobe::feedbackImage() const
{
    const Feedback feedback = this->feedback();
    Image image(feedback.width, feedback.height, 4);
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const FeedbackSample& sample = feedback.samples[static_cast<std::size_t>(y) * image.width + x];
            std::array<std::uint8_t, 4> color{0, 0, 0, 255};
            if (sample.fallback) {
                color = {255, 255, 255, 255};
            } else if (sample.covered) {
                color = levelColor(sample.page.level);
            }
            std::memcpy(image.pixel(x, image.height - 1 - y), color.data(), 4);
        }
    }
    return image;
}

} // namespace orbis::scene
