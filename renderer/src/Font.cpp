#include "orbis/renderer/Font.h"

#include "orbis/core/Error.h"

// The implementation is compiled into libstb (Debian's libstb-dev); only the declarations here.
#include <stb/stb_truetype.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <vector>

namespace orbis::renderer {

struct Font::Impl {
    std::filesystem::path path;
    std::vector<unsigned char> data;
    stbtt_fontinfo info{};

    float scale(float sizePixels) const { return stbtt_ScaleForMappingEmToPixels(&info, sizePixels); }
};

Font::Font(const std::filesystem::path& path) : _impl(std::make_unique<Impl>())
{
    _impl->path = path;
    // Only a regular file: opening a named pipe would wait for a writer.
    std::error_code ignored;
    if (std::filesystem::exists(path, ignored) && !std::filesystem::is_regular_file(path, ignored)) {
        throw Error(path.string() + ": cannot open font file: not a regular file");
    }
    std::ifstream file(path, std::ios::binary | std::ios::ate);
    if (!file) {
        throw Error(path.string() + ": cannot open font file: " + std::strerror(errno));
    }
    const std::streamoff size = file.tellg();
    if (size < 0) {
        throw Error(path.string() + ": cannot read font file");
    }
    _impl->data.resize(static_cast<std::size_t>(size));
    file.seekg(0);
    if (!file.read(reinterpret_cast<char*>(_impl->data.data()), size)) {
        throw Error(path.string() + ": cannot read font file");
    }
    // stb_truetype reads the 12-byte header and the table directory without bounds checks.
    const unsigned char* bytes = _impl->data.data();
    const bool knownTag = _impl->data.size() >= 12 &&
                          (std::memcmp(bytes, "\0\1\0\0", 4) == 0 || std::memcmp(bytes, "true", 4) == 0 ||
                           std::memcmp(bytes, "OTTO", 4) == 0 || std::memcmp(bytes, "ttcf", 4) == 0);
    const int offset = knownTag ? stbtt_GetFontOffsetForIndex(bytes, 0) : -1;
    if (offset < 0 || !stbtt_InitFont(&_impl->info, bytes, offset)) {
        throw Error(path.string() + ": not a TrueType or OpenType font");
    }
}

Font::~Font() = default;
Font::Font(Font&&) noexcept = default;
Font& Font::operator=(Font&&) noexcept = default;

const std::filesystem::path& Font::path() const noexcept
{
    return _impl->path;
}

int Font::glyphIndex(char32_t codepoint) const noexcept
{
    return stbtt_FindGlyphIndex(&_impl->info, static_cast<int>(codepoint));
}

FontVerticalMetrics Font::verticalMetrics(float sizePixels) const noexcept
{
    int ascent = 0;
    int descent = 0;
    int lineGap = 0;
    stbtt_GetFontVMetrics(&_impl->info, &ascent, &descent, &lineGap);
    const float scale = _impl->scale(sizePixels);
    return {static_cast<float>(ascent) * scale, static_cast<float>(descent) * scale,
            static_cast<float>(lineGap) * scale};
}

GlyphMetrics Font::glyphMetrics(int glyph, float sizePixels) const noexcept
{
    int advance = 0;
    int bearing = 0;
    stbtt_GetGlyphHMetrics(&_impl->info, glyph, &advance, &bearing);
    const float scale = _impl->scale(sizePixels);
    return {static_cast<float>(advance) * scale, static_cast<float>(bearing) * scale};
}

float Font::kerning(int leftGlyph, int rightGlyph, float sizePixels) const noexcept
{
    return static_cast<float>(stbtt_GetGlyphKernAdvance(&_impl->info, leftGlyph, rightGlyph)) *
           _impl->scale(sizePixels);
}

GlyphBitmap Font::rasterize(int glyph, float sizePixels) const
{
    GlyphBitmap bitmap;
    if (stbtt_IsGlyphEmpty(&_impl->info, glyph)) {
        return bitmap;
    }
    const float scale = _impl->scale(sizePixels);
    int x0 = 0;
    int y0 = 0;
    int x1 = 0;
    int y1 = 0;
    stbtt_GetGlyphBitmapBox(&_impl->info, glyph, scale, scale, &x0, &y0, &x1, &y1);
    if (x1 <= x0 || y1 <= y0) {
        return bitmap;
    }
    bitmap.coverage = Image(x1 - x0, y1 - y0, 1);
    bitmap.left = x0;
    bitmap.top = y0;
    stbtt_MakeGlyphBitmap(&_impl->info, bitmap.coverage.pixels.data(), bitmap.coverage.width,
                          bitmap.coverage.height, bitmap.coverage.width, scale, scale, glyph);
    return bitmap;
}

} // namespace orbis::renderer
