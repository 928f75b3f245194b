#pragma once

#include <orbis/core/Image.h>

#include <filesystem>
#include <memory>

namespace orbis::renderer {

/// A font's vertical metrics at a size, in pixels: ascent above the baseline (positive), descent
/// below it (negative), and the gap between one line's descent and the next line's ascent.
struct FontVerticalMetrics {
    float ascent = 0.0f;
    float descent = 0.0f;
    float lineGap = 0.0f;

    /// Baseline-to-baseline distance.
    float lineHeight() const noexcept { return ascent - descent + lineGap; }
};

/// One glyph's horizontal metrics at a size, in pixels.
struct GlyphMetrics {
    float advance = 0.0f;         ///< how far the pen moves after the glyph
    float leftSideBearing = 0.0f; ///< from the pen to the left edge of the outline
};

/// A glyph's coverage (1 channel, 0 to 255) and where its top-left pixel lies relative to the pen
/// on the baseline, y down. Empty (0x0) for a glyph without outline, such as a space.
struct GlyphBitmap {
    Image coverage{0, 0, 1};
    int left = 0;
    int top = 0;
};

/// A TrueType font file in memory, read with stb_truetype. Sizes are em sizes in pixels (as CSS
/// font-size). Fonts are trusted input: stb_truetype does not check every table of a font file.
///
///     const Font font("DejaVuSans.ttf"); // a path; scene::findFont (fontconfig) finds installed fonts
///     const GlyphBitmap a = font.rasterize(font.glyphIndex(U'a'), 16.0f);
class Font {
public:
    /// Reads the font. Throws orbis::Error naming the path when the file is missing, unreadable or
    /// not a TrueType font.
    explicit Font(const std::filesystem::path& path);
    ~Font();
    Font(Font&&) noexcept;
    Font& operator=(Font&&) noexcept;

    const std::filesystem::path& path() const noexcept;

    /// The font's glyph for a character; 0, the font's missing-character glyph, when it has none.
    int glyphIndex(char32_t codepoint) const noexcept;
    FontVerticalMetrics verticalMetrics(float sizePixels) const noexcept;
    GlyphMetrics glyphMetrics(int glyph, float sizePixels) const noexcept;
    /// Extra advance between two glyphs side by side (usually negative or 0), pixels; from the
    /// font's 'kern' table or its GPOS pair adjustments.
    float kerning(int leftGlyph, int rightGlyph, float sizePixels) const noexcept;
    /// The glyph's anti-aliased coverage at the size, unhinted, its origin on a pixel corner.
    GlyphBitmap rasterize(int glyph, float sizePixels) const;

private:
    struct Impl;
    std::unique_ptr<Impl> _impl;
};

} // namespace orbis::renderer
