#pragma once

// What BillboardCollection and LabelCollection share: the packed vertex layouts, a vertex buffer
// kept in step with a copy in memory by uploading only changed runs, the atlas texture, the
// bounding volumes, and the draw command of the billboard program. Private to orbis::scene.

#include "orbis/scene/BillboardCollection.h"

#include "DepthPrograms.h"

#include <orbis/core/BoundingSphere.h>
#include <orbis/core/EllipsoidalOccluder.h>
#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>
#include <orbis/renderer/Texture2D.h>
#include <orbis/renderer/VertexArray.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace orbis::scene::detail {

/// Splits x so that double(high) + double(low) holds it to about 48 bits. The rounded value goes
/// through a volatile so that the compiler cannot keep it in double precision (GCC 12 at -O3 was
/// seen to, which left low = 0).
inline void splitToFloats(double x, float& high, float& low) noexcept
{
    volatile float rounded = static_cast<float>(x);
    high = rounded;
    low = static_cast<float>(x - static_cast<double>(high));
}

/// Scale (8.8 fixed point), origins and visibility in one 32-bit word: bits 0-15 scale x 256,
/// 16-17 horizontal origin, 18-19 vertical origin, 20 visible. The shader unpacks the same bits.
inline std::uint32_t packScaleOriginVisibility(float scale, HorizontalOrigin horizontal, VerticalOrigin vertical,
                                               bool visible) noexcept
{
    const float fixed = std::clamp(std::isfinite(scale) ? scale : 0.0f, 0.0f, 65535.0f / 256.0f) * 256.0f;
    return static_cast<std::uint32_t>(std::lround(fixed)) | static_cast<std::uint32_t>(horizontal) << 16 |
           static_cast<std::uint32_t>(vertical) << 18 | (visible ? 1u << 20 : 0u);
}

inline std::int16_t clampToShort(int value) noexcept
{
    return static_cast<std::int16_t>(std::clamp(value, -32768, 32767));
}

inline void packColor(const glm::vec4& color, std::uint8_t (&out)[4]) noexcept
{
    for (int i = 0; i < 4; ++i) {
        out[i] = static_cast<std::uint8_t>(std::lround(std::clamp(color[i], 0.0f, 1.0f) * 255.0f));
    }
}

/// One billboard: 44 bytes.
struct BillboardVertex {
    float positionHigh[3];
    float positionLow[3];
    std::int16_t pixelOffset[2];
    std::uint16_t textureRectangle[4]; ///< texels: x, y (rows from the top), width, height
    std::uint8_t color[4];
    std::uint32_t scaleOriginVisibility;

    static constexpr bool kHalo = false;
};
static_assert(sizeof(BillboardVertex) == 44);

/// One glyph of a label: a billboard's fields and a halo colour, 48 bytes.
struct GlyphVertex {
    float positionHigh[3];
    float positionLow[3];
    std::int16_t pixelOffset[2];
    std::uint16_t textureRectangle[4];
    std::uint8_t color[4];
    std::uint32_t scaleOriginVisibility;
    std::uint8_t haloColor[4];

    static constexpr bool kHalo = true;
};
static_assert(sizeof(GlyphVertex) == 48);

template <typename Vertex>
void setPosition(Vertex& vertex, const glm::dvec3& position) noexcept
{
    for (int i = 0; i < 3; ++i) {
        splitToFloats(position[i], vertex.positionHigh[i], vertex.positionLow[i]);
    }
}

template <typename Vertex>
void setTextureRectangle(Vertex& vertex, const renderer::PixelRectangle& rectangle) noexcept
{
    vertex.textureRectangle[0] = static_cast<std::uint16_t>(rectangle.x);
    vertex.textureRectangle[1] = static_cast<std::uint16_t>(rectangle.y);
    vertex.textureRectangle[2] = static_cast<std::uint16_t>(rectangle.width);
    vertex.textureRectangle[3] = static_cast<std::uint16_t>(rectangle.height);
}

