#include "orbis/scene/BillboardCollection.h"

#include "orbis/scene/Effect.h"

#include "BillboardBatch.h"

#include <orbis/core/Error.h>

#include <string>

namespace orbis::scene {

Image billboardShapeImage(BillboardShape shape, int sizePixels)
{
    const int size = std::max(sizePixels, 1);
    Image image(size, size, 4);
    const double radius = 0.5 * size;
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            // The dot's coverage of a pixel: 1 inside, falling over the pixel the edge crosses.
            const double distance = std::hypot(x + 0.5 - radius, y + 0.5 - radius);
            const double coverage = shape == BillboardShape::Square ? 1.0 : std::clamp(radius - distance + 0.5, 0.0, 1.0);
            std::uint8_t* p = image.pixel(x, y);
            p[0] = p[1] = p[2] = 255;
            p[3] = static_cast<std::uint8_t>(std::lround(255.0 * coverage));
        }
    }
    return image;
}

namespace {

/// The image as RGBA: grey and RGB become opaque colours.
Image toRgba(const Image& image)
{
    if (image.channels == 4) {
        return image;
    }
    if (image.channels != 1 && image.channels != 3) {
        throw Error("BillboardCollection::addImage: an image of " + std::to_string(image.channels) +
                    " channels; expected 1 (grey), 3 (RGB) or 4 (RGBA)");
    }
    Image rgba(image.width, image.height, 4);
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const std::uint8_t* from = image.pixel(x, y);
            std::uint8_t* to = rgba.pixel(x, y);
            for (int c = 0; c < 3; ++c) {
                to[c] = from[image.channels == 1 ? 0 : c];
            }
            to[3] = 255;
        }
    }
    return rgba;
}

} // namespace

BillboardCollection::BillboardCollection(const BillboardCollectionOptions& options)
    : _options(options)
    , _atlas(renderer::TextureAtlasOptions{4, options.atlasPadding, options.atlasInitialSize, options.atlasMaxSize})
    , _batch(std::make_unique<detail::BillboardBatch<detail::BillboardVertex>>())
    , _bounds(std::make_unique<detail::BillboardBounds>())
    , _texture(std::make_unique<detail::AtlasTexture>())
    , _programs(detail::billboardPrograms(false))
{
}

BillboardCollection::~BillboardCollection() = default;

std::size_t BillboardCollection::vertexSizeInBytes() noexcept
{
    return sizeof(detail::BillboardVertex);
}

std::size_t BillboardCollection::addImage(const Image& image)
{
    return addImages(std::span(&image, 1));
}

std::size_t BillboardCollection::addImages(std::span<const Image> images)
{
    std::vector<Image> rgba;
    rgba.reserve(images.size());
    for (const Image& image : images) {
        rgba.push_back(toRgba(image));
    }
    const renderer::TextureAtlas::AddResult result = _atlas.add(rgba);
    _texture->noteChange(result);
    if (result.repacked) {
        // Every image moved: every billboard's texel rectangle changes.
        for (std::size_t i = 0; i < _billboards.size(); ++i) {
            writeVertex(i);
        }
        _batch->markAll();
    }
    return result.first;
}

std::size_t BillboardCollection::add(const Billboard& billboard)
{
    assert(billboard.image < _atlas.size());
    _billboards.push_back(billboard);
    _batch->vertices().emplace_back();
    writeVertex(_billboards.size() - 1);
    _batch->markAll();
    _bounds->add(billboard.position);
    return _billboards.size() - 1;
}

void BillboardCollection::reserve(std::size_t count)
{
    _billboards.reserve(count);
    _batch->vertices().reserve(count);
}

void BillboardCollection::clear()
{
    _billboards.clear();
    _batch->vertices().clear();
    _batch->markAll();
    _bounds->clear();
}

void BillboardCollection::writeVertex(std::size_t index)
{
    const Billboard& b = _billboards[index];
    detail::BillboardVertex& v = _batch->vertices()[index];
    detail::setPosition(v, b.position);
    v.pixelOffset[0] = detail::clampToShort(b.pixelOffset.x);
    v.pixelOffset[1] = detail::clampToShort(b.pixelOffset.y);
    detail::setTextureRectangle(v, _atlas.rectangle(b.image));
    detail::packColor(b.color, v.color);
    v.scaleOriginVisibility =
        detail::packScaleOriginVisibility(b.scale, b.horizontalOrigin, b.verticalOrigin, b.visible);
}

