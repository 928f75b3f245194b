#include "TileSources.h"

#include "orbis/world/FileAccess.h"
#include "orbis/world/ImageCodec.h"
#include "orbis/world/TerrainLayer.h"

#include <orbis/core/Error.h>
#include <orbis/core/Math.h>

#include <sqlite3.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <condition_variable>
#include <map>
#include <mutex>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace orbis::world::detail {

namespace {

/// The first bytes of every SQLite 3 database.
constexpr char kSqliteMagic[] = "SQLite format 3";

/// Refuses anything but a regular file that starts as an SQLite database, before SQLite opens it
/// (SQLite would block on a named pipe, and report a text file only as "file is not a database").
void checkDatabaseFile(const std::string& path)
{
    const std::string where = cutForMessage(path);
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        throw Error(where + ": cannot open the MBTiles file: " + std::strerror(errno));
    }
    struct stat status {};
    char header[16] = {};
    const bool regular = ::fstat(fd, &status) == 0 && S_ISREG(status.st_mode);
    const ssize_t count = regular ? ::read(fd, header, sizeof header) : 0;
    ::close(fd);
    if (!regular) {
        throw Error(where + ": the MBTiles path is not a regular file");
    }
    if (count != static_cast<ssize_t>(sizeof header) || std::memcmp(header, kSqliteMagic, sizeof header) != 0) {
        throw Error(where + ": not an MBTiles file (no SQLite database header), not a TMS folder and not a template");
    }
}

class Statement {
public:
    Statement(sqlite3* database, const char* sql) { _result = sqlite3_prepare_v2(database, sql, -1, &_statement, nullptr); }
    ~Statement() { sqlite3_finalize(_statement); }
    Statement(const Statement&) = delete;
    Statement& operator=(const Statement&) = delete;
    int prepared() const noexcept { return _result; }
    sqlite3_stmt* get() const noexcept { return _statement; }

private:
    sqlite3_stmt* _statement = nullptr;
    int _result = SQLITE_ERROR;
};

class MBTilesSource final : public TileSource {
public:
    MBTilesSource(const std::string& path, const TileSourceOptions& options)
        : _path(path), _maximumBytes(options.maximumTileBytes)
    {
        checkDatabaseFile(path);
        sqlite3* database = openConnection();
        try {
            readMetadata(database, options);
        } catch (...) {
            sqlite3_close(database);
            throw;
        }
        _idle.push_back(database);
        _open = 1;
    }

    ~MBTilesSource() override
    {
        for (sqlite3* database : _idle) {
            sqlite3_close(database);
        }
    }

    const TileSourceInfo& info() const noexcept override { return _info; }

    TileFetch fetch(const TileKey& key) override
    {
        TileFetch result;
        if (!sourceHasTile(_info, key)) {
            result.status = TileFetch::Status::Missing;
            return result;
        }
        sqlite3* database = nullptr;
        try {
            database = acquire();
        } catch (const Error& error) {
            result.message = error.what();
            return result;
        }
        {
            Statement query(database, "SELECT tile_data FROM tiles WHERE zoom_level = ?1 AND tile_column = ?2 AND tile_row = ?3");
            if (query.prepared() != SQLITE_OK) {
                result.message = locate(key) + ": " + sqlite3_errmsg(database);
            } else {
                sqlite3_bind_int64(query.get(), 1, key.level);
                sqlite3_bind_int64(query.get(), 2, key.x);
                sqlite3_bind_int64(query.get(), 3, rowFromSouth(key));
                const int step = sqlite3_step(query.get());
                if (step == SQLITE_DONE) {
                    result.status = TileFetch::Status::Missing;
                } else if (step != SQLITE_ROW) {
                    result.message = locate(key) + ": " + sqlite3_errmsg(database);
                } else if (sqlite3_column_type(query.get(), 0) != SQLITE_BLOB && sqlite3_column_type(query.get(), 0) != SQLITE_NULL) {
                    result.message = locate(key) + ": tile_data is not a blob";
                } else {
                    const int size = sqlite3_column_bytes(query.get(), 0);
                    const auto* data = static_cast<const std::uint8_t*>(sqlite3_column_blob(query.get(), 0));
                    if (static_cast<std::size_t>(size) > _maximumBytes) {
                        result.message = locate(key) + ": a tile of " + std::to_string(size) + " bytes, more than the " +
                                         std::to_string(_maximumBytes) + " allowed";
                    } else if (size == 0 || !data) {
                        result.status = TileFetch::Status::Missing; // an empty row holds no tile
                    } else {
                        result.status = TileFetch::Status::Ok;
                        result.bytes.assign(data, data + size);
                    }
                }
            }
        }
        release(database);
        return result;
    }

