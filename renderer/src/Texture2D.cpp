#include "orbis/renderer/Texture2D.h"

#include "ContextState.h"
#include "GlEnums.h"

#include "orbis/core/Error.h"
#include "orbis/renderer/Device.h"

#include <algorithm>
#include <cstring>
#include <utility>

namespace orbis::renderer {
namespace {

struct GlFormat {
    GLint internalFormat;
    GLenum format;
    GLenum type;
};

GlFormat glFormat(TextureFormat format) noexcept
{
    switch (format) {
    case TextureFormat::RGBA8: return {GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE};
    case TextureFormat::RGB8: return {GL_RGB8, GL_RGB, GL_UNSIGNED_BYTE};
    case TextureFormat::R32F: return {GL_R32F, GL_RED, GL_FLOAT};
    case TextureFormat::RG32F: return {GL_RG32F, GL_RG, GL_FLOAT};
    case TextureFormat::RGBA32F: return {GL_RGBA32F, GL_RGBA, GL_FLOAT};
    case TextureFormat::Depth24: return {GL_DEPTH_COMPONENT24, GL_DEPTH_COMPONENT, GL_FLOAT};
    case TextureFormat::Depth32F: return {GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, GL_FLOAT};
    case TextureFormat::Depth24Stencil8: return {GL_DEPTH24_STENCIL8, GL_DEPTH_STENCIL, GL_UNSIGNED_INT_24_8};
    case TextureFormat::SRGB8Alpha8: return {GL_SRGB8_ALPHA8, GL_RGBA, GL_UNSIGNED_BYTE};
    case TextureFormat::Depth32FStencil8:
        return {GL_DEPTH32F_STENCIL8, GL_DEPTH_STENCIL, GL_FLOAT_32_UNSIGNED_INT_24_8_REV};
    case TextureFormat::R8: return {GL_R8, GL_RED, GL_UNSIGNED_BYTE};
    }
    return {GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE};
}

int levelSize(int size, int level) noexcept
{
    return std::max(1, size >> level);
}

void flipRows(std::uint8_t* data, int rowBytes, int rows)
{
    std::vector<std::uint8_t> row(static_cast<std::size_t>(rowBytes));
    for (int y = 0; y < rows / 2; ++y) {
        std::uint8_t* a = data + static_cast<std::size_t>(y) * rowBytes;
        std::uint8_t* b = data + static_cast<std::size_t>(rows - 1 - y) * rowBytes;
        std::memcpy(row.data(), a, rowBytes);
        std::memcpy(a, b, rowBytes);
        std::memcpy(b, row.data(), rowBytes);
    }
}

} // namespace

std::size_t bytesPerTexel(TextureFormat format) noexcept
{
    switch (format) {
    case TextureFormat::RGBA8: return 4;
    case TextureFormat::RGB8: return 3;
    case TextureFormat::R32F: return 4;
    case TextureFormat::RG32F: return 8;
    case TextureFormat::RGBA32F: return 16;
    case TextureFormat::Depth24: return 4;
    case TextureFormat::Depth32F: return 4;
    case TextureFormat::Depth24Stencil8: return 4;
    case TextureFormat::SRGB8Alpha8: return 4;
    case TextureFormat::Depth32FStencil8: return 8;
    case TextureFormat::R8: return 1;
    }
    return 4;
}

bool isDepthFormat(TextureFormat format) noexcept
{
    return format == TextureFormat::Depth24 || format == TextureFormat::Depth32F || hasStencil(format);
}

bool hasStencil(TextureFormat format) noexcept
{
    return format == TextureFormat::Depth24Stencil8 || format == TextureFormat::Depth32FStencil8;
}

const char* textureFormatName(TextureFormat format) noexcept
{
    switch (format) {
    case TextureFormat::RGBA8: return "RGBA8";
    case TextureFormat::RGB8: return "RGB8";
    case TextureFormat::R32F: return "R32F";
    case TextureFormat::RG32F: return "RG32F";
    case TextureFormat::RGBA32F: return "RGBA32F";
    case TextureFormat::Depth24: return "Depth24";
    case TextureFormat::Depth32F: return "Depth32F";
    case TextureFormat::Depth24Stencil8: return "Depth24Stencil8";
    case TextureFormat::SRGB8Alpha8: return "SRGB8Alpha8";
    case TextureFormat::Depth32FStencil8: return "Depth32FStencil8";
    case TextureFormat::R8: return "R8";
    }
    return "?";
}

Texture2D::Texture2D(Device& device, unsigned name, const TextureDescription& description, int levels) noexcept
    : _device(&device), _name(name), _serial(detail::nextObjectSerial()), _description(description), _levels(levels)
{
}

Texture2D::~Texture2D()
{
    if (_name) {
        if (detail::ContextState* state = detail::currentStateOf(_device)) {
            state->gl.glDeleteTextures.unchecked(1, &_name);
        }
    }
}

Texture2D::Texture2D(Texture2D&& other) noexcept
    : _device(other._device)
    , _name(std::exchange(other._name, 0u))
    , _serial(std::exchange(other._serial, 0u))
    , _description(other._description)
    , _levels(other._levels)
    , _sparseLevels(other._sparseLevels)
    , _sparsePage(other._sparsePage)
{
}

Texture2D& Texture2D::operator=(Texture2D&& other) noexcept
{
    if (this != &other) {
        Texture2D moved(std::move(other));
        std::swap(_device, moved._device);
        std::swap(_name, moved._name);
        std::swap(_serial, moved._serial);
        std::swap(_description, moved._description);
        std::swap(_levels, moved._levels);
        std::swap(_sparseLevels, moved._sparseLevels);
        std::swap(_sparsePage, moved._sparsePage);
    }
    return *this;
}

Texture2D Device::createTexture2D(const TextureDescription& description)
{
    detail::ContextState& state = detail::requireCurrent(this, "Device::createTexture2D");
    if (description.sparse && (!info().sparseTexture || description.samples > 1 ||
                               std::max(description.width, description.height) > info().maxSparseTextureSize)) {
        throw Error("Device::createTexture2D: a sparse " + std::to_string(description.width) + " x " +
                    std::to_string(description.height) + " texture" +
                    (info().sparseTexture ? " is beyond this device's " + std::to_string(info().maxSparseTextureSize) +
                                                " texels for one (or multisampled)"
                                          : " needs GL_ARB_sparse_texture, which this device lacks"));
    }
    const int maximum = info().maxTextureSize;
    if (description.width < 1 || description.height < 1 || description.width > maximum ||
        description.height > maximum) {
        throw Error("Device::createTexture2D: size " + std::to_string(description.width) + " x " +
                    std::to_string(description.height) + " is invalid (width and height must be 1.." +
                    std::to_string(maximum) + ")");
    }
    if (description.samples < 1 || description.samples > info().maxSamples ||
        (description.samples > 1 && description.mipmaps)) {
        throw Error("Device::createTexture2D: " + std::to_string(description.samples) + " samples" +
                    (description.mipmaps ? " with mipmaps" : "") + " (1.." + std::to_string(info().maxSamples) +
                    " on this device, and a multisampled texture has no mipmaps)");
    }
    if (description.samples > 1) {
        // Bound on the upload unit's multisample target: the plain 2D binding the context tracks
        // there is left as it was.
        const detail::GlApi& gl = state.gl;
        GLuint name = 0;
        gl.glGenTextures(1, &name);
        Texture2D texture(*this, name, description, 1);
        state.bindTextureForUpload(0, 0); // the upload unit active
        gl.glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, name);
        gl.glTexImage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, description.samples, glFormat(description.format).internalFormat,
                                   description.width, description.height, GL_TRUE);
        gl.glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, 0);
        return texture;
    }
    int levels = 1;
    if (description.mipmaps) {
        for (int size = std::max(description.width, description.height); size > 1; size /= 2) {
            ++levels;
        }
    }
    const detail::GlApi& gl = state.gl;
    GLuint name = 0;
    gl.glGenTextures(1, &name);
    Texture2D texture(*this, name, description, levels);
    state.bindTextureForUpload(texture._serial, name);
    const GlFormat f = glFormat(description.format);
    if (description.sparse) {
        // Immutable storage, reserved and not backed; the first virtual page size (sparsePageSize).
        texture._sparsePage = sparsePageSize(description.format);
        gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_SPARSE_ARB, GL_TRUE);
        gl.glTexParameteri(GL_TEXTURE_2D, GL_VIRTUAL_PAGE_SIZE_INDEX_ARB, 0);
        gl.glTexStorage2D(GL_TEXTURE_2D, levels, f.internalFormat, description.width, description.height);
        GLint sparseLevels = 0;
        gl.glGetTexParameteriv(GL_TEXTURE_2D, GL_NUM_SPARSE_LEVELS_ARB, &sparseLevels);
        texture._sparseLevels = sparseLevels;
    } else {
        for (int level = 0; level < levels; ++level) {
            gl.glTexImage2D(GL_TEXTURE_2D, level, f.internalFormat, levelSize(description.width, level),
                            levelSize(description.height, level), 0, f.format, f.type, nullptr);
        }
    }
    const bool depth = isDepthFormat(description.format);
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, levels - 1);
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER,
                       depth ? GL_NEAREST : (levels > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR));
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, depth ? GL_NEAREST : GL_LINEAR);
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return texture;
}

