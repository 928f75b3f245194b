#include "orbis/world/TerrainSource.h"

#include "DemRaster.h"
#include "TerrainMesh.h"
#include "HttpClient.h"
#include "TileSources.h"

#include "orbis/world/FileAccess.h"
#include "orbis/world/TerrainCodec.h"

#include <orbis/core/Error.h>
#include <orbis/core/Math.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <list>
#include <map>
#include <mutex>
#include <set>
#include <shared_mutex>
#include <unordered_map>

namespace orbis::world {

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

std::string tileName(const TileKey& key)
{
    return std::to_string(key.level) + "/" + std::to_string(key.x) + "/" + std::to_string(key.y);
}

TerrainFetch missing()
{
    TerrainFetch fetch;
    fetch.status = TerrainFetch::Status::Missing;
    return fetch;
}

TerrainFetch failed(std::string message)
{
    TerrainFetch fetch;
    fetch.status = TerrainFetch::Status::Failed;
    fetch.message = std::move(message);
    return fetch;
}

int log2Exact(int value) noexcept
{
    int log = 0;
    while ((1 << log) < value) {
        ++log;
    }
    return log;
}

/// Longitude intervals touch or overlap; `b` may cross the antimeridian (east < west).
bool longitudesTouch(double westA, double eastA, double westB, double eastB) noexcept
{
    if (westB <= eastB) {
        return westA <= eastB && westB <= eastA;
    }
    return westA <= eastB || westB <= eastA;
}

/// A geographic tile shares area with the extent (touching its boundary only is not enough).
bool tileOverlaps(const TileKey& key, const GeodeticExtent& extent) noexcept
{
    const GeodeticExtent tile = TilingScheme::geographic().tileExtent(key);
    return tile.south < extent.north && extent.south < tile.north &&
           longitudesTouch(tile.west, tile.east, extent.west, extent.east) &&
           !(tile.east == extent.west || tile.west == extent.east);
}

/// Minimum and maximum of the heights (NaN-free by then).
void setRange(TerrainTileData& tile)
{
    const auto [low, high] = std::minmax_element(tile.heights.begin(), tile.heights.end());
    if (tile.heights.empty()) {
        return;
    }
    tile.minimumHeight = static_cast<double>(*low);
    tile.maximumHeight = static_cast<double>(*high);
}

/// The child mask from which children a source has.
std::uint8_t childMaskOf(const TerrainSource& source, const TileKey& key)
{
    if (key.level >= kMaximumTileLevel) {
        return 0;
    }
    std::uint8_t mask = 0;
    for (int child = 0; child < 4; ++child) {
        // TileKey::child counts rows from the south like TMS: 0 SW, 1 SE, 2 NW, 3 NE.
        if (source.hasTile(key.child(child))) {
            mask |= static_cast<std::uint8_t>(1 << child);
        }
    }
    return mask;
}

// ---- Tiles one to one: quantized-mesh, heightmap-1.0, 2^k + 1 PNG heights ------------------------

enum class TileFormat { QuantizedMesh, Heightmap, Png16 };

class TiledTerrainSource final : public TerrainSource {
public:
    TiledTerrainSource(std::unique_ptr<TileSource> tiles, TileFormat format, std::optional<TerrainLayer> layer)
        : _tiles(std::move(tiles)), _format(format), _layer(std::move(layer))
    {
        const TileSourceInfo& source = _tiles->info();
        _info.name = source.name;
        _info.format = format == TileFormat::QuantizedMesh ? "quantized-mesh" : format == TileFormat::Heightmap ? "heightmap" : "png16";
        _info.scheme = TilingScheme::geographic();
        _info.minimumLevel = source.minimumLevel;
        _info.maximumLevel = source.maximumLevel;
        _info.extent = source.extent;
        _info.attribution = source.attribution;
        _info.gridSize = format == TileFormat::QuantizedMesh ? 0 : format == TileFormat::Heightmap ? 65 : source.tileWidth;
        if (_layer) {
            if (!_layer->attribution.empty()) {
                _info.attribution = _layer->attribution;
            }
            _info.minimumLevel = std::max(_info.minimumLevel, _layer->minimumLevel);
            _info.maximumLevel = std::min(_info.maximumLevel, _layer->maximumLevel);
        }
    }

    const TerrainSourceInfo& info() const noexcept override { return _info; }

    std::optional<double> geometricError(const TileKey& key) const override
    {
        return _layer ? _layer->geometricError(key) : std::nullopt;
    }

