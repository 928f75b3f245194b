// Font, GlyphAtlas and decodeUtf8 live in the renderer (image work, no GL); their tests sit in the
// scene suite, which links the renderer, until a renderer suite exists.

#include <orbis/renderer/GlyphAtlas.h>
#include <orbis/renderer/Utf8.h>
#include <orbis/scene/FontLookup.h>

#include <orbis/core/Error.h>

#include "TempFiles.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace orbis;
using namespace orbis::renderer;
using namespace orbis::scene;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using Catch::Matchers::WithinAbs;

namespace {

// Debian's fonts-dejavu-core (scripts/install-deps.sh), found through fontconfig.
const std::filesystem::path kDejaVuSans = findFont("DejaVu Sans").value_or("DejaVu Sans: no such font");

std::shared_ptr<const Font> dejaVuSans()
{
    static const auto font = std::make_shared<const Font>(kDejaVuSans);
    return font;
}

/// Channel `c` of a glyph's bitmap in the atlas at (x, y) of the bitmap; 0 outside it.
int texel(const GlyphAtlas& atlas, const Glyph& glyph, int x, int y, int c)
{
    if (x < 0 || y < 0 || x >= glyph.width || y >= glyph.height) {
        return 0;
    }
    const PixelRectangle& r = atlas.atlas().rectangle(glyph.atlasIndex);
    return atlas.atlas().image().pixel(r.x + x, r.y + y)[c];
}

} // namespace

TEST_CASE("Font names the path of a missing or invalid font file", "[scene][font]")
{
    CHECK_THAT(test::errorMessage([] { Font("/nonexistent/fonts/Missing.ttf"); }),
               Equals("/nonexistent/fonts/Missing.ttf: cannot open font file: No such file or directory"));
    const test::TempDirectory directory;
    const auto text = directory.write("not-a-font.ttf", "This is a text file, not a font at all.\n");
    CHECK_THAT(test::errorMessage([&] { Font{text}; }), Equals(text.string() + ": not a TrueType or OpenType font"));
    const auto tiny = directory.write("tiny.ttf", std::string("\0\1\0", 3));
    CHECK_THAT(test::errorMessage([&] { Font{tiny}; }), Contains("not a TrueType or OpenType font"));
}

TEST_CASE("decodeUtf8 decodes the characters of place names and replaces malformed bytes", "[scene][font]")
{
    CHECK(decodeUtf8("Z\xC3\xBCrich") == U"Z\u00FCrich");
    CHECK(decodeUtf8("Espa\xC3\xB1" "a, S\xC3\xA3o Tom\xC3\xA9") == U"Espa\u00F1a, S\u00E3o Tom\u00E9");
    CHECK(decodeUtf8("\xE1\xBB\x87 \xF0\x9F\x8C\x8D") == U"\u1EC7 \U0001F30D");
    CHECK(decodeUtf8("a\x80" "b") == U"a\uFFFDb");         // stray continuation byte
    CHECK(decodeUtf8("a\xC3") == U"a\uFFFD");               // truncated at the end
    CHECK(decodeUtf8("\xC3(") == U"\uFFFD(");               // truncated before ASCII
    CHECK(decodeUtf8("\xC0\xAF") == U"\uFFFD");             // overlong '/'
    CHECK(decodeUtf8("\xED\xA0\x80") == U"\uFFFD");         // a surrogate
    CHECK(decodeUtf8("\xF4\x90\x80\x80") == U"\uFFFD");     // beyond U+10FFFF
    CHECK(decodeUtf8("") == U"");
}