SparsePageSize Device::sparsePageSize(TextureFormat format)
{
    detail::ContextState& state = detail::requireCurrent(this, "Device::sparsePageSize");
    if (!info().sparseTexture) {
        return {};
    }
    const GLenum internalFormat = glFormat(format).internalFormat;
    GLint count = 0;
    state.gl.glGetInternalformativ(GL_TEXTURE_2D, internalFormat, GL_NUM_VIRTUAL_PAGE_SIZES_ARB, 1, &count);
    if (count < 1) {
        return {};
    }
    GLint width = 0, height = 0;
    state.gl.glGetInternalformativ(GL_TEXTURE_2D, internalFormat, GL_VIRTUAL_PAGE_SIZE_X_ARB, 1, &width);
    state.gl.glGetInternalformativ(GL_TEXTURE_2D, internalFormat, GL_VIRTUAL_PAGE_SIZE_Y_ARB, 1, &height);
    return {width, height};
}

Texture2D Device::createTexture2D(const Image& image, bool mipmaps)
{
    if (image.channels != 4 && image.channels != 3) {
        throw Error("Device::createTexture2D: an image of " + std::to_string(image.channels) +
                    " channels; 3 (RGB8) or 4 (RGBA8) are supported");
    }
    Texture2D texture = createTexture2D(
        {image.width, image.height, image.channels == 4 ? TextureFormat::RGBA8 : TextureFormat::RGB8, mipmaps});
    texture.copyFromImage(image);
    if (mipmaps) {
        texture.generateMipmaps();
    }
    return texture;
}

