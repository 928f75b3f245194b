#include "orbis/world/TileMapResource.h"

#include "XmlScanner.h"

#include "orbis/world/FileAccess.h"

#include <orbis/core/Error.h>
#include <orbis/core/Math.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

namespace orbis::world {

namespace {

using detail::XmlDocument;
using detail::XmlElement;

/// Web Mercator's half width in metres (pi times the WGS84 semi-major axis), TMS's origin.
constexpr double kMercatorHalfWidth = 20037508.342789244;
constexpr double kMercatorRadius = 6378137.0;

std::string_view trim(std::string_view text)
{
    while (!text.empty() && (text.front() == ' ' || text.front() == '\t' || text.front() == '\r' || text.front() == '\n')) {
        text.remove_prefix(1);
    }
    while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r' || text.back() == '\n')) {
        text.remove_suffix(1);
    }
    return text;
}

class Reader {
public:
    Reader(std::string_view xml, std::string_view name)
        : _name(cutForMessage(name)), _document(detail::parseXml(xml, name))
    {
    }

    TileMapResource read()
    {
        const XmlElement& root = _document.root();
        if (root.name == "TileMapService") {
            fail(root, "is a TileMapService listing, not a TileMap: open one of the TileMaps it lists");
        }
        if (root.name != "TileMap") {
            fail(root, "expected a <TileMap> root element");
        }
        TileMapResource resource;
        if (const XmlElement* title = _document.child(root, "Title")) {
            resource.title = std::string(trim(title->text));
        }
        if (const XmlElement* abstract = _document.child(root, "Abstract")) {
            resource.abstract = std::string(trim(abstract->text));
        }
        if (const XmlElement* attribution = _document.child(root, "Attribution")) {
            if (const XmlElement* title = _document.child(*attribution, "Title")) {
                resource.attribution = std::string(trim(title->text));
            }
        }
        const bool mercator = readProjection(root);
        resource.scheme = mercator ? TilingScheme::webMercator() : TilingScheme::geographic();
        readOrigin(root, mercator);
        resource.extent = readBoundingBox(root, mercator, resource.scheme.coverage());
        readTileFormat(root, resource);
        readTileSets(root, resource, mercator);
        return resource;
    }

private:
    [[noreturn]] void fail(const XmlElement& element, const std::string& what) const
    {
        throw Error(_name + ":" + std::to_string(element.line) + ": <" + element.name + "> " + what);
    }

    const XmlElement& required(const XmlElement& parent, std::string_view name) const
    {
        const XmlElement* element = _document.child(parent, name);
        if (!element) {
            fail(parent, "has no <" + std::string(name) + ">");
        }
        return *element;
    }

    std::string_view attribute(const XmlElement& element, std::string_view name) const
    {
        const auto value = element.attribute(name);
        if (!value) {
            fail(element, "has no " + std::string(name) + " attribute");
        }
        return *value;
    }

