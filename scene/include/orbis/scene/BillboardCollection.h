#pragma once

#include "orbis/scene/FrameState.h"

#include <orbis/core/Image.h>
#include <orbis/renderer/TextureAtlas.h>
#include <orbis/world/BillboardShape.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace orbis::renderer {
class ShaderProgram;
} // namespace orbis::renderer

namespace orbis::scene {

// A scene file's word, so the world layer's (scene::BillboardShape is world::BillboardShape).
using world::BillboardShape;

/// A built-in marker as an image for BillboardCollection::addImage: white (a billboard's colour
/// tints it), `sizePixels` across (at least 1), straight alpha. Drawn at scale 1 it stays crisp:
/// the dot's edge is anti-aliased by its coverage of each pixel, the square is opaque to its edge.
Image billboardShapeImage(BillboardShape shape, int sizePixels);

/// Which side of a billboard (or a label's box) sits on its anchor, left to right.
enum class HorizontalOrigin : std::uint8_t { Left, Center, Right };
/// Which side of a billboard (or a label's box) sits on its anchor, bottom to top.
enum class VerticalOrigin : std::uint8_t { Bottom, Center, Top };

/// How billboards and labels are hidden by what lies in front of them. Shared by
/// BillboardCollection and LabelCollection.
///
/// The globe hides them by a horizon test per billboard in the vertex shader (ellipsoid-scaled
/// space, as EllipsoidalOccluder): exact for the ellipsoid whatever the globe's method or depth
/// precision, so a billboard on the surface never z-fights it, and a quad that reaches over the
/// surface near the limb is not cut by it. The depth test hides them behind other occluders
/// (models, terrain above the ellipsoid, a mountain in front), anchor by anchor: in the geometry
/// shader, the anchor's depth, moved towards the eye by depthOffsetFraction of its distance (the
/// screen position is unchanged), is compared with the depth the opaque commands of its frustum
/// wrote at the four pixels around the anchor, the farthest of them (FrameState::sceneDepth, a
/// copy: the ground the anchor stands on never hides it, however slanted). A quad that passes is drawn
/// whole: a label is never cut by the ground it stands on, and an aircraft 1,500 m above a
/// billboard on the ground hides it. Within disableDepthTestDistance of the eye the test is off
/// (CesiumJS's disableDepthTestDistance). A scene drawn into a window's framebuffer, whose depth
/// cannot be copied, tests none.
struct BillboardDepthOptions {
    bool horizonCulling = true; ///< hide anchors below the scene ellipsoid's horizon
    /// Metres from the eye within which an anchor is not depth-tested: 0, the default, tests every
    /// one; infinity tests none (drawn over models and terrain as long as the horizon test lets
    /// them show).
    double disableDepthTestDistance = 0.0;
    /// Fraction of the eye-to-anchor distance the depth is taken nearer the eye. 1e-3
    /// clears the 24-bit depth steps of a frustum of far/near 1000 (about 6e-5 of the distance)
    /// with margin, and those of logarithmic (about 1e-6) and complementary depth (1.2e-7); not
    /// those of DepthStrategy::Single far from the eye (60 km at 1,000 km).
    float depthOffsetFraction = 1e-3f;
};

struct BillboardCollectionOptions {
    BillboardDepthOptions depth;
    int atlasPadding = 1;       ///< texels between images in the atlas (no bleeding when scaled)
    int atlasInitialSize = 64;  ///< a power of two
    int atlasMaxSize = 4096;    ///< a power of two
};

/// One billboard: an atlas image drawn screen-aligned at a world position, sized in pixels.
struct Billboard {
    glm::dvec3 position{0.0};  ///< world, metres
    std::size_t image = 0;     ///< index returned by BillboardCollection::addImage
    /// Moves the image from its anchor, in pixels: x to the right, y down (as rows of an image,
    /// and as scene files give it).
    glm::ivec2 pixelOffset{0, 0};
    HorizontalOrigin horizontalOrigin = HorizontalOrigin::Center;
    VerticalOrigin verticalOrigin = VerticalOrigin::Center;
    glm::vec4 color{1.0f};     ///< multiplies the image (straight alpha)
    float scale = 1.0f;        ///< 0 to 255 in steps of 1/256; the size is rounded to whole pixels
    bool visible = true;
};

/// What the last update() sent to the GPU, so tests and benchmarks can see that a change
/// rewrites only what changed.
struct BillboardUploadStatistics {
    std::size_t bytesUploaded = 0;     ///< vertex bytes
    std::size_t uploadCalls = 0;       ///< buffer writes (runs of changed vertices)
    std::size_t verticesUploaded = 0;
    bool fullUpload = false;           ///< the whole buffer was (re)written
    std::size_t textureBytesUploaded = 0;
};

namespace detail {
template <typename Vertex>
class BillboardBatch;
struct BillboardVertex;
class BillboardBounds;
class AtlasTexture;
class DepthPrograms;
} // namespace detail

/// Billboards of book chapter 9: points expanded into screen-aligned quads by a geometry shader,
/// sized in pixels and snapped to whole pixels, so a 1:1 image is drawn texel for pixel. All
/// images share one texture atlas and all billboards one vertex buffer: the collection draws in
/// one call, in the translucent pass. Positions go to the GPU as two floats each (high and low)
/// and are made relative to the eye there, so they stay precise at any distance.
///
/// A setter rewrites the billboard's vertex in memory and marks it; update() uploads only the
/// marked vertices, in runs (lastUpload() says how many bytes).
///
/// Each vertex is 44 bytes: position high and low (24), pixel offset (2 x int16), atlas texel
/// rectangle (4 x uint16), colour (4 x uint8), scale, origins and visibility packed in a uint32.
///
/// ```
/// auto billboards = std::make_shared<BillboardCollection>();
/// const std::size_t pin = billboards->addImage(world::readImage("pin.png"));
/// const std::size_t square = billboards->addImage(billboardShapeImage(BillboardShape::Square, 8));
/// billboards->add({.position = ellipsoid.toCartesian(where), .image = pin});
/// billboards->add({.position = ellipsoid.toCartesian(there), .image = square, .color = {1, 0, 0, 1}});
/// scene.add(billboards);
/// billboards->setPosition(0, elsewhere); // one vertex uploaded on the next frame
/// ```
class BillboardCollection final : public Primitive {
public:
    explicit BillboardCollection(const BillboardCollectionOptions& options = {});
    ~BillboardCollection() override;
    BillboardCollection(const BillboardCollection&) = delete;
    BillboardCollection& operator=(const BillboardCollection&) = delete;