    bool hasTile(const TileKey& key) const override
    {
        if (!detail::sourceHasTile(_tiles->info(), key) || key.level < _info.minimumLevel || key.level > _info.maximumLevel) {
            return false;
        }
        if (!_layer || !_layer->hasAvailable) {
            return true;
        }
        if (key.level < _layer->available.size() || !_layer->metadataAvailability) {
            return layerHasTile(*_layer, key);
        }
        const std::shared_lock lock(_learnedMutex);
        if (key.level < _learned.size()) {
            const LevelAvailability& level = _learned[key.level];
            if (std::any_of(level.begin(), level.end(), [&](const TileRectangle& r) { return r.contains(key.x, key.y); })) {
                return true;
            }
        }
        // The tile whose metadata lists this one's level: tiles every metadataAvailability levels
        // list the levels below them. Until it has loaded, the answer is not known: yes.
        const std::uint32_t every = *_layer->metadataAvailability;
        const std::uint32_t carrierLevel = (key.level - 1) / every * every;
        return _metadataLoaded.count(key.ancestor(carrierLevel)) == 0;
    }

    TerrainFetch load(const TileKey& key) override
    {
        if (!hasTile(key)) {
            return missing();
        }
        const TileFetch fetched = _tiles->fetch(key);
        if (fetched.status == TileFetch::Status::Missing) {
            return missing();
        }
        const std::string location = _tiles->locate(key);
        if (fetched.status != TileFetch::Status::Ok) {
            return failed(fetched.message.empty() ? location + ": cannot be read" : fetched.message);
        }
        TerrainFetch result;
        try {
            switch (_format) {
            case TileFormat::QuantizedMesh: result.tile = decodeQuantizedMesh(fetched.bytes, key, location); break;
            case TileFormat::Heightmap: result.tile = decodeHeightmapTerrain(fetched.bytes, key, location); break;
            case TileFormat::Png16: {
                HeightGrid grid = decodeHeightImage(fetched.bytes, HeightEncoding::Png16, location);
                if (grid.width != _info.gridSize || grid.height != _info.gridSize) {
                    return failed(cutForMessage(location) + ": a tile of " + std::to_string(grid.width) + " x " +
                                  std::to_string(grid.height) + " samples in a set of " + std::to_string(_info.gridSize) +
                                  " x " + std::to_string(_info.gridSize));
                }
                result.tile.key = key;
                result.tile.size = grid.width;
                result.tile.heights = std::move(grid.heights);
                setRange(result.tile);
                break;
            }
            }
        } catch (const Error& error) {
            return failed(error.what());
        }
        if (_format != TileFormat::Heightmap) {
            result.tile.childMask = childMaskOf(*this, key);
        }
        if (_layer) {
            result.tile.geometricError = _layer->geometricError(key);
        }
        if (!result.tile.availableBelow.empty()) {
            learn(key, result.tile.availableBelow);
        }
        result.status = TerrainFetch::Status::Ok;
        return result;
    }

private:
    void learn(const TileKey& key, const std::vector<LevelAvailability>& below)
    {
        const std::unique_lock lock(_learnedMutex);
        _metadataLoaded.insert(key);
        for (std::size_t i = 0; i < below.size(); ++i) {
            const std::size_t level = key.level + 1 + i;
            if (_learned.size() <= level) {
                _learned.resize(level + 1);
            }
            _learned[level].insert(_learned[level].end(), below[i].begin(), below[i].end());
        }
    }

    std::unique_ptr<TileSource> _tiles;
    TileFormat _format;
    std::optional<TerrainLayer> _layer;
    TerrainSourceInfo _info;
    mutable std::shared_mutex _learnedMutex;
    std::vector<LevelAvailability> _learned;   ///< from metadata extensions, by level
    std::set<TileKey> _metadataLoaded;         ///< tiles whose metadata has been learned
};

// ---- Height fields sampled into grids ------------------------------------------------------------

/// A source whose tiles are its height field point-sampled at each grid sample (see
/// terrainGridPosition): the same sample gives the same height in every tile that has it.
class GridTerrainSource : public TerrainSource {
public:
    const TerrainSourceInfo& info() const noexcept override { return _info; }

    bool hasTile(const TileKey& key) const override
    {
        return TilingScheme::geographic().isValid(key) && key.level >= _info.minimumLevel &&
               key.level <= _info.maximumLevel && tileOverlaps(key, _info.extent) && covers(key);
    }

    TerrainFetch load(const TileKey& key) override
    {
        if (!hasTile(key)) {
            return missing();
        }
        TerrainFetch result;
        TerrainTileData& tile = result.tile;
        tile.key = key;
        tile.size = _info.gridSize;
        // With a margin of one sample, for normals that see across the tile's edges: tiles sharing
        // an edge then shade it alike.
        const std::vector<Geodetic2D> positions = detail::gridPositionsWithMargin(key, tile.size);
        std::vector<float> withMargin(positions.size(), kNaN);
        try {
            if (!sample(key, positions, withMargin)) {
                return missing();
            }
        } catch (const Error& error) {
            return failed("tile " + tileName(key) + " of " + cutForMessage(_info.name) + ": " + error.what());
        }
        for (float& h : withMargin) {
            if (std::isnan(h)) {
                h = static_cast<float>(_noDataHeight);
            }
        }
        tile.heights = detail::withoutMargin(withMargin, tile.size);
        tile.normals = detail::gridNormals(key, tile.size, withMargin, Ellipsoid::wgs84());
        setRange(tile);
        tile.childMask = childMaskOf(*this, key);
        result.status = TerrainFetch::Status::Ok;
        return result;
    }

protected:
    GridTerrainSource(const TerrainSourceOptions& options) : _noDataHeight(options.noDataHeight)
    {
        if (!isTerrainGridSize(options.gridSize)) {
            throw Error("a terrain grid of " + std::to_string(options.gridSize) + " samples a side (2^k + 1, 3 to 1025)");
        }
        _info.gridSize = options.gridSize;
    }