    std::string locate(const TileKey& key) const override
    {
        return cutForMessage(_path) + ": tile " + std::to_string(key.level) + "/" + std::to_string(key.x) + "/" +
               std::to_string(key.y) + " (tile_row " + std::to_string(rowFromSouth(key)) + ")";
    }

private:
    /// MBTiles counts rows from the south (TMS), whatever the TileKey's scheme counts from.
    std::uint32_t rowFromSouth(const TileKey& key) const
    {
        return _info.scheme.projection() == TilingProjection::Geographic ? key.y
                                                                          : _info.scheme.tilesY(key.level) - 1 - key.y;
    }

    sqlite3* openConnection() const
    {
        sqlite3* database = nullptr;
        const int result = sqlite3_open_v2(_path.c_str(), &database, SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX, nullptr);
        if (result != SQLITE_OK) {
            const std::string message = database ? sqlite3_errmsg(database) : sqlite3_errstr(result);
            sqlite3_close(database);
            throw Error(cutForMessage(_path) + ": cannot open the MBTiles database: " + message);
        }
        sqlite3_busy_timeout(database, 2000);
        return database;
    }

    /// A connection of this source's own; SQLite connections are not shared between threads here.
    sqlite3* acquire()
    {
        std::unique_lock lock(_mutex);
        _available.wait(lock, [&] { return !_idle.empty() || _open < kMaximumConnections; });
        if (!_idle.empty()) {
            sqlite3* database = _idle.back();
            _idle.pop_back();
            return database;
        }
        ++_open;
        lock.unlock();
        try {
            return openConnection();
        } catch (...) {
            lock.lock();
            --_open;
            _available.notify_one();
            throw;
        }
    }

    void release(sqlite3* database)
    {
        {
            const std::lock_guard lock(_mutex);
            _idle.push_back(database);
        }
        _available.notify_one();
    }

