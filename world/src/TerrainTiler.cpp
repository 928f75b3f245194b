#include "orbis/world/TerrainTiler.h"

#include "DemRaster.h"
#include "TerrainMesh.h"

#include "orbis/world/FileAccess.h"
#include "orbis/world/TerrainCodec.h"
#include "orbis/world/TerrainLayer.h"
#include "orbis/world/TerrainSampler.h"
#include "orbis/world/TerrainSource.h"

#include <orbis/core/Error.h>
#include <orbis/core/Math.h>
#include <orbis/core/TilingScheme.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <thread>

namespace orbis::world {

namespace {

using Clock = std::chrono::steady_clock;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

/// A geographic tile shares area with the extent (touching its boundary only is not enough);
/// the extent may cross the antimeridian.
bool overlaps(const TileKey& key, const GeodeticExtent& extent) noexcept
{
    const GeodeticExtent tile = TilingScheme::geographic().tileExtent(key);
    if (!(tile.south < extent.north && extent.south < tile.north)) {
        return false;
    }
    if (extent.west <= extent.east) {
        return tile.west < extent.east && extent.west < tile.east;
    }
    return tile.west < extent.east || extent.west < tile.east;
}

/// The columns and rows (from the south) of a level that the footprint's rectangle touches: runs
/// of columns (two where the footprint crosses the antimeridian), so that a deep level's count is
/// known without listing its columns.
struct LevelTiles {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> columnRuns; ///< first, last; ascending, disjoint
    std::uint32_t firstRow = 0;
    std::uint32_t lastRow = 0;

    std::size_t count() const noexcept
    {
        std::size_t columns = 0;
        for (const auto& [first, last] : columnRuns) {
            columns += std::size_t{last - first} + 1;
        }
        return columns * (std::size_t{lastRow - firstRow} + 1);
    }
    template <class Visit>
    void forEachColumn(Visit visit) const
    {
        for (const auto& [first, last] : columnRuns) {
            for (std::uint32_t x = first;; ++x) {
                visit(x);
                if (x == last) {
                    break;
                }
            }
        }
    }
};

LevelTiles levelTiles(const GeodeticExtent& footprint, std::uint32_t level)
{
    const TilingScheme scheme = TilingScheme::geographic();
    LevelTiles tiles;
    const double span = kPi / static_cast<double>(std::uint64_t{1} << level);
    auto index = [&](double offset, std::uint32_t count) {
        return static_cast<std::uint32_t>(std::clamp(std::floor(offset / span), 0.0, static_cast<double>(count - 1)));
    };
    tiles.firstRow = index(footprint.south + kHalfPi, scheme.tilesY(level));
    tiles.lastRow = index(footprint.north + kHalfPi, scheme.tilesY(level));
    GeodeticExtent band = footprint;
    band.south = -kHalfPi;
    band.north = kHalfPi;
    auto addColumns = [&](double west, double east) {
        std::uint32_t first = index(west + kPi, scheme.tilesX(level));
        std::uint32_t last = index(east + kPi, scheme.tilesX(level));
        // Columns touched only at their edge are left out, as rows are where tiles are cut.
        if (first < last && !overlaps({level, first, tiles.firstRow}, band)) {
            ++first;
        }
        if (first < last && !overlaps({level, last, tiles.firstRow}, band)) {
            --last;
        }
        if (!overlaps({level, first, tiles.firstRow}, band)) {
            return;
        }
        if (!tiles.columnRuns.empty() && first <= tiles.columnRuns.back().second + 1) {
            tiles.columnRuns.back().second = std::max(tiles.columnRuns.back().second, last);
        } else {
            tiles.columnRuns.emplace_back(first, last);
        }
    };
    if (footprint.west <= footprint.east) {
        addColumns(footprint.west, footprint.east);
    } else {
        addColumns(-kPi, footprint.east);
        addColumns(footprint.west, kPi);
    }
    return tiles;
}

/// An error as stored: rounded up to centimetres, so the stored value still bounds it.
float storedError(double error)
{
    return static_cast<float>(std::ceil(error * 100.0 - 1e-9) / 100.0);
}

std::string formatError(float error)
{
    char text[32];
    std::snprintf(text, sizeof text, "%.2f", static_cast<double>(error));
    return text;
}

} // namespace

struct TerrainTiler::Impl {
    TerrainTilerOptions options;
    std::shared_ptr<const detail::DemDescription> dem;
    std::uint32_t levelCount = 0;
    double levelZeroTolerance = 0.0;