    /// Heights at the positions into `heights` (NaN where there is no data); false when the
    /// source has nothing for the tile (Missing). Throws orbis::Error for a read that fails.
    virtual bool sample(const TileKey& key, std::span<const Geodetic2D> positions, std::span<float> heights) = 0;
    /// Whether the source has data in the tile, beyond its extent (a folder of .hgt cells).
    virtual bool covers(const TileKey&) const { return true; }

    TerrainSourceInfo _info;
    double _noDataHeight = 0.0;
};

/// The deepest level of a resampled source: from its resolution unless told.
std::uint32_t deepestLevel(const TerrainSourceOptions& options, double degreesPerSample)
{
    if (options.maximumLevel) {
        return std::min(*options.maximumLevel, kMaximumTileLevel);
    }
    return terrainLevelForResolution(degreesPerSample, options.gridSize);
}

// ---- One DEM through GDAL ------------------------------------------------------------------------

class DemTerrainSource final : public GridTerrainSource {
public:
    DemTerrainSource(const std::filesystem::path& path, const TerrainSourceOptions& options) : GridTerrainSource(options)
    {
        _description = detail::describeDem(path);
        _info.name = path.string();
        _info.format = "gdal";
        _info.extent = _description->footprint.extent;
        _info.maximumLevel = deepestLevel(options, _description->footprint.degreesPerPixel);
        _info.attribution = options.tiles.attribution;
        _idle.push_back(std::make_unique<detail::DemReader>(_description)); // fails now rather than per tile
    }

protected:
    bool sample(const TileKey&, std::span<const Geodetic2D> positions, std::span<float> heights) override
    {
        std::unique_ptr<detail::DemReader> reader;
        {
            const std::lock_guard lock(_mutex);
            if (!_idle.empty()) {
                reader = std::move(_idle.back());
                _idle.pop_back();
            }
        }
        if (!reader) {
            reader = std::make_unique<detail::DemReader>(_description);
        }
        reader->sample(positions, heights);
        const std::lock_guard lock(_mutex);
        _idle.push_back(std::move(reader));
        return true;
    }

private:
    std::shared_ptr<const detail::DemDescription> _description;
    std::mutex _mutex;
    std::vector<std::unique_ptr<detail::DemReader>> _idle; ///< one per thread that has loaded, reused
};

// ---- SRTM .hgt cells -----------------------------------------------------------------------------

/// Decoded grids kept for reuse, the least recently used dropped beyond a byte budget.
template <class Key, class Value, class Hash = std::hash<Key>>
class SharedLruCache {
public:
    explicit SharedLruCache(std::size_t maximumBytes) : _maximumBytes(maximumBytes) {}

    std::shared_ptr<const Value> find(const Key& key)
    {
        const std::lock_guard lock(_mutex);
        const auto found = _entries.find(key);
        if (found == _entries.end()) {
            return nullptr;
        }
        _order.splice(_order.begin(), _order, found->second.position);
        return found->second.value;
    }

    void insert(const Key& key, std::shared_ptr<const Value> value, std::size_t bytes)
    {
        const std::lock_guard lock(_mutex);
        if (_entries.count(key) != 0) {
            return;
        }
        _order.push_front(key);
        _entries[key] = {std::move(value), bytes, _order.begin()};
        _bytes += bytes;
        while (_bytes > _maximumBytes && _order.size() > 1) {
            const auto last = _entries.find(_order.back());
            _order.pop_back();
            if (last != _entries.end()) {
                _bytes -= last->second.bytes;
                _entries.erase(last);
            }
        }
    }

private:
    struct Entry {
        std::shared_ptr<const Value> value;
        std::size_t bytes = 0;
        typename std::list<Key>::iterator position;
    };
    std::mutex _mutex;
    std::size_t _maximumBytes;
    std::size_t _bytes = 0;
    std::list<Key> _order;
    std::unordered_map<Key, Entry, Hash> _entries;
};

struct CellHash {
    std::size_t operator()(const std::pair<int, int>& cell) const noexcept
    {
        const auto packed = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(cell.first)) << 32) |
                            static_cast<std::uint32_t>(cell.second);
        return static_cast<std::size_t>(packed * 0x9e3779b97f4a7c15ULL);
    }
};

/// The most .hgt files a folder may hold: the whole globe at 1 degree.
constexpr std::size_t kMaximumHgtFiles = 360 * 180;