TEST_CASE("Text layout width is the sum of the advances plus kerning", "[scene][font]")
{
    const auto font = dejaVuSans();
    GlyphAtlas glyphs(font);
    const float size = glyphs.options().sizePixels;

    // DejaVu Sans kerns "AV": the test would not notice kerning being ignored otherwise.
    CHECK(font->kerning(font->glyphIndex(U'A'), font->glyphIndex(U'V'), size) < -0.1f);

    for (const std::u32string text : {U"Hello", U"AVATAR", U"Wolfgang"}) {
        std::string utf8;
        for (char32_t c : text) {
            utf8 += static_cast<char>(c);
        }
        INFO(utf8);
        float expected = 0.0f;
        std::vector<float> pens;
        for (std::size_t i = 0; i < text.size(); ++i) {
            const int glyph = font->glyphIndex(text[i]);
            if (i > 0) {
                expected += font->kerning(font->glyphIndex(text[i - 1]), glyph, size);
            }
            pens.push_back(expected);
            expected += font->glyphMetrics(glyph, size).advance;
        }
        const TextLayout layout = glyphs.layout(utf8);
        // Float sums in the same order: equal up to rounding.
        CHECK_THAT(static_cast<double>(layout.width), WithinAbs(static_cast<double>(expected), 1e-4));
        CHECK(layout.lineCount == 1);
        REQUIRE(layout.quads.size() == text.size());
        // Each glyph at its pen position rounded to a whole pixel.
        for (std::size_t i = 0; i < text.size(); ++i) {
            const Glyph& glyph = glyphs.glyph(text[i]);
            CHECK(layout.quads[i].codepoint == text[i]);
            CHECK(layout.quads[i].x == std::lround(pens[i]) + glyph.left);
            CHECK(layout.quads[i].y == glyph.top);
            CHECK(layout.quads[i].width == glyph.width);
            CHECK(layout.quads[i].atlasIndex == glyph.atlasIndex);
        }
    }
}

TEST_CASE("Visible glyphs have bitmaps, a space has none but advances", "[scene][font]")
{
    GlyphAtlas glyphs(dejaVuSans());
    for (char32_t c : {U'H', U'e', U'l', U'o', U'.', U'\u00E9'}) {
        const Glyph& glyph = glyphs.glyph(c);
        CHECK(glyph.width > 2 * glyphs.options().outlinePixels);
        CHECK(glyph.height > 2 * glyphs.options().outlinePixels);
        CHECK(glyph.advance > 0.0f);
        int covered = 0;
        for (int y = 0; y < glyph.height; ++y) {
            for (int x = 0; x < glyph.width; ++x) {
                covered += texel(glyphs, glyph, x, y, 0) > 0;
            }
        }
        CHECK(covered > 0);
    }
    const Glyph& space = glyphs.glyph(U' ');
    CHECK(space.width == 0);
    CHECK(space.height == 0);
    CHECK(space.advance > 0.0f);

    const TextLayout layout = glyphs.layout("a b");
    REQUIRE(layout.quads.size() == 2);
    CHECK(layout.quads[1].codepoint == U'b');
}

TEST_CASE("The atlas holds each glyph's exact coverage in channel 0", "[scene][font]")
{
    const auto font = dejaVuSans();
    GlyphAtlas glyphs(font);
    const int margin = glyphs.options().outlinePixels;
    glyphs.addCharacters("Hello, w\xC3\xB6rld");
    CHECK(glyphs.atlas().image().channels == 2);
    for (char32_t c : {U'H', U'w', U'\u00F6'}) {
        const Glyph& glyph = glyphs.glyph(c);
        const GlyphBitmap raster = font->rasterize(font->glyphIndex(c), glyphs.options().sizePixels);
        REQUIRE(glyph.width == raster.coverage.width + 2 * margin);
        REQUIRE(glyph.height == raster.coverage.height + 2 * margin);
        CHECK(glyph.left == raster.left - margin);
        CHECK(glyph.top == raster.top - margin);
        bool same = true;
        for (int y = 0; y < raster.coverage.height; ++y) {
            for (int x = 0; x < raster.coverage.width; ++x) {
                same = same && texel(glyphs, glyph, x + margin, y + margin, 0) == raster.coverage.pixel(x, y)[0];
            }
        }
        CHECK(same);
    }
}

