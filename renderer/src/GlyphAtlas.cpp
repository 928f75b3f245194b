#include "orbis/renderer/GlyphAtlas.h"

#include "orbis/renderer/Utf8.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <span>
#include <vector>
#include <unordered_set>

namespace orbis::renderer {

namespace {

/// Squared distances along one line of samples to the nearest site: the lower envelope of the
/// parabolas (x - site)^2 + height(site) (Felzenszwalb and Huttenlocher's distance transform of
/// sampled functions), in O(n). height is kNoSite where there is no site.
constexpr double kNoSite = 1e30;

void distanceAlongLine(std::span<const double> height, std::span<double> squared, std::vector<int>& sites,
                       std::vector<double>& starts)
{
    const int n = static_cast<int>(height.size());
    sites.clear();
    starts.clear();
    auto at = [&](int i) { return height[static_cast<std::size_t>(i)]; };
    for (int q = 0; q < n; ++q) {
        if (at(q) >= kNoSite) {
            continue;
        }
        // Where the parabola of q overtakes the last one of the envelope.
        double s = -kNoSite;
        while (!sites.empty()) {
            const int v = sites.back();
            s = ((at(q) + double(q) * q) - (at(v) + double(v) * v)) / (2.0 * (q - v));
            if (s > starts.back()) {
                break;
            }
            sites.pop_back();
            starts.pop_back();
            s = -kNoSite;
        }
        sites.push_back(q);
        starts.push_back(s);
    }
    std::size_t k = 0;
    for (int x = 0; x < n; ++x) {
        if (sites.empty()) {
            squared[static_cast<std::size_t>(x)] = kNoSite;
            continue;
        }
        while (k + 1 < sites.size() && starts[k + 1] <= x) {
            ++k;
        }
        const int v = sites[k];
        squared[static_cast<std::size_t>(x)] = double(x - v) * (x - v) + at(v);
    }
}

/// For each pixel, the squared distance to the nearest pixel of `image` (1 channel) that `isSite`
/// accepts (kNoSite where there is none): the exact Euclidean distance transform, along columns,
/// then along rows, in O(width x height).
template <typename IsSite>
void squaredDistanceToSites(const Image& image, IsSite isSite, std::vector<double>& squared)
{
    const int width = image.width;
    const int height = image.height;
    const auto index = [width](int x, int y) { return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x); };
    std::vector<double> columns(index(0, height));
    std::vector<int> sites;
    std::vector<double> starts;
    std::vector<double> line(static_cast<std::size_t>(std::max(width, height)));
    std::vector<double> lineSquared(line.size());
    for (int x = 0; x < width; ++x) {
        for (int y = 0; y < height; ++y) {
            line[static_cast<std::size_t>(y)] = isSite(image.pixel(x, y)[0]) ? 0.0 : kNoSite;
        }
        distanceAlongLine(std::span(line).first(static_cast<std::size_t>(height)), lineSquared, sites, starts);
        for (int y = 0; y < height; ++y) {
            columns[index(x, y)] = lineSquared[static_cast<std::size_t>(y)];
        }
    }
    squared.resize(index(0, height));
    for (int y = 0; y < height; ++y) {
        distanceAlongLine(std::span<const double>(columns).subspan(index(0, y), static_cast<std::size_t>(width)),
                          std::span(squared).subspan(index(0, y), static_cast<std::size_t>(width)), sites, starts);
    }
}

/// The halo of a coverage mask, into channel 1 of `out` (2 channels, the size of `coverage`, which
/// is 1 channel and already has `radius` empty pixels on each side); channel 0 receives the
/// coverage itself. halo(p) = max over q of coverage(q) x clamp(radius + 1 - |p - q|, 0, 1), a disc
/// anti-aliased over its last pixel. Up to kExactRadius directly, exactly (the disc is small); beyond
/// it, in O(width x height x kLevels) whatever the radius, as the max over coverage levels t of
/// t x disc(distance to the nearest pixel covered at least t): exact for masks of those levels,
/// within 1 / kLevels at the anti-aliased rim otherwise. (An outline of 1024 pixels, the largest
/// a scene allows, would take hours directly.)
void dilateCoverage(const Image& coverage, int radius, Image& out)
{
    assert(coverage.channels == 1 && out.channels == 2);
    assert(out.width == coverage.width && out.height == coverage.height);
    constexpr int kExactRadius = 4;
    constexpr int kLevels = 16;
    const auto disc = [radius](double squared) { return std::clamp(radius + 1.0 - std::sqrt(squared), 0.0, 1.0); };
    const int width = coverage.width;
    const int height = coverage.height;
    std::vector<double> halo(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), 0.0);
    if (radius <= kExactRadius) {
        const int reach = radius + 1;
        std::size_t i = 0;
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x, ++i) {
                for (int sy = std::max(0, y - reach); sy <= std::min(height - 1, y + reach); ++sy) {
                    for (int sx = std::max(0, x - reach); sx <= std::min(width - 1, x + reach); ++sx) {
                        const double squared = double(sx - x) * (sx - x) + double(sy - y) * (sy - y);
                        halo[i] = std::max(halo[i], coverage.pixel(sx, sy)[0] * disc(squared));
                    }
                }
            }
        }
    } else {
        std::vector<double> squared;
        for (int level = 1; level <= kLevels; ++level) {
            const int threshold = (255 * level + kLevels - 1) / kLevels;
            squaredDistanceToSites(coverage, [threshold](std::uint8_t c) { return c >= threshold; }, squared);
            for (std::size_t i = 0; i < halo.size(); ++i) {
                halo[i] = std::max(halo[i], threshold * disc(squared[i]));
            }
        }
    }
    std::size_t i = 0;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x, ++i) {
            const std::uint8_t own = coverage.pixel(x, y)[0];
            std::uint8_t* target = out.pixel(x, y);
            target[0] = own;
            target[1] = std::max(own, static_cast<std::uint8_t>(std::lround(std::min(halo[i], 255.0))));
        }
    }
}

} // namespace