class HgtTerrainSource final : public GridTerrainSource {
public:
    HgtTerrainSource(const std::filesystem::path& path, const TerrainSourceOptions& options)
        : GridTerrainSource(options), _cache(std::size_t{512} << 20)
    {
        const std::string where = cutForMessage(path.string());
        std::error_code error;
        std::vector<std::filesystem::path> files;
        if (std::filesystem::is_directory(path, error)) {
            std::size_t entries = 0;
            for (auto it = std::filesystem::directory_iterator(path, error); !error && it != std::filesystem::directory_iterator();
                 it.increment(error)) {
                if (++entries > 4 * kMaximumHgtFiles) {
                    throw Error(where + ": more than " + std::to_string(4 * kMaximumHgtFiles) + " entries in the folder");
                }
                if (hgtCorner(it->path().filename().string())) {
                    files.push_back(it->path());
                }
            }
            if (error) {
                throw Error(where + ": cannot list the folder: " + error.message());
            }
        } else {
            files.push_back(path);
        }
        double finest = 3.0 / 3600.0;
        int west = 180, east = -180, south = 90, north = -90;
        for (const std::filesystem::path& file : files) {
            const auto corner = hgtCorner(file.filename().string());
            if (!corner) {
                continue;
            }
            const auto bytes = std::filesystem::file_size(file, error);
            if (error || (bytes != 2u * 1201 * 1201 && bytes != 2u * 3601 * 3601)) {
                throw Error(cutForMessage(file.string()) + ": " + (error ? error.message() : std::to_string(bytes) + " bytes") +
                            ", not an SRTM .hgt file of 1201 x 1201 or 3601 x 3601 samples");
            }
            if (bytes == 2u * 3601 * 3601) {
                finest = 1.0 / 3600.0;
            }
            _cells[*corner] = file;
            west = std::min(west, corner->first);
            east = std::max(east, corner->first + 1);
            south = std::min(south, corner->second);
            north = std::max(north, corner->second + 1);
        }
        if (_cells.empty()) {
            throw Error(where + ": no SRTM .hgt files (named like N37W123.hgt)");
        }
        _info.name = path.string();
        _info.format = "hgt";
        _info.extent = GeodeticExtent::fromDegrees(west, south, east, north);
        _info.maximumLevel = deepestLevel(options, finest);
        _info.attribution = options.tiles.attribution;
    }

protected:
    bool covers(const TileKey& key) const override
    {
        const GeodeticExtent tile = TilingScheme::geographic().tileExtent(key);
        const int west = static_cast<int>(std::floor(toDegrees(tile.west)));
        const int east = static_cast<int>(std::ceil(toDegrees(tile.east)));
        const int south = static_cast<int>(std::floor(toDegrees(tile.south)));
        const int north = static_cast<int>(std::ceil(toDegrees(tile.north)));
        if (static_cast<std::size_t>(east - west) * static_cast<std::size_t>(north - south) > _cells.size()) {
            return std::any_of(_cells.begin(), _cells.end(), [&](const auto& cell) {
                return cell.first.first < east && cell.first.first + 1 > west && cell.first.second < north &&
                       cell.first.second + 1 > south;
            });
        }
        for (int lon = west; lon < east; ++lon) {
            for (int lat = south; lat < north; ++lat) {
                if (_cells.count({lon, lat})) {
                    return true;
                }
            }
        }
        return false;
    }

    bool sample(const TileKey&, std::span<const Geodetic2D> positions, std::span<float> heights) override
    {
        bool any = false;
        std::pair<int, int> current{std::numeric_limits<int>::min(), 0};
        std::shared_ptr<const HeightGrid> grid;
        for (std::size_t i = 0; i < positions.size(); ++i) {
            double longitude = toDegrees(positions[i].longitude);
            const double latitude = toDegrees(positions[i].latitude);
            if (longitude >= 180.0) {
                longitude -= 360.0;
            }
            // A sample on a cell's edge is in both cells' files: the cell west and south of it is
            // used only where the other does not exist.
            int west = static_cast<int>(std::floor(longitude));
            int south = std::min(static_cast<int>(std::floor(latitude)), 89);
            if (!_cells.count({west, south}) && longitude == west && _cells.count({west - 1, south})) {
                --west;
            }
            if (!_cells.count({west, south}) && latitude == south && _cells.count({west, south - 1})) {
                --south;
            }
            const std::pair cell(west, south);
            if (cell != current) {
                current = cell;
                grid = cellGrid(cell);
            }
            if (!grid) {
                continue;
            }
            any = true;
            const int n = grid->width;
            const double column = (longitude - west) * (n - 1);
            const double row = (south + 1 - latitude) * (n - 1);
            const int c0 = std::clamp(static_cast<int>(std::floor(column)), 0, n - 2);
            const int r0 = std::clamp(static_cast<int>(std::floor(row)), 0, n - 2);
            const double fx = column - c0;
            const double fy = row - r0;
            double sum = 0.0;
            double weights = 0.0;
            for (int corner = 0; corner < 4; ++corner) {
                const int dx = corner & 1;
                const int dy = corner >> 1;
                const double weight = (dx ? fx : 1.0 - fx) * (dy ? fy : 1.0 - fy);
                const float value = grid->at(c0 + dx, r0 + dy);
                if (weight > 0.0 && !std::isnan(value)) {
                    sum += weight * static_cast<double>(value);
                    weights += weight;
                }
            }
            if (weights > 0.0) {
                heights[i] = static_cast<float>(sum / weights);
            }
        }
        return any;
    }

private:
    std::shared_ptr<const HeightGrid> cellGrid(const std::pair<int, int>& cell)
    {
        const auto found = _cells.find(cell);
        if (found == _cells.end()) {
            return nullptr;
        }
        if (auto cached = _cache.find(cell)) {
            return cached;
        }
        const std::vector<std::uint8_t> bytes = readFileBytes(found->second, ".hgt file", std::size_t{2} * 3601 * 3601);
        auto grid = std::make_shared<const HeightGrid>(decodeHgt(bytes, found->second.string()));
        _cache.insert(cell, grid, grid->heights.size() * sizeof(float));
        return grid;
    }