void BillboardCollection::set(std::size_t index, const Billboard& billboard)
{
    assert(index < _billboards.size() && billboard.image < _atlas.size());
    const bool moved = billboard.position != _billboards[index].position;
    _billboards[index] = billboard;
    writeVertex(index);
    _batch->mark(index);
    if (moved) {
        _bounds->move(billboard.position);
    }
}

void BillboardCollection::setPosition(std::size_t index, const glm::dvec3& position)
{
    assert(index < _billboards.size());
    _billboards[index].position = position;
    detail::setPosition(_batch->vertices()[index], position);
    _batch->mark(index);
    _bounds->move(position);
}

void BillboardCollection::setImage(std::size_t index, std::size_t image)
{
    assert(index < _billboards.size() && image < _atlas.size());
    _billboards[index].image = image;
    detail::setTextureRectangle(_batch->vertices()[index], _atlas.rectangle(image));
    _batch->mark(index);
}

void BillboardCollection::setPixelOffset(std::size_t index, const glm::ivec2& pixelOffset)
{
    assert(index < _billboards.size());
    _billboards[index].pixelOffset = pixelOffset;
    detail::BillboardVertex& v = _batch->vertices()[index];
    v.pixelOffset[0] = detail::clampToShort(pixelOffset.x);
    v.pixelOffset[1] = detail::clampToShort(pixelOffset.y);
    _batch->mark(index);
}

void BillboardCollection::setOrigin(std::size_t index, HorizontalOrigin horizontal, VerticalOrigin vertical)
{
    assert(index < _billboards.size());
    Billboard& b = _billboards[index];
    b.horizontalOrigin = horizontal;
    b.verticalOrigin = vertical;
    _batch->vertices()[index].scaleOriginVisibility =
        detail::packScaleOriginVisibility(b.scale, b.horizontalOrigin, b.verticalOrigin, b.visible);
    _batch->mark(index);
}

void BillboardCollection::setColor(std::size_t index, const glm::vec4& color)
{
    assert(index < _billboards.size());
    _billboards[index].color = color;
    detail::packColor(color, _batch->vertices()[index].color);
    _batch->mark(index);
}

void BillboardCollection::setScale(std::size_t index, float scale)
{
    assert(index < _billboards.size());
    Billboard& b = _billboards[index];
    b.scale = scale;
    _batch->vertices()[index].scaleOriginVisibility =
        detail::packScaleOriginVisibility(b.scale, b.horizontalOrigin, b.verticalOrigin, b.visible);
    _batch->mark(index);
}

void BillboardCollection::setVisible(std::size_t index, bool visible)
{
    assert(index < _billboards.size());
    Billboard& b = _billboards[index];
    b.visible = visible;
    _batch->vertices()[index].scaleOriginVisibility =
        detail::packScaleOriginVisibility(b.scale, b.horizontalOrigin, b.verticalOrigin, b.visible);
    _batch->mark(index);
}

std::optional<BoundingSphere> BillboardCollection::boundingSphere() const
{
    return _bounds->sphere();
}

void BillboardCollection::update(FrameState& frameState, CommandList& commands)
{
    if (_lastUploadFrame != frameState.frameNumber) {
        _lastUpload = {};
        _lastUploadFrame = frameState.frameNumber;
    }
    if (_billboards.empty()) {
        return;
    }
    renderer::ShaderProgram& program = _programs->get(frameState, Pass::Translucent);
    _lastUpload.textureBytesUploaded += _texture->synchronize(frameState.device, _atlas);
    _batch->upload(frameState, program, _lastUpload);

    std::vector<glm::dvec3> positions;
    if (_bounds->needsPositions(frameState.ellipsoid)) {
        positions.reserve(_billboards.size());
        for (const Billboard& b : _billboards) {
            positions.push_back(b.position);
        }
    }
    SceneCommand command;
    command.draw.debugName = "billboards";
    command.tags = static_cast<std::uint32_t>(Effect::Billboards);
    command.horizonOcclusionPoint = _bounds->refresh(frameState.ellipsoid, positions);
    command.boundingSphere = _bounds->sphere();
    command.draw.vertexArray = _batch->vertexArray();
    command.draw.shaderProgram = &program;
    command.draw.count = _billboards.size();
    command.draw.textures.push_back({0, _texture->texture(), nullptr});
    detail::prepareBillboardCommand(command, frameState, _options.depth, _atlas);
    commands.push_back(std::move(command));
}

} // namespace orbis::scene