GlyphAtlas::GlyphAtlas(std::shared_ptr<const Font> font, const GlyphAtlasOptions& options)
    : _font(std::move(font))
    , _options(options)
    , _atlas(TextureAtlasOptions{2, options.padding, options.initialSize, options.maxSize})
{
    assert(_font && options.outlinePixels >= 0 && options.sizePixels > 0.0f);
}

Glyph GlyphAtlas::prepare(int glyphIndex, Image& bitmap) const
{
    Glyph glyph;
    glyph.glyphIndex = glyphIndex;
    glyph.advance = _font->glyphMetrics(glyphIndex, _options.sizePixels).advance;
    const GlyphBitmap raster = _font->rasterize(glyphIndex, _options.sizePixels);
    if (raster.coverage.width == 0) {
        bitmap = Image(0, 0, 2);
        return glyph;
    }
    // Room for the halo on every side, then the halo itself.
    const int margin = _options.outlinePixels;
    Image padded(raster.coverage.width + 2 * margin, raster.coverage.height + 2 * margin, 1);
    for (int y = 0; y < raster.coverage.height; ++y) {
        std::copy_n(raster.coverage.pixel(0, y), raster.coverage.width, padded.pixel(margin, y + margin));
    }
    bitmap = Image(padded.width, padded.height, 2);
    dilateCoverage(padded, margin, bitmap);
    glyph.left = raster.left - margin;
    glyph.top = raster.top - margin;
    glyph.width = bitmap.width;
    glyph.height = bitmap.height;
    return glyph;
}

const Glyph& GlyphAtlas::glyph(char32_t codepoint)
{
    if (const auto found = _glyphs.find(codepoint); found != _glyphs.end()) {
        return found->second;
    }
    addCodepoints(std::u32string(1, codepoint));
    return _glyphs.at(codepoint);
}

TextureAtlas::AddResult GlyphAtlas::addCharacters(std::string_view utf8)
{
    return addCodepoints(decodeUtf8(utf8));
}