    std::map<std::pair<int, int>, std::filesystem::path> _cells; ///< south-west corner (lon, lat) to file
    SharedLruCache<std::pair<int, int>, HeightGrid, CellHash> _cache;
};

// ---- Pyramids of height images resampled into the geographic grid --------------------------------

class ImagePyramidTerrainSource final : public GridTerrainSource {
public:
    ImagePyramidTerrainSource(std::unique_ptr<TileSource> tiles, HeightEncoding encoding, const TerrainSourceOptions& options)
        : GridTerrainSource(options), _tiles(std::move(tiles)), _encoding(encoding), _cache(std::size_t{64} << 20)
    {
        const TileSourceInfo& source = _tiles->info();
        _info.name = source.name;
        _info.format = encoding == HeightEncoding::TerrainRgb ? "terrain-rgb" : encoding == HeightEncoding::Terrarium ? "terrarium" : "png16";
        _info.extent = source.extent;
        _info.attribution = source.attribution;
        _info.maximumLevel = deepestLevel(options, sourceSpacing(source.maximumLevel));
        if (source.scheme.projection() == TilingProjection::WebMercator) {
            // The poles beyond the Mercator limit take its last rows: the extent is the globe's.
            const GeodeticExtent limits = source.scheme.coverage();
            if (_info.extent.north >= limits.north) {
                _info.extent.north = kHalfPi;
            }
            if (_info.extent.south <= limits.south) {
                _info.extent.south = -kHalfPi;
            }
        }
    }

protected:
    bool sample(const TileKey& key, std::span<const Geodetic2D> positions, std::span<float> heights) override
    {
        const TileSourceInfo& source = _tiles->info();
        const TilingScheme& scheme = source.scheme;
        const std::uint32_t level = sourceLevel(key.level);
        const bool mercator = scheme.projection() == TilingProjection::WebMercator;
        const double pixelsX = static_cast<double>(scheme.tilesX(level)) * source.tileWidth;
        const double pixelsY = static_cast<double>(scheme.tilesY(level)) * source.tileHeight;
        const auto widthX = static_cast<std::int64_t>(pixelsX);
        const auto heightY = static_cast<std::int64_t>(pixelsY);
        // Global pixel-centre coordinates of each sample, rows from the north.
        std::vector<double> columns(positions.size());
        std::vector<double> rows(positions.size());
        std::set<std::pair<std::int64_t, std::int64_t>> needed; // tile column, tile row from the north
        for (std::size_t i = 0; i < positions.size(); ++i) {
            const Geodetic2D& g = positions[i];
            columns[i] = (g.longitude + kPi) / kTwoPi * pixelsX - 0.5;
            if (mercator) {
                const double latitude = std::clamp(g.latitude, -TilingScheme::kMaximumMercatorLatitude,
                                                   TilingScheme::kMaximumMercatorLatitude);
                rows[i] = (kPi - TilingScheme::mercatorY(latitude)) / kTwoPi * pixelsY - 0.5;
            } else {
                rows[i] = (kHalfPi - g.latitude) / kPi * pixelsY - 0.5;
            }
            const auto c0 = static_cast<std::int64_t>(std::floor(columns[i]));
            const auto r0 = static_cast<std::int64_t>(std::floor(rows[i]));
            for (int corner = 0; corner < 4; ++corner) {
                const std::int64_t c = ((c0 + (corner & 1)) % widthX + widthX) % widthX;
                const std::int64_t r = std::clamp<std::int64_t>(r0 + (corner >> 1), 0, heightY - 1);
                needed.insert({c / source.tileWidth, r / source.tileHeight});
            }
        }
        std::map<std::pair<std::int64_t, std::int64_t>, std::shared_ptr<const HeightGrid>> grids;
        bool any = false;
        for (const auto& [tileColumn, tileRow] : needed) {
            const auto rowInScheme = static_cast<std::uint32_t>(mercator ? tileRow : scheme.tilesY(level) - 1 - tileRow);
            const TileKey sourceKey{level, static_cast<std::uint32_t>(tileColumn), rowInScheme};
            auto grid = fetch(sourceKey);
            any = any || grid != nullptr;
            grids[{tileColumn, tileRow}] = std::move(grid);
        }
        if (!any) {
            return false;
        }
        for (std::size_t i = 0; i < positions.size(); ++i) {
            const double c0 = std::floor(columns[i]);
            const double r0 = std::floor(rows[i]);
            const double fx = columns[i] - c0;
            const double fy = rows[i] - r0;
            double sum = 0.0;
            double weights = 0.0;
            for (int corner = 0; corner < 4; ++corner) {
                const int dx = corner & 1;
                const int dy = corner >> 1;
                const double weight = (dx ? fx : 1.0 - fx) * (dy ? fy : 1.0 - fy);
                if (weight <= 0.0) {
                    continue;
                }
                const std::int64_t c = ((static_cast<std::int64_t>(c0) + dx) % widthX + widthX) % widthX;
                const std::int64_t r = std::clamp<std::int64_t>(static_cast<std::int64_t>(r0) + dy, 0, heightY - 1);
                const auto& grid = grids[{c / source.tileWidth, r / source.tileHeight}];
                if (!grid) {
                    continue;
                }
                const float value = grid->at(static_cast<int>(c % source.tileWidth), static_cast<int>(r % source.tileHeight));
                if (!std::isnan(value)) {
                    sum += weight * static_cast<double>(value);
                    weights += weight;
                }
            }
            if (weights > 0.0) {
                heights[i] = static_cast<float>(sum / weights);
            }
        }
        return true;
    }

private:
    /// Degrees of longitude per pixel at a level of the source.
    double sourceSpacing(std::uint32_t level) const
    {
        const TileSourceInfo& source = _tiles->info();
        return 360.0 / source.scheme.tilesX(level) / source.tileWidth;
    }

