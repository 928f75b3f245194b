#include "orbis/world/TileSource.h"

#include "DiskCache.h"
#include "HttpClient.h"
#include "TileSources.h"

#include "orbis/world/FileAccess.h"
#include "orbis/world/ImageCodec.h"
#include "orbis/world/TileMapResource.h"

#include <orbis/core/Error.h>

#include <algorithm>
#include <functional>

namespace orbis::world {

namespace detail {

namespace {

/// Longitude intervals [west, east] overlap, or touch; `b` may cross the antimeridian (east < west).
bool longitudesOverlap(double westA, double eastA, double westB, double eastB) noexcept
{
    if (westB <= eastB) {
        return westA <= eastB && westB <= eastA;
    }
    return westA <= eastB || westB <= eastA;
}

} // namespace

bool sourceHasTile(const TileSourceInfo& info, const TileKey& key) noexcept
{
    if (key.level < info.minimumLevel || key.level > info.maximumLevel || !info.scheme.isValid(key)) {
        return false;
    }
    const GeodeticExtent tile = info.scheme.tileExtent(key);
    // Strict for latitude: a tile that only shares its southern edge with the extent holds none of it.
    return tile.south < info.extent.north && info.extent.south < tile.north &&
           longitudesOverlap(tile.west, tile.east, info.extent.west, info.extent.east) &&
           !(tile.east == info.extent.west || tile.west == info.extent.east);
}

} // namespace detail

namespace {

using detail::HttpClient;
using detail::isHttpUrl;

/// Where a tile's bytes come from: files, or HTTP with an optional disk cache.
class Transport {
public:
    explicit Transport(std::size_t maximumBytes) : _maximumBytes(maximumBytes) {}
    Transport(const TileSourceOptions& options, const std::string& sourceName)
        : _maximumBytes(options.maximumTileBytes)
        , _http(std::make_unique<HttpClient>(options.http, options.maximumTileBytes))
    {
        if (!options.cacheFolder.empty()) {
            _cache = std::make_unique<detail::DiskCache>(options.cacheFolder, sourceName);
        }
    }

    /// The extension of the tiles' files in the cache.
    void setExtension(std::string extension) { _extension = std::move(extension); }

    TileFetch fetch(const TileKey& key, const std::string& location) const
    {
        if (_http) {
            if (_cache) {
                if (auto cached = _cache->load(key, _extension, _maximumBytes)) {
                    return std::move(*cached);
                }
            }
            TileFetch fetched = _http->get(location);
            if (_cache) {
                _cache->store(key, _extension, fetched);
            }
            return fetched;
        }
        TileFetch fetched;
        try {
            if (auto bytes = readFileBytesIfExists(location, "tile", _maximumBytes)) {
                fetched.status = TileFetch::Status::Ok;
                fetched.bytes = std::move(*bytes);
            } else {
                fetched.status = TileFetch::Status::Missing;
            }
        } catch (const Error& error) {
            fetched.status = TileFetch::Status::Failed;
            fetched.message = error.what();
        }
        return fetched;
    }

    /// A file of the source other than a tile, through the cache when there is one (cached first,
    /// as tiles are). Throws orbis::Error when it cannot be had.
    std::vector<std::uint8_t> fetchFile(const std::string& url, const std::string& cacheName, std::size_t maximumBytes) const
    {
        if (_cache) {
            if (auto cached = _cache->loadFile(cacheName, maximumBytes)) {
                return std::move(*cached);
            }
        }
        TileFetch fetched = _http->get(url);
        if (fetched.status == TileFetch::Status::Missing) {
            throw Error(cutForMessage(url) + ": no such file (HTTP 404)");
        }
        if (fetched.status != TileFetch::Status::Ok) {
            throw Error(fetched.message);
        }
        if (fetched.bytes.size() > maximumBytes) {
            throw Error(cutForMessage(url) + ": " + std::to_string(fetched.bytes.size()) + " bytes, more than the " +
                        std::to_string(maximumBytes) + " allowed");
        }
        if (_cache) {
            _cache->storeFile(cacheName, fetched.bytes);
        }
        return std::move(fetched.bytes);
    }

private:
    std::size_t _maximumBytes;
    std::unique_ptr<HttpClient> _http;
    std::unique_ptr<detail::DiskCache> _cache;
    std::string _extension;
};

/// A source whose tiles are found by computing their path or URL: TMS pyramids and templates.
class LocatedTileSource final : public TileSource {
public:
    using Locator = std::function<std::string(const TileKey&)>;