/// The collection's bounding sphere and horizon occlusion point. An added position grows the
/// sphere at once (so whole-primitive culling never misses it) and marks both for a tight rebuild
/// from every position on the next refresh; a moved position only grows them (conservative, O(1)
/// per move, no pass over the collection).
class BillboardBounds {
public:
    void clear() noexcept
    {
        _sphere.reset();
        _occlusion.reset();
        _moved.clear();
        _rebuild = false;
    }
    void add(const glm::dvec3& position)
    {
        grow(position);
        _rebuild = true;
    }
    void move(const glm::dvec3& position)
    {
        grow(position);
        if (!_rebuild && _occlusion) {
            _moved.push_back(position);
            if (_moved.size() > kMaxMoved) {
                _rebuild = true; // cheaper to start again than to test them one by one
                _moved.clear();
            }
        }
    }
    const std::optional<BoundingSphere>& sphere() const noexcept { return _sphere; }

    /// True when refresh() needs every position.
    bool needsPositions(const Ellipsoid& ellipsoid) const noexcept
    {
        return _rebuild || !_occlusion || _occlusion->radii != ellipsoid.radii();
    }
    /// Brings both up to date (positions: all of them when needsPositions(), else ignored) and
    /// returns the horizon occlusion point (scaled space) for this ellipsoid; empty when none
    /// exists (positions all around the globe).
    std::optional<glm::dvec3> refresh(const Ellipsoid& ellipsoid, std::span<const glm::dvec3> positions)
    {
        if (_rebuild) {
            _sphere = positions.empty() ? std::nullopt : std::optional(BoundingSphere::fromPoints(positions));
            _occlusion.reset();
            _rebuild = false;
        }
        if (!_sphere) {
            return std::nullopt;
        }
        const EllipsoidalOccluder occluder(ellipsoid, glm::dvec3(0.0));
        if (!_occlusion || _occlusion->radii != ellipsoid.radii()) {
            const double length = glm::length(_sphere->centre);
            Occlusion occlusion{ellipsoid.radii(), length > 0.0 ? _sphere->centre / length : glm::dvec3(0.0), {}};
            if (length > 0.0) {
                occlusion.point = occluder.horizonOcclusionPoint(occlusion.direction, positions);
            }
            _occlusion = occlusion;
            _moved.clear();
        }
        for (const glm::dvec3& moved : _moved) {
            if (!_occlusion->point) {
                break;
            }
            const std::optional<glm::dvec3> single =
                occluder.horizonOcclusionPoint(_occlusion->direction, std::span(&moved, 1));
            // The hidden points of one line from the centre form an interval from the surface
            // out, so the point for a set is the farthest of the points for each member.
            if (!single) {
                _occlusion->point.reset();
            } else if (glm::length(*single) > glm::length(*_occlusion->point)) {
                _occlusion->point = single;
            }
        }
        _moved.clear();
        return _occlusion->point;
    }

private:
    static constexpr std::size_t kMaxMoved = 65536;

    void grow(const glm::dvec3& position)
    {
        if (!_sphere) {
            _sphere = BoundingSphere{position, 0.0};
        } else if (!_sphere->contains(position)) {
            _sphere = BoundingSphere::merge(*_sphere, BoundingSphere{position, 0.0});
        }
    }

    struct Occlusion {
        glm::dvec3 radii;
        glm::dvec3 direction;
        std::optional<glm::dvec3> point;
    };
    std::optional<BoundingSphere> _sphere;
    std::optional<Occlusion> _occlusion;
    std::vector<glm::dvec3> _moved;
    bool _rebuild = false;
};

/// A texture holding a TextureAtlas's image as RGBA8, rows uploaded in the image's order (row 0
/// at t = 0, as TextureRectangle expects). A 4-channel atlas is premultiplied by its alpha on
/// the way; a 2-channel one (glyph coverage and halo) goes to red and green as it is.
class AtlasTexture {
public:
    /// Notes the pixels an addition to the atlas changed.
    void noteChange(const renderer::TextureAtlas::AddResult& result) noexcept
    {
        if (!result.resized && !result.repacked && (result.changed.width <= 0 || result.changed.height <= 0)) {
            return; // nothing new (characters already there, or without pixels)
        }
        if (result.resized || result.repacked || !_pending) {
            _pending = result.changed;
            _whole = _whole || result.resized || result.repacked;
            return;
        }
        const int left = std::min(_pending->x, result.changed.x);
        const int top = std::min(_pending->y, result.changed.y);
        const int right = std::max(_pending->x + _pending->width, result.changed.x + result.changed.width);
        const int bottom = std::max(_pending->y + _pending->height, result.changed.y + result.changed.height);
        _pending = renderer::PixelRectangle{left, top, right - left, bottom - top};
    }

