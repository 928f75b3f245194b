// Terrain I/O: decoding the shipped ETOPO5 quantized-mesh tiles (data/terrain/etopo5) against
// reading them from disk, and the terrain tiler's tiles per second and MB/s over ETOPO5 on one
// and two threads. The tiler's input is the full 5 arc-minute ETOPO5 PNG when ORBIS_ETOPO5 names
// it (see data/terrain/README.md), else the 1-degree grid shipped in data/terrain/etopo5-source; quick
// runs cut fewer levels. The accuracy side (each tile's measured error) is in layer.json and
// tested in tests/world/TerrainHeightTests.cpp.

#include "Report.h"

#include <orbis/world/FileAccess.h>
#include <orbis/world/TerrainCodec.h>
#include <orbis/world/TerrainTiler.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>

#include <unistd.h>

namespace orbis::bench {
namespace {

const std::filesystem::path kTiles = std::filesystem::path(ORBIS_SOURCE_DIR) / "data/terrain/etopo5";

struct TileFile {
    std::filesystem::path path;
    TileKey key;
};

/// The tile files of the shipped set's deepest level.
std::vector<TileFile> deepestTiles(std::uint32_t& level)
{
    level = 0;
    while (std::filesystem::is_directory(kTiles / std::to_string(level + 1))) {
        ++level;
    }
    std::vector<TileFile> files;
    for (const auto& column : std::filesystem::directory_iterator(kTiles / std::to_string(level))) {
        for (const auto& file : std::filesystem::directory_iterator(column.path())) {
            const auto x = static_cast<std::uint32_t>(std::stoul(column.path().filename().string()));
            const auto y = static_cast<std::uint32_t>(std::stoul(file.path().stem().string()));
            files.push_back({file.path(), {level, x, y}});
        }
    }
    std::sort(files.begin(), files.end(), [](const TileFile& a, const TileFile& b) { return a.path < b.path; });
    return files;
}

std::vector<Table> decoding(const Options& options)
{
    std::uint32_t level = 0;
    std::vector<TileFile> files = deepestTiles(level);
    if (options.quick && files.size() > 64) {
        files.resize(64);
    }
    std::vector<std::vector<std::uint8_t>> compressed;
    std::vector<std::vector<std::uint8_t>> inflated;
    std::size_t compressedBytes = 0;
    std::size_t inflatedBytes = 0;
    std::size_t vertices = 0;
    for (const TileFile& file : files) {
        compressed.push_back(world::readFileBytes(file.path, "tile"));
        inflated.push_back(world::gunzipIfCompressed(compressed.back(), file.path.string()));
        compressedBytes += compressed.back().size();
        inflatedBytes += inflated.back().size();
        vertices += world::decodeQuantizedMesh(compressed.back(), file.key, file.path.string()).vertices.size();
    }
    const std::size_t count = files.size();
    const int repeats = options.quick ? 1 : 9;
    // Reading from disk: the files are in the page cache after the first pass, so this is the
    // cost of the system calls and the copy, the least any tile load pays.
    const std::function<void()> steps[] = {
        [&] {
            for (const TileFile& file : files) {
                doNotOptimize(world::readFileBytes(file.path, "tile").size());
            }
        },
        [&] {
            for (std::size_t i = 0; i < count; ++i) {
                doNotOptimize(world::gunzipIfCompressed(compressed[i], "tile").size());
            }
        },
        [&] {
            for (std::size_t i = 0; i < count; ++i) {
                doNotOptimize(world::decodeQuantizedMesh(inflated[i], files[i].key, "tile").vertices.size());
            }
        },
        [&] {
            for (std::size_t i = 0; i < count; ++i) {
                doNotOptimize(world::decodeQuantizedMesh(compressed[i], files[i].key, "tile").vertices.size());
            }
        },
    };
    constexpr int kSteps = 4;
    double best[kSteps];
    std::fill_n(best, kSteps, HUGE_VAL);
    for (int r = 0; r < repeats; ++r) {
        for (int s = 0; s < kSteps; ++s) {
            best[s] = std::min(best[s], threadCpuNanosecondsPerItem(count, steps[s]));
        }
    }
    const double bytesPerTile = static_cast<double>(compressedBytes) / static_cast<double>(count);
    auto row = [&](const std::string& name, double nanoseconds) {
        const double seconds = nanoseconds * 1e-9;
        return std::vector<std::string>{name, formatNumber(nanoseconds * 1e-3, 3), formatNumber(1.0 / seconds, 3),
                                        formatNumber(bytesPerTile / seconds / 1e6, 3),
                                        formatNumber(100.0 * nanoseconds / best[0], 3) + " %"};
    };
    Table table;
    table.title = "Decoding the shipped ETOPO5 quantized-mesh tiles (level " + std::to_string(level) + "), one thread";
    table.description = "The " + std::to_string(count) + " tiles of data/terrain/etopo5/" + std::to_string(level) + " (" +
                        formatNumber(bytesPerTile / 1024.0, 3) + " KiB gzip-compressed, " +
                        formatNumber(static_cast<double>(inflatedBytes) / static_cast<double>(count) / 1024.0, 3) +
                        " KiB inflated and " + formatNumber(static_cast<double>(vertices) / static_cast<double>(count), 3) +
                        " vertices each on average with oct normals) one after another on one thread; the thread's CPU "
                        "time, best of " +
                        std::to_string(repeats) + " runs taken in turns. MB/s counts the compressed bytes.";
    table.columns = {"step", "us per tile", "tiles/s", "MB/s (compressed)", "against reading the file"};
    table.rows.push_back(row("read the file (world::readFileBytes, page cache warm)", best[0]));
    table.rows.push_back(row("inflate the gzip (world::gunzipIfCompressed)", best[1]));
    table.rows.push_back(row("decode the inflated tile (world::decodeQuantizedMesh)", best[2]));
    table.rows.push_back(row("inflate and decode (what a tile load does after reading)", best[3]));
    table.notes = "Decoding checks every count, index and edge list and decodes the normals; inflating is most of a "
                  "load's work.";
    return {table};
}

/// A VRT giving GDAL the geotransform and offset of the full ETOPO5 PNG (grid-registered samples
/// from 180 W, 90 N; height = value - 32768), as data/terrain/etopo5-source/etopo5_1deg.vrt does
/// for the 1-degree grid.
std::string etopo5Vrt(const std::filesystem::path& png)
{
    const int width = 4320;
    const int height = 2161;
    const double spacing = 360.0 / width;
    char text[1024];
    std::snprintf(text, sizeof text,
                  "<VRTDataset rasterXSize=\"%d\" rasterYSize=\"%d\"><SRS>EPSG:4326</SRS>"
                  "<GeoTransform>%.17g, %.17g, 0, %.17g, 0, %.17g</GeoTransform>"
                  "<VRTRasterBand dataType=\"UInt16\" band=\"1\"><Offset>-32768</Offset><SimpleSource>"
                  "<SourceFilename relativeToVRT=\"0\">%s</SourceFilename><SourceBand>1</SourceBand>"
                  "</SimpleSource></VRTRasterBand></VRTDataset>\n",
                  width, height, -180.0 - spacing / 2.0, spacing, 90.0 + spacing / 2.0, -spacing, png.c_str());
    return text;
}

std::vector<Table> tiling(const Options& options)
{
    const char* full = std::getenv("ORBIS_ETOPO5");
    const bool native = full && *full && !options.quick;
    const std::filesystem::path scratch =
        std::filesystem::temp_directory_path() / ("orbis-bench-terrain-" + std::to_string(::getpid()));
    std::filesystem::remove_all(scratch);
    std::filesystem::path input = kTiles.parent_path() / "etopo5-source/etopo5_1deg.vrt";
    if (native) {
        input = scratch / "etopo5.vrt";
        world::writeFileAtomically(input, etopo5Vrt(std::filesystem::absolute(full)));
    }
    Table table;
    table.title = std::string("The terrain tiler: ETOPO5 ") + (native ? "(5 arc-minutes, 4320 x 2161)" : "at 1 degree (360 x 181)") +
                  " to quantized-mesh at its native resolution";
    table.description = "`orbis tile terrain` as a class (world::TerrainTiler), default options (65 x 65 point samples a "
                        "tile, greedy TIN within the level's tolerance, oct normals, gzip 6, each tile decoded again "
                        "and its error measured against every DEM pixel in it and along its triangles' edges), levels 0 to the first as fine as the "
                        "input. Best of " +
                        std::to_string(options.quick ? 1 : 2) + " runs by wall clock; " +
                        std::to_string(std::thread::hardware_concurrency()) +
                        " hardware threads on this machine. MB/s counts the tile files written.";
    table.columns = {"threads", "levels", "tiles", "MB written", "wall seconds", "tiles/s", "MB/s", "speed-up",
                     "CPU seconds", "CPU ms per tile"};
    double oneThread = 0.0;
    for (const int threads : {1, 2}) {
        world::TerrainTilerSummary summary;
        double bestWall = HUGE_VAL;
        double cpuOfBest = 0.0;
        for (int r = 0; r < (options.quick ? 1 : 2); ++r) {
            std::filesystem::remove_all(scratch / "out");
            world::TerrainTilerOptions tilerOptions;
            tilerOptions.input = input;
            tilerOptions.output = scratch / "out";
            tilerOptions.threads = threads;
            if (options.quick) {
                tilerOptions.levels = 3;
            }
            const std::clock_t cpuStart = std::clock();
            const auto start = std::chrono::steady_clock::now();
            summary = world::TerrainTiler(tilerOptions).run();
            const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            const double cpu = static_cast<double>(std::clock() - cpuStart) / CLOCKS_PER_SEC;
            if (wall < bestWall) {
                bestWall = wall;
                cpuOfBest = cpu;
            }
        }
        oneThread = threads == 1 ? bestWall : oneThread;
        const auto tiles = static_cast<double>(summary.tilesWritten);
        const double megabytes = static_cast<double>(summary.bytesWritten) / 1e6;
        table.rows.push_back({std::to_string(threads), "0-" + std::to_string(summary.levelCount - 1),
                              std::to_string(summary.tilesWritten), formatNumber(megabytes, 3), formatNumber(bestWall, 3),
                              formatNumber(tiles / bestWall, 3), formatNumber(megabytes / bestWall, 3),
                              formatNumber(oneThread / bestWall, 3), formatNumber(cpuOfBest, 3),
                              formatNumber(1e3 * cpuOfBest / tiles, 3)});
    }
    std::filesystem::remove_all(scratch);
    table.notes = "Each level runs its columns on the threads; the levels run one after another, so the two tiles of "
                  "level 0 and the eight of level 1 are the serial part.";
    return {table};
}

std::vector<Table> run(const Options& options)
{
    std::vector<Table> tables = decoding(options);
    for (Table& table : tiling(options)) {
        tables.push_back(std::move(table));
    }
    return tables;
}

const SectionRegistration registration("terrain io", 62, run);

} // namespace
} // namespace orbis::bench