TEST_CASE("The halo covers the glyph and extends beyond it by the outline width", "[scene][font]")
{
    const int radius = GENERATE(1, 2, 3);
    INFO("outline " << radius << " px");
    GlyphAtlasOptions options;
    options.outlinePixels = radius;
    GlyphAtlas glyphs(dejaVuSans(), options);
    for (char32_t c : {U'H', U'o', U'\u00F1', U'.'}) {
        INFO("character U+" << std::hex << static_cast<unsigned>(c));
        const Glyph& glyph = glyphs.glyph(c);
        bool covers = true;        // halo >= coverage everywhere
        bool solidAround = true;   // within `radius` of a fully covered pixel the halo is full
        bool nearGlyph = true;     // no halo farther than radius + 1 from the glyph
        int haloOnly = 0;          // pixels of at least half halo and no glyph
        int full = 0;              // fully covered glyph pixels (solidAround is checked around them)
        for (int y = -1; y <= glyph.height; ++y) {
            for (int x = -1; x <= glyph.width; ++x) {
                const int own = texel(glyphs, glyph, x, y, 0);
                const int halo = texel(glyphs, glyph, x, y, 1);
                covers = covers && halo >= own;
                haloOnly += own == 0 && halo >= 128;
                full += own == 255;
                bool near = false;
                for (int dy = -radius - 1; dy <= radius + 1; ++dy) {
                    for (int dx = -radius - 1; dx <= radius + 1; ++dx) {
                        const int other = texel(glyphs, glyph, x + dx, y + dy, 0);
                        const double distance = std::hypot(dx, dy);
                        near = near || (other > 0 && distance < radius + 1.0);
                        if (own == 255 && distance <= radius) {
                            solidAround = solidAround && texel(glyphs, glyph, x + dx, y + dy, 1) == 255;
                        }
                    }
                }
                nearGlyph = nearGlyph && (halo == 0 || near);
            }
        }
        CHECK(covers);
        CHECK(solidAround);
        CHECK(nearGlyph);
        CHECK(haloOnly > 0);
        CHECK(full > 0);
        // The bitmap's outer ring stays for the halo's anti-aliased edge: the glyph never reaches it.
        for (int x = 0; x < glyph.width; ++x) {
            CHECK(texel(glyphs, glyph, x, 0, 0) == 0);
            CHECK(texel(glyphs, glyph, x, glyph.height - 1, 0) == 0);
        }
    }

    GlyphAtlasOptions none;
    none.outlinePixels = 0;
    GlyphAtlas plain(dejaVuSans(), none);
    const Glyph& h = plain.glyph(U'H');
    bool equal = true;
    for (int y = 0; y < h.height; ++y) {
        for (int x = 0; x < h.width; ++x) {
            equal = equal && texel(plain, h, x, y, 0) == texel(plain, h, x, y, 1);
        }
    }
    CHECK(equal);
}

TEST_CASE("An outline of 1024 pixels, the largest a scene allows, is a disc of that radius round the glyph", "[scene][font]")
{
    // Beyond a few pixels the halo comes from distance transforms, linear in the bitmap (the disc
    // taken directly would take hours here); its time is in the benchmark (orbis_bench --only
    // "vector data").
    GlyphAtlasOptions options;
    options.outlinePixels = 1024;
    GlyphAtlas glyphs(dejaVuSans(), options);
    const Glyph& dot = glyphs.glyph(U'.');
    REQUIRE(dot.width > 2048);
    REQUIRE(dot.height > 2048);
    // The dot's fully covered pixels, and the halo along the row through the middle of them.
    int left = dot.width;
    int right = -1;
    int row = -1;
    for (int y = 0; y < dot.height && row < 0; ++y) {
        for (int x = 0; x < dot.width; ++x) {
            if (texel(glyphs, dot, x, y, 0) == 255) {
                row = y;
                left = std::min(left, x);
                right = std::max(right, x);
            }
        }
    }
    REQUIRE(row >= 0);
    CHECK(texel(glyphs, dot, left - 1000, row, 1) == 255);
    CHECK(texel(glyphs, dot, left - 1024, row, 1) == 255);
    CHECK(texel(glyphs, dot, right + 1024, row, 1) == 255);
    // The bitmap's corners lie farther than 1025 from any covered pixel.
    CHECK(texel(glyphs, dot, 0, 0, 1) == 0);
    CHECK(texel(glyphs, dot, dot.width - 1, dot.height - 1, 1) == 0);
    // Above and below as far: a disc, not a square.
    CHECK(texel(glyphs, dot, left, row - 1000, 1) == 255);
    CHECK(texel(glyphs, dot, left - 800, row - 800, 1) == 0); // 1131 away
}

