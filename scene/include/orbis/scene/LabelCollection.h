#pragma once

#include "orbis/scene/BillboardCollection.h"

#include <orbis/renderer/GlyphAtlas.h>

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace orbis::renderer {
class Font;
} // namespace orbis::renderer

namespace orbis::scene {

struct LabelCollectionOptions {
    /// A TrueType file; empty: defaultFontPath() (ORBIS_FONT, else fontconfig's DejaVu Sans or the
    /// closest sans-serif; FontLookup.h).
    std::filesystem::path fontPath;
    int haloPixels = 2; ///< width of the halo around the glyphs; 0 for none
    /// Each frame, hide the labels whose box overlaps that of an earlier label shown (earlier
    /// labels win, so add the most important first). Labels behind the horizon take no room.
    bool declutter = false;
    BillboardDepthOptions depth;
};

/// One label: UTF-8 text drawn at 1:1 at a world position, its box placed by its origins.
struct Label {
    glm::dvec3 position{0.0}; ///< world, metres
    std::string text;         ///< UTF-8; '\n' starts a new line
    float fontSizePixels = 16.0f; ///< em size; each size has its own glyph atlas and draw call
    glm::vec4 fillColor{1.0f};
    glm::vec4 haloColor{0.0f, 0.0f, 0.0f, 1.0f}; ///< alpha 0: no halo
    /// Moves the box from its anchor, in pixels: x to the right, y down.
    glm::ivec2 pixelOffset{0, 0};
    /// Which side of the text's box (its glyphs' bitmaps, halo included) sits on the anchor. The
    /// default centres the text above the point.
    HorizontalOrigin horizontalOrigin = HorizontalOrigin::Center;
    VerticalOrigin verticalOrigin = VerticalOrigin::Bottom;
    bool visible = true;
};

namespace detail {
struct GlyphVertex;
class DepthPrograms;
} // namespace detail

/// Labels of book chapter 9 on the billboard machinery: each label is a run of glyph quads from
/// a GlyphAtlas of the font (DejaVu Sans by default), laid out at whole pixels with kerning and drawn through the
/// billboard geometry shader, which snaps them to whole pixels, so text is crisp at 1:1. The fill
/// is drawn over a halo (the glyphs' coverage dilated by haloPixels) for readability over any
/// background. One draw call per font size, in the translucent pass; hidden below the horizon
/// like billboards (BillboardDepthOptions).
///
/// Setters rewrite only the label's glyph vertices; a new text rewrites the vertices of its
/// font size (the runs move).
///
/// ```
/// auto labels = std::make_shared<LabelCollection>();
/// labels->add({.position = ellipsoid.toCartesian(paris), .text = "Paris"});
/// scene.add(labels);
/// ```
class LabelCollection final : public Primitive {
public:
    /// Reads the font; throws orbis::Error naming the path when it cannot.
    explicit LabelCollection(const LabelCollectionOptions& options = {});
    ~LabelCollection() override;
    LabelCollection(const LabelCollection&) = delete;
    LabelCollection& operator=(const LabelCollection&) = delete;

    /// Adds a label; returns its index. Throws orbis::Error when the glyph atlas is full.
    std::size_t add(const Label& label);
    void clear();
    std::size_t size() const noexcept { return _labels.size(); }
    const Label& label(std::size_t index) const { return _labels.at(index).label; }

    /// Replace one property of label `index` (< size(), asserted).
    void set(std::size_t index, const Label& label);
    void setPosition(std::size_t index, const glm::dvec3& position);
    void setText(std::size_t index, const std::string& text);
    void setColors(std::size_t index, const glm::vec4& fillColor, const glm::vec4& haloColor);
    void setPixelOffset(std::size_t index, const glm::ivec2& pixelOffset);
    void setOrigin(std::size_t index, HorizontalOrigin horizontal, VerticalOrigin vertical);
    void setVisible(std::size_t index, bool visible);

    /// The box of label `index`'s glyph quads relative to its anchor's pixel corner, offset and
    /// origins applied, in pixels x right and y down ((x, y) its top-left corner): where its
    /// pixels land.
    renderer::PixelRectangle placement(std::size_t index) const;
    /// The laid-out text of label `index` (glyph positions y down from the first baseline).
    const renderer::TextLayout& layout(std::size_t index) const { return _labels.at(index).layout; }
    /// The glyph atlas of a font size, created on first use.
    const renderer::GlyphAtlas& glyphAtlas(float fontSizePixels);

    const LabelCollectionOptions& options() const noexcept { return _options; }
    void setDepthOptions(const BillboardDepthOptions& depth) noexcept { _options.depth = depth; }
    /// Turns decluttering on or off from the next update (LabelCollectionOptions::declutter).
    void setDeclutter(bool declutter) noexcept { _options.declutter = declutter; }
    /// Labels the last update hid because they overlapped an earlier one.
    std::size_t lastDecluttered() const noexcept { return _lastDecluttered; }
    /// What the last frame's updates uploaded, over every font size.
    const BillboardUploadStatistics& lastUpload() const noexcept { return _lastUpload; }
    /// Draw calls (font sizes with glyphs) of the last update.
    std::size_t lastDrawCalls() const noexcept { return _lastDrawCalls; }

    std::optional<BoundingSphere> boundingSphere() const override;
    void update(FrameState& frameState, CommandList& commands) override;
    /// Its glyph quads write every DepthStrategy's depth (at their depth point).
    bool supportsLogarithmicDepth() const override { return true; }

private:
    struct SizeBatch;
    struct Record {
        Label label;
        renderer::TextLayout layout;
        std::size_t firstVertex = 0; ///< in its size's batch
        bool decluttered = false;    ///< hidden this frame by an overlapping earlier label
    };

    SizeBatch& sizeBatch(float fontSizePixels);
    void layOut(Record& record);
    /// Rewrites the glyph vertices of one label (marking them when mark).
    void writeVertices(std::size_t index, bool mark);
    /// Assigns vertex runs again for every label of a size and rewrites them all.
    void rebuild(SizeBatch& batch);
    /// Sets each label's decluttered flag for the frame's view, rewriting the labels it changes.
    void declutter(const FrameState& frameState);

    LabelCollectionOptions _options;
    std::shared_ptr<const renderer::Font> _font;
    std::map<float, std::unique_ptr<SizeBatch>> _sizes;
    std::vector<Record> _labels;
    std::unique_ptr<detail::BillboardBounds> _bounds;
    std::unique_ptr<detail::DepthPrograms> _programs;
    BillboardUploadStatistics _lastUpload;
    std::uint64_t _lastUploadFrame = 0; ///< the frame _lastUpload counts
    std::size_t _lastDrawCalls = 0;
    std::size_t _lastDecluttered = 0;
};

} // namespace orbis::scene