    std::filesystem::path tilePath(const TileKey& key) const
    {
        return options.output / std::to_string(key.level) / std::to_string(key.x) / (std::to_string(key.y) + ".terrain");
    }
    std::filesystem::path errorPath(std::uint32_t level, std::uint32_t x) const
    {
        return options.output / "geometric-error" / std::to_string(level) / (std::to_string(x) + ".txt");
    }
    const GeodeticExtent& footprint() const { return dem->footprint.extent; }

    double tolerance(std::uint32_t level) const { return std::ldexp(levelZeroTolerance, -static_cast<int>(level)); }

    /// One tile: its file's bytes and its measured error.
    std::pair<std::vector<std::uint8_t>, double> cut(detail::DemReader& reader, const TileKey& key) const;
    /// The largest difference between a mesh's triangle edges and the DEM along them. Where an
    /// edge crosses a DEM cell the DEM's bilinear surface bends away from it, most between the
    /// pixels (the difference of a plane and a bilinear patch has no extremum inside a triangle:
    /// only on its edges and the cells' edges, whose ends are pixels, measured apart).
    double edgeError(detail::DemReader& reader, const TerrainTileData& mesh, const GeodeticExtent& extent) const;
    void writeLayer() const;
};

std::pair<std::vector<std::uint8_t>, double> TerrainTiler::Impl::cut(detail::DemReader& reader, const TileKey& key) const
{
    const int size = options.gridSize;
    const bool mesh = options.format == TerrainTileFormat::QuantizedMesh;
    // The grid with a margin of one sample (for normals that agree across edges), the margin's
    // latitudes held at the poles.
    const std::vector<Geodetic2D> positions = detail::gridPositionsWithMargin(key, size);
    std::vector<float> sampled(positions.size());
    reader.sample(positions, sampled);
    std::vector<float> withMargin(sampled);
    for (float& h : withMargin) {
        h = std::isnan(h) ? static_cast<float>(options.noDataHeight) : h;
    }
    const std::vector<float> truth = detail::withoutMargin(sampled, size);
    const std::vector<float> grid = detail::withoutMargin(withMargin, size);

    const GeodeticExtent extent = TilingScheme::geographic().tileExtent(key);
    const std::string name = tilePath(key).string();
    std::vector<std::uint8_t> bytes;
    TerrainTileData decoded;
    if (mesh) {
        const detail::SimplifiedMesh simplified = detail::simplifyGrid(grid, size, tolerance(key.level));
        TerrainTileData tile;
        tile.key = key;
        tile.vertices = simplified.vertices;
        tile.indices = simplified.indices;
        QuantizedMeshEncoding encoding;
        encoding.gzipLevel = options.gzipLevel;
        encoding.normals = options.normals;
        if (options.normals) {
            const std::vector<glm::vec3> normals = detail::gridNormals(key, size, withMargin, Ellipsoid::wgs84());
            for (const int sample : simplified.gridIndex) {
                tile.normals.push_back(normals[static_cast<std::size_t>(sample)]);
            }
        }
        bytes = encodeQuantizedMesh(tile, encoding);
        decoded = decodeQuantizedMesh(bytes, key, name);
    } else {
        TerrainTileData tile;
        tile.key = key;
        tile.size = size;
        tile.heights = grid;
        tile.childMask = 0;
        if (key.level + 1 < levelCount) {
            for (int child = 0; child < 4; ++child) {
                if (overlaps(key.child(child), footprint())) {
                    tile.childMask |= static_cast<std::uint8_t>(1 << child);
                }
            }
        }
        bytes = encodeHeightmapTerrain(tile, options.gzipLevel);
        decoded = decodeHeightmapTerrain(bytes, key, name);
    }

    // The error: the tile as written against the DEM.
    std::optional<TerrainSampler> meshSurface;
    if (mesh) {
        meshSurface.emplace(std::make_shared<const TerrainTileData>(std::move(decoded)));
    }
    double worst = 0.0;
    auto deviation = [&](double u, double v, double h) {
        if (meshSurface) {
            const std::optional<double> surface = meshSurface->heightOnTriangles(u, v);
            return surface ? std::abs(h - *surface) : std::numeric_limits<double>::infinity();
        }
        return detail::gridDeviation(decoded.heights, size, u, v, h);
    };
    const double width = extent.east - extent.west;
    const double height = extent.north - extent.south;
    reader.forEachPixel(extent, [&](double longitude, double latitude, float h) {
        worst = std::max(worst, deviation((longitude - extent.west) / width, (latitude - extent.south) / height,
                                          static_cast<double>(h)));
    });
    const double last = size - 1;
    std::vector<Geodetic2D> centres;
    centres.reserve(static_cast<std::size_t>(size - 1) * static_cast<std::size_t>(size - 1));
    for (int row = 0; row < size; ++row) {
        for (int column = 0; column < size; ++column) {
            const float h = truth[static_cast<std::size_t>(row * size + column)];
            if (!std::isnan(h)) {
                worst = std::max(worst, deviation(column / last, 1.0 - row / last, static_cast<double>(h)));
            }
            if (row + 1 < size && column + 1 < size) {
                const Geodetic2D a = terrainGridPosition(key, size, column, row);
                const Geodetic2D b = terrainGridPosition(key, size, column + 1, row + 1);
                centres.push_back({0.5 * (a.longitude + b.longitude), 0.5 * (a.latitude + b.latitude)});
            }
        }
    }
    std::vector<float> centreHeights(centres.size());
    reader.sample(centres, centreHeights);
    for (std::size_t i = 0; i < centres.size(); ++i) {
        if (!std::isnan(centreHeights[i])) {
            worst = std::max(worst, deviation((centres[i].longitude - extent.west) / width,
                                              (centres[i].latitude - extent.south) / height,
                                              static_cast<double>(centreHeights[i])));
        }
    }
    if (meshSurface) {
        worst = std::max(worst, edgeError(reader, meshSurface->data(), extent));
    }
    if (!std::isfinite(worst)) {
        throw Error(name + ": the mesh does not cover the tile");
    }
    return {std::move(bytes), worst};
}

double TerrainTiler::Impl::edgeError(detail::DemReader& reader, const TerrainTileData& mesh, const GeodeticExtent& extent) const
{
    // DEM pixels across the tile each way (for a projected DEM, as its footprint spreads them).
    const GeodeticExtent& covered = footprint();
    const double pixelsEast = extent.width() / (covered.width() / dem->width);
    const double pixelsNorth = extent.height() / (covered.height() / dem->height);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    edges.reserve(mesh.indices.size());
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        for (std::size_t e = 0; e < 3; ++e) {
            const std::uint32_t a = mesh.indices[t + e];
            const std::uint32_t b = mesh.indices[t + (e + 1) % 3];
            edges.emplace_back(std::min(a, b), std::max(a, b));
        }
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    // Four points a pixel crossed: the bend of a cell's surface along a straight line is a
    // parabola, its top found to within a sixteenth of the cell's bend.
    std::vector<Geodetic2D> points;
    std::vector<double> onMesh;
    for (const auto& [a, b] : edges) {
        const glm::dvec3 from(mesh.vertices[a]);
        const glm::dvec3 to(mesh.vertices[b]);
        const double pixels = std::hypot((to.x - from.x) * pixelsEast, (to.y - from.y) * pixelsNorth);
        const int steps = static_cast<int>(std::clamp(std::ceil(4.0 * pixels), 1.0, 65536.0));
        for (int k = 1; k < steps; ++k) {
            const glm::dvec3 p = from + (to - from) * (static_cast<double>(k) / steps);
            points.push_back({extent.west + p.x * extent.width(), extent.south + p.y * extent.height()});
            onMesh.push_back(p.z);
        }
    }
    std::vector<float> heights(points.size());
    reader.sample(points, heights);
    double worst = 0.0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (!std::isnan(heights[i])) {
            worst = std::max(worst, std::abs(static_cast<double>(heights[i]) - onMesh[i]));
        }
    }
    return worst;
}