    /// Brings the texture up to the atlas; returns the bytes uploaded.
    std::size_t synchronize(renderer::Device& device, const renderer::TextureAtlas& atlas)
    {
        const Image& image = atlas.image();
        if (_texture && _version == atlas.version()) {
            return 0;
        }
        _version = atlas.version();
        const bool sizeChanged = !_texture || _texture->width() != image.width || _texture->height() != image.height;
        if (sizeChanged) {
            _texture = device.createTexture2D(renderer::TextureDescription{image.width, image.height, renderer::TextureFormat::RGBA8});
        }
        const renderer::PixelRectangle region = (sizeChanged || _whole || !_pending)
                                          ? renderer::PixelRectangle{0, 0, image.width, image.height}
                                          : *_pending;
        _pending.reset();
        _whole = false;
        if (region.width <= 0 || region.height <= 0) {
            return 0;
        }
        std::vector<std::byte> texels(static_cast<std::size_t>(region.width) * region.height * 4);
        std::byte* out = texels.data();
        for (int y = region.y; y < region.y + region.height; ++y) {
            for (int x = region.x; x < region.x + region.width; ++x) {
                const std::uint8_t* p = image.pixel(x, y);
                std::uint8_t rgba[4] = {p[0], 0, 0, 255};
                if (image.channels == 2) {
                    rgba[1] = p[1];
                } else {
                    for (int c = 0; c < 3; ++c) {
                        rgba[c] = static_cast<std::uint8_t>((p[c] * p[3] + 127) / 255);
                    }
                    rgba[3] = p[3];
                }
                std::memcpy(out, rgba, 4);
                out += 4;
            }
        }
        _texture->copyFromSystemMemory(texels, region);
        return texels.size();
    }

    const renderer::Texture2D* texture() const noexcept { return _texture ? &*_texture : nullptr; }

private:
    std::optional<renderer::Texture2D> _texture;
    std::uint64_t _version = 0;
    std::optional<renderer::PixelRectangle> _pending;
    bool _whole = false;
};

/// The uniforms, render state, pass and scene-depth texture (unit 1) every billboard or label
/// command shares; the command's bounding sphere (set before) grows to cover the points the depth
/// is taken at. The atlas texture must be bound on unit 0 before.
void prepareBillboardCommand(SceneCommand& command, const FrameState& frameState, const BillboardDepthOptions& depth,
                             const renderer::TextureAtlas& atlas);

/// The billboard program (LABEL: the glyph variant) under every depth strategy: the quads keep
/// their depth point's clip z and w, so the strategy applies to them as to any vertex.
std::unique_ptr<DepthPrograms> billboardPrograms(bool label);

/// Vertices in memory and their copy in a vertex buffer. Changed vertices are marked; upload()
/// writes the marked ones in runs (gaps of up to kMergeGap unchanged vertices are rewritten
/// rather than split into another call), or everything in one call when most changed.
template <typename Vertex>
class BillboardBatch {
public:
    static constexpr std::size_t kMergeGap = 8;

    std::vector<Vertex>& vertices() noexcept { return _vertices; }
    const std::vector<Vertex>& vertices() const noexcept { return _vertices; }

    /// Marks vertex i as changed.
    void mark(std::size_t i)
    {
        if (_allDirty) {
            return;
        }
        if (_dirtyFlags.size() < _vertices.size()) {
            _dirtyFlags.resize(_vertices.size(), 0);
        }
        if (!_dirtyFlags[i]) {
            _dirtyFlags[i] = 1;
            _dirty.push_back(static_cast<std::uint32_t>(i));
        }
    }
    /// Marks every vertex (additions, removals, rebuilds).
    void markAll() noexcept
    {
        _allDirty = true;
        _dirty.clear();
        _dirtyFlags.clear();
    }

