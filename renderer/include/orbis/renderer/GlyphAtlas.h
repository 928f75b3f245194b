#pragma once

#include <orbis/renderer/Font.h>
#include <orbis/renderer/TextureAtlas.h>

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace orbis::renderer {

/// How a GlyphAtlas rasterizes.
struct GlyphAtlasOptions {
    float sizePixels = 16.0f; ///< em size in pixels; labels are drawn at 1:1
    int outlinePixels = 2;    ///< width of the halo around each glyph; 0 for none
    int padding = 1;          ///< empty pixels between glyph bitmaps in the atlas
    int initialSize = 256;    ///< atlas width and height to start with; a power of two
    int maxSize = 4096;       ///< the atlas never grows beyond this; a power of two
};

/// A character rasterized into the atlas. Bitmaps include the outline margin on every side.
struct Glyph {
    char32_t codepoint = 0;
    int glyphIndex = 0;  ///< in the font; 0 when the font lacks the character (its missing-glyph box)
    float advance = 0.0f; ///< pixels the pen moves after it
    int left = 0;        ///< from the pen to the bitmap's left column, pixels
    int top = 0;         ///< from the baseline to the bitmap's top row, pixels, y down (negative above)
    int width = 0;       ///< bitmap size; 0 x 0 for a character with nothing to draw (space)
    int height = 0;
    std::size_t atlasIndex = 0; ///< its rectangle in GlyphAtlas::atlas(), shared by characters with the same
                                ///< glyph; unused when the bitmap is empty
};

/// One glyph of a laid-out text: a width x height quad at integer pixel (x, y) relative to the
/// text's origin (the pen's start on the first baseline, y down), textured by atlas rectangle
/// atlasIndex. At 1:1 with the origin on a pixel corner, texels map to pixels exactly.
struct GlyphQuad {
    int x = 0;
    int y = 0;
    int width = 0;
    int height = 0;
    std::size_t atlasIndex = 0;
    char32_t codepoint = 0;
};

/// A text laid out on baselines, ready to be drawn as quads.
struct TextLayout {
    std::vector<GlyphQuad> quads; ///< glyphs with pixels, in text order (spaces have none)
    float width = 0.0f;           ///< the longest line's advance: its glyph advances plus kerning
    int lineCount = 0;
    int lineHeight = 0; ///< baseline-to-baseline distance, whole pixels
    PixelRectangle bounds; ///< the smallest rectangle holding every quad (halo included), relative to the origin
};

/// Glyphs of one font at one size, rasterized on first use into a 2-channel TextureAtlas: channel
/// 0 is the glyph's coverage, channel 1 its halo, the coverage dilated by outlinePixels (a disc,
/// anti-aliased over its last pixel), so channel 1 >= channel 0 everywhere. A shader draws
/// mix(haloColour, textColour, c0) with alpha c1. The halo is a dilated mask rather than a signed
/// distance field because labels are drawn at 1:1: the mask keeps the rasterizer's exact coverage
/// (crisp, no threshold rounding of corners at 12-16 px) and needs no smoothing in the shader.
///
///     GlyphAtlas glyphs(std::make_shared<Font>("DejaVuSans.ttf")); // scene::findFont finds one
///     const TextLayout label = glyphs.layout("Zürich");
///     // upload glyphs.atlas().image() when its version() changed, then draw label.quads
class GlyphAtlas {
public:
    explicit GlyphAtlas(std::shared_ptr<const Font> font, const GlyphAtlasOptions& options = {});

    /// The glyph of a character, rasterized into the atlas on first use. The reference stays valid
    /// as long as the GlyphAtlas. Throws orbis::Error when the atlas is full (maxSize).
    const Glyph& glyph(char32_t codepoint);
    /// Rasterizes the characters of the UTF-8 text that are not in the atlas yet, in one batch
    /// (packed tighter than one by one). Throws orbis::Error when the atlas is full.
    TextureAtlas::AddResult addCharacters(std::string_view utf8);
    /// Lays out UTF-8 text (malformed bytes become U+FFFD; '\n' starts a new line) with kerning,
    /// each glyph at the pen position rounded to a whole pixel. Adds missing glyphs to the atlas.
    TextLayout layout(std::string_view utf8);

    const TextureAtlas& atlas() const noexcept { return _atlas; }
    const Font& font() const noexcept { return *_font; }
    const GlyphAtlasOptions& options() const noexcept { return _options; }
    /// Number of distinct characters met so far (characters sharing a font glyph share its bitmap).
    std::size_t glyphCount() const noexcept { return _glyphs.size(); }

private:
    /// Rasterizes a font glyph into a 2-channel bitmap with its halo, without touching the atlas.
    Glyph prepare(int glyphIndex, Image& bitmap) const;
    /// The font's kerning of two glyphs at the atlas's size, remembered.
    float kerning(int left, int right);
    /// Adds the glyphs of these characters that are missing, in one batch.
    TextureAtlas::AddResult addCodepoints(const std::u32string& codepoints);

    std::shared_ptr<const Font> _font;
    GlyphAtlasOptions _options;
    TextureAtlas _atlas;
    std::unordered_map<char32_t, Glyph> _glyphs;  ///< by character
    std::unordered_map<int, Glyph> _byGlyphIndex; ///< by font glyph; codepoint unset
    std::unordered_map<std::uint64_t, float> _kerning; ///< by (left glyph << 32 | right glyph)
};

} // namespace orbis::renderer