    void readMetadata(sqlite3* database, const TileSourceOptions& options)
    {
        const std::string where = cutForMessage(_path);
        std::map<std::string, std::string> metadata;
        {
            Statement rows(database, "SELECT name, value FROM metadata");
            if (rows.prepared() != SQLITE_OK) {
                throw Error(where + ": not an MBTiles database (no metadata table): " + sqlite3_errmsg(database));
            }
            int step = SQLITE_ROW;
            for (int count = 0; (step = sqlite3_step(rows.get())) == SQLITE_ROW && count < 1000; ++count) {
                const auto* name = reinterpret_cast<const char*>(sqlite3_column_text(rows.get(), 0));
                const auto* value = reinterpret_cast<const char*>(sqlite3_column_text(rows.get(), 1));
                // The "json" row of a terrain set holds its layer.json, availability and all.
                const std::size_t limit = name && std::strcmp(name, "json") == 0 ? kMaximumTerrainLayerBytes : 65536;
                if (name && value && std::strlen(value) < limit) {
                    metadata[name] = value;
                }
            }
            if (step != SQLITE_DONE && step != SQLITE_ROW) {
                throw Error(where + ": cannot read the MBTiles metadata: " + sqlite3_errmsg(database));
            }
        }
        Statement tiles(database, "SELECT min(zoom_level), max(zoom_level) FROM tiles");
        if (tiles.prepared() != SQLITE_OK) {
            throw Error(where + ": not an MBTiles database (no tiles table): " + sqlite3_errmsg(database));
        }
        if (sqlite3_step(tiles.get()) != SQLITE_ROW) {
            throw Error(where + ": cannot read the MBTiles tiles: " + sqlite3_errmsg(database));
        }
        const bool empty = sqlite3_column_type(tiles.get(), 0) == SQLITE_NULL;
        auto level = [&](const char* key, int column) -> std::uint32_t {
            long long value = 0;
            if (const auto found = metadata.find(key); found != metadata.end()) {
                const std::string& text = found->second;
                const auto [rest, error] = std::from_chars(text.data(), text.data() + text.size(), value);
                if (error != std::errc() || rest != text.data() + text.size() || value < 0 || value > kMaximumTileLevel) {
                    throw Error(where + ": metadata " + key + " \"" + cutForMessage(text, 40) +
                                "\" is not a level from 0 to " + std::to_string(kMaximumTileLevel));
                }
                return static_cast<std::uint32_t>(value);
            }
            value = empty ? 0 : sqlite3_column_int64(tiles.get(), column);
            if (value < 0 || value > kMaximumTileLevel) {
                throw Error(where + ": the tiles table has zoom level " + std::to_string(value) + ", beyond 0 to " +
                            std::to_string(kMaximumTileLevel));
            }
            return static_cast<std::uint32_t>(value);
        };
        _info.name = _path;
        _info.scheme = options.scheme.value_or(TilingScheme::webMercator());
        _info.minimumLevel = level("minzoom", 0);
        _info.maximumLevel = level("maxzoom", 1);
        if (_info.minimumLevel > _info.maximumLevel) {
            throw Error(where + ": metadata minzoom " + std::to_string(_info.minimumLevel) + " is above maxzoom " +
                        std::to_string(_info.maximumLevel));
        }
        _info.extent = options.extent;
        if (const auto bounds = metadata.find("bounds"); bounds != metadata.end()) {
            _info.extent = parseBounds(bounds->second);
        }
        _info.format = options.format;
        if (const auto format = metadata.find("format"); format != metadata.end() && _info.format.empty()) {
            _info.format = format->second.substr(0, 16);
        }
        if (const auto attribution = metadata.find("attribution"); attribution != metadata.end()) {
            _info.attribution = attribution->second;
        } else {
            _info.attribution = options.attribution;
        }
        _info.tileWidth = options.tileWidth;
        _info.tileHeight = options.tileHeight;
        if (const auto json = metadata.find("json"); json != metadata.end()) {
            _info.metadataJson = json->second;
        }
    }

    /// "west,south,east,north" in degrees.
    GeodeticExtent parseBounds(const std::string& text) const
    {
        double values[4] = {};
        std::size_t start = 0;
        for (int i = 0; i < 4; ++i) {
            const std::size_t end = i < 3 ? text.find(',', start) : text.size();
            std::string_view field = end == std::string::npos ? std::string_view() : std::string_view(text).substr(start, end - start);
            while (!field.empty() && field.front() == ' ') {
                field.remove_prefix(1);
            }
            while (!field.empty() && field.back() == ' ') {
                field.remove_suffix(1);
            }
            const auto [rest, error] = std::from_chars(field.data(), field.data() + field.size(), values[i]);
            if (field.empty() || error != std::errc() || rest != field.data() + field.size() || !std::isfinite(values[i])) {
                throw Error(cutForMessage(_path) + ": metadata bounds \"" + cutForMessage(text, 80) +
                            "\" is not west,south,east,north in degrees");
            }
            start = end + 1;
        }
        const auto [west, south, east, north] = values;
        if (west < -180.0 || east > 180.0 || south < -90.0 || north > 90.0 || !(south < north) || west == east) {
            throw Error(cutForMessage(_path) + ": metadata bounds \"" + cutForMessage(text, 80) +
                        "\" is not a rectangle on the globe");
        }
        return GeodeticExtent::fromDegrees(west, south, east, north);
    }

    static constexpr int kMaximumConnections = 8;

    std::string _path;
    std::size_t _maximumBytes;
    TileSourceInfo _info;
    std::mutex _mutex;
    std::condition_variable _available;
    std::vector<sqlite3*> _idle;
    int _open = 0;
};

} // namespace

std::unique_ptr<TileSource> openMBTiles(const std::string& path, const TileSourceOptions& options)
{
    return std::make_unique<MBTilesSource>(path, options);
}

} // namespace orbis::world::detail