void TerrainTiler::Impl::writeLayer() const
{
    TerrainLayer layer;
    layer.name = options.title.empty() ? options.input.filename().string() : options.title;
    layer.attribution = options.attribution;
    const bool mesh = options.format == TerrainTileFormat::QuantizedMesh;
    layer.format = mesh ? "quantized-mesh-1.0" : "heightmap-1.0";
    char description[256];
    if (mesh) {
        std::snprintf(description, sizeof description,
                      "orbis tile terrain: quantized-mesh from %d x %d point samples a tile, simplified within %.6g m at "
                      "level 0, halved at each level",
                      options.gridSize, options.gridSize, levelZeroTolerance);
    } else {
        std::snprintf(description, sizeof description, "orbis tile terrain: heightmap-1.0, 65 x 65 point samples a tile");
    }
    layer.description = description;
    layer.tiles = {"{z}/{x}/{y}.terrain?v={version}"};
    layer.rowsFromSouth = true;
    const GeodeticExtent& footprint = this->footprint();
    layer.bounds = footprint.west <= footprint.east ? footprint : GeodeticExtent{-kPi, footprint.south, kPi, footprint.north};
    layer.minimumLevel = 0;
    layer.maximumLevel = levelCount - 1;
    layer.hasAvailable = true;
    if (mesh && options.normals) {
        layer.extensions = {"octvertexnormals"};
    }
    for (std::uint32_t level = 0; level < levelCount; ++level) {
        std::vector<std::pair<std::uint32_t, std::uint32_t>> tiles;
        std::vector<float> errors;
        levelTiles(footprint, level).forEachColumn([&](std::uint32_t x) {
            const std::filesystem::path path = errorPath(level, x);
            const auto bytes = readFileBytesIfExists(path, "geometric-error file", std::size_t{16} << 20);
            if (!bytes) {
                return;
            }
            const std::string_view text(reinterpret_cast<const char*>(bytes->data()), bytes->size());
            std::size_t line = 0;
            for (std::size_t start = 0; start < text.size();) {
                const std::size_t end = std::min(text.find('\n', start), text.size());
                const std::string_view entry = text.substr(start, end - start);
                start = end + 1;
                ++line;
                std::uint32_t y = 0;
                float error = 0.0f;
                const std::size_t space = entry.find(' ');
                const auto [rowEnd, rowError] = std::from_chars(entry.data(), entry.data() + std::min(space, entry.size()), y);
                const char* errorStart = space == std::string_view::npos ? entry.data() + entry.size() : entry.data() + space + 1;
                const auto [errorEnd, errorError] = std::from_chars(errorStart, entry.data() + entry.size(), error);
                if (space == std::string_view::npos || rowError != std::errc() || errorError != std::errc() ||
                    errorEnd != entry.data() + entry.size() || y >= TilingScheme::geographic().tilesY(level) ||
                    !(error >= 0.0f)) {
                    throw Error(cutForMessage(path.string()) + ":" + std::to_string(line) +
                                ": expected \"ROW ERROR\" (a row of the level and metres)");
                }
                tiles.emplace_back(x, y);
                errors.push_back(error);
            }
        });
        layer.available.push_back(rectanglesOf(tiles));
        if (tiles.empty()) {
            continue;
        }
        LevelGeometricErrors grid;
        grid.level = level;
        std::uint32_t endX = 0;
        std::uint32_t endY = 0;
        grid.startX = grid.startY = std::numeric_limits<std::uint32_t>::max();
        for (const auto& [x, y] : tiles) {
            grid.startX = std::min(grid.startX, x);
            grid.startY = std::min(grid.startY, y);
            endX = std::max(endX, x);
            endY = std::max(endY, y);
        }
        grid.width = endX - grid.startX + 1;
        grid.height = endY - grid.startY + 1;
        grid.errors.assign(std::size_t{grid.width} * grid.height, kNaN);
        for (std::size_t i = 0; i < tiles.size(); ++i) {
            grid.errors[std::size_t{tiles[i].second - grid.startY} * grid.width + (tiles[i].first - grid.startX)] = errors[i];
        }
        layer.geometricErrors.push_back(std::move(grid));
    }
    writeFileAtomically(options.output / "layer.json", formatTerrainLayer(layer));
}

