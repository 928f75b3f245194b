#pragma once

#include <orbis/core/GeodeticExtent.h>
#include <orbis/core/TileKey.h>
#include <orbis/core/TilingScheme.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace orbis::world {

/// What a tile source holds.
struct TileSourceInfo {
    std::string name;                 ///< the path or URL, for messages
    orbis::TilingScheme scheme = orbis::TilingScheme::geographic();
    std::uint32_t minimumLevel = 0;
    std::uint32_t maximumLevel = 0;   ///< deepest level the source has
    int tileWidth = 256, tileHeight = 256;
    orbis::GeodeticExtent extent = orbis::GeodeticExtent::maximum(); ///< where tiles exist
    std::string format;               ///< "jpg", "png", "webp", ...; empty when unknown (decoders detect it)
    std::string attribution;
    /// MBTiles: the metadata table's "json" row (terrain sets keep layer.json there); else empty.
    std::string metadataJson;
};

/// The outcome of fetching one tile.
struct TileFetch {
    enum class Status { Ok, Missing, Failed };  ///< Missing: the tile does not exist (404, no file, no row)
    Status status = Status::Failed;
    std::vector<std::uint8_t> bytes;            ///< Ok only
    std::string message;                        ///< Failed: names the URL or path and what went wrong
    int attempts = 0;                           ///< HTTP requests made (retries included); 0 from disk
    bool fromCache = false;                     ///< served by the on-disk cache
};

/// A pyramid of tiles, read one tile at a time. fetch() may be called from several threads at once;
/// the source must outlive those calls.
class TileSource {
public:
    virtual ~TileSource() = default;
    virtual const TileSourceInfo& info() const noexcept = 0;
    /// Blocking; never throws for one tile's trouble. A key outside the source's levels, its
    /// scheme or its extent is Missing without any request.
    virtual TileFetch fetch(const orbis::TileKey& key) = 0;
    /// The path or URL of that tile (for MBTiles, the file and the row), for messages and caches.
    virtual std::string locate(const orbis::TileKey& key) const = 0;
};

/// How HTTP requests are made.
struct HttpOptions {
    /// At most this many requests of one source are on the wire at once; other fetches wait.
    int maximumRequestsInFlight = 6;
    std::chrono::milliseconds connectTimeout{5000};
    /// The limit for one attempt, connection and body included.
    std::chrono::milliseconds totalTimeout{20000};
    /// Further attempts after a 5xx or 429 answer or a broken connection (refused, reset, cut short);
    /// not after a timeout, a 4xx, or a bad URL.
    int retries = 3;
    /// The wait before the first retry, doubled before each further one, up to maximumBackoff.
    std::chrono::milliseconds backoff{250};
    std::chrono::milliseconds maximumBackoff{4000};
    std::string userAgent = "Orbis/0.1 (virtual globe; libcurl)";
    /// Further request headers, each "Name: value" (an Accept header for quantized-mesh servers).
    std::vector<std::string> headers;
};

/// How openTileSource reads a source.
struct TileSourceOptions {
    /// For URL and path templates, which name no scheme: Web Mercator (as XYZ maps are) unless
    /// told. For MBTiles, overrides the Web Mercator of the specification. TMS descriptions give
    /// their own, and this must then agree or be empty.
    std::optional<orbis::TilingScheme> scheme;
    /// Tile format ("jpg", "png", "webp", "pbf", ...) where the source does not say: for templates,
    /// the extension in the template is used when this is empty.
    std::string format;
    /// Levels of a template source (a TMS description or MBTiles metadata gives its own).
    std::uint32_t minimumLevel = 0;
    std::uint32_t maximumLevel = 18;
    orbis::GeodeticExtent extent = orbis::GeodeticExtent::maximum();
    int tileWidth = 256, tileHeight = 256;
    /// Replaces {s} in templates, one character (or comma-separated name) per server, chosen by the tile.
    std::string subdomains = "abc";
    std::string attribution;
    /// The largest tile accepted, from a file, a database row or a response.
    std::size_t maximumTileBytes = std::size_t{16} << 20;
    HttpOptions http;
    /// Where HTTP tiles (and 404s) are kept on disk and served from on later runs; empty: no cache.
    /// The folder belongs to one source: a `source.txt` in it names the URL, and opening the
    /// folder for another source fails. Entries never expire: delete the folder to refresh it.
    std::filesystem::path cacheFolder;
};

/// Opens a tile source by its path or URL:
///  - `http(s)://.../{z}/{x}/{y}.png` or a local path with `{z}`, `{x}`, `{y}` or `{reverseY}` (also
///    `{-y}`) and optionally `{s}`: a template. `{y}` counts rows from the north and `{reverseY}`
///    from the south, whatever the scheme (as XYZ and TMS URLs do).
///  - a `.mbtiles` file: an MBTiles database (SQLite), read only.
///  - a folder or URL with tilemapresource.xml, or the description's own path or URL: a TMS pyramid.
/// Throws orbis::Error naming the source when it cannot be opened: no such file, a malformed
/// description or template, an unreadable database, a cache folder of another source.
std::unique_ptr<TileSource> openTileSource(const std::string& pathOrUrl, const TileSourceOptions& options = {});

} // namespace orbis::world