    /// Sends the marked vertices to the GPU, creating or growing the buffer (and the vertex
    /// array reading it) as needed. Adds to statistics.
    void upload(FrameState& frameState, const renderer::ShaderProgram& program, BillboardUploadStatistics& statistics)
    {
        const std::size_t stride = sizeof(Vertex);
        const std::size_t needed = _vertices.size() * stride;
        if (!_buffer.valid() || _buffer.sizeInBytes() < needed) {
            const std::size_t capacity = std::max(needed, _buffer.sizeInBytes() + _buffer.sizeInBytes() / 2);
            _buffer = frameState.device.createVertexBuffer(capacity, renderer::BufferUsage::DynamicDraw);
            _vertexArray = frameState.context.createVertexArray();
            attach(program);
            _allDirty = true;
        }
        const auto bytes = std::as_bytes(std::span(_vertices));
        auto write = [&](std::size_t first, std::size_t last) {
            _buffer.copyFromSystemMemory(bytes.subspan(first * stride, (last - first) * stride), first * stride);
            statistics.bytesUploaded += (last - first) * stride;
            statistics.verticesUploaded += last - first;
            ++statistics.uploadCalls;
        };
        if (_allDirty || _dirty.size() * 2 > _vertices.size()) {
            if (!_vertices.empty()) {
                write(0, _vertices.size());
            }
            statistics.fullUpload = true;
        } else if (!_dirty.empty()) {
            std::sort(_dirty.begin(), _dirty.end());
            std::size_t first = _dirty.front();
            std::size_t last = first + 1;
            for (std::size_t k = 1; k < _dirty.size(); ++k) {
                if (_dirty[k] > last + kMergeGap) {
                    write(first, last);
                    first = _dirty[k];
                }
                last = _dirty[k] + 1;
            }
            write(first, last);
        }
        for (const std::uint32_t i : _dirty) {
            _dirtyFlags[i] = 0;
        }
        _dirty.clear();
        _allDirty = false;
    }

    const renderer::VertexArray* vertexArray() const noexcept { return _vertexArray ? &*_vertexArray : nullptr; }

private:
    void attach(const renderer::ShaderProgram& program)
    {
        auto set = [&](const char* name, renderer::ComponentType type, int components, bool normalized, bool integer,
                       std::size_t offset) {
            const renderer::ShaderVertexAttribute* attribute = program.findVertexAttribute(name);
            if (attribute && attribute->location >= 0) {
                _vertexArray->setAttribute(attribute->location, _buffer,
                                           renderer::VertexAttributeFormat{type, components, normalized, integer, sizeof(Vertex),
                                                                 offset});
            }
        };
        set("positionHigh", renderer::ComponentType::Float, 3, false, false, offsetof(Vertex, positionHigh));
        set("positionLow", renderer::ComponentType::Float, 3, false, false, offsetof(Vertex, positionLow));
        set("pixelOffset", renderer::ComponentType::Short, 2, false, false, offsetof(Vertex, pixelOffset));
        set("textureRectangle", renderer::ComponentType::UnsignedShort, 4, false, false, offsetof(Vertex, textureRectangle));
        set("color", renderer::ComponentType::UnsignedByte, 4, true, false, offsetof(Vertex, color));
        set("scaleOriginVisibility", renderer::ComponentType::UnsignedInt, 1, false, true, offsetof(Vertex, scaleOriginVisibility));
        if constexpr (Vertex::kHalo) {
            set("haloColor", renderer::ComponentType::UnsignedByte, 4, true, false, offsetof(Vertex, haloColor));
        }
    }

    std::vector<Vertex> _vertices;
    std::vector<std::uint32_t> _dirty;
    std::vector<std::uint8_t> _dirtyFlags;
    bool _allDirty = true;
    renderer::VertexBuffer _buffer;
    std::optional<renderer::VertexArray> _vertexArray;
};

} // namespace orbis::scene::detail