TerrainTiler::TerrainTiler(TerrainTilerOptions options) : _impl(std::make_unique<Impl>())
{
    Impl& impl = *_impl;
    impl.options = std::move(options);
    const TerrainTilerOptions& o = impl.options;
    if (o.format == TerrainTileFormat::Heightmap && o.gridSize != 65) {
        throw Error("orbis tile terrain: heightmap-1.0 tiles are 65 x 65 samples, not " + std::to_string(o.gridSize));
    }
    if (!isTerrainGridSize(o.gridSize) || o.gridSize < 5) {
        throw Error("orbis tile terrain: a grid of " + std::to_string(o.gridSize) + " samples a side (2^k + 1, 5 to 1025)");
    }
    if (o.maximumError && !(*o.maximumError >= 0.0 && std::isfinite(*o.maximumError))) {
        throw Error("orbis tile terrain: the maximum error must be a finite number of metres, 0 or more");
    }
    if (o.gzipLevel < 0 || o.gzipLevel > 9) {
        throw Error("orbis tile terrain: gzip level " + std::to_string(o.gzipLevel) + " (0 to 9)");
    }
    if (o.columns && !o.onlyLevel) {
        throw Error("orbis tile terrain: a range of columns needs the level it belongs to");
    }
    impl.dem = detail::describeDem(o.input);
    impl.levelZeroTolerance =
        o.maximumError.value_or(TilingScheme::geographic().geometricError(Ellipsoid::wgs84(), 0, 65) / 16.0);
    impl.levelCount = o.levels.value_or(terrainLevelForResolution(impl.dem->footprint.degreesPerPixel, o.gridSize) + 1);
    if (impl.levelCount < 1 || impl.levelCount > kMaximumTileLevel + 1) {
        throw Error("orbis tile terrain: " + std::to_string(impl.levelCount) + " levels (1 to " +
                    std::to_string(kMaximumTileLevel + 1) + ")");
    }
    const std::size_t deepestCount = levelTiles(impl.footprint(), impl.levelCount - 1).count();
    if (deepestCount > (std::size_t{1} << 30)) {
        throw Error(impl.dem->name + ": " + std::to_string(impl.levelCount) + " levels would cut " +
                    std::to_string(deepestCount) + " tiles at the deepest level alone; ask for fewer levels");
    }
    if (o.onlyLevel && *o.onlyLevel >= impl.levelCount) {
        throw Error("orbis tile terrain: level " + std::to_string(*o.onlyLevel) + " is not in the pyramid (0 to " +
                    std::to_string(impl.levelCount - 1) + ")");
    }
    if (o.columns) {
        const std::uint32_t columns = TilingScheme::geographic().tilesX(*o.onlyLevel);
        if (o.columns->first > o.columns->second || o.columns->second >= columns) {
            throw Error("orbis tile terrain: columns " + std::to_string(o.columns->first) + ":" +
                        std::to_string(o.columns->second) + " are not within 0:" + std::to_string(columns - 1) +
                        " of level " + std::to_string(*o.onlyLevel));
        }
    }
    std::error_code error;
    if (std::filesystem::exists(o.output, error) && !std::filesystem::is_directory(o.output, error)) {
        throw Error(cutForMessage(o.output.string()) + ": the output exists and is not a folder");
    }
}