TEST_CASE("Accented letters of place names render their own glyphs", "[scene][font]")
{
    const auto font = dejaVuSans();
    GlyphAtlas glyphs(font);
    const struct {
        char32_t accented;
        char32_t base;
    } pairs[] = {{U'\u00E9', U'e'}, {U'\u00FC', U'u'}, {U'\u00F1', U'n'}, {U'\u0107', U'c'}, {U'\u1EC7', U'e'}};
    // Characters the font lacks (CJK here) share its missing-glyph box, rasterized once.
    const Glyph& missing = glyphs.glyph(U'\u4E2D');
    CHECK(missing.glyphIndex == 0);
    CHECK(missing.width > 0);
    const std::size_t bitmaps = glyphs.atlas().size();
    const Glyph& alsoMissing = glyphs.glyph(U'\u6587');
    CHECK(alsoMissing.codepoint == U'\u6587');
    CHECK(alsoMissing.atlasIndex == missing.atlasIndex);
    CHECK(glyphs.atlas().size() == bitmaps);
    for (const auto& pair : pairs) {
        INFO("U+" << std::hex << static_cast<unsigned>(pair.accented));
        const Glyph& accented = glyphs.glyph(pair.accented);
        const Glyph& base = glyphs.glyph(pair.base);
        CHECK(accented.glyphIndex != 0);
        CHECK(accented.glyphIndex != base.glyphIndex);
        CHECK(accented.atlasIndex != base.atlasIndex);
        // Same letter body, plus an accent above or below: a taller bitmap.
        CHECK(accented.height > base.height);
        CHECK_THAT(static_cast<double>(accented.advance), WithinAbs(static_cast<double>(base.advance), 0.01));
    }

    const TextLayout layout = glyphs.layout("Z\xC3\xBCrich");
    REQUIRE(layout.quads.size() == 6);
    CHECK(layout.quads[1].codepoint == U'\u00FC');
}

TEST_CASE("Layout breaks lines at newlines and reports its bounds", "[scene][font]")
{
    GlyphAtlas glyphs(dejaVuSans());
    const TextLayout one = glyphs.layout("Ag");
    const TextLayout two = glyphs.layout("Ag\nAg");
    CHECK(two.lineCount == 2);
    CHECK(two.lineHeight > 0);
    REQUIRE(two.quads.size() == 4);
    CHECK(two.quads[2].x == two.quads[0].x);
    CHECK(two.quads[2].y == two.quads[0].y + two.lineHeight);
    CHECK(two.width == one.width);
    CHECK(two.bounds.height == one.bounds.height + two.lineHeight);
    // The bounds hold every quad, the halo included: 'A' rises above the baseline, 'g' descends.
    CHECK(one.bounds.y < 0);
    CHECK(one.bounds.y + one.bounds.height > 0);
    for (const GlyphQuad& quad : one.quads) {
        CHECK(quad.x >= one.bounds.x);
        CHECK(quad.y >= one.bounds.y);
        CHECK(quad.x + quad.width <= one.bounds.x + one.bounds.width);
        CHECK(quad.y + quad.height <= one.bounds.y + one.bounds.height);
    }
    const TextLayout empty = glyphs.layout("");
    CHECK(empty.quads.empty());
    CHECK(empty.width == 0.0f);
}