    LocatedTileSource(TileSourceInfo info, Locator locator, std::unique_ptr<Transport> transport)
        : _info(std::move(info)), _locate(std::move(locator)), _transport(std::move(transport))
    {
    }

    const TileSourceInfo& info() const noexcept override { return _info; }

    TileFetch fetch(const TileKey& key) override
    {
        if (!detail::sourceHasTile(_info, key)) {
            TileFetch missing;
            missing.status = TileFetch::Status::Missing;
            return missing;
        }
        return _transport->fetch(key, _locate(key));
    }

    std::string locate(const TileKey& key) const override { return _locate(key); }

private:
    TileSourceInfo _info;
    Locator _locate;
    std::unique_ptr<Transport> _transport;
};

/// Tile rows counted from the south (TMS), whatever the scheme counts from.
std::uint32_t rowFromSouth(const TilingScheme& scheme, const TileKey& key)
{
    return scheme.projection() == TilingProjection::Geographic ? key.y : scheme.tilesY(key.level) - 1 - key.y;
}

/// Tile rows counted from the north (XYZ).
std::uint32_t rowFromNorth(const TilingScheme& scheme, const TileKey& key)
{
    return scheme.tilesY(key.level) - 1 - rowFromSouth(scheme, key);
}

// ---- Templates -----------------------------------------------------------------------------------

struct TemplatePart {
    enum class Kind { Text, Level, Column, RowFromNorth, RowFromSouth, Subdomain } kind = Kind::Text;
    std::string text;
};

std::vector<TemplatePart> parseTemplate(const std::string& pattern)
{
    const std::string where = cutForMessage(pattern);
    if (pattern.size() > 4096) {
        throw Error(where + ": a template longer than 4096 characters");
    }
    std::vector<TemplatePart> parts;
    bool level = false;
    bool column = false;
    bool row = false;
    std::size_t position = 0;
    while (position < pattern.size()) {
        const std::size_t open = pattern.find('{', position);
        if (open == std::string::npos) {
            parts.push_back({TemplatePart::Kind::Text, pattern.substr(position)});
            break;
        }
        if (open > position) {
            parts.push_back({TemplatePart::Kind::Text, pattern.substr(position, open - position)});
        }
        const std::size_t close = pattern.find('}', open);
        if (close == std::string::npos) {
            throw Error(where + ": a '{' without '}' at character " + std::to_string(open + 1));
        }
        const std::string name = pattern.substr(open + 1, close - open - 1);
        using Kind = TemplatePart::Kind;
        Kind kind = Kind::Text;
        if (name == "z") {
            kind = Kind::Level;
            level = true;
        } else if (name == "x") {
            kind = Kind::Column;
            column = true;
        } else if (name == "y") {
            kind = Kind::RowFromNorth;
            row = true;
        } else if (name == "reverseY" || name == "-y") {
            kind = Kind::RowFromSouth;
            row = true;
        } else if (name == "s") {
            kind = Kind::Subdomain;
        } else {
            throw Error(where + ": unknown placeholder {" + cutForMessage(name, 40) +
                        "} (known: {z} {x} {y} {reverseY} {-y} {s})");
        }
        parts.push_back({kind, {}});
        position = close + 1;
    }
    if (!level || !column || !row) {
        throw Error(where + ": a template needs {z}, {x} and {y} or {reverseY}");
    }
    return parts;
}

std::vector<std::string> splitSubdomains(const std::string& subdomains)
{
    std::vector<std::string> names;
    if (subdomains.find(',') == std::string::npos) {
        for (const char c : subdomains) {
            names.emplace_back(1, c);
        }
    } else {
        std::size_t start = 0;
        while (start <= subdomains.size()) {
            const std::size_t end = std::min(subdomains.find(',', start), subdomains.size());
            if (end > start) {
                names.push_back(subdomains.substr(start, end - start));
            }
            start = end + 1;
        }
    }
    return names;
}

/// The extension before the end or the query of a template ("png" of ".../{y}.png?key=1").
std::string templateExtension(const std::string& pattern)
{
    const std::string path = pattern.substr(0, pattern.find('?'));
    const std::size_t dot = path.rfind('.');
    const std::size_t slash = path.rfind('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash) || path.find('}', dot) != std::string::npos) {
        return "";
    }
    return path.substr(dot + 1);
}

/// The path or URL of a tile from a parsed template.
LocatedTileSource::Locator templateLocator(std::vector<TemplatePart> parts, std::vector<std::string> subdomains,
                                           const TilingScheme& scheme)
{
    return [parts = std::move(parts), subdomains = std::move(subdomains), scheme](const TileKey& key) {
        std::string location;
        for (const TemplatePart& part : parts) {
            using Kind = TemplatePart::Kind;
            switch (part.kind) {
            case Kind::Text: location += part.text; break;
            case Kind::Level: location += std::to_string(key.level); break;
            case Kind::Column: location += std::to_string(key.x); break;
            case Kind::RowFromNorth: location += std::to_string(rowFromNorth(scheme, key)); break;
            case Kind::RowFromSouth: location += std::to_string(rowFromSouth(scheme, key)); break;
            case Kind::Subdomain:
                location += subdomains[(std::size_t{key.x} + key.y + key.level) % subdomains.size()];
                break;
            }
        }
        return location;
    };
}

std::unique_ptr<TileSource> openTemplate(const std::string& pattern, const TileSourceOptions& options)
{
    const std::string where = cutForMessage(pattern);
    std::vector<TemplatePart> parts = parseTemplate(pattern);
    const std::vector<std::string> subdomains = splitSubdomains(options.subdomains);
    const bool usesSubdomain =
        std::any_of(parts.begin(), parts.end(), [](const TemplatePart& p) { return p.kind == TemplatePart::Kind::Subdomain; });
    if (usesSubdomain && subdomains.empty()) {
        throw Error(where + ": the template uses {s} but no subdomains are given");
    }
    if (options.minimumLevel > options.maximumLevel || options.maximumLevel > kMaximumTileLevel) {
        throw Error(where + ": levels " + std::to_string(options.minimumLevel) + " to " +
                    std::to_string(options.maximumLevel) + " are not within 0 to " + std::to_string(kMaximumTileLevel));
    }
    if (options.tileWidth < 1 || options.tileHeight < 1 || options.tileWidth > kMaximumTileSide ||
        options.tileHeight > kMaximumTileSide) {
        throw Error(where + ": tiles of " + std::to_string(options.tileWidth) + "x" + std::to_string(options.tileHeight) +
                    " pixels (1 to " + std::to_string(kMaximumTileSide) + " a side)");
    }
    TileSourceInfo info;
    info.name = pattern;
    info.scheme = options.scheme.value_or(TilingScheme::webMercator());
    info.minimumLevel = options.minimumLevel;
    info.maximumLevel = options.maximumLevel;
    info.tileWidth = options.tileWidth;
    info.tileHeight = options.tileHeight;
    info.extent = options.extent;
    const std::string extension = templateExtension(pattern);
    info.format = options.format.empty() ? extension : options.format;
    info.attribution = options.attribution;
    auto locate = templateLocator(std::move(parts), subdomains, info.scheme);
    auto transport = isHttpUrl(pattern) ? std::make_unique<Transport>(options, pattern)
                                        : std::make_unique<Transport>(options.maximumTileBytes);
    transport->setExtension(extension.empty() ? info.format : extension);
    return std::make_unique<LocatedTileSource>(std::move(info), std::move(locate), std::move(transport));
}

// ---- TMS -----------------------------------------------------------------------------------------

std::unique_ptr<TileSource> openTms(const std::string& base, const TileMapResource& resource, const std::string& name,
                                    const TileSourceOptions& options, std::unique_ptr<Transport> transport)
{
    if (options.scheme && !(*options.scheme == resource.scheme)) {
        throw Error(cutForMessage(name) + ": the description's scheme differs from the one asked for");
    }
    TileSourceInfo info;
    info.name = name;
    info.scheme = resource.scheme;
    info.minimumLevel = resource.minimumLevel();
    info.maximumLevel = resource.maximumLevel();
    info.tileWidth = resource.tileWidth;
    info.tileHeight = resource.tileHeight;
    info.extent = resource.extent;
    info.format = resource.extension;
    info.attribution = resource.attribution.empty() ? options.attribution : resource.attribution;
    std::vector<std::string> levelPrefixes;
    for (const TileMapResource::TileSet& set : resource.tileSets) {
        levelPrefixes.push_back((isHttpUrl(set.href) ? set.href : base + "/" + set.href) + "/");
    }
    const std::string suffix = "." + resource.extension;
    const TilingScheme scheme = resource.scheme;
    const std::uint32_t firstLevel = info.minimumLevel;
    auto locate = [levelPrefixes = std::move(levelPrefixes), suffix, scheme, firstLevel](const TileKey& key) {
        const std::size_t index = std::min<std::size_t>(key.level - std::min(key.level, firstLevel), levelPrefixes.size() - 1);
        return levelPrefixes[index] + std::to_string(key.x) + "/" + std::to_string(rowFromSouth(scheme, key)) + suffix;
    };
    return std::make_unique<LocatedTileSource>(std::move(info), std::move(locate), std::move(transport));
}

std::unique_ptr<TileSource> openHttpTms(const std::string& url, const TileSourceOptions& options)
{
    std::string base = url;
    std::string descriptionUrl;
    if (url.ends_with(".xml")) {
        descriptionUrl = url;
        base = url.substr(0, url.rfind('/'));
    } else {
        while (base.ends_with("/")) {
            base.pop_back();
        }
        descriptionUrl = base + "/tilemapresource.xml";
    }
    auto transport = std::make_unique<Transport>(options, base);
    const std::vector<std::uint8_t> bytes = transport->fetchFile(descriptionUrl, "tilemapresource.xml", std::size_t{1} << 20);
    const TileMapResource resource =
        parseTileMapResource(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), descriptionUrl);
    transport->setExtension(resource.extension);
    return openTms(base, resource, url, options, std::move(transport));
}

