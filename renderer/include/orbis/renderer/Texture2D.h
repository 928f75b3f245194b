#pragma once

#include "orbis/core/Image.h"
#include "orbis/renderer/RenderState.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace orbis::renderer {

class Device;

/// How a texture stores a texel, and the layout copyFromSystemMemory and copyToSystemMemory use:
/// RGBA8 4 bytes, RGB8 3, R32F one float, RG32F two, RGBA32F four; Depth24 and Depth32F one float
/// (0..1); Depth24Stencil8 one 32-bit word, depth in the high 24 bits, stencil in the low 8;
/// Depth32FStencil8 a float depth, then a 32-bit word with the stencil in its low 8 bits;
/// SRGB8Alpha8 4 bytes as RGBA8, the colour sRGB-encoded: sampling decodes it to linear values
/// (before filtering, as it should be), alpha is linear.
enum class TextureFormat : std::uint8_t {
    RGBA8,
    RGB8,
    R32F,
    RG32F,
    RGBA32F,
    Depth24,
    Depth32F,
    Depth24Stencil8,
    SRGB8Alpha8,
    Depth32FStencil8,
    R8 ///< one unsigned normalised byte (masks)

};

/// Bytes per texel in the system-memory layout above.
std::size_t bytesPerTexel(TextureFormat format) noexcept;
/// True for Depth24, Depth32F, Depth24Stencil8 and Depth32FStencil8.
bool isDepthFormat(TextureFormat format) noexcept;
/// True for Depth24Stencil8 and Depth32FStencil8.
bool hasStencil(TextureFormat format) noexcept;
/// "RGBA8", ... for messages.
const char* textureFormatName(TextureFormat format) noexcept;

struct TextureDescription {
    int width = 0;
    int height = 0;
    TextureFormat format = TextureFormat::RGBA8;
    bool mipmaps = false; ///< allocate the full mipmap chain
    /// Samples per texel: 1 for an ordinary texture; more for a multisampled one, which can only
    /// be drawn into (a Framebuffer attachment) and resolved by Context::blit or copyDepth: it has
    /// no mipmaps, is not sampled by commands and cannot be copied to or from memory (orbis::Error).
    int samples = 1;
    /// Partially resident (ARB_sparse_texture; DeviceInfo::sparseTexture): the texture's size is
    /// reserved but no memory is, until Texture2D::commit gives it page by page. Reading texels
    /// that are not committed gives undefined values: the reader must keep off them.
    bool sparse = false;
};

/// The texels a page of a sparse texture spans (Device::sparsePageSize).
struct SparsePageSize {
    int width = 0;
    int height = 0;
    friend bool operator==(const SparsePageSize&, const SparsePageSize&) = default;
};

/// A 2D texture: one GL texture object, move-only, shared between the device's contexts. Rows in
/// system memory go bottom to top (GL's order, t = 0 first), tightly packed; Images (top to bottom)
/// are flipped on the way in and out so that an image looks upright when drawn with t up.
///
/// ```
/// Texture2D texture = device.createTexture2D(world::readImage("earth.png"), true); // mipmapped; world/ImageFile.h
/// command.textures.push_back({0, &texture, &sampler}); // read by og_texture0
/// ```
class Texture2D final {
public:
    Texture2D() noexcept = default;
    ~Texture2D();
    Texture2D(Texture2D&& other) noexcept;
    Texture2D& operator=(Texture2D&& other) noexcept;
    Texture2D(const Texture2D&) = delete;
    Texture2D& operator=(const Texture2D&) = delete;

    int width() const noexcept { return _description.width; }
    int height() const noexcept { return _description.height; }
    TextureFormat format() const noexcept { return _description.format; }
    const TextureDescription& description() const noexcept { return _description; }
    /// Mipmap levels allocated: 1 without mipmaps.
    int levelCount() const noexcept { return _levels; }
    /// Samples per texel: above 1 for a multisampled texture (TextureDescription::samples).
    int samples() const noexcept { return _description.samples; }
    bool valid() const noexcept { return _name != 0; }

    /// Replaces a whole level. Throws orbis::Error unless texels holds exactly
    /// width x height x bytesPerTexel of that level.
    void copyFromSystemMemory(std::span<const std::byte> texels, int level = 0);
    /// Replaces a rectangle of a level (origin and rows bottom to top). Throws when it leaves the level.
    void copyFromSystemMemory(std::span<const std::byte> texels, const PixelRectangle& region, int level = 0);
    /// Replaces a level with an image of that level's size (flipped to bottom-up). RGBA8 takes 4
    /// channels, RGB8 3; throws for other formats, sizes or levels.
    void copyFromImage(const Image& image, int level = 0);
    /// Recomputes levels 1.. from level 0. Throws when the texture has no mipmaps.
    void generateMipmaps();

    /// Of a sparse texture: the levels committed page by page; the levels from this one on (those
    /// smaller than a page: the "mip tail") are committed and released as one. 0 otherwise.
    int sparseLevelCount() const noexcept { return _sparseLevels; }
    /// Of a sparse texture: gives memory to (commit) or takes it from a rectangle of a level. The
    /// rectangle must be whole pages (Device::sparsePageSize), or reach the level's edge; in the
    /// mip tail (level >= sparseLevelCount()) any rectangle commits or releases the whole tail.
    /// New memory holds undefined texels until copied to. Throws for a texture that is not sparse
    /// or a rectangle out of the level or off the page grid.
    void commit(const PixelRectangle& region, int level, bool committed);

    /// A whole level in the system-memory layout of the format.
    std::vector<std::byte> copyToSystemMemory(int level = 0) const;
    /// Level 0 as an image, top to bottom (RGBA8: 4 channels, RGB8: 3); throws for other formats.
    Image copyToImage() const;

private:
    friend class Device;
    friend class Context;
    friend class Framebuffer;
    Texture2D(Device& device, unsigned name, const TextureDescription& description, int levels) noexcept;
    void checkLevel(int level, const char* what) const;

    Device* _device = nullptr;
    unsigned _name = 0;
    std::uint64_t _serial = 0;
    TextureDescription _description;
    int _levels = 1;
    int _sparseLevels = 0;
    SparsePageSize _sparsePage;
};

} // namespace orbis::renderer