    /// The source level whose pixels are about as fine as a grid tile's samples at `level`.
    std::uint32_t sourceLevel(std::uint32_t level) const
    {
        const TileSourceInfo& source = _tiles->info();
        const double wanted = 180.0 / static_cast<double>(std::uint64_t{1} << level) / (_info.gridSize - 1);
        for (std::uint32_t candidate = source.minimumLevel; candidate < source.maximumLevel; ++candidate) {
            if (sourceSpacing(candidate) <= 1.1 * wanted) {
                return candidate;
            }
        }
        return source.maximumLevel;
    }

    /// A source tile's heights, or null where the source has none; throws for one that fails.
    std::shared_ptr<const HeightGrid> fetch(const TileKey& key)
    {
        const std::pair cacheKey(key.level, (std::uint64_t{key.x} << 32) | key.y);
        if (auto cached = _cache.find(cacheKey)) {
            return cached->width == 0 ? nullptr : cached;
        }
        const TileFetch fetched = _tiles->fetch(key);
        std::shared_ptr<const HeightGrid> grid;
        if (fetched.status == TileFetch::Status::Missing) {
            grid = std::make_shared<const HeightGrid>(); // known missing: width 0
        } else if (fetched.status != TileFetch::Status::Ok) {
            throw Error(fetched.message);
        } else {
            const std::string location = _tiles->locate(key);
            HeightGrid decoded = decodeHeightImage(fetched.bytes, _encoding, location);
            const TileSourceInfo& source = _tiles->info();
            if (decoded.width != source.tileWidth || decoded.height != source.tileHeight) {
                throw Error(cutForMessage(location) + ": a tile of " + std::to_string(decoded.width) + " x " +
                            std::to_string(decoded.height) + " pixels in a set of " + std::to_string(source.tileWidth) +
                            " x " + std::to_string(source.tileHeight));
            }
            grid = std::make_shared<const HeightGrid>(std::move(decoded));
        }
        _cache.insert(cacheKey, grid, grid->heights.size() * sizeof(float) + 64);
        return grid->width == 0 ? nullptr : grid;
    }

    struct KeyHash {
        std::size_t operator()(const std::pair<std::uint32_t, std::uint64_t>& key) const noexcept
        {
            return std::hash<std::uint64_t>()(key.second * 31 + key.first);
        }
    };

    std::unique_ptr<TileSource> _tiles;
    HeightEncoding _encoding;
    SharedLruCache<std::pair<std::uint32_t, std::uint64_t>, HeightGrid, KeyHash> _cache;
};

// ---- Opening -------------------------------------------------------------------------------------

const char* const kFormatNames[] = {"quantized-mesh", "heightmap", "png16", "terrain-rgb", "terrarium", "hgt", "gdal"};

