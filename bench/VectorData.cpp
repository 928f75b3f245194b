// Vector data on the CPU: loading GeoJSON and CSV, packing a texture atlas, building a glyph atlas.
// No accuracy knob here: the figures are what a billboard or label collection pays before the GPU.

#include "Report.h"

#include <orbis/renderer/GlyphAtlas.h>
#include <orbis/renderer/TextureAtlas.h>
#include <orbis/renderer/Utf8.h>
#include <orbis/scene/FontLookup.h>
#include <orbis/world/CsvPoints.h>
#include <orbis/world/GeoJson.h>
#include <orbis/world/SceneFile.h>

#include <filesystem>
#include <random>
#include <unordered_set>

using namespace orbis::world;
using namespace orbis::renderer;

namespace orbis::bench {
namespace {

const std::filesystem::path kData = std::filesystem::path(ORBIS_SOURCE_DIR) / "data";
const std::filesystem::path kFont = scene::defaultFontPath();

double milliseconds(const std::function<void()>& run, int repeats)
{
    return nanosecondsPerItem(1, run, repeats) * 1e-6;
}

std::size_t countPositions(const Geometry& geometry)
{
    return std::visit(
        [](const auto& g) -> std::size_t {
            using T = std::decay_t<decltype(g)>;
            std::size_t n = 0;
            if constexpr (std::is_same_v<T, Point>) {
                n = 1;
            } else if constexpr (std::is_same_v<T, MultiPoint> || std::is_same_v<T, LineString>) {
                n = g.positions.size();
            } else if constexpr (std::is_same_v<T, MultiLineString>) {
                for (const LineString& line : g.lines) {
                    n += line.positions.size();
                }
            } else if constexpr (std::is_same_v<T, Polygon>) {
                for (const LinearRing& ring : g.rings) {
                    n += ring.size();
                }
            } else if constexpr (std::is_same_v<T, MultiPolygon>) {
                for (const Polygon& polygon : g.polygons) {
                    for (const LinearRing& ring : polygon.rings) {
                        n += ring.size();
                    }
                }
            } else {
                for (const Geometry& inner : g.geometries) {
                    n += countPositions(inner);
                }
            }
            return n;
        },
        geometry.value);
}

Table loading(const Options& options)
{
    const int repeats = options.quick ? 2 : 7;
    Table table;
    table.title = "Loading vector data";
    table.description = "Whole-file load into Orbis types (positions converted to radians, properties kept), best of " +
                        std::to_string(repeats) + " runs, files in the page cache.";
    table.columns = {"file", "size", "features or points", "positions", "load time", "throughput"};
    auto row = [&](const std::string& name, std::size_t items, std::size_t positions, double ms) {
        const double megabytes = static_cast<double>(std::filesystem::file_size(kData / name)) / 1e6;
        table.rows.push_back({name, formatNumber(megabytes, 3) + " MB", std::to_string(items), std::to_string(positions),
                              formatNumber(ms, 3) + " ms", formatNumber(megabytes / (ms * 1e-3), 3) + " MB/s"});
    };
    for (const char* name : {"natural-earth/countries-110m.geojson", "natural-earth/land-110m.geojson"}) {
        FeatureCollection features;
        const double ms = milliseconds([&] { features = loadGeoJson(kData / name); }, repeats);
        std::size_t positions = 0;
        for (const Feature& feature : features.features) {
            positions += feature.geometry ? countPositions(*feature.geometry) : 0;
        }
        row(name, features.features.size(), positions, ms);
    }
    CsvPoints cities;
    const double ms = milliseconds([&] { cities = loadCsvPoints(kData / "geonames/cities.csv"); }, repeats);
    row("geonames/cities.csv", cities.size(), cities.size(), ms);
    table.notes = "GeoJSON goes through nlohmann::json's document model, then validation and conversion; the CSV "
                  "reader splits the file in place and keeps the name and country columns as strings.";
    return table;
}

Table atlasPacking(const Options& options)
{
    Table table;
    table.title = "Texture atlas packing";
    table.description = "Random images of 8 to 64 px a side (seeded), RGBA, 1 px padding, atlas from 64x64 up to "
                        "at most 8192x8192: added in one batch (tallest first) or one by one (as a billboard "
                        "collection gains images). Time includes copying the pixels and growing the atlas.";
    table.columns = {"images", "added", "time", "per image", "atlas", "occupancy", "resizes", "repacks"};
    std::vector<std::size_t> counts = {100, 1000};
    if (!options.quick) {
        counts.push_back(10000);
    }
    for (const std::size_t count : counts) {
        std::mt19937 random(60);
        std::uniform_int_distribution<int> side(8, 64);
        std::vector<Image> images;
        double area = 0.0;
        for (std::size_t i = 0; i < count; ++i) {
            images.emplace_back(side(random), side(random), 4);
            area += images.back().width * images.back().height;
        }
        TextureAtlasOptions atlasOptions;
        atlasOptions.maxSize = 8192;
        for (const bool batch : {true, false}) {
            int resizes = 0;
            int repacks = 0;
            std::unique_ptr<TextureAtlas> atlas;
            const double ms = milliseconds(
                [&] {
                    atlas = std::make_unique<TextureAtlas>(atlasOptions);
                    resizes = 0;
                    repacks = 0;
                    if (batch) {
                        atlas->add(images);
                        return;
                    }
                    for (const Image& image : images) {
                        const auto result = atlas->add(image);
                        resizes += result.resized;
                        repacks += result.repacked;
                    }
                },
                options.quick ? 1 : 3);
            const double atlasArea = static_cast<double>(atlas->width()) * atlas->height();
            table.rows.push_back({std::to_string(count), batch ? "one batch" : "one by one", formatNumber(ms, 3) + " ms",
                                  formatNumber(ms * 1e3 / static_cast<double>(count), 3) + " µs",
                                  std::to_string(atlas->width()) + "x" + std::to_string(atlas->height()),
                                  formatNumber(100.0 * area / atlasArea, 3) + " %", batch ? "-" : std::to_string(resizes),
                                  batch ? "-" : std::to_string(repacks)});
        }
    }
    table.notes = "Occupancy: image pixels over atlas pixels (padding and power-of-two rounding make up the rest).";
    return table;
}

Table glyphAtlas(const Options& options)
{
    const CsvPoints cities = loadCsvPoints(kData / "geonames/cities.csv");
    const std::vector<std::string>& names = *cities.column("name");
    std::string allNames;
    for (const std::string& name : names) {
        allNames += name;
        allNames += ' ';
    }
    const std::u32string codepoints = decodeUtf8(allNames);
    const std::unordered_set<char32_t> distinct(codepoints.begin(), codepoints.end());
    const auto font = std::make_shared<const Font>(kFont);
    std::size_t missing = 0;
    for (char32_t c : distinct) {
        missing += font->glyphIndex(c) == 0;
    }

    Table table;
    table.title = "Glyph atlas for the GeoNames city names";
    table.description = "DejaVu Sans, every distinct character of the " + std::to_string(names.size()) + " city names (" +
                        std::to_string(distinct.size()) + " distinct, " + std::to_string(missing) +
                        " of them not in the font; " + std::to_string(codepoints.size()) +
                        " in all) rasterized with stb_truetype, haloed and packed in one batch; then every name "
                        "laid out (UTF-8 decoding, kerning, whole-pixel positions).";
    table.columns = {"size", "halo", "build time", "atlas", "glyphs with pixels", "layout of all names", "per name"};
    const int repeats = options.quick ? 1 : 3;
    std::vector<std::pair<float, int>> settings = {{16.0f, 2}};
    if (!options.quick) {
        settings.insert(settings.begin(), {12.0f, 1});
        settings.push_back({24.0f, 3});
    }
    for (const auto& [size, halo] : settings) {
        GlyphAtlasOptions glyphOptions;
        glyphOptions.sizePixels = size;
        glyphOptions.outlinePixels = halo;
        std::unique_ptr<GlyphAtlas> glyphs;
        const double buildMs = milliseconds(
            [&] {
                glyphs = std::make_unique<GlyphAtlas>(font, glyphOptions);
                glyphs->addCharacters(allNames);
            },
            repeats);
        std::size_t quads = 0;
        const double layoutMs = milliseconds(
            [&] {
                quads = 0;
                for (const std::string& name : names) {
                    quads += glyphs->layout(name).quads.size();
                }
            },
            repeats);
        doNotOptimize(quads);
        table.rows.push_back({formatNumber(size, 2) + " px", std::to_string(halo) + " px", formatNumber(buildMs, 3) + " ms",
                              std::to_string(glyphs->atlas().width()) + "x" + std::to_string(glyphs->atlas().height()),
                              std::to_string(glyphs->atlas().size()), formatNumber(layoutMs, 3) + " ms",
                              formatNumber(layoutMs * 1e6 / static_cast<double>(names.size()), 3) + " ns"});
    }
    table.notes = "Characters DejaVu Sans lacks share its missing-glyph box. Combining marks are drawn as "
                  "separate zero-advance glyphs (no shaping).";
    return table;
}

Table cameraPaths(const Options& options)
{
    Table table;
    table.title = "Reading long camera paths";
    const int repeats = options.quick ? 1 : 3;
    table.description = "parseCameraPathText on generated paths (keyframes a second apart, eye and target as the "
                        "example path writes them), best of " + std::to_string(repeats) +
                        " runs. The nesting depth is checked by a scan of the text before nlohmann parses it.";
    table.columns = {"keyframes", "size", "time", "per keyframe"};
    const std::vector<int> counts = options.quick ? std::vector<int>{1000} : std::vector<int>{12500, 25000, 50000};
    for (const int count : counts) {
        std::string text = "{\"version\": 1, \"keyframes\": [\n";
        for (int k = 0; k < count; ++k) {
            text += "  { \"time\": " + std::to_string(k) + ", \"position\": { \"lon\": " + std::to_string(k % 359 - 179) +
                    ".25, \"lat\": 20.5, \"height\": 2000000 }, \"target\": { \"lon\": 10.125, \"lat\": 45.5, "
                    "\"height\": 0 } }" + (k + 1 < count ? ",\n" : "\n");
        }
        text += "]}\n";
        std::size_t read = 0;
        const double ms = milliseconds([&] { read = parseCameraPathText(text, "path.json").size(); }, repeats);
        doNotOptimize(read);
        table.rows.push_back({std::to_string(count), formatNumber(static_cast<double>(text.size()) / 1e6, 3) + " MB",
                              formatNumber(ms, 3) + " ms", formatNumber(ms * 1e6 / count, 3) + " ns"});
    }
    table.notes = "Linear: the time per keyframe stays flat as the path grows. With the depth limited by nlohmann's "
                  "parser callback instead, a 4.6 MB path took 2.2 s (quadratic in the array).";
    return table;
}

Table haloWidths(const Options& options)
{
    const auto font = std::make_shared<const Font>(kFont);
    Table table;
    table.title = "Glyph halo width";
    const int repeats = options.quick ? 1 : 3;
    table.description = "One glyph, W of DejaVu Sans at 16 px, rasterized and haloed into a fresh atlas, best of " +
                        std::to_string(repeats) + " runs. Up to 4 px the disc is taken directly (exact); beyond, "
                        "as 16 distance transforms of the coverage's levels, linear in the bitmap.";
    table.columns = {"halo", "bitmap", "time"};
    const std::vector<int> widths = options.quick ? std::vector<int>{2, 64} : std::vector<int>{1, 2, 4, 5, 64, 256, 1024};
    for (const int width : widths) {
        GlyphAtlasOptions glyphOptions;
        glyphOptions.outlinePixels = width;
        Glyph glyph;
        const double ms = milliseconds(
            [&] {
                GlyphAtlas glyphs(font, glyphOptions);
                glyph = glyphs.glyph(U'W');
            },
            repeats);
        table.rows.push_back({std::to_string(width) + " px", std::to_string(glyph.width) + "x" + std::to_string(glyph.height),
                              formatNumber(ms, 3) + " ms"});
    }
    table.notes = "Before, the disc was taken directly at every width: O(width x height x radius^2), hours at "
                  "1024 px (the largest outline a scene file allows).";
    return table;
}

std::vector<Table> run(const Options& options)
{
    return {loading(options), atlasPacking(options), glyphAtlas(options), haloWidths(options), cameraPaths(options)};
}

const SectionRegistration registration("vector data", 60, run);

} // namespace
} // namespace orbis::bench