bool hasMBTilesName(const std::string& path)
{
    std::string lower = path.substr(path.size() > 8 ? path.size() - 8 : 0);
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](char c) { return static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c); });
    return lower == ".mbtiles";
}

void replaceAll(std::string& text, std::string_view from, std::string_view to)
{
    for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
        text.replace(at, from.size(), to);
    }
}

} // namespace

bool detail::looksLikeLayer(const std::string& location)
{
    if (location.ends_with("layer.json")) {
        return true;
    }
    if (isHttpUrl(location)) {
        return false;
    }
    std::error_code error;
    return std::filesystem::is_directory(location, error) &&
           std::filesystem::is_regular_file(std::filesystem::path(location) / "layer.json", error);
}

detail::LayerTiles detail::openLayerTiles(const std::string& location, const TileSourceOptions& options)
{
    const bool http = isHttpUrl(location);
    std::string base = location;
    std::string layerLocation;
    if (location.ends_with("layer.json")) {
        layerLocation = location;
        const std::size_t slash = location.rfind('/');
        base = slash == std::string::npos ? "." : location.substr(0, slash);
    } else {
        while (base.size() > 1 && base.ends_with("/")) {
            base.pop_back();
        }
        layerLocation = base + "/layer.json";
    }
    std::unique_ptr<Transport> transport =
        http ? std::make_unique<Transport>(options, base) : std::make_unique<Transport>(options.maximumTileBytes);
    const std::vector<std::uint8_t> bytes = http ? transport->fetchFile(layerLocation, "layer.json", kMaximumTerrainLayerBytes)
                                                 : readFileBytes(layerLocation, "layer.json", kMaximumTerrainLayerBytes);
    LayerTiles result;
    result.layer = parseTerrainLayer(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), layerLocation);
    const TerrainLayer& layer = result.layer;
    const std::string where = cutForMessage(layerLocation);
    if (layer.projection != "EPSG:4326") {
        throw Error(where + ": terrain in " + layer.projection +
                    " is not supported (quantized-mesh and heightmap tiles must be in EPSG:4326)");
    }
    std::string pattern = layer.tiles.front();
    replaceAll(pattern, "{version}", layer.version);
    if (!http) {
        pattern = pattern.substr(0, pattern.find('?'));
    }
    if (layer.rowsFromSouth) {
        replaceAll(pattern, "{y}", "{reverseY}");
    }
    if (!isHttpUrl(pattern)) {
        pattern = base + "/" + (pattern.starts_with("./") ? pattern.substr(2) : pattern);
    }
    std::vector<TemplatePart> parts;
    try {
        parts = parseTemplate(pattern);
    } catch (const Error& error) {
        throw Error(where + ": /tiles/0: " + error.what());
    }
    TileSourceInfo info;
    info.name = location;
    info.scheme = TilingScheme::geographic();
    info.minimumLevel = layer.minimumLevel;
    info.maximumLevel = layer.maximumLevel;
    info.extent = layer.bounds;
    info.format = layer.format;
    info.attribution = layer.attribution.empty() ? options.attribution : layer.attribution;
    transport->setExtension("terrain");
    auto locate = templateLocator(std::move(parts), splitSubdomains(options.subdomains), info.scheme);
    result.tiles = std::make_unique<LocatedTileSource>(std::move(info), std::move(locate), std::move(transport));
    return result;
}