TextureAtlas::AddResult GlyphAtlas::addCodepoints(const std::u32string& codepoints)
{
    // New characters and the font glyphs they need that are not rasterized yet, both in order of
    // first appearance so the packing is deterministic. Characters sharing a glyph share its
    // bitmap: every character the font lacks gets glyph 0, the missing-glyph box, only once.
    std::u32string characters;
    std::vector<int> newGlyphs;
    std::unordered_set<char32_t> seenCharacters;
    std::unordered_set<int> seenGlyphs;
    for (char32_t c : codepoints) {
        if (c == U'\n' || _glyphs.contains(c) || !seenCharacters.insert(c).second) {
            continue;
        }
        characters.push_back(c);
        const int glyphIndex = _font->glyphIndex(c);
        if (!_byGlyphIndex.contains(glyphIndex) && seenGlyphs.insert(glyphIndex).second) {
            newGlyphs.push_back(glyphIndex);
        }
    }
    std::vector<Glyph> glyphs;
    std::vector<Image> bitmaps;
    for (int glyphIndex : newGlyphs) {
        Image bitmap;
        glyphs.push_back(prepare(glyphIndex, bitmap));
        if (glyphs.back().width > 0) {
            bitmaps.push_back(std::move(bitmap));
        }
    }
    const TextureAtlas::AddResult result = _atlas.add(bitmaps);
    std::size_t next = result.first;
    for (Glyph& glyph : glyphs) {
        if (glyph.width > 0) {
            glyph.atlasIndex = next++;
        }
        _byGlyphIndex.emplace(glyph.glyphIndex, glyph);
    }
    for (char32_t c : characters) {
        Glyph glyph = _byGlyphIndex.at(_font->glyphIndex(c));
        glyph.codepoint = c;
        _glyphs.emplace(c, glyph);
    }
    return result;
}

float GlyphAtlas::kerning(int left, int right)
{
    // stb_truetype searches the GPOS tables on every call; a label collection repeats pairs.
    const std::uint64_t key = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(left)) << 32) |
                              static_cast<std::uint32_t>(right);
    const auto [it, inserted] = _kerning.try_emplace(key, 0.0f);
    if (inserted) {
        it->second = _font->kerning(left, right, _options.sizePixels);
    }
    return it->second;
}

TextLayout GlyphAtlas::layout(std::string_view utf8)
{
    TextLayout layout;
    layout.lineHeight = static_cast<int>(std::lround(_font->verticalMetrics(_options.sizePixels).lineHeight()));
    layout.lineCount = 1;
    float pen = 0.0f;
    int baseline = 0;
    const Glyph* previous = nullptr;
    int left = 0;
    int top = 0;
    int right = 0;
    int bottom = 0;
    const std::u32string codepoints = decodeUtf8(utf8);
    // New characters go into the atlas in one batch; most texts have none.
    if (std::any_of(codepoints.begin(), codepoints.end(), [&](char32_t c) { return c != U'\n' && !_glyphs.contains(c); })) {
        addCodepoints(codepoints);
    }
    for (char32_t c : codepoints) {
        if (c == U'\n') {
            layout.width = std::max(layout.width, pen);
            pen = 0.0f;
            baseline += layout.lineHeight;
            ++layout.lineCount;
            previous = nullptr;
            continue;
        }
        const Glyph& g = glyph(c);
        if (previous) {
            pen += kerning(previous->glyphIndex, g.glyphIndex);
        }
        if (g.width > 0) {
            const GlyphQuad quad{static_cast<int>(std::lround(pen)) + g.left, baseline + g.top, g.width, g.height,
                                 g.atlasIndex, c};
            if (layout.quads.empty()) {
                left = quad.x;
                top = quad.y;
                right = quad.x + quad.width;
                bottom = quad.y + quad.height;
            }
            left = std::min(left, quad.x);
            top = std::min(top, quad.y);
            right = std::max(right, quad.x + quad.width);
            bottom = std::max(bottom, quad.y + quad.height);
            layout.quads.push_back(quad);
        }
        pen += g.advance;
        previous = &g;
    }
    layout.width = std::max(layout.width, pen);
    layout.bounds = {left, top, right - left, bottom - top};
    return layout;
}

} // namespace orbis::renderer