    /// Adds an image to the atlas (1 channel: grey, 3: opaque RGB, 4: RGBA; others throw
    /// orbis::Error); returns its index. Throws orbis::Error when it cannot fit the atlas.
    std::size_t addImage(const Image& image);
    /// Adds several at once (packed tighter); returns the index of the first.
    std::size_t addImages(std::span<const Image> images);
    const renderer::TextureAtlas& atlas() const noexcept { return _atlas; }

    /// Adds a billboard; returns its index. Its image must have been added (asserted).
    std::size_t add(const Billboard& billboard);
    /// Reserves room for that many billboards in memory (not on the GPU).
    void reserve(std::size_t count);
    /// Removes every billboard (images stay in the atlas).
    void clear();
    std::size_t size() const noexcept { return _billboards.size(); }
    const Billboard& billboard(std::size_t index) const { return _billboards.at(index); }

    /// Replace one property of billboard `index` (< size(), asserted).
    void set(std::size_t index, const Billboard& billboard);
    void setPosition(std::size_t index, const glm::dvec3& position);
    void setImage(std::size_t index, std::size_t image);
    void setPixelOffset(std::size_t index, const glm::ivec2& pixelOffset);
    void setOrigin(std::size_t index, HorizontalOrigin horizontal, VerticalOrigin vertical);
    void setColor(std::size_t index, const glm::vec4& color);
    void setScale(std::size_t index, float scale);
    void setVisible(std::size_t index, bool visible);

    const BillboardCollectionOptions& options() const noexcept { return _options; }
    /// Changes how billboards are hidden (takes effect on the next frame; no upload).
    void setDepthOptions(const BillboardDepthOptions& depth) noexcept { _options.depth = depth; }

    /// What the last frame's updates uploaded (a frame whose depth strategy Automatic changes
    /// updates twice).
    const BillboardUploadStatistics& lastUpload() const noexcept { return _lastUpload; }
    /// Bytes of one vertex on the GPU.
    static std::size_t vertexSizeInBytes() noexcept;

    /// The sphere around every position added or moved since the last clear() (it grows when a
    /// billboard moves out of it and never shrinks); empty with no billboards.
    std::optional<BoundingSphere> boundingSphere() const override;
    void update(FrameState& frameState, CommandList& commands) override;
    /// Its quads write every DepthStrategy's depth (at their depth point).
    bool supportsLogarithmicDepth() const override { return true; }

private:
    void writeVertex(std::size_t index);
    std::size_t addToAtlas(std::span<const Image> images);

    BillboardCollectionOptions _options;
    renderer::TextureAtlas _atlas;
    std::vector<Billboard> _billboards;
    std::unique_ptr<detail::BillboardBatch<detail::BillboardVertex>> _batch;
    std::unique_ptr<detail::BillboardBounds> _bounds;
    std::unique_ptr<detail::AtlasTexture> _texture;
    std::unique_ptr<detail::DepthPrograms> _programs;
    BillboardUploadStatistics _lastUpload;
    std::uint64_t _lastUploadFrame = 0; ///< the frame _lastUpload counts
};

} // namespace orbis::scene