std::unique_ptr<TileSource> openTileSource(const std::string& pathOrUrl, const TileSourceOptions& options)
{
    const std::string where = cutForMessage(pathOrUrl);
    if (pathOrUrl.empty()) {
        throw Error("an empty tile source path");
    }
    if (pathOrUrl.find('\0') != std::string::npos) {
        throw Error(where + ": a NUL character in a tile source path");
    }
    const std::string source = pathOrUrl.starts_with("file://") ? pathOrUrl.substr(7) : pathOrUrl;
    if (source.find('{') != std::string::npos) {
        return openTemplate(source, options);
    }
    if (isHttpUrl(source)) {
        if (hasMBTilesName(source)) {
            throw Error(where + ": MBTiles files are read from disk, not over HTTP (download it first)");
        }
        return openHttpTms(source, options);
    }
    std::error_code error;
    const std::filesystem::path path(source);
    const auto status = std::filesystem::status(path, error);
    if (error || !std::filesystem::exists(status)) {
        throw Error(where + ": no such file or folder");
    }
    if (std::filesystem::is_directory(status) || path.extension() == ".xml") {
        const std::filesystem::path folder = std::filesystem::is_directory(status) ? path : path.parent_path();
        const TileMapResource resource = readTileMapResource(path);
        std::string base = folder.string();
        while (base.size() > 1 && base.ends_with("/")) {
            base.pop_back();
        }
        return openTms(base, resource, source, options, std::make_unique<Transport>(options.maximumTileBytes));
    }
    return detail::openMBTiles(source, options);
}

} // namespace orbis::world