    double number(const XmlElement& element, std::string_view name) const
    {
        const std::string_view text = trim(attribute(element, name));
        double value = 0.0;
        const auto [rest, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (text.empty() || error != std::errc() || rest != text.data() + text.size() || !std::isfinite(value)) {
            fail(element, std::string(name) + "=\"" + cutForMessage(text, 40) + "\" is not a finite number");
        }
        return value;
    }

    long long integer(const XmlElement& element, std::string_view name, long long minimum, long long maximum) const
    {
        const std::string_view text = trim(attribute(element, name));
        long long value = 0;
        const auto [rest, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (text.empty() || error != std::errc() || rest != text.data() + text.size() || value < minimum ||
            value > maximum) {
            fail(element, std::string(name) + "=\"" + cutForMessage(text, 40) + "\" is not a whole number from " +
                              std::to_string(minimum) + " to " + std::to_string(maximum));
        }
        return value;
    }

    /// True for the mercator profile, false for the geodetic one.
    bool readProjection(const XmlElement& root) const
    {
        const XmlElement& srs = required(root, "SRS");
        const std::string_view code = trim(srs.text);
        bool mercator = false;
        if (code == "EPSG:4326" || code == "CRS:84" || code == "OGC:CRS84") {
            mercator = false;
        } else if (code == "EPSG:3857" || code == "EPSG:900913" || code == "EPSG:3785" || code == "OSGEO:41001" ||
                   code == "EPSG:102100") {
            mercator = true;
        } else {
            std::string message = cutForMessage(code, 40);
            message.insert(message.begin(), '"');
            fail(srs, message + "\" is not supported: the geodetic (EPSG:4326) and mercator (EPSG:3857) profiles are");
        }
        if (const XmlElement* tileSets = _document.child(root, "TileSets")) {
            if (const auto profile = tileSets->attribute("profile")) {
                const bool geodeticProfile = *profile == "geodetic" || *profile == "global-geodetic";
                const bool mercatorProfile = *profile == "mercator" || *profile == "global-mercator";
                if (!geodeticProfile && !mercatorProfile && *profile != "local" && *profile != "none") {
                    fail(*tileSets, "profile=\"" + cutForMessage(*profile, 40) + "\" is not geodetic or mercator");
                }
                if ((geodeticProfile && mercator) || (mercatorProfile && !mercator)) {
                    fail(*tileSets, "profile=\"" + std::string(*profile) + "\" contradicts the SRS " + std::string(code));
                }
            }
        }
        return mercator;
    }

    void readOrigin(const XmlElement& root, bool mercator) const
    {
        const XmlElement& origin = required(root, "Origin");
        const double x = number(origin, "x");
        const double y = number(origin, "y");
        const double expectedX = mercator ? -kMercatorHalfWidth : -180.0;
        const double expectedY = mercator ? -kMercatorHalfWidth : -90.0;
        const double tolerance = mercator ? 1.0 : 1e-9;
        if (std::abs(x - expectedX) > tolerance || std::abs(y - expectedY) > tolerance) {
            char expected[96];
            std::snprintf(expected, sizeof expected, "(%.9g, %.9g)", expectedX, expectedY);
            fail(origin, "must be the lower left of the " + std::string(mercator ? "mercator" : "geodetic") +
                             " profile " + expected + ": other origins are not supported");
        }
    }

    GeodeticExtent readBoundingBox(const XmlElement& root, bool mercator, const GeodeticExtent& coverage) const
    {
        const XmlElement* box = _document.child(root, "BoundingBox");
        if (!box) {
            return coverage;
        }
        double minX = number(*box, "minx");
        double minY = number(*box, "miny");
        double maxX = number(*box, "maxx");
        double maxY = number(*box, "maxy");
        const double limitX = mercator ? kMercatorHalfWidth : 180.0;
        const double limitY = mercator ? kMercatorHalfWidth : 90.0;
        // Rounding in the writer's decimals may put an edge a hair outside the globe.
        const double slack = mercator ? 1.0 : 1e-9;
        // Ordered once held to the globe: a box entirely in the slack beyond a pole is empty.
        const bool onGlobe = minX >= -limitX - slack && maxX <= limitX + slack && minY >= -limitY - slack &&
                             maxY <= limitY + slack;
        minX = std::max(minX, -limitX);
        maxX = std::min(maxX, limitX);
        minY = std::max(minY, -limitY);
        maxY = std::min(maxY, limitY);
        if (!onGlobe || !(minX < maxX) || !(minY < maxY)) {
            fail(*box, "is not an ordered rectangle on the globe");
        }
        if (!mercator) {
            return GeodeticExtent::fromDegrees(minX, minY, maxX, maxY);
        }
        auto latitude = [](double y) { return std::atan(std::sinh(y / kMercatorRadius)); };
        return {minX / kMercatorHalfWidth * kPi, latitude(minY), maxX / kMercatorHalfWidth * kPi, latitude(maxY)};
    }

    void readTileFormat(const XmlElement& root, TileMapResource& resource) const
    {
        const XmlElement& format = required(root, "TileFormat");
        resource.tileWidth = static_cast<int>(integer(format, "width", 1, kMaximumTileSide));
        resource.tileHeight = static_cast<int>(integer(format, "height", 1, kMaximumTileSide));
        const std::string_view extension = trim(attribute(format, "extension"));
        const bool plain = !extension.empty() && extension.size() <= 8 &&
                           std::all_of(extension.begin(), extension.end(), [](char c) {
                               return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
                           });
        if (!plain) {
            fail(format, "extension=\"" + cutForMessage(extension, 40) + "\" is not 1 to 8 letters and digits");
        }
        resource.extension = std::string(extension);
        resource.mimeType = std::string(trim(format.attribute("mime-type").value_or("")));
    }

    void readTileSets(const XmlElement& root, TileMapResource& resource, bool mercator) const
    {
        const XmlElement& tileSets = required(root, "TileSets");
        const std::vector<const XmlElement*> sets = _document.children(tileSets, "TileSet");
        constexpr std::size_t kMaximumSets = kMaximumTileLevel + 1;
        if (sets.empty() || sets.size() > kMaximumSets) {
            fail(tileSets, "has " + std::to_string(sets.size()) + " <TileSet> elements, expected 1 to " +
                               std::to_string(kMaximumSets));
        }
        for (const XmlElement* set : sets) {
            TileMapResource::TileSet tileSet;
            tileSet.level = static_cast<std::uint32_t>(integer(*set, "order", 0, kMaximumTileLevel));
            tileSet.unitsPerPixel = number(*set, "units-per-pixel");
            const double expected = tileMapUnitsPerPixel(resource.scheme, tileSet.level, resource.tileWidth);
            // Height tiles of 2^k + 1 samples (neighbours sharing their edge samples) span k intervals.
            const double pointRegistered =
                resource.tileWidth % 2 == 1 ? tileMapUnitsPerPixel(resource.scheme, tileSet.level, resource.tileWidth - 1)
                                            : expected;
            const auto matches = [&](double value) { return std::abs(tileSet.unitsPerPixel - value) <= value * 1e-6; };
            if (!matches(expected) && !matches(pointRegistered)) {
                char numbers[96];
                std::snprintf(numbers, sizeof numbers, "units-per-pixel=\"%.10g\" does not match level %u", tileSet.unitsPerPixel,
                              tileSet.level);
                char expectedText[32];
                std::snprintf(expectedText, sizeof expectedText, "%.10g", expected);
                const bool oneRoot = !mercator && std::abs(tileSet.unitsPerPixel - 2 * expected) <= expected * 1e-6;
                fail(*set, std::string(numbers) + " of the " + (mercator ? "mercator" : "geodetic") + " profile (" +
                               expectedText + ")" +
                               (oneRoot ? ": one root tile of 360 degrees (gdal2tiles without --tmscompatible) is not supported"
                                        : ""));
            }
            const std::string_view href = trim(attribute(*set, "href"));
            checkHref(*set, href);
            tileSet.href = std::string(href);
            resource.tileSets.push_back(std::move(tileSet));
        }
        std::sort(resource.tileSets.begin(), resource.tileSets.end(),
                  [](const auto& a, const auto& b) { return a.level < b.level; });
        for (std::size_t i = 1; i < resource.tileSets.size(); ++i) {
            if (resource.tileSets[i].level != resource.tileSets[i - 1].level + 1) {
                fail(tileSets, "levels must be contiguous and appear once: " +
                                   std::to_string(resource.tileSets[i - 1].level) + " is followed by " +
                                   std::to_string(resource.tileSets[i].level));
            }
        }
    }

    /// A level's href: a relative folder (no "..", not absolute) or an http(s) URL.
    void checkHref(const XmlElement& set, std::string_view href) const
    {
        const bool url = href.starts_with("http://") || href.starts_with("https://");
        bool bad = href.empty() || href.size() > 1024 || (!url && (href.front() == '/' || href.find(':') != std::string_view::npos));
        for (std::size_t start = 0; !bad && start <= href.size();) {
            const std::size_t end = std::min(href.find('/', start), href.size());
            bad = href.substr(start, end - start) == "..";
            start = end + 1;
        }
        if (bad) {
            fail(set, "href=\"" + cutForMessage(href, 60) +
                          "\" is not a relative folder without \"..\" or an http(s) URL");
        }
    }

    std::string _name;
    XmlDocument _document;
};

std::string xmlNumber(double value)
{
    char text[64];
    std::snprintf(text, sizeof text, "%.14f", value);
    return text;
}

} // namespace

double tileMapUnitsPerPixel(const TilingScheme& scheme, std::uint32_t level, int tileWidth) noexcept
{
    const double width = scheme.projection() == TilingProjection::WebMercator ? 2.0 * kMercatorHalfWidth : 360.0;
    return width / (static_cast<double>(scheme.tilesX(std::min(level, kMaximumTileLevel))) * tileWidth);
}

TileMapResource parseTileMapResource(std::string_view xml, std::string_view nameForMessages)
{
    return Reader(xml, nameForMessages).read();
}

TileMapResource readTileMapResource(const std::filesystem::path& path)
{
    std::error_code ignored;
    const std::filesystem::path file =
        std::filesystem::is_directory(path, ignored) ? path / "tilemapresource.xml" : path;
    const std::vector<std::uint8_t> bytes = readFileBytes(file, "tilemapresource.xml", detail::XmlLimits{}.maximumBytes);
    return parseTileMapResource(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
                                file.string());
}

std::string formatTileMapResource(const TileMapResource& resource)
{
    using detail::escapeXml;
    const bool mercator = resource.scheme.projection() == TilingProjection::WebMercator;
    auto x = [&](double longitude) { return mercator ? longitude / kPi * kMercatorHalfWidth : toDegrees(longitude); };
    auto y = [&](double latitude) {
        // The extent may reach the poles; the mercator profile ends at its square's edge.
        const double limit = TilingScheme::kMaximumMercatorLatitude;
        return mercator ? TilingScheme::mercatorY(std::clamp(latitude, -limit, limit)) * kMercatorRadius
                        : toDegrees(latitude);
    };
    std::string xml = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n"
                      "<TileMap version=\"1.0.0\" tilemapservice=\"http://tms.osgeo.org/1.0.0\">\n";
    xml += "  <Title>" + escapeXml(resource.title) + "</Title>\n";
    xml += "  <Abstract>" + escapeXml(resource.abstract) + "</Abstract>\n";
    if (!resource.attribution.empty()) {
        xml += "  <Attribution><Title>" + escapeXml(resource.attribution) + "</Title></Attribution>\n";
    }
    xml += std::string("  <SRS>") + (mercator ? "EPSG:3857" : "EPSG:4326") + "</SRS>\n";
    xml += "  <BoundingBox minx=\"" + xmlNumber(x(resource.extent.west)) + "\" miny=\"" +
           xmlNumber(y(resource.extent.south)) + "\" maxx=\"" + xmlNumber(x(resource.extent.east)) +
           "\" maxy=\"" + xmlNumber(y(resource.extent.north)) + "\"/>\n";
    const double origin = mercator ? -kMercatorHalfWidth : -180.0;
    xml += "  <Origin x=\"" + xmlNumber(origin) + "\" y=\"" + xmlNumber(mercator ? origin : -90.0) + "\"/>\n";
    xml += "  <TileFormat width=\"" + std::to_string(resource.tileWidth) + "\" height=\"" +
           std::to_string(resource.tileHeight) + "\" mime-type=\"" + escapeXml(resource.mimeType) + "\" extension=\"" +
           escapeXml(resource.extension) + "\"/>\n";
    xml += std::string("  <TileSets profile=\"") + (mercator ? "mercator" : "geodetic") + "\">\n";
    for (const TileMapResource::TileSet& set : resource.tileSets) {
        xml += "    <TileSet href=\"" + escapeXml(set.href) + "\" units-per-pixel=\"" + xmlNumber(set.unitsPerPixel) +
               "\" order=\"" + std::to_string(set.level) + "\"/>\n";
    }
    xml += "  </TileSets>\n</TileMap>\n";
    return xml;
}

} // namespace orbis::world