bool endsWithCaseless(std::string_view text, std::string_view suffix)
{
    if (text.size() < suffix.size()) {
        return false;
    }
    for (std::size_t i = 0; i < suffix.size(); ++i) {
        char c = text[text.size() - suffix.size() + i];
        c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
        if (c != suffix[i]) {
            return false;
        }
    }
    return true;
}

/// The terrain format a tile set's own format name stands for ("terrain", "quantized-mesh-1.0",
/// "heightmap-1.0", "png", "image/png", ...); empty when it names none.
std::string formatOfTiles(const std::string& name)
{
    std::string lower = name;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](char c) { return static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c); });
    if (lower == "terrain" || lower.starts_with("quantized-mesh") || lower == "application/vnd.quantized-mesh") {
        return "quantized-mesh";
    }
    if (lower.starts_with("heightmap")) {
        return "heightmap";
    }
    if (lower == "png" || lower == "image/png") {
        return "png16";
    }
    return "";
}

bool isPowerOfTwoPlusOne(int size)
{
    return size >= 3 && ((size - 1) & (size - 2)) == 0;
}

std::unique_ptr<TerrainSource> fromTiles(std::unique_ptr<TileSource> tiles, std::string format,
                                         const TerrainSourceOptions& options, std::optional<TerrainLayer> layer)
{
    const TileSourceInfo& info = tiles->info();
    const std::string where = cutForMessage(info.name);
    if (format.empty()) {
        format = formatOfTiles(info.format);
    }
    if (format.empty()) {
        throw Error(where + ": tiles of format \"" + cutForMessage(info.format, 20) +
                    "\": name the terrain format (" + kTerrainFormats + ")");
    }
    if (format == "quantized-mesh" || format == "heightmap") {
        if (info.scheme.projection() != TilingProjection::Geographic) {
            throw Error(where + ": " + format + " tiles must be in the geographic scheme (EPSG:4326), not Web Mercator");
        }
        return std::make_unique<TiledTerrainSource>(std::move(tiles),
                                                    format == "heightmap" ? TileFormat::Heightmap : TileFormat::QuantizedMesh,
                                                    std::move(layer));
    }
    if (format == "png16" && info.scheme.projection() == TilingProjection::Geographic && info.tileWidth == info.tileHeight &&
        isPowerOfTwoPlusOne(info.tileWidth) && info.tileWidth <= 1025) {
        return std::make_unique<TiledTerrainSource>(std::move(tiles), TileFormat::Png16, std::move(layer));
    }
    const HeightEncoding encoding = format == "terrain-rgb" ? HeightEncoding::TerrainRgb
                                    : format == "terrarium" ? HeightEncoding::Terrarium
                                    : format == "png16"     ? HeightEncoding::Png16
                                                            : throw Error(where + ": " + format + " is not a format of tiles");
    return std::make_unique<ImagePyramidTerrainSource>(std::move(tiles), encoding, options);
}

/// Tile-source options for a terrain format: quantized-mesh and heightmap tiles are geographic.
TileSourceOptions tileOptionsFor(const TerrainSourceOptions& options, const std::string& format)
{
    TileSourceOptions tiles = options.tiles;
    if ((format == "quantized-mesh" || format == "heightmap") && !tiles.scheme) {
        tiles.scheme = TilingScheme::geographic();
    }
    if (options.requestExtensions && (format.empty() || format == "quantized-mesh")) {
        tiles.http.headers.push_back("Accept: application/vnd.quantized-mesh;extensions=octvertexnormals-watermask-metadata,"
                                     "application/octet-stream;q=0.9,*/*;q=0.01");
    }
    return tiles;
}

std::unique_ptr<TerrainSource> fromLayer(const std::string& location, const TerrainSourceOptions& options)
{
    detail::LayerTiles opened = detail::openLayerTiles(location, tileOptionsFor(options, options.format));
    const std::string format = opened.layer.format == "heightmap-1.0" ? "heightmap" : "quantized-mesh";
    if (!options.format.empty() && options.format != format) {
        throw Error(cutForMessage(location) + ": layer.json says " + opened.layer.format + ", not " + options.format);
    }
    return fromTiles(std::move(opened.tiles), format, options, std::move(opened.layer));
}

std::unique_ptr<TerrainSource> fromMBTiles(const std::string& path, const TerrainSourceOptions& options)
{
    // Read once for the format its metadata names, then with the scheme that format needs.
    std::string format = options.format;
    if (format.empty()) {
        format = formatOfTiles(openTileSource(path, options.tiles)->info().format);
    }
    std::unique_ptr<TileSource> tiles = openTileSource(path, tileOptionsFor(options, format));
    std::optional<TerrainLayer> layer;
    if (!tiles->info().metadataJson.empty()) {
        TerrainLayer parsed = parseTerrainLayer(tiles->info().metadataJson, path + " (metadata json)");
        if (parsed.hasAvailable || !parsed.geometricErrors.empty()) {
            parsed.minimumLevel = tiles->info().minimumLevel;
            parsed.maximumLevel = tiles->info().maximumLevel;
            layer = std::move(parsed);
        }
    }
    return fromTiles(std::move(tiles), format, options, std::move(layer));
}

} // namespace