TerrainTiler::~TerrainTiler() = default;

const GeodeticExtent& TerrainTiler::footprint() const noexcept
{
    return _impl->footprint();
}

std::uint32_t TerrainTiler::levelCount() const noexcept
{
    return _impl->levelCount;
}

double TerrainTiler::tolerance(std::uint32_t level) const noexcept
{
    return _impl->tolerance(level);
}

TerrainTilerSummary TerrainTiler::run()
{
    const Impl& impl = *_impl;
    const TerrainTilerOptions& options = impl.options;
    const auto start = Clock::now();
    std::vector<std::uint32_t> levels;
    if (options.onlyLevel) {
        levels.push_back(*options.onlyLevel);
    } else {
        for (std::uint32_t level = 0; level < impl.levelCount; ++level) {
            levels.push_back(level);
        }
    }
    // Each level's columns and their rows; a column is one worker's job (its errors are one file).
    struct Job {
        std::uint32_t level;
        std::uint32_t x;
        std::vector<std::uint32_t> rows;
    };
    std::vector<std::vector<Job>> jobs;
    std::size_t total = 0;
    for (const std::uint32_t level : levels) {
        const LevelTiles tiles = levelTiles(impl.footprint(), level);
        std::vector<Job> levelJobs;
        tiles.forEachColumn([&](std::uint32_t x) {
            if (options.columns && (x < options.columns->first || x > options.columns->second)) {
                return;
            }
            Job job{level, x, {}};
            for (std::uint32_t y = tiles.firstRow; y <= tiles.lastRow; ++y) {
                if (overlaps({level, x, y}, impl.footprint())) {
                    job.rows.push_back(y);
                }
            }
            total += job.rows.size();
            levelJobs.push_back(std::move(job));
        });
        jobs.push_back(std::move(levelJobs));
    }
    const int threadCount =
        options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));

    TerrainTilerSummary summary;
    summary.levelCount = impl.levelCount;
    summary.maximumErrors.assign(impl.levelCount, 0.0);
    std::mutex mutex;
    std::size_t done = 0;
    std::string firstError;
    std::atomic<bool> failed{false};
    for (std::size_t l = 0; l < levels.size(); ++l) {
        const std::uint32_t level = levels[l];
        const std::vector<Job>& levelJobs = jobs[l];
        std::size_t levelTotal = 0;
        for (const Job& job : levelJobs) {
            levelTotal += job.rows.size();
        }
        std::atomic<std::size_t> next{0};
        std::size_t levelDone = 0;
        auto work = [&] {
            try {
                std::unique_ptr<detail::DemReader> reader;
                for (std::size_t index; !failed && (index = next++) < levelJobs.size();) {
                    const Job& job = levelJobs[index];
                    if (!reader) {
                        reader = std::make_unique<detail::DemReader>(impl.dem);
                    }
                    std::string errors;
                    for (const std::uint32_t y : job.rows) {
                        if (failed) {
                            return;
                        }
                        const TileKey key{level, job.x, y};
                        auto [bytes, error] = impl.cut(*reader, key);
                        writeFileAtomically(impl.tilePath(key), bytes);
                        const float stored = storedError(error);
                        errors += std::to_string(y) + " " + formatError(stored) + "\n";
                        const std::lock_guard lock(mutex);
                        ++summary.tilesWritten;
                        summary.bytesWritten += bytes.size();
                        summary.maximumErrors[level] = std::max(summary.maximumErrors[level], static_cast<double>(stored));
                        ++done;
                        ++levelDone;
                        if (options.progress) {
                            options.progress({level, levelDone, levelTotal, done, total,
                                              std::chrono::duration<double>(Clock::now() - start).count()});
                        }
                    }
                    writeFileAtomically(impl.errorPath(level, job.x), std::string_view(errors));
                }
            } catch (const std::exception& error) {
                const std::lock_guard lock(mutex);
                if (!failed.exchange(true)) {
                    firstError = error.what();
                }
            }
        };
        std::vector<std::thread> workers;
        const int levelThreads = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(threadCount), levelJobs.size()));
        for (int t = 1; t < levelThreads; ++t) {
            workers.emplace_back(work);
        }
        work();
        for (std::thread& worker : workers) {
            worker.join();
        }
        if (failed) {
            throw Error(firstError);
        }
    }
    impl.writeLayer();
    summary.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return summary;
}

} // namespace orbis::world