Texture2D Device::createTexture2D(const Image& image, std::span<const Image> mipmapLevels)
{
    if (mipmapLevels.empty()) {
        return createTexture2D(image, false);
    }
    if (image.channels != 4 && image.channels != 3) {
        throw Error("Device::createTexture2D: an image of " + std::to_string(image.channels) +
                    " channels; 3 (RGB8) or 4 (RGBA8) are supported");
    }
    Texture2D mipmapped = createTexture2D(
        {image.width, image.height, image.channels == 4 ? TextureFormat::RGBA8 : TextureFormat::RGB8, true});
    if (static_cast<int>(mipmapLevels.size()) + 1 != mipmapped.levelCount()) {
        throw Error("Device::createTexture2D: " + std::to_string(mipmapLevels.size()) + " mipmap levels given for a " +
                    std::to_string(image.width) + " x " + std::to_string(image.height) + " image, which has " +
                    std::to_string(mipmapped.levelCount() - 1));
    }
    mipmapped.copyFromImage(image, 0);
    for (std::size_t level = 0; level < mipmapLevels.size(); ++level) {
        mipmapped.copyFromImage(mipmapLevels[level], static_cast<int>(level) + 1);
    }
    return mipmapped;
}

void Texture2D::checkLevel(int level, const char* what) const
{
    if (!_name) {
        throw Error(std::string(what) + ": empty texture");
    }
    if (samples() > 1) {
        throw Error(std::string(what) + ": a multisampled texture (" + std::to_string(samples()) +
                    " samples) has no texels to copy; resolve it with Context::blit");
    }
    if (level < 0 || level >= _levels) {
        throw Error(std::string(what) + ": level " + std::to_string(level) + " does not exist (the texture has " +
                    std::to_string(_levels) + ")");
    }
}

void Texture2D::copyFromSystemMemory(std::span<const std::byte> texels, int level)
{
    checkLevel(level, "Texture2D::copyFromSystemMemory");
    copyFromSystemMemory(texels, {0, 0, levelSize(width(), level), levelSize(height(), level)}, level);
}

void Texture2D::copyFromSystemMemory(std::span<const std::byte> texels, const PixelRectangle& region, int level)
{
    constexpr const char* what = "Texture2D::copyFromSystemMemory";
    detail::ContextState& state = detail::requireCurrent(_device, what);
    checkLevel(level, what);
    const int w = levelSize(width(), level);
    const int h = levelSize(height(), level);
    if (region.x < 0 || region.y < 0 || region.width < 0 || region.height < 0 || region.x + region.width > w ||
        region.y + region.height > h) {
        throw Error(std::string(what) + ": region (" + std::to_string(region.x) + ", " + std::to_string(region.y) +
                    ", " + std::to_string(region.width) + " x " + std::to_string(region.height) +
                    ") leaves level " + std::to_string(level) + " of " + std::to_string(w) + " x " +
                    std::to_string(h));
    }
    const std::size_t expected =
        static_cast<std::size_t>(region.width) * static_cast<std::size_t>(region.height) * bytesPerTexel(format());
    if (texels.size() != expected) {
        throw Error(std::string(what) + ": " + std::to_string(texels.size()) + " bytes given, " +
                    std::to_string(expected) + " expected for " + std::to_string(region.width) + " x " +
                    std::to_string(region.height) + " " + textureFormatName(format()) + " texels");
    }
    if (expected == 0) {
        return;
    }
    state.bindTextureForUpload(_serial, _name);
    const GlFormat f = glFormat(format());
    state.gl.glTexSubImage2D(GL_TEXTURE_2D, level, region.x, region.y, region.width, region.height, f.format, f.type,
                             texels.data());
}