Geodetic2D terrainGridPosition(const TileKey& key, int size, int column, int row) noexcept
{
    const int k = log2Exact(size - 1);
    const std::int64_t steps = size - 1;
    const auto gx = static_cast<double>(std::int64_t{key.x} * steps + column);
    const auto gy = static_cast<double>(std::int64_t{key.y} * steps + (size - 1 - row));
    // The same exact dyadic fractions as TilingScheme's edges, scaled by pi once.
    const int shift = static_cast<int>(key.level) + k;
    return {kPi * (std::ldexp(gx, -shift) - 1.0), kHalfPi * (std::ldexp(gy, 1 - shift) - 1.0)};
}

std::uint32_t terrainLevelForResolution(double degreesPerSample, int gridSize) noexcept
{
    for (std::uint32_t level = 0; level < kMaximumTileLevel; ++level) {
        const double spacing = 180.0 / static_cast<double>(std::uint64_t{1} << level) / (gridSize - 1);
        if (spacing <= 1.1 * degreesPerSample) {
            return level;
        }
    }
    return kMaximumTileLevel;
}

bool isTerrainGridSize(int size) noexcept
{
    return size <= 1025 && isPowerOfTwoPlusOne(size);
}

std::unique_ptr<TerrainSource> openTerrainSource(const std::string& pathOrUrl, const TerrainSourceOptions& options)
{
    const std::string where = cutForMessage(pathOrUrl);
    if (pathOrUrl.empty()) {
        throw Error("an empty terrain source path");
    }
    if (pathOrUrl.find('\0') != std::string::npos) {
        throw Error(where + ": a NUL character in a terrain source path");
    }
    const std::string& format = options.format;
    if (!format.empty() && std::find(std::begin(kFormatNames), std::end(kFormatNames), format) == std::end(kFormatNames)) {
        throw Error(where + ": unknown terrain format \"" + cutForMessage(format, 40) + "\" (" + kTerrainFormats + ")");
    }
    if (!isTerrainGridSize(options.gridSize)) {
        throw Error(where + ": a terrain grid of " + std::to_string(options.gridSize) +
                    " samples a side (2^k + 1, 3 to 1025)");
    }
    const std::string source = pathOrUrl.starts_with("file://") ? pathOrUrl.substr(7) : pathOrUrl;
    const bool http = detail::isHttpUrl(source);
    if (source.find('{') != std::string::npos) {
        std::string templateFormat = format;
        if (templateFormat.empty()) {
            const std::string path = source.substr(0, source.find('?'));
            templateFormat = endsWithCaseless(path, ".terrain") ? "quantized-mesh"
                             : endsWithCaseless(path, ".png")   ? "png16"
                                                                : "";
        }
        return fromTiles(openTileSource(source, tileOptionsFor(options, templateFormat)), templateFormat, options, std::nullopt);
    }
    if (http) {
        if (endsWithCaseless(source, ".xml") || format == "png16" || format == "terrain-rgb" || format == "terrarium") {
            return fromTiles(openTileSource(source, tileOptionsFor(options, format)), format, options, std::nullopt);
        }
        return fromLayer(source, options);
    }
    std::error_code error;
    const std::filesystem::path path(source);
    const auto status = std::filesystem::status(path, error);
    if (error || !std::filesystem::exists(status)) {
        throw Error(where + ": no such file or folder");
    }
    if (detail::looksLikeLayer(source)) {
        return fromLayer(source, options);
    }
    if (std::filesystem::is_directory(status)) {
        if (std::filesystem::is_regular_file(path / "tilemapresource.xml", error)) {
            return fromTiles(openTileSource(source, tileOptionsFor(options, format)), format, options, std::nullopt);
        }
        if (format.empty() || format == "hgt") {
            return std::make_unique<HgtTerrainSource>(path, options);
        }
        throw Error(where + ": a folder without layer.json or tilemapresource.xml");
    }
    if (endsWithCaseless(source, ".xml")) {
        return fromTiles(openTileSource(source, tileOptionsFor(options, format)), format, options, std::nullopt);
    }
    if (endsWithCaseless(source, ".mbtiles")) {
        return fromMBTiles(source, options);
    }
    if (format == "hgt" || (format.empty() && hgtCorner(path.filename().string()))) {
        return std::make_unique<HgtTerrainSource>(path, options);
    }
    if (!format.empty() && format != "gdal") {
        throw Error(where + ": a single file cannot hold " + format + " tiles (give its folder, layer.json or .mbtiles)");
    }
    return std::make_unique<DemTerrainSource>(path, options);
}

} // namespace orbis::world
