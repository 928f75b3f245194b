#include "orbis/scene/LabelCollection.h"

#include "orbis/scene/Effect.h"
#include "orbis/scene/FontLookup.h"

#include "BillboardBatch.h"

#include <orbis/renderer/Font.h>

#include <glm/mat4x4.hpp>

#include <algorithm>
#include <cmath>

namespace orbis::scene {

struct LabelCollection::SizeBatch {
    SizeBatch(std::shared_ptr<const renderer::Font> font, const renderer::GlyphAtlasOptions& options) : glyphs(std::move(font), options) {}

    renderer::GlyphAtlas glyphs;
    detail::AtlasTexture texture;
    detail::BillboardBatch<detail::GlyphVertex> batch;
    std::vector<std::size_t> labels; ///< indices of the labels of this size, ascending
    bool rebuild = false;            ///< vertex runs to assign again before the next upload
};

namespace {

/// floor(fraction x size) for an origin: 0, half (rounded down) or all of the size.
int originShift(int origin, int size)
{
    return origin == 0 ? 0 : origin == 1 ? size / 2 : size;
}

bool overlap(const renderer::PixelRectangle& a, const renderer::PixelRectangle& b) noexcept
{
    return a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height;
}

/// The boxes of the labels shown so far in a frame, in a grid of square cells so that a box is
/// compared with its neighbours only.
class ScreenOccupancy {
public:
    ScreenOccupancy(int width, int height)
        : _columns(std::max(1, (width + kCell - 1) / kCell))
        , _rows(std::max(1, (height + kCell - 1) / kCell))
        , _cells(static_cast<std::size_t>(_columns) * static_cast<std::size_t>(_rows))
    {
    }

    /// Takes the box unless it overlaps one taken before; false then.
    bool take(const renderer::PixelRectangle& box)
    {
        const int x0 = std::clamp(floorDivide(box.x), 0, _columns);
        const int x1 = std::clamp(floorDivide(box.x + box.width - 1) + 1, 0, _columns);
        const int y0 = std::clamp(floorDivide(box.y), 0, _rows);
        const int y1 = std::clamp(floorDivide(box.y + box.height - 1) + 1, 0, _rows);
        for (int y = y0; y < y1; ++y) {
            for (int x = x0; x < x1; ++x) {
                for (const renderer::PixelRectangle& taken : cell(x, y)) {
                    if (overlap(box, taken)) {
                        return false;
                    }
                }
            }
        }
        for (int y = y0; y < y1; ++y) {
            for (int x = x0; x < x1; ++x) {
                cell(x, y).push_back(box);
            }
        }
        return true;
    }

private:
    static constexpr int kCell = 64; ///< pixels: a few cells for a typical label

    static int floorDivide(int value) noexcept { return value >= 0 ? value / kCell : -((-value + kCell - 1) / kCell); }
    std::vector<renderer::PixelRectangle>& cell(int x, int y) { return _cells[static_cast<std::size_t>(y) * _columns + x]; }