void Texture2D::commit(const PixelRectangle& region, int level, bool committed)
{
    checkLevel(level, "Texture2D::commit");
    if (!_description.sparse) {
        throw Error("Texture2D::commit: the texture is not sparse (TextureDescription::sparse)");
    }
    const int w = levelSize(width(), level), h = levelSize(height(), level);
    auto onGrid = [](int start, int size, int page, int extent) {
        return start % page == 0 && (size % page == 0 || start + size == extent);
    };
    if (region.x < 0 || region.y < 0 || region.width < 1 || region.height < 1 || region.x + region.width > w ||
        region.y + region.height > h ||
        (level < _sparseLevels && !(onGrid(region.x, region.width, _sparsePage.width, w) &&
                                    onGrid(region.y, region.height, _sparsePage.height, h)))) {
        throw Error("Texture2D::commit: " + std::to_string(region.width) + " x " + std::to_string(region.height) +
                    " at (" + std::to_string(region.x) + ", " + std::to_string(region.y) + ") is not whole pages of " +
                    std::to_string(_sparsePage.width) + " x " + std::to_string(_sparsePage.height) + " inside level " +
                    std::to_string(level) + " (" + std::to_string(w) + " x " + std::to_string(h) + ")");
    }
    detail::ContextState& state = detail::requireCurrent(_device, "Texture2D::commit");
    state.bindTextureForUpload(_serial, _name);
    state.gl.glTexPageCommitmentARB(GL_TEXTURE_2D, level, region.x, region.y, 0, region.width, region.height, 1,
                                    committed ? GL_TRUE : GL_FALSE);
}

void Texture2D::copyFromImage(const Image& image, int level)
{
    checkLevel(level, "Texture2D::copyFromImage");
    const int channels = format() == TextureFormat::RGBA8 || format() == TextureFormat::SRGB8Alpha8 ? 4
                         : format() == TextureFormat::RGB8                                      ? 3
                                                                                                : 0;
    const int levelWidth = std::max(1, width() >> level);
    const int levelHeight = std::max(1, height() >> level);
    if (channels == 0 || image.channels != channels || image.width != levelWidth || image.height != levelHeight) {
        throw Error(std::string("Texture2D::copyFromImage: a ") + std::to_string(image.width) + " x " +
                    std::to_string(image.height) + " image of " + std::to_string(image.channels) +
                    " channels does not fit level " + std::to_string(level) + " (" + std::to_string(levelWidth) +
                    " x " + std::to_string(levelHeight) + ") of a " + textureFormatName(format()) + " texture");
    }
    std::vector<std::uint8_t> flipped = image.pixels;
    flipRows(flipped.data(), image.width * image.channels, image.height);
    copyFromSystemMemory(std::as_bytes(std::span(flipped)), level);
}

void Texture2D::generateMipmaps()
{
    detail::ContextState& state = detail::requireCurrent(_device, "Texture2D::generateMipmaps");
    if (_levels < 2) {
        throw Error("Texture2D::generateMipmaps: the texture was created without mipmaps");
    }
    state.bindTextureForUpload(_serial, _name);
    state.gl.glGenerateMipmap(GL_TEXTURE_2D);
}

std::vector<std::byte> Texture2D::copyToSystemMemory(int level) const
{
    constexpr const char* what = "Texture2D::copyToSystemMemory";
    detail::ContextState& state = detail::requireCurrent(_device, what);
    checkLevel(level, what);
    std::vector<std::byte> texels(static_cast<std::size_t>(levelSize(width(), level)) *
                                  static_cast<std::size_t>(levelSize(height(), level)) * bytesPerTexel(format()));
    state.bindTextureForUpload(_serial, _name);
    const GlFormat f = glFormat(format());
    state.gl.glGetTexImage(GL_TEXTURE_2D, level, f.format, f.type, texels.data());
    return texels;
}

Image Texture2D::copyToImage() const
{
    const int channels = format() == TextureFormat::RGBA8 || format() == TextureFormat::SRGB8Alpha8 ? 4
                         : format() == TextureFormat::RGB8                                      ? 3
                                                                                                : 0;
    if (channels == 0) {
        throw Error(std::string("Texture2D::copyToImage: a ") + textureFormatName(format()) +
                    " texture is not an 8-bit image (use copyToSystemMemory)");
    }
    const std::vector<std::byte> texels = copyToSystemMemory(0);
    Image image(width(), height(), channels);
    std::memcpy(image.pixels.data(), texels.data(), texels.size());
    flipRows(image.pixels.data(), width() * channels, height());
    return image;
}

} // namespace orbis::renderer
