// Tile I/O: decoding the Blue Marble's level-4 tiles with TurboJPEG alone and through
// orbis::world::decodeImage (the reference for the streaming pipeline's overhead), and the imagery
// tiler's tiles per second on one and two threads. No accuracy knob: decoding is exact, and the
// tiler's accuracy is tested (tests/world/ImageryTilerTests.cpp).

#include "Report.h"

#include <orbis/world/FileAccess.h>
#include <orbis/world/ImageCodec.h>
#include <orbis/world/ImageryTiler.h>

#include <turbojpeg.h>

#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <thread>

#include <unistd.h>

namespace orbis::bench {
namespace {

const std::filesystem::path kBlueMarble = std::filesystem::path(ORBIS_SOURCE_DIR) / "data/imagery/BlueMarble";

/// Every tile of one level of the shipped Blue Marble pyramid, read into memory.
std::vector<std::vector<std::uint8_t>> readLevel(std::uint32_t level)
{
    std::vector<std::vector<std::uint8_t>> tiles;
    for (std::uint32_t x = 0; x < (2u << level); ++x) {
        for (std::uint32_t y = 0; y < (1u << level); ++y) {
            tiles.push_back(world::readFileBytes(kBlueMarble / std::to_string(level) / std::to_string(x) /
                                                     (std::to_string(y) + ".jpg"),
                                                 "tile"));
        }
    }
    return tiles;
}

/// The tiles of one level joined into the equirectangular image they were cut from.
Image mosaic(std::uint32_t level)
{
    const auto tiles = readLevel(level);
    const int columns = 2 << level;
    const int rows = 1 << level;
    Image image(columns * 256, rows * 256, 3);
    std::size_t index = 0;
    for (int x = 0; x < columns; ++x) {
        for (int y = 0; y < rows; ++y) {
            const Image tile = world::decodeImage(tiles[index++], "tile", 3);
            for (int row = 0; row < 256; ++row) {
                std::copy_n(tile.pixel(0, row), 256 * 3, image.pixel(x * 256, (rows - 1 - y) * 256 + row));
            }
        }
    }
    return image;
}

std::vector<Table> decoding(const Options& options)
{
    const auto tiles = readLevel(4);
    std::size_t compressed = 0;
    for (const auto& tile : tiles) {
        compressed += tile.size();
    }
    const int repeats = options.quick ? 1 : 15;
    const std::size_t count = options.quick ? 64 : tiles.size();
    std::vector<std::uint8_t> pixels(256 * 256 * 4);
    tjhandle handle = tjInitDecompress();
    auto turboAlone = [&](TJPF format) {
        for (std::size_t i = 0; i < count; ++i) {
            if (tjDecompress2(handle, tiles[i].data(), static_cast<unsigned long>(tiles[i].size()), pixels.data(), 256, 0,
                              256, format, 0) != 0) {
                throw std::runtime_error("TurboJPEG failed");
            }
            doNotOptimize(pixels[0]);
        }
    };
    auto ours = [&](int channels) {
        for (std::size_t i = 0; i < count; ++i) {
            const Image image = world::decodeImage(tiles[i], "tile", channels);
            doNotOptimize(image.pixels[0]);
        }
    };
    // The decoders take turns, each keeping its best run, so that a change in the machine's load
    // during the measurement touches all of them alike.
    const std::function<void()> decoders[] = {[&] { turboAlone(TJPF_RGB); }, [&] { ours(3); },
                                              [&] { turboAlone(TJPF_RGBA); }, [&] { ours(4); }};
    constexpr int kDecoders = 4;
    double best[kDecoders];
    std::fill_n(best, kDecoders, HUGE_VAL);
    for (int r = 0; r < repeats; ++r) {
        for (int d = 0; d < kDecoders; ++d) {
            best[d] = std::min(best[d], threadCpuNanosecondsPerItem(count, decoders[d]));
        }
    }
    tjDestroy(handle);

    const double bytesPerTile = static_cast<double>(compressed) / static_cast<double>(tiles.size());
    auto row = [&](const std::string& name, double nanoseconds, double reference) {
        const double seconds = nanoseconds * 1e-9;
        return std::vector<std::string>{name, formatNumber(nanoseconds * 1e-6, 3), formatNumber(1.0 / seconds, 3),
                                        formatNumber(bytesPerTile / seconds / 1e6, 3),
                                        formatNumber(256.0 * 256.0 / seconds / 1e6, 3),
                                        reference > 0.0 ? formatNumber(100.0 * (nanoseconds / reference - 1.0), 2) + " %"
                                                        : "reference"};
    };
    Table table;
    table.title = "Decoding the Blue Marble's level-4 tiles (256 x 256 JPEG, quality 88), one thread";
    table.description = "The " + std::to_string(count) + " tiles of data/imagery/BlueMarble/4 (" +
                        formatNumber(bytesPerTile / 1024.0, 3) +
                        " KiB each on average) in memory, decoded one after another on one thread; the thread's "
                        "CPU time, best of " +
                        std::to_string(repeats) + " runs taken in turns. MB/s counts the compressed bytes read.";
    table.columns = {"decoder", "ms per tile", "tiles/s", "MB/s (compressed)", "Mpixel/s", "against TurboJPEG alone"};
    table.rows.push_back(row("TurboJPEG alone, RGB (one handle, one output buffer)", best[0], 0.0));
    table.rows.push_back(row("world::decodeImage, 3 channels (a new Image each)", best[1], best[0]));
    table.rows.push_back(row("TurboJPEG alone, RGBA", best[2], 0.0));
    table.rows.push_back(row("world::decodeImage, 4 channels (a new Image each)", best[3], best[2]));
    table.notes = "decodeImage adds the format check, the header and pixel-count check, the strict flags "
                  "(warnings are errors, limited progressive scans) and a new zeroed Image per tile to "
                  "TurboJPEG's work; the streaming pipeline's overhead is measured against the TurboJPEG-alone "
                  "rows.";
    return {table};
}

std::vector<Table> tiling(const Options& options)
{
    // The tiler's input: the level-3 (or, quick, level-2) mosaic of the shipped pyramid as one
    // whole-globe JPEG, cut again into levels 0-3 (0-2).
    const std::uint32_t level = options.quick ? 2 : 3;
    const std::filesystem::path scratch =
        std::filesystem::temp_directory_path() / ("orbis-bench-tiler-" + std::to_string(::getpid()));
    std::filesystem::remove_all(scratch);
    const Image input = mosaic(level);
    world::writeFileAtomically(scratch / "input.jpg", world::encodeJpeg(input, 90));
    Table table;
    table.title = "The imagery tiler: a whole-globe JPEG of " + std::to_string(input.width) + " x " +
                  std::to_string(input.height) + " cut into levels 0-" + std::to_string(level);
    table.description = "`orbis tile imagery` as a class (world::ImageryTiler): decode the input once, warp each tile "
                        "of the deepest level with GDAL (bilinear), make each level above from the four tiles below, "
                        "encode JPEG quality 90, write each file atomically. Best of " +
                        std::to_string(options.quick ? 1 : 3) + " runs by wall clock; " +
                        std::to_string(std::thread::hardware_concurrency()) + " hardware threads on this machine.";
    table.columns = {"threads", "tiles", "wall seconds", "tiles/s", "speed-up", "CPU seconds", "CPU ms per tile"};
    double oneThread = 0.0;
    for (const int threads : {1, 2}) {
        world::TilerSummary summary;
        double bestWall = HUGE_VAL;
        double cpuOfBest = 0.0;
        for (int r = 0; r < (options.quick ? 1 : 3); ++r) {
            std::filesystem::remove_all(scratch / "out");
            world::ImageryTilerOptions tilerOptions;
            tilerOptions.input = scratch / "input.jpg";
            tilerOptions.output = scratch / "out";
            tilerOptions.levels = level + 1;
            tilerOptions.threads = threads;
            // The process's CPU time (all threads) beside the wall clock: on a shared machine the
            // first shows the work, the second what the threads got of the cores.
            const std::clock_t cpuStart = std::clock();
            const auto start = std::chrono::steady_clock::now();
            summary = world::ImageryTiler(tilerOptions).run();
            const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            const double cpu = static_cast<double>(std::clock() - cpuStart) / CLOCKS_PER_SEC;
            if (wall < bestWall) {
                bestWall = wall;
                cpuOfBest = cpu;
            }
        }
        oneThread = threads == 1 ? bestWall : oneThread;
        const auto tiles = static_cast<double>(summary.tilesWritten);
        table.rows.push_back({std::to_string(threads), std::to_string(summary.tilesWritten), formatNumber(bestWall, 3),
                              formatNumber(tiles / bestWall, 3), formatNumber(oneThread / bestWall, 3),
                              formatNumber(cpuOfBest, 3), formatNumber(1e3 * cpuOfBest / tiles, 3)});
    }
    std::filesystem::remove_all(scratch);
    table.notes = "Decoding the input (once, before the workers start) and the two root tiles are the serial part.";
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

const SectionRegistration registration("tile io", 60, run);

} // namespace
} // namespace orbis::bench