    int _columns;
    int _rows;
    std::vector<std::vector<renderer::PixelRectangle>> _cells;
};

} // namespace

LabelCollection::LabelCollection(const LabelCollectionOptions& options)
    : _options(options)
    , _font(std::make_shared<renderer::Font>(options.fontPath.empty() ? defaultFontPath() : options.fontPath))
    , _bounds(std::make_unique<detail::BillboardBounds>())
    , _programs(detail::billboardPrograms(true))
{
}

LabelCollection::~LabelCollection() = default;

LabelCollection::SizeBatch& LabelCollection::sizeBatch(float fontSizePixels)
{
    std::unique_ptr<SizeBatch>& batch = _sizes[fontSizePixels];
    if (!batch) {
        renderer::GlyphAtlasOptions options;
        options.sizePixels = fontSizePixels;
        options.outlinePixels = std::max(_options.haloPixels, 0);
        batch = std::make_unique<SizeBatch>(_font, options);
    }
    return *batch;
}

const renderer::GlyphAtlas& LabelCollection::glyphAtlas(float fontSizePixels)
{
    return sizeBatch(fontSizePixels).glyphs;
}

void LabelCollection::layOut(Record& record)
{
    SizeBatch& batch = sizeBatch(record.label.fontSizePixels);
    const renderer::TextureAtlas::AddResult added = batch.glyphs.addCharacters(record.label.text);
    batch.texture.noteChange(added);
    if (added.repacked) {
        batch.rebuild = true; // every glyph moved in the atlas
    }
    record.layout = batch.glyphs.layout(record.label.text);
}

renderer::PixelRectangle LabelCollection::placement(std::size_t index) const
{
    const Record& record = _labels.at(index);
    const renderer::PixelRectangle& box = record.layout.bounds;
    // The origin's side sits on the anchor: its bottom edge for Bottom, so the top is a box
    // height above (y down: negative).
    return {record.label.pixelOffset.x - originShift(static_cast<int>(record.label.horizontalOrigin), box.width),
            record.label.pixelOffset.y + originShift(static_cast<int>(record.label.verticalOrigin), box.height) -
                box.height,
            box.width, box.height};
}

void LabelCollection::writeVertices(std::size_t index, bool mark)
{
    const Record& record = _labels[index];
    SizeBatch& batch = *_sizes.at(record.label.fontSizePixels);
    const Label& label = record.label;
    const renderer::PixelRectangle place = placement(index);
    // The layout's box (y down from the baseline) moved so that its top-left is `place`; each
    // glyph is a billboard whose top-left corner sits at its offset.
    const int shiftX = place.x - record.layout.bounds.x;
    const int shiftY = place.y - record.layout.bounds.y;
    detail::GlyphVertex common{};
    detail::setPosition(common, label.position);
    detail::packColor(label.fillColor, common.color);
    detail::packColor(label.haloColor, common.haloColor);
    common.scaleOriginVisibility = detail::packScaleOriginVisibility(1.0f, HorizontalOrigin::Left, VerticalOrigin::Top,
                                                                     label.visible && !record.decluttered);
    std::vector<detail::GlyphVertex>& vertices = batch.batch.vertices();
    for (std::size_t q = 0; q < record.layout.quads.size(); ++q) {
        const renderer::GlyphQuad& quad = record.layout.quads[q];
        detail::GlyphVertex& v = vertices[record.firstVertex + q];
        v = common;
        v.pixelOffset[0] = detail::clampToShort(shiftX + quad.x);
        v.pixelOffset[1] = detail::clampToShort(shiftY + quad.y);
        detail::setTextureRectangle(v, batch.glyphs.atlas().rectangle(quad.atlasIndex));
        if (mark) {
            batch.batch.mark(record.firstVertex + q);
        }
    }
}

void LabelCollection::rebuild(SizeBatch& batch)
{
    std::vector<detail::GlyphVertex>& vertices = batch.batch.vertices();
    vertices.clear();
    for (const std::size_t index : batch.labels) {
        Record& record = _labels[index];
        record.firstVertex = vertices.size();
        vertices.resize(vertices.size() + record.layout.quads.size());
        writeVertices(index, false);
    }
    batch.batch.markAll();
    batch.rebuild = false;
}

std::size_t LabelCollection::add(const Label& label)
{
    const std::size_t index = _labels.size();
    _labels.push_back({label, {}, 0});
    Record& record = _labels.back();
    layOut(record);
    SizeBatch& batch = *_sizes.at(label.fontSizePixels);
    batch.labels.push_back(index);
    if (!batch.rebuild) {
        record.firstVertex = batch.batch.vertices().size();
        batch.batch.vertices().resize(record.firstVertex + record.layout.quads.size());
        writeVertices(index, false);
        batch.batch.markAll(); // the buffer grows: written whole
    }
    _bounds->add(label.position);
    return index;
}

void LabelCollection::clear()
{
    _labels.clear();
    for (auto& [size, batch] : _sizes) {
        batch->labels.clear();
        batch->batch.vertices().clear();
        batch->batch.markAll();
    }
    _bounds->clear();
}

void LabelCollection::set(std::size_t index, const Label& label)
{
    assert(index < _labels.size());
    Record& record = _labels[index];
    const Label old = record.label;
    record.label = label;
    if (old.position != label.position) {
        _bounds->move(label.position);
    }
    if (old.fontSizePixels != label.fontSizePixels) {
        SizeBatch& from = *_sizes.at(old.fontSizePixels);
        std::erase(from.labels, index);
        from.rebuild = true;
        layOut(record);
        SizeBatch& to = *_sizes.at(label.fontSizePixels);
        to.labels.insert(std::lower_bound(to.labels.begin(), to.labels.end(), index), index);
        to.rebuild = true;
        return;
    }
    if (old.text != label.text) {
        const std::size_t glyphsBefore = record.layout.quads.size();
        layOut(record);
        SizeBatch& batch = *_sizes.at(label.fontSizePixels);
        if (record.layout.quads.size() != glyphsBefore) {
            batch.rebuild = true;
        }
        if (batch.rebuild) {
            return;
        }
    }
    if (!_sizes.at(label.fontSizePixels)->rebuild) {
        writeVertices(index, true);
    }
}

void LabelCollection::setPosition(std::size_t index, const glm::dvec3& position)
{
    Label label = this->label(index);
    label.position = position;
    set(index, label);
}

void LabelCollection::setText(std::size_t index, const std::string& text)
{
    Label label = this->label(index);
    label.text = text;
    set(index, label);
}

void LabelCollection::setColors(std::size_t index, const glm::vec4& fillColor, const glm::vec4& haloColor)
{
    Label label = this->label(index);
    label.fillColor = fillColor;
    label.haloColor = haloColor;
    set(index, label);
}

void LabelCollection::setPixelOffset(std::size_t index, const glm::ivec2& pixelOffset)
{
    Label label = this->label(index);
    label.pixelOffset = pixelOffset;
    set(index, label);
}

void LabelCollection::setOrigin(std::size_t index, HorizontalOrigin horizontal, VerticalOrigin vertical)
{
    Label label = this->label(index);
    label.horizontalOrigin = horizontal;
    label.verticalOrigin = vertical;
    set(index, label);
}

void LabelCollection::setVisible(std::size_t index, bool visible)
{
    Label label = this->label(index);
    label.visible = visible;
    set(index, label);
}

std::optional<BoundingSphere> LabelCollection::boundingSphere() const
{
    return _bounds->sphere();
}

void LabelCollection::declutter(const FrameState& frameState)
{
    if (!_options.declutter && _lastDecluttered == 0) {
        return; // nothing to do, nor to undo
    }
    // The window position of an anchor does not depend on the near and far distances.
    const double aspectRatio = static_cast<double>(frameState.width) / std::max(frameState.height, 1);
    const glm::dmat4 viewProjection =
        frameState.camera.projectionMatrix(aspectRatio, 1.0, 2.0) * frameState.camera.viewMatrix();
    ScreenOccupancy occupancy(frameState.width, frameState.height);
    _lastDecluttered = 0;
    for (std::size_t index = 0; index < _labels.size(); ++index) {
        Record& record = _labels[index];
        bool hidden = false;
        if (_options.declutter && record.label.visible && frameState.occluder.isPointVisible(record.label.position)) {
            const glm::dvec4 clip = viewProjection * glm::dvec4(record.label.position, 1.0);
            if (clip.w > 0.0) {
                // Where the billboard shader puts the anchor: the nearest pixel corner, y down here.
                const glm::dvec2 window = clipToWindow(clip, frameState.width, frameState.height);
                renderer::PixelRectangle box = placement(index);
                box.x += static_cast<int>(std::floor(window.x + 0.5));
                box.y += frameState.height - static_cast<int>(std::floor(window.y + 0.5));
                hidden = !occupancy.take(box);
            }
        }
        _lastDecluttered += hidden ? 1 : 0;
        if (hidden != record.decluttered) {
            record.decluttered = hidden;
            if (!_sizes.at(record.label.fontSizePixels)->rebuild) {
                writeVertices(index, true);
            }
        }
    }
}

void LabelCollection::update(FrameState& frameState, CommandList& commands)
{
    if (_lastUploadFrame != frameState.frameNumber) {
        _lastUpload = {};
        _lastUploadFrame = frameState.frameNumber;
    }
    _lastDrawCalls = 0;
    if (_labels.empty()) {
        return;
    }
    declutter(frameState);
    std::vector<glm::dvec3> positions;
    if (_bounds->needsPositions(frameState.ellipsoid)) {
        positions.reserve(_labels.size());
        for (const Record& record : _labels) {
            positions.push_back(record.label.position);
        }
    }
    const std::optional<glm::dvec3> occlusionPoint = _bounds->refresh(frameState.ellipsoid, positions);
    for (auto& [size, batch] : _sizes) {
        if (batch->rebuild) {
            rebuild(*batch);
        }
        if (batch->batch.vertices().empty()) {
            continue;
        }
        renderer::ShaderProgram& program = _programs->get(frameState, Pass::Translucent);
        _lastUpload.textureBytesUploaded += batch->texture.synchronize(frameState.device, batch->glyphs.atlas());
        batch->batch.upload(frameState, program, _lastUpload);

        SceneCommand command;
        command.draw.debugName = "labels";
        command.tags = static_cast<std::uint32_t>(Effect::Labels);
        command.horizonOcclusionPoint = occlusionPoint;
        command.boundingSphere = _bounds->sphere();
        command.draw.vertexArray = batch->batch.vertexArray();
        command.draw.shaderProgram = &program;
        command.draw.count = batch->batch.vertices().size();
        command.draw.textures.push_back({0, batch->texture.texture(), nullptr});
        detail::prepareBillboardCommand(command, frameState, _options.depth, batch->glyphs.atlas());
        commands.push_back(std::move(command));
        ++_lastDrawCalls;
    }
}

} // namespace orbis::scene
