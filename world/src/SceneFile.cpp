#include "orbis/world/SceneFile.h"

#include "orbis/world/CsvPoints.h"
#include "orbis/world/FileAccess.h"
#include "orbis/world/TerrainSource.h"

#include "JsonText.h"

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/SunPosition.h>

#include <nlohmann/json.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <span>
#include <sstream>
#include <system_error>

namespace orbis::world {

SceneFileError::SceneFileError(std::string origin, std::string pointer, std::size_t line, std::size_t column,
                               std::string reason)
    : Error(Diagnostic{origin, line, column, pointer, reason}.text()),
      _origin(std::move(origin)), _pointer(std::move(pointer)), _line(line), _column(column), _reason(std::move(reason))
{
}

namespace {

using Json = nlohmann::ordered_json;
using detail::describeJson;
namespace fs = std::filesystem;
using Keys = std::span<const std::string_view>;

/// No scene file needs more; deeper documents are refused before they cost memory.
constexpr std::size_t kMaxDepth = 64;
/// Sizes in pixels beyond this are typing errors.
constexpr double kMaxPixels = 1024.0;

// ---------------------------------------------------------------------------------------------
// Text helpers

std::string lowercase(std::string_view s)
{
    std::string out(s);
    std::transform(out.begin(), out.end(), out.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return out;
}

/// The first columns, quoted, for a message.
std::string joinColumns(const std::vector<std::string>& columns)
{
    constexpr std::size_t kMaxListed = 20;
    std::string list;
    for (std::size_t i = 0; i < columns.size() && i < kMaxListed; ++i) {
        list += (i == 0 ? "" : ", ") + quote(columns[i]);
    }
    if (columns.size() > kMaxListed) {
        list += " and " + std::to_string(columns.size() - kMaxListed) + " more";
    }
    return list;
}

constexpr auto kLongitudeColumns = kLongitudeColumnNames;
constexpr auto kLatitudeColumns = kLatitudeColumnNames;

bool hasColumn(const std::vector<std::string>& columns, Keys names)
{
    return std::any_of(columns.begin(), columns.end(), [&](const std::string& column) {
        const std::string lower = lowercase(column);
        return std::find(names.begin(), names.end(), lower) != names.end();
    });
}

// ---------------------------------------------------------------------------------------------
// Key tables

constexpr std::array<std::string_view, 11> kRootKeys = {"version", "width", "height", "background", "camera", "sun",
                                                        "time",    "depth", "samples", "globe",     "layers"};
constexpr std::array<std::string_view, 6> kCameraKeys = {"position", "target", "heading", "pitch", "roll", "fovY"};
constexpr std::array<std::string_view, 3> kPositionKeys = {"lon", "lat", "height"};
constexpr std::array<std::string_view, 2> kCameraPathKeys = {"version", "keyframes"};
constexpr std::array<std::string_view, 3> kKeyframeKeys = {"time", "position", "target"};
constexpr std::array<std::string_view, 2> kSunKeys = {"lon", "lat"};
constexpr std::array<std::string_view, 8> kGlobeKeys = {"method",  "texture", "nightTexture",
                                                        "grid",    "imagery", "terrain",
                                                        "maximumScreenSpaceError", "cacheMegabytes"};
constexpr std::array<std::string_view, 8> kTerrainKeys = {"source", "format", "exaggeration", "cacheFolder", "shading",
                                                          "method", "posts",  "morphFrames"};
constexpr std::array<std::string_view, 5> kShadingKeys = {"color", "heightRange", "contours", "hillshade", "water"};
constexpr std::array<std::string_view, 3> kContourKeys = {"interval", "color", "width"};
constexpr std::array<std::string_view, 2> kHillshadeKeys = {"azimuth", "altitude"};
constexpr std::array<std::string_view, 7> kTerrainFormatNames = {"quantized-mesh", "heightmap", "png16", "terrain-rgb",
                                                                 "terrarium",      "hgt",       "gdal"};
constexpr std::array<std::string_view, 11> kImageryKeys = {"source",   "scheme",    "alpha",        "brightness",
                                                          "contrast", "gamma",     "rectangle",    "minimumLevel",
                                                          "maximumLevel", "cacheFolder", "virtualTexture"};
constexpr std::array<std::string_view, 12> kVirtualTextureKeys = {
    "pageSize",  "border",            "physicalPages", "feedbackDivisor", "feedbackLatencyFrames", "priorities",
    "trilinear", "maximumAnisotropy", "lodBias",       "dynamicLodBias",  "uploadMegabytesPerFrame", "sparse"};
constexpr std::array<std::string_view, 4> kRectangleKeys = {"west", "south", "east", "north"};
constexpr std::array<std::string_view, 4> kLayerTypes = {"geojson", "points", "polyline", "model"};
constexpr std::array<std::string_view, 8> kGeoJsonKeys = {"type",  "source",          "stroke", "fill", "granularity",
                                                          "curve", "heightReference", "invalid"};
constexpr std::array<std::string_view, 5> kPointsKeys = {"type", "source", "billboard", "label", "heightReference"};
constexpr std::array<std::string_view, 7> kPolylineKeys = {"type", "positions", "width", "color",
                                                            "granularity", "curve", "heightReference"};
constexpr std::array<std::string_view, 8> kModelKeys = {"type",    "source", "position", "scale",
                                                        "heading", "pitch",  "roll",     "heightReference"};
constexpr std::array<std::string_view, 4> kStrokeKeys = {"color", "width", "outlineColor", "outlineWidth"};
constexpr std::array<std::string_view, 1> kFillKeys = {"color"};
constexpr std::array<std::string_view, 7> kBillboardKeys = {"image",  "shape",  "size", "color",
                                                            "origin", "offset", "disableDepthTestDistance"};
constexpr std::array<std::string_view, 7> kLabelKeys = {"field",        "size",         "color",
                                                        "outlineColor", "outlineWidth", "declutter",
                                                        "disableDepthTestDistance"};

template <class T>
struct Named {
    std::string_view name;
    T value;
};

constexpr std::array<Named<DepthStrategy>, 5> kDepthStrategies = {{
    {"auto", DepthStrategy::Automatic},
    {"multi-frustum", DepthStrategy::MultiFrustum}, // as depthStrategyName and the statistics say it
    {"logarithmic", DepthStrategy::Logarithmic},
    {"complementary", DepthStrategy::Complementary},
    {"single", DepthStrategy::Single},
}};
constexpr std::array<Named<GlobeMethod>, 2> kGlobeMethods = {{
    {"raycast", GlobeMethod::RayCast},
    {"tessellated", GlobeMethod::Tessellated},
}};
constexpr std::array<Named<TerrainMethod>, 2> kTerrainMethods = {{
    {"quadtree", TerrainMethod::Quadtree},
    {"clipmap", TerrainMethod::Clipmap},
}};
constexpr std::array<Named<TilingProjection>, 2> kTilingSchemes = {{
    {"geographic", TilingProjection::Geographic},
    {"webmercator", TilingProjection::WebMercator},
}};
constexpr std::array<Named<TerrainShadingDescription::Color>, 3> kShadingColors = {{
    {"base", TerrainShadingDescription::Color::Base},
    {"height", TerrainShadingDescription::Color::Height},
    {"slope", TerrainShadingDescription::Color::Slope},
}};
constexpr std::array<Named<HeightReference>, 3> kHeightReferences = {{
    {"absolute", HeightReference::Absolute},
    {"clampToGround", HeightReference::ClampToGround},
    {"relativeToGround", HeightReference::RelativeToGround},
}};
constexpr std::array<Named<bool>, 2> kInvalidFeatures = {{ // true: skip them
    {"error", false},
    {"skip", true},
}};
constexpr std::array<Named<CurveType>, 2> kCurves = {{
    {"section", CurveType::PlaneSection},
    {"geodesic", CurveType::Geodesic},
}};
constexpr std::array<Named<BillboardShape>, 2> kBillboardShapes = {{
    {"dot", BillboardShape::Dot},
    {"square", BillboardShape::Square},
}};
constexpr std::array<Named<Origin>, 9> kOrigins = {{
    {"center", Origin::Center},
    {"top", Origin::Top},
    {"bottom", Origin::Bottom},
    {"left", Origin::Left},
    {"right", Origin::Right},
    {"top-left", Origin::TopLeft},
    {"top-right", Origin::TopRight},
    {"bottom-left", Origin::BottomLeft},
    {"bottom-right", Origin::BottomRight},
}};

/// A closed, open or half-open interval of accepted numbers (infinite ends are unbounded).
struct Range {
    double minimum = -std::numeric_limits<double>::infinity();
    double maximum = std::numeric_limits<double>::infinity();
    bool minimumOpen = false;
    bool maximumOpen = false;

    bool contains(double v) const noexcept
    {
        return (minimumOpen ? v > minimum : v >= minimum) && (maximumOpen ? v < maximum : v <= maximum);
    }

    std::string text() const
    {
        if (std::isinf(maximum)) {
            return std::string(minimumOpen ? "(expected > " : "(expected >= ") + formatNumber(minimum) + ")";
        }
        return std::string(minimumOpen ? "(" : "[") + formatNumber(minimum) + ", " + formatNumber(maximum) +
               (maximumOpen ? ")" : "]");
    }
};

constexpr Range kLongitudeRange{-180.0, 180.0};
constexpr Range kLatitudeRange{-90.0, 90.0};
constexpr Range kPositivePixels{0.0, kMaxPixels, true, false};
constexpr Range kNonNegativePixels{0.0, kMaxPixels};
/// From 1,000 km underground to a billion kilometres out: anything else is a typing error (and
/// would lose all precision, or overflow when squared).
constexpr Range kHeightRange{-1.0e6, 1.0e12};
constexpr Range kPixelOffsetRange{-16384.0, 16384.0};
constexpr Range kUnitRange{0.0, 1.0};
constexpr Range kNonNegativeRange{0.0, std::numeric_limits<double>::infinity()};
constexpr Range kPositiveRange{0.0, std::numeric_limits<double>::infinity(), true, false};
/// Screen-space error in pixels: below 0.1 a view asks for millions of tiles.
constexpr Range kScreenSpaceErrorRange{0.1, 1000.0};
/// The tile cache in MiB: from a few tiles to 64 GiB.
constexpr Range kCacheMegabytesRange{1.0, 65536.0};
constexpr Range kExaggerationRange{0.0, 100.0};
/// Metres: from below the deepest trench to above the highest summit, with room for exaggeration.
constexpr Range kShadingHeightRange{-20000.0, 20000.0};
constexpr Range kContourIntervalRange{0.0, 100000.0, true, false};
constexpr Range kContourWidthRange{0.0, 64.0, true, false};
constexpr Range kAzimuthRange{-360.0, 360.0};
constexpr Range kAltitudeRange{0.0, 90.0, true, false};
/// Degrees. Finer than 0.1 would cut the world's borders into millions of vertices and its
/// countries into tens of millions of triangles; coarser than 10 lifts lines 24 km off the ground.
constexpr Range kGranularityRange{0.1, 10.0};

// ---------------------------------------------------------------------------------------------
// The reader: one scene's text, origin and folder; every value checked where it is read.

class SceneReader {
public:
    SceneReader(std::string_view text, std::string origin, fs::path baseDirectory, const SceneParseOptions& options)
        : _text(text), _origin(std::move(origin)), _baseDirectory(std::move(baseDirectory)), _options(options)
    {
    }

    SceneDescription read(const Json& root) const
    {
        if (!root.is_object()) {
            fail("", "expected a JSON object at the top of the file, got " + describeJson(root));
        }
        SceneDescription scene;
        // Each part read on its own, so that when faults are collected one does not hide the next.
        attempt([&] { scene.version = readVersion(root, kSceneFileVersion); });
        _version = scene.version;
        checkKeys(root, "", kRootKeys);
        if (const Json* width = member(root, "width")) {
            attempt([&] { scene.width = readInteger(*width, "/width", 1, 16384, "a positive integer"); });
        }
        if (const Json* height = member(root, "height")) {
            attempt([&] { scene.height = readInteger(*height, "/height", 1, 16384, "a positive integer"); });
        }
        if (const Json* background = member(root, "background")) {
            attempt([&] { scene.background = readColor(*background, "/background"); });
        }
        if (const Json* samples = member(root, "samples")) {
            attempt([&] { scene.samples = readInteger(*samples, "/samples", 1, 16, "samples per pixel"); });
        }
        if (const Json* camera = member(root, "camera")) {
            attempt([&] { scene.camera = readCamera(*camera, "/camera"); });
        }
        attempt([&] { scene.sun = readSun(root, scene.camera); });
        if (const Json* depth = member(root, "depth")) {
            attempt([&] {
                // "multifrustum", the spelling of files written before "multi-frustum", still reads.
                scene.depth = depth->is_string() && depth->get<std::string>() == "multifrustum"
                                  ? DepthStrategy::MultiFrustum
                                  : readEnum(*depth, "/depth", kDepthStrategies);
            });
        }
        if (const Json* globe = member(root, "globe")) {
            attempt([&] { scene.globe = readGlobe(*globe, "/globe"); });
        }
        if (const Json* layers = member(root, "layers")) {
            if (!layers->is_array()) {
                fail("/layers", "expected an array of layers, got " + describeJson(*layers));
            }
            for (std::size_t i = 0; i < layers->size(); ++i) {
                const std::string pointer = "/layers/" + std::to_string(i);
                attempt([&] { scene.layers.push_back(readLayer((*layers)[i], pointer)); });
            }
        }
        return scene;
    }

    std::vector<CameraKeyframe> readCameraPath(const Json& root) const
    {
        if (!root.is_object()) {
            fail("", "expected a JSON object at the top of the file, got " + describeJson(root));
        }
        readVersion(root, kCameraPathVersion);
        checkKeys(root, "", kCameraPathKeys);
        const Json& keyframes = required(root, "", "keyframes");
        if (!keyframes.is_array() || keyframes.size() < 2) {
            fail("/keyframes", "expected an array of at least two keyframes, got " + describeJson(keyframes));
        }
        std::vector<CameraKeyframe> path;
        for (std::size_t i = 0; i < keyframes.size(); ++i) {
            const std::string pointer = "/keyframes/" + std::to_string(i);
            const Json& keyframe = keyframes[i];
            expectObject(keyframe, pointer);
            checkKeys(keyframe, pointer, kKeyframeKeys);
            const double seconds = readNumber(required(keyframe, pointer, "time"), pointer + "/time", {0.0, 1e9});
            if (!path.empty() && !(seconds > path.back().seconds)) {
                fail(pointer + "/time", formatNumber(seconds) + " is not after the previous keyframe's time (" +
                                            formatNumber(path.back().seconds) + ")");
            }
            path.push_back({seconds, readPosition(required(keyframe, pointer, "position"), pointer + "/position"),
                            readPosition(required(keyframe, pointer, "target"), pointer + "/target")});
            checkEyeAvoidsTarget(path, pointer);
        }
        return path;
    }

    /// Fails where the last keyframe's eye is its target, or where the flight from the one before
    /// passes through its target: the camera would look nowhere (NaN views, blank frames).
    void checkEyeAvoidsTarget(const std::vector<CameraKeyframe>& path, const std::string& pointer) const
    {
        constexpr double kToleranceMetres = 1e-3; // as for the scene's camera
        const Ellipsoid earth = Ellipsoid::wgs84();
        const CameraKeyframe& last = path.back();
        if (glm::distance(earth.toCartesian(last.eye), earth.toCartesian(last.target)) < kToleranceMetres) {
            fail(pointer + "/target", "the target is the camera's position; the camera would look nowhere");
        }
        if (path.size() < 2) {
            return;
        }
        if (const std::optional<double> meets = eyeMeetsTarget(earth, path[path.size() - 2], last, kToleranceMetres)) {
            std::string what = "flying here from the keyframe before, the camera passes through its target at ";
            const double milliseconds = std::round(*meets * 1000.0);
            what.append(formatNumber(milliseconds / 1000.0)).append(" s and would look nowhere; move a position or a target");
            fail(pointer, what);
        }
    }

    /// Thrown by fail() when faults are collected: the value being read is given up, and the
    /// nearest attempt() goes on with the next.
    struct Abandoned {};

    /// Runs one step of reading; when faults are collected, a fault in it ends only that step.
    template <class Read>
    void attempt(Read&& read) const
    {
        try {
            read();
        } catch (const Abandoned&) {
        }
    }

private:
    enum class At { Value, Key };

    /// Reports a fault and gives up the value being read.
    [[noreturn]] void fail(const std::string& pointer, std::string reason, At at = At::Value) const
    {
        report(pointer, std::move(reason), at);
        throw Abandoned{};
    }

    /// Records a fault when they are collected (SceneParseOptions::diagnostics) and goes on;
    /// otherwise throws it as a SceneFileError.
    void report(const std::string& pointer, std::string reason, At at = At::Value) const
    {
        const detail::TextPosition position = detail::positionOf(_text, pointer, at == At::Key);
        if (!_options.diagnostics) {
            throw SceneFileError(_origin, pointer, position.line, position.column, std::move(reason));
        }
        _options.diagnostics->add({_origin, position.line, position.column, pointer, std::move(reason)});
    }


    static const Json* member(const Json& object, std::string_view key)
    {
        const auto it = object.find(key);
        return it == object.end() ? nullptr : &*it;
    }

    const Json& required(const Json& object, const std::string& pointer, std::string_view key,
                         std::string_view hint = {}) const
    {
        if (const Json* value = member(object, key)) {
            return *value;
        }
        fail(pointer, "missing required key " + quote(key) + std::string(hint));
    }

    void expectObject(const Json& value, const std::string& pointer) const
    {
        if (!value.is_object()) {
            fail(pointer, "expected an object, got " + describeJson(value));
        }
    }

    /// Reports every key (in file order) that is not one of known.
    void checkKeys(const Json& object, const std::string& pointer, Keys known) const
    {
        for (const auto& item : object.items()) {
            if (std::find(known.begin(), known.end(), item.key()) == known.end()) {
                report(detail::appendToPointer(pointer, item.key()),
                       "unknown key " + quote(item.key()) + suggestion(item.key(), known), At::Key);
            }
        }
    }

    int readVersion(const Json& root, int newest) const
    {
        const std::string reads =
            newest == 1 ? std::string("version 1") : "version " + std::to_string(newest) + " and earlier";
        const Json& version = required(root, "", "version", " (this orbis reads " + reads + ")");
        if (!version.is_number_integer()) {
            fail("/version", "expected an integer, got " + describeJson(version));
        }
        if (version.is_number_unsigned() ? version.get<std::uint64_t>() > static_cast<std::uint64_t>(newest)
                                         : version.get<std::int64_t>() > newest) {
            fail("/version", "version " + describeJson(version) + " is newer than this orbis understands (it reads " +
                                 reads + ")");
        }
        if (version.get<std::int64_t>() < 1) {
            fail("/version", describeJson(version) + " is not a version; versions start at 1");
        }
        return static_cast<int>(version.get<std::int64_t>());
    }

    int readInteger(const Json& value, const std::string& pointer, int minimum, int maximum,
                    std::string_view expected) const
    {
        if (!value.is_number_integer()) {
            fail(pointer, "expected " + std::string(expected) + ", got " + describeJson(value));
        }
        // nlohmann reads non-negative integers as unsigned, and those beyond int64 only as unsigned.
        bool inRange = false;
        if (value.is_number_unsigned()) {
            const std::uint64_t number = value.get<std::uint64_t>();
            inRange = number <= static_cast<std::uint64_t>(maximum) &&
                      (minimum <= 0 || number >= static_cast<std::uint64_t>(minimum));
        } else {
            const std::int64_t number = value.get<std::int64_t>();
            inRange = number >= minimum && number <= maximum;
        }
        if (!inRange) {
            fail(pointer, describeJson(value) + " is out of range [" + std::to_string(minimum) + ", " +
                              std::to_string(maximum) + "]");
        }
        return static_cast<int>(value.get<std::int64_t>());
    }

    double readNumber(const Json& value, const std::string& pointer, const Range& range = {}) const
    {
        if (!value.is_number()) {
            fail(pointer, "expected a number, got " + describeJson(value));
        }
        const double number = value.get<double>();
        if (!std::isfinite(number)) {
            fail(pointer, "expected a finite number, got " + describeJson(value));
        }
        if (!range.contains(number)) {
            fail(pointer, describeJson(value) + " is out of range " + range.text());
        }
        return number;
    }

    double readDegrees(const Json& value, const std::string& pointer, const Range& range) const
    {
        return toRadians(readNumber(value, pointer, range));
    }

    bool readBoolean(const Json& value, const std::string& pointer) const
    {
        if (!value.is_boolean()) {
            fail(pointer, "expected true or false, got " + describeJson(value));
        }
        return value.get<bool>();
    }

    const std::string& readString(const Json& value, const std::string& pointer, std::string_view expected) const
    {
        if (!value.is_string()) {
            fail(pointer, "expected " + std::string(expected) + ", got " + describeJson(value));
        }
        return value.get_ref<const std::string&>();
    }

    template <class T, std::size_t N>
    T readEnum(const Json& value, const std::string& pointer, const std::array<Named<T>, N>& table) const
    {
        std::vector<std::string_view> names;
        for (const Named<T>& entry : table) {
            names.push_back(entry.name);
        }
        const std::string& text = readString(value, pointer, "one of " + quoteList(names));
        for (const Named<T>& entry : table) {
            if (entry.name == text) {
                return entry.value;
            }
        }
        fail(pointer, "unknown value " + quote(text) + suggestion(text, names));
    }

    glm::vec4 readColor(const Json& value, const std::string& pointer) const
    {
        constexpr std::string_view kExpected = "a color \"#rrggbb\" or \"#rrggbbaa\"";
        const std::string& text = readString(value, pointer, kExpected);
        const bool hex = std::all_of(text.begin() + (text.empty() ? 0 : 1), text.end(),
                                     [](unsigned char c) { return std::isxdigit(c) != 0; });
        if (!text.starts_with('#') || (text.size() != 7 && text.size() != 9) || !hex) {
            fail(pointer, "expected " + std::string(kExpected) + ", got " + quote(text));
        }
        std::array<float, 4> channels{0.0f, 0.0f, 0.0f, 1.0f};
        for (std::size_t i = 0; 1 + 2 * i < text.size(); ++i) {
            unsigned byte = 0;
            std::from_chars(text.data() + 1 + 2 * i, text.data() + 3 + 2 * i, byte, 16);
            channels[i] = static_cast<float>(byte) / 255.0f;
        }
        return {channels[0], channels[1], channels[2], channels[3]};
    }

    glm::dvec2 readPixelOffset(const Json& value, const std::string& pointer) const
    {
        if (!value.is_array() || value.size() != 2) {
            fail(pointer, "expected [x, y] in pixels, got " + describeJson(value));
        }
        return {readNumber(value[0], pointer + "/0", kPixelOffsetRange),
                readNumber(value[1], pointer + "/1", kPixelOffsetRange)};
    }

    /// {"lon": deg, "lat": deg, "height": m}; height optional (0) when withHeight.
    Geodetic3D readPosition(const Json& value, const std::string& pointer, bool withHeight = true) const
    {
        expectObject(value, pointer);
        checkKeys(value, pointer, withHeight ? Keys(kPositionKeys) : Keys(kSunKeys));
        Geodetic3D position;
        position.longitude = readDegrees(required(value, pointer, "lon"), pointer + "/lon", kLongitudeRange);
        position.latitude = readDegrees(required(value, pointer, "lat"), pointer + "/lat", kLatitudeRange);
        if (const Json* height = withHeight ? member(value, "height") : nullptr) {
            position.height = readNumber(*height, pointer + "/height", kHeightRange);
        }
        return position;
    }

    // ------------------------------------------------------------------------------------------
    // Paths

    /// A path string resolved against the scene's folder, lexically normalised.
    fs::path readPath(const Json& value, const std::string& pointer) const
    {
        const std::string& text = readString(value, pointer, "a path");
        if (text.empty()) {
            fail(pointer, "expected a path, got an empty string");
        }
        if (text.find('\0') != std::string::npos) {
            fail(pointer, "a path cannot contain a NUL character");
        }
        const fs::path path(text);
        return (path.is_absolute() ? path : _baseDirectory / path).lexically_normal();
    }

    /// "file "x" not found (looked for /abs/x)"; the resolved path only when it adds something.
    std::string notFound(const Json& value, const fs::path& resolved, std::string_view what = "file") const
    {
        const std::string& written = value.get_ref<const std::string&>();
        std::string reason = std::string(what) + " " + quote(written) + " not found";
        if (fs::path(written) != resolved) {
            reason += " (looked for " + quote(resolved.string()) + ")";
        }
        return reason;
    }

    /// Fails when a sandbox is set (setFileSandbox) and resolved lies outside it.
    void requireInSandbox(const std::string& pointer, const fs::path& resolved) const
    {
        try {
            resolveInSandbox(resolved, "file");
        } catch (const Error& error) {
            fail(pointer, error.what());
        }
    }

    /// Fails unless resolved is a regular file (when files are checked).
    void requireFile(const Json& value, const std::string& pointer, const fs::path& resolved) const
    {
        if (!_options.checkFiles) {
            return;
        }
        requireInSandbox(pointer, resolved);
        std::error_code error;
        const fs::file_status status = fs::status(resolved, error);
        if (status.type() == fs::file_type::not_found) {
            fail(pointer, notFound(value, resolved));
        }
        if (error) {
            fail(pointer, quote(value.get_ref<const std::string&>()) + " cannot be accessed: " + error.message());
        }
        if (status.type() == fs::file_type::directory) {
            fail(pointer, quote(value.get_ref<const std::string&>()) + " is a folder; expected a file");
        }
        if (status.type() != fs::file_type::regular) {
            fail(pointer, quote(value.get_ref<const std::string&>()) + " is not a regular file");
        }
    }

    /// Fails unless the path ends in one of the extensions (compared ignoring case).
    void requireExtension(const std::string& pointer, const fs::path& resolved, Keys extensions,
                          std::string_view expected) const
    {
        const std::string extension = lowercase(resolved.extension().string());
        if (std::find(extensions.begin(), extensions.end(), extension) == extensions.end()) {
            fail(pointer, "expected " + std::string(expected) + ", got " + quote(resolved.filename().string()));
        }
    }

    // ------------------------------------------------------------------------------------------
    // Camera and Sun

    CameraDescription readCamera(const Json& value, const std::string& pointer) const
    {
        expectObject(value, pointer);
        checkKeys(value, pointer, kCameraKeys);
        CameraDescription camera;
        if (const Json* position = member(value, "position")) {
            attempt([&] { camera.position = readPosition(*position, pointer + "/position"); });
        }
        const Json* target = member(value, "target");
        const bool hasOrientation = member(value, "heading") || member(value, "pitch") || member(value, "roll");
        if (target != nullptr && hasOrientation) {
            const std::string_view key = member(value, "heading") ? "heading" : member(value, "pitch") ? "pitch" : "roll";
            fail(detail::appendToPointer(pointer, key),
                 "\"target\" and \"heading\"/\"pitch\"/\"roll\" both aim the camera; give one or the other", At::Key);
        }
        if (target != nullptr) {
            const Geodetic3D targetPosition = readPosition(*target, pointer + "/target");
            const Ellipsoid earth = Ellipsoid::wgs84();
            if (glm::distance(earth.toCartesian(targetPosition), earth.toCartesian(camera.position)) < 1e-3) {
                fail(pointer + "/target", "the target is the camera's position; the camera would look nowhere");
            }
            camera.aim = targetPosition;
        } else {
            camera.aim = readOrientation(value, pointer, HeadingPitchRoll{0.0, -kHalfPi, 0.0});
        }
        if (const Json* fieldOfView = member(value, "fovY")) {
            attempt([&] {
                camera.fieldOfViewY = readDegrees(*fieldOfView, pointer + "/fovY", Range{0.0, 180.0, true, true});
            });
        }
        return camera;
    }

    /// heading, pitch and roll keys of an object, in degrees; absent ones keep the defaults.
    HeadingPitchRoll readOrientation(const Json& object, const std::string& pointer, HeadingPitchRoll defaults) const
    {
        HeadingPitchRoll orientation = defaults;
        if (const Json* heading = member(object, "heading")) {
            orientation.heading = readDegrees(*heading, pointer + "/heading", Range{-360.0, 360.0});
        }
        if (const Json* pitch = member(object, "pitch")) {
            orientation.pitch = readDegrees(*pitch, pointer + "/pitch", Range{-90.0, 90.0});
        }
        if (const Json* roll = member(object, "roll")) {
            orientation.roll = readDegrees(*roll, pointer + "/roll", Range{-180.0, 180.0});
        }
        return orientation;
    }

    SunDescription readSun(const Json& root, const CameraDescription& camera) const
    {
        const Json* sun = member(root, "sun");
        const Json* time = member(root, "time");
        SunDescription result;
        if (sun != nullptr && time != nullptr) {
            fail("/time", "\"sun\" and \"time\" both place the Sun; give one or the other", At::Key);
        }
        if (sun != nullptr) {
            const Geodetic3D point = readPosition(*sun, "/sun", false);
            result.source = SunSource::Position;
            result.subsolarPoint = point.toGeodetic2D();
            result.directionEarthFixed = Ellipsoid::geodeticSurfaceNormal(result.subsolarPoint);
            return result;
        }
        glm::dvec3 direction;
        if (time != nullptr) {
            constexpr std::string_view kExpected = "a UTC time \"YYYY-MM-DDTHH:MM:SSZ\"";
            const std::string& text = readString(*time, "/time", kExpected);
            const std::optional<std::chrono::sys_seconds> utc = parseUtcTime(text);
            if (!utc) {
                fail("/time", "expected " + std::string(kExpected) + ", got " + quote(text));
            }
            result.source = SunSource::Time;
            result.time = *utc;
            direction = sunDirectionEarthFixed(*utc);
        } else {
            result.source = SunSource::Camera;
            direction = Ellipsoid::wgs84().toCartesian(camera.position);
        }
        const double length = glm::length(direction);
        result.directionEarthFixed = length > 0.0 ? direction / length : glm::dvec3(1.0, 0.0, 0.0);
        const glm::dvec3& d = result.directionEarthFixed;
        result.subsolarPoint = {std::atan2(d.y, d.x), std::asin(std::clamp(d.z, -1.0, 1.0))};
        return result;
    }

    // ------------------------------------------------------------------------------------------
    // Globe

    GlobeDescription readGlobe(const Json& value, const std::string& pointer) const
    {
        expectObject(value, pointer);
        checkKeys(value, pointer, kGlobeKeys);
        GlobeDescription globe;
        if (const Json* method = member(value, "method")) {
            attempt([&] { globe.method = readEnum(*method, pointer + "/method", kGlobeMethods); });
        }
        if (const Json* texture = member(value, "texture")) {
            attempt([&] { globe.texture = readGlobeTexture(*texture, pointer + "/texture"); });
        }
        if (const Json* night = member(value, "nightTexture")) {
            attempt([&] {
                const fs::path path = readPath(*night, pointer + "/nightTexture");
                requireFile(*night, pointer + "/nightTexture", path);
                globe.nightTexture = path;
            });
        }
        if (const Json* grid = member(value, "grid")) {
            attempt([&] { globe.grid = readBoolean(*grid, pointer + "/grid"); });
        }
        if (const Json* imagery = member(value, "imagery")) {
            const std::string imageryPointer = pointer + "/imagery";
            if (!imagery->is_array() || imagery->empty()) {
                fail(imageryPointer, "expected an array of imagery layers, got " + describeJson(*imagery));
            }
            if (globe.texture || globe.nightTexture) {
                fail(imageryPointer, "a globe of tiled imagery has no \"texture\" or \"nightTexture\": give one or the "
                                     "other");
            }
            for (std::size_t i = 0; i < imagery->size(); ++i) {
                attempt([&] {
                    std::string layerPointer = imageryPointer;
                    layerPointer.append("/").append(std::to_string(i));
                    const ImageryLayerDescription& layer = globe.imagery.emplace_back(
                        readImageryLayer((*imagery)[i], layerPointer));
                    if (layer.virtualTexture && imagery->size() > 1) {
                        fail(layerPointer + "/virtualTexture", "a virtual texture must be the globe's only imagery layer");
                    }
                });
            }
        }
        if (const Json* terrain = member(value, "terrain")) {
            if (globe.texture || globe.nightTexture) {
                fail(pointer + "/terrain", "a globe with terrain has no \"texture\" or \"nightTexture\": give its "
                                           "imagery as \"imagery\" layers");
            }
            attempt([&] { globe.terrain = readTerrain(*terrain, pointer + "/terrain"); });
            if (std::any_of(globe.imagery.begin(), globe.imagery.end(),
                            [](const ImageryLayerDescription& layer) { return layer.virtualTexture.has_value(); })) {
                fail(pointer + "/terrain", "a virtual texture is drawn on the ellipsoid's surface: no \"terrain\" with it");
            }
        }
        if (const Json* error = member(value, "maximumScreenSpaceError")) {
            attempt([&] {
                globe.maximumScreenSpaceError =
                    readNumber(*error, pointer + "/maximumScreenSpaceError", kScreenSpaceErrorRange);
            });
        }
        if (const Json* cache = member(value, "cacheMegabytes")) {
            attempt([&] { globe.cacheMegabytes = readNumber(*cache, pointer + "/cacheMegabytes", kCacheMegabytesRange); });
        }
        return globe;
    }

    /// A tile source's "source": an http(s) URL as it is, or a path resolved against the file's
    /// folder (which must exist unless it is a {z}/{x}/{y} template).
    std::string readTileSourceLocation(const Json& value, const std::string& pointer) const
    {
        const Json& source = required(value, pointer, "source");
        const std::string& text = readString(source, pointer + "/source", "a path or an http(s) URL");
        if (text.starts_with("http://") || text.starts_with("https://")) {
            return text;
        }
        const fs::path path = readPath(source, pointer + "/source");
        // A template names its tiles, not one file; a folder or a file must be there.
        if (_options.checkFiles && text.find('{') == std::string::npos) {
            std::error_code error;
            if (!fs::exists(path, error)) {
                fail(pointer + "/source", notFound(source, path, "tile source"));
            }
        }
        return path.string();
    }

    TerrainDescription readTerrain(const Json& value, const std::string& pointer) const
    {
        expectObject(value, pointer);
        checkKeys(value, pointer, kTerrainKeys);
        TerrainDescription terrain;
        terrain.source = readTileSourceLocation(value, pointer);
        if (const Json* format = member(value, "format")) {
            terrain.format = readString(*format, pointer + "/format", "a terrain format");
            if (std::find(kTerrainFormatNames.begin(), kTerrainFormatNames.end(), terrain.format) ==
                kTerrainFormatNames.end()) {
                fail(pointer + "/format", quote(terrain.format) + " is not a terrain format (" +
                                              std::string(kTerrainFormats) + ")");
            }
        }
        if (const Json* exaggeration = member(value, "exaggeration")) {
            terrain.exaggeration = readNumber(*exaggeration, pointer + "/exaggeration", kExaggerationRange);
        }
        if (const Json* cache = member(value, "cacheFolder")) {
            terrain.cacheFolder = readPath(*cache, pointer + "/cacheFolder");
        }
        if (const Json* shading = member(value, "shading")) {
            terrain.shading = readShading(*shading, pointer + "/shading");
        }
        if (const Json* method = member(value, "method")) {
            terrain.method = readEnum(*method, pointer + "/method", kTerrainMethods);
        }
        if (const Json* posts = member(value, "posts")) {
            terrain.posts = readInteger(*posts, pointer + "/posts", 15, 1023, "an integer 2^k - 1 from 15 to 1023");
            if (((terrain.posts + 1) & terrain.posts) != 0) {
                fail(pointer + "/posts", std::to_string(terrain.posts) + " is not 2^k - 1 (15, 31, 63, 127, 255, 511, 1023)");
            }
        }
        if (const Json* frames = member(value, "morphFrames")) {
            terrain.morphFrames = readInteger(*frames, pointer + "/morphFrames", 0, 600, "a number of frames");
        }
        return terrain;
    }

    TerrainShadingDescription readShading(const Json& value, const std::string& pointer) const
    {
        expectObject(value, pointer);
        checkKeys(value, pointer, kShadingKeys);
        TerrainShadingDescription shading;
        if (const Json* color = member(value, "color")) {
            shading.color = readEnum(*color, pointer + "/color", kShadingColors);
        }
        if (const Json* range = member(value, "heightRange")) {
            const std::string rangePointer = pointer + "/heightRange";
            if (!range->is_array() || range->size() != 2) {
                fail(rangePointer, "expected [lowest, highest] in metres, got " + describeJson(*range));
            }
            shading.minimumHeight = readNumber((*range)[0], rangePointer + "/0", kShadingHeightRange);
            shading.maximumHeight = readNumber((*range)[1], rangePointer + "/1", kShadingHeightRange);
            if (!(shading.minimumHeight < shading.maximumHeight)) {
                fail(rangePointer, "the lowest height must be below the highest, got " + describeJson(*range));
            }
        }
        if (const Json* contours = member(value, "contours")) {
            const std::string contoursPointer = pointer + "/contours";
            expectObject(*contours, contoursPointer);
            checkKeys(*contours, contoursPointer, kContourKeys);
            shading.contourInterval = readNumber(required(*contours, contoursPointer, "interval"),
                                                 contoursPointer + "/interval", kContourIntervalRange);
            if (const Json* color = member(*contours, "color")) {
                shading.contourColor = readColor(*color, contoursPointer + "/color");
            }
            if (const Json* width = member(*contours, "width")) {
                shading.contourWidth = readNumber(*width, contoursPointer + "/width", kContourWidthRange);
            }
        }
        if (const Json* hillshade = member(value, "hillshade")) {
            const std::string hillshadePointer = pointer + "/hillshade";
            if (hillshade->is_boolean()) {
                shading.hillshade = readBoolean(*hillshade, hillshadePointer);
            } else {
                if (!hillshade->is_object()) {
                    fail(hillshadePointer, "expected true, false or {\"azimuth\": degrees, \"altitude\": degrees}, got " +
                                               describeJson(*hillshade));
                }
                checkKeys(*hillshade, hillshadePointer, kHillshadeKeys);
                shading.hillshade = true;
                if (const Json* azimuth = member(*hillshade, "azimuth")) {
                    shading.hillshadeAzimuth = readNumber(*azimuth, hillshadePointer + "/azimuth", kAzimuthRange);
                }
                if (const Json* altitude = member(*hillshade, "altitude")) {
                    shading.hillshadeAltitude = readNumber(*altitude, hillshadePointer + "/altitude", kAltitudeRange);
                }
            }
        }
        if (const Json* water = member(value, "water")) {
            shading.water = readBoolean(*water, pointer + "/water");
        }
        return shading;
    }

    ImageryLayerDescription readImageryLayer(const Json& value, const std::string& pointer) const
    {
        expectObject(value, pointer);
        checkKeys(value, pointer, kImageryKeys);
        ImageryLayerDescription layer;
        layer.source = readTileSourceLocation(value, pointer);
        if (const Json* scheme = member(value, "scheme")) {
            layer.scheme = readEnum(*scheme, pointer + "/scheme", kTilingSchemes);
        }
        if (const Json* alpha = member(value, "alpha")) {
            layer.alpha = readNumber(*alpha, pointer + "/alpha", kUnitRange);
        }
        if (const Json* brightness = member(value, "brightness")) {
            layer.brightness = readNumber(*brightness, pointer + "/brightness", kNonNegativeRange);
        }
        if (const Json* contrast = member(value, "contrast")) {
            layer.contrast = readNumber(*contrast, pointer + "/contrast", kNonNegativeRange);
        }
        if (const Json* gamma = member(value, "gamma")) {
            layer.gamma = readNumber(*gamma, pointer + "/gamma", kPositiveRange);
        }
        if (const Json* rectangle = member(value, "rectangle")) {
            const std::string rectanglePointer = pointer + "/rectangle";
            expectObject(*rectangle, rectanglePointer);
            checkKeys(*rectangle, rectanglePointer, kRectangleKeys);
            GeodeticExtent extent;
            extent.west = readDegrees(required(*rectangle, rectanglePointer, "west"), rectanglePointer + "/west",
                                      kLongitudeRange);
            extent.south = readDegrees(required(*rectangle, rectanglePointer, "south"), rectanglePointer + "/south",
                                       kLatitudeRange);
            extent.east = readDegrees(required(*rectangle, rectanglePointer, "east"), rectanglePointer + "/east",
                                      kLongitudeRange);
            extent.north = readDegrees(required(*rectangle, rectanglePointer, "north"), rectanglePointer + "/north",
                                       kLatitudeRange);
            if (extent.north <= extent.south) {
                fail(rectanglePointer, "north must be above south");
            }
            layer.rectangle = extent; // east below west crosses the antimeridian
        }
        auto readLevel = [&](const char* key) -> std::optional<std::uint32_t> {
            if (const Json* level = member(value, key)) {
                return static_cast<std::uint32_t>(
                    readInteger(*level, pointer + "/" + key, 0, static_cast<int>(kMaximumTileLevel), "a level 0 to 30"));
            }
            return std::nullopt;
        };
        layer.minimumLevel = readLevel("minimumLevel");
        layer.maximumLevel = readLevel("maximumLevel");
        if (layer.minimumLevel && layer.maximumLevel && *layer.minimumLevel > *layer.maximumLevel) {
            fail(pointer + "/minimumLevel", "the minimum level is above the maximum level");
        }
        if (const Json* cache = member(value, "cacheFolder")) {
            layer.cacheFolder = readPath(*cache, pointer + "/cacheFolder");
        }
        if (const Json* virtualTexture = member(value, "virtualTexture")) {
            if (layer.rectangle) {
                fail(pointer + "/virtualTexture", "a virtual texture covers the whole globe: give it no \"rectangle\"");
            }
            layer.virtualTexture = readVirtualTexture(*virtualTexture, pointer + "/virtualTexture");
        }
        return layer;
    }

    VirtualTextureDescription readVirtualTexture(const Json& value, const std::string& pointer) const
    {
        expectObject(value, pointer);
        checkKeys(value, pointer, kVirtualTextureKeys);
        VirtualTextureDescription vt;
        auto integer = [&](const char* key, int& target, int minimum, int maximum) {
            if (const Json* member_ = member(value, key)) {
                target = readInteger(*member_, pointer + "/" + key, minimum, maximum,
                                     "an integer " + std::to_string(minimum) + " to " + std::to_string(maximum));
            }
        };
        auto boolean = [&](const char* key, bool& target) {
            if (const Json* member_ = member(value, key)) {
                target = readBoolean(*member_, pointer + "/" + key);
            }
        };
        integer("pageSize", vt.pageSize, 16, 1024);
        if (!std::has_single_bit(static_cast<unsigned>(vt.pageSize))) {
            fail(pointer + "/pageSize", std::to_string(vt.pageSize) + " is not a power of two (16, 32, ... 1024)");
        }
        integer("border", vt.border, 0, vt.pageSize / 4);
        integer("physicalPages", vt.physicalPages, 4, 65536);
        integer("feedbackDivisor", vt.feedbackDivisor, 1, 16);
        integer("feedbackLatencyFrames", vt.feedbackLatencyFrames, 1, 8);
        boolean("priorities", vt.priorities);
        boolean("trilinear", vt.trilinear);
        if (const Json* anisotropy = member(value, "maximumAnisotropy")) {
            vt.maximumAnisotropy = readNumber(*anisotropy, pointer + "/maximumAnisotropy",
                                              {1.0, std::max(1.0, 2.0 * vt.border)});
        }
        if (const Json* bias = member(value, "lodBias")) {
            vt.lodBias = readNumber(*bias, pointer + "/lodBias", {-8.0, 16.0});
        }
        boolean("dynamicLodBias", vt.dynamicLodBias);
        boolean("sparse", vt.sparse);
        if (vt.sparse && vt.maximumAnisotropy > 1.0) {
            fail(pointer + "/maximumAnisotropy", "the sparse path filters trilinearly or with the nearest level: "
                                                 "maximumAnisotropy must be 1 with \"sparse\": true");
        }
        if (const Json* upload = member(value, "uploadMegabytesPerFrame")) {
            vt.uploadMegabytesPerFrame = readNumber(*upload, pointer + "/uploadMegabytesPerFrame", {0.0, 4096.0, true});
        }
        return vt;
    }

    GlobeTexture readGlobeTexture(const Json& value, const std::string& pointer) const
    {
        GlobeTexture texture{readPath(value, pointer), GlobeTexture::Kind::Image};
        if (!_options.checkFiles) {
            texture.kind = texture.path.has_extension() ? GlobeTexture::Kind::Image : GlobeTexture::Kind::TileMapService;
            return texture;
        }
        requireInSandbox(pointer, texture.path);
        std::error_code error;
        if (fs::is_directory(texture.path, error)) {
            if (!fs::is_regular_file(texture.path / "tilemapresource.xml", error)) {
                fail(pointer, "the folder " + quote(value.get_ref<const std::string&>()) +
                                  " is not a TMS tile set: it has no tilemapresource.xml");
            }
            texture.kind = GlobeTexture::Kind::TileMapService;
            return texture;
        }
        requireFile(value, pointer, texture.path);
        return texture;
    }

    // ------------------------------------------------------------------------------------------
    // Layers

    LayerDescription readLayer(const Json& value, const std::string& pointer) const
    {
        expectObject(value, pointer);
        const Json& type = required(value, pointer, "type", " (one of " + quoteList(kLayerTypes) + ")");
        const std::string& name = readString(type, pointer + "/type", "one of " + quoteList(kLayerTypes));
        if (name == "geojson") {
            return readGeoJsonLayer(value, pointer);
        }
        if (name == "points") {
            return readPointsLayer(value, pointer);
        }
        if (name == "polyline") {
            return readPolylineLayer(value, pointer);
        }
        if (name == "model") {
            return readModelLayer(value, pointer);
        }
        fail(pointer + "/type", "unknown layer type " + quote(name) + suggestion(name, kLayerTypes));
    }

    GeoJsonLayer readGeoJsonLayer(const Json& value, const std::string& pointer) const
    {
        checkKeys(value, pointer, kGeoJsonKeys);
        GeoJsonLayer layer;
        const Json& source = required(value, pointer, "source");
        layer.source = readPath(source, pointer + "/source");
        requireExtension(pointer + "/source", layer.source, std::array<std::string_view, 2>{".geojson", ".json"},
                         "a .geojson or .json file");
        requireFile(source, pointer + "/source", layer.source);
        if (const Json* stroke = member(value, "stroke")) {
            attempt([&] { layer.stroke = readStroke(*stroke, pointer + "/stroke"); });
        }
        if (const Json* fill = member(value, "fill")) {
            attempt([&] {
                const std::string fillPointer = pointer + "/fill";
                expectObject(*fill, fillPointer);
                checkKeys(*fill, fillPointer, kFillKeys);
                layer.fill = FillStyle{};
                if (const Json* color = member(*fill, "color")) {
                    layer.fill->color = readColor(*color, fillPointer + "/color");
                }
            });
        }
        if (!layer.stroke && !layer.fill) {
            layer.stroke = StrokeStyle{};
        }
        attempt([&] { layer.path = readLinePath(value, pointer); });
        readHeightReference(value, pointer, layer.heightReference);
        if (const Json* invalid = member(value, "invalid")) {
            attempt([&] { layer.skipInvalid = readEnum(*invalid, pointer + "/invalid", kInvalidFeatures); });
        }
        return layer;
    }

    StrokeStyle readStroke(const Json& value, const std::string& pointer) const
    {
        expectObject(value, pointer);
        checkKeys(value, pointer, kStrokeKeys);
        StrokeStyle stroke;
        if (const Json* color = member(value, "color")) {
            stroke.color = readColor(*color, pointer + "/color");
        }
        if (const Json* width = member(value, "width")) {
            stroke.widthPixels = readNumber(*width, pointer + "/width", kPositivePixels);
        }
        if (const Json* color = member(value, "outlineColor")) {
            stroke.outlineColor = readColor(*color, pointer + "/outlineColor");
        }
        if (const Json* width = member(value, "outlineWidth")) {
            stroke.outlineWidthPixels = readNumber(*width, pointer + "/outlineWidth", kNonNegativePixels);
        }
        return stroke;
    }

    PointsLayer readPointsLayer(const Json& value, const std::string& pointer) const
    {
        checkKeys(value, pointer, kPointsKeys);
        PointsLayer layer;
        const std::string sourcePointer = pointer + "/source";
        const Json& source = required(value, pointer, "source");
        layer.source = readPath(source, sourcePointer);
        requireExtension(sourcePointer, layer.source, std::array<std::string_view, 3>{".csv", ".geojson", ".json"},
                         "a .csv, .geojson or .json file");
        layer.format = lowercase(layer.source.extension().string()) == ".csv" ? PointsLayer::Format::Csv
                                                                               : PointsLayer::Format::GeoJson;
        requireFile(source, sourcePointer, layer.source);
        layer.billboard.disableDepthTestDistance = defaultDepthTestDistance();
        if (const Json* billboard = member(value, "billboard")) {
            attempt([&] { layer.billboard = readBillboard(*billboard, pointer + "/billboard"); });
        }
        if (const Json* label = member(value, "label")) {
            attempt([&] { layer.label = readLabel(*label, pointer + "/label"); });
        }
        readHeightReference(value, pointer, layer.heightReference);
        if (_options.checkFiles && layer.format == PointsLayer::Format::Csv) {
            checkCsvColumns(source, sourcePointer, layer, pointer + "/label/field");
        }
        return layer;
    }

    /// The CSV must name its longitude and latitude columns, and the label's field.
    void checkCsvColumns(const Json& source, const std::string& sourcePointer, const PointsLayer& layer,
                         const std::string& fieldPointer) const
    {
        const std::string written = quote(source.get_ref<const std::string&>());
        std::vector<std::string> columns;
        try {
            columns = readCsvHeader(layer.source);
        } catch (const Error& error) {
            fail(sourcePointer, error.what());
        }
        if (!hasColumn(columns, kLongitudeColumns)) {
            fail(sourcePointer, written + " has no longitude column (one of " + quoteList(kLongitudeColumns) +
                                    "); its columns are " + joinColumns(columns));
        }
        if (!hasColumn(columns, kLatitudeColumns)) {
            fail(sourcePointer, written + " has no latitude column (one of " + quoteList(kLatitudeColumns) +
                                    "); its columns are " + joinColumns(columns));
        }
        if (layer.label && std::find(columns.begin(), columns.end(), layer.label->field) == columns.end()) {
            std::vector<std::string_view> names(columns.begin(), columns.end());
            const auto closest = closestWord(layer.label->field, names);
            fail(fieldPointer, "no column " + quote(layer.label->field) + " in " + written +
                                   (closest ? " (did you mean " + quote(*closest) + "?)"
                                            : "; its columns are " + joinColumns(columns)));
        }
    }

    BillboardStyle readBillboard(const Json& value, const std::string& pointer) const
    {
        expectObject(value, pointer);
        checkKeys(value, pointer, kBillboardKeys);
        BillboardStyle billboard;
        if (const Json* image = member(value, "image")) {
            const fs::path path = readPath(*image, pointer + "/image");
            requireFile(*image, pointer + "/image", path);
            billboard.image = path;
        }
        if (const Json* shape = member(value, "shape")) {
            if (billboard.image) {
                fail(pointer + "/shape", "give either \"image\" or \"shape\", not both");
            }
            billboard.shape = readEnum(*shape, pointer + "/shape", kBillboardShapes);
        }
        if (const Json* size = member(value, "size")) {
            billboard.sizePixels = readNumber(*size, pointer + "/size", kPositivePixels);
        }
        if (const Json* color = member(value, "color")) {
            billboard.color = readColor(*color, pointer + "/color");
        }
        if (const Json* origin = member(value, "origin")) {
            billboard.origin = readEnum(*origin, pointer + "/origin", kOrigins);
        }
        if (const Json* offset = member(value, "offset")) {
            billboard.offsetPixels = readPixelOffset(*offset, pointer + "/offset");
        }
        billboard.disableDepthTestDistance = defaultDepthTestDistance();
        if (const Json* distance = member(value, "disableDepthTestDistance")) {
            billboard.disableDepthTestDistance = readDepthTestDistance(*distance, pointer + "/disableDepthTestDistance");
        }
        return billboard;
    }

    LabelStyle readLabel(const Json& value, const std::string& pointer) const
    {
        expectObject(value, pointer);
        checkKeys(value, pointer, kLabelKeys);
        LabelStyle label;
        label.field = readString(required(value, pointer, "field"), pointer + "/field", "a column or property name");
        if (label.field.empty()) {
            fail(pointer + "/field", "expected a column or property name, got an empty string");
        }
        if (const Json* size = member(value, "size")) {
            label.fontSizePixels = readNumber(*size, pointer + "/size", kPositivePixels);
        }
        if (const Json* color = member(value, "color")) {
            label.color = readColor(*color, pointer + "/color");
        }
        if (const Json* color = member(value, "outlineColor")) {
            label.outlineColor = readColor(*color, pointer + "/outlineColor");
        }
        if (const Json* width = member(value, "outlineWidth")) {
            label.outlineWidthPixels = readNumber(*width, pointer + "/outlineWidth", kNonNegativePixels);
        }
        if (const Json* declutter = member(value, "declutter")) {
            label.declutter = readBoolean(*declutter, pointer + "/declutter");
        }
        label.disableDepthTestDistance = defaultDepthTestDistance();
        if (const Json* distance = member(value, "disableDepthTestDistance")) {
            label.disableDepthTestDistance = readDepthTestDistance(*distance, pointer + "/disableDepthTestDistance");
        }
        return label;
    }

    /// Version 1 files were written when markers and labels were never depth-tested.
    double defaultDepthTestDistance() const
    {
        return _version >= 2 ? 0.0 : std::numeric_limits<double>::infinity();
    }

    /// Metres (>= 0), or "always": never depth-tested.
    double readDepthTestDistance(const Json& value, const std::string& pointer) const
    {
        constexpr std::string_view kExpected = "a distance in metres or \"always\"";
        if (value.is_string()) {
            const std::string& text = value.get<std::string>();
            if (text != "always") {
                fail(pointer, "unknown value " + quote(text) + "; expected " + std::string(kExpected));
            }
            return std::numeric_limits<double>::infinity();
        }
        if (!value.is_number()) {
            fail(pointer, "expected " + std::string(kExpected) + ", got " + describeJson(value));
        }
        return readNumber(value, pointer, kNonNegativeRange);
    }

    PolylineLayer readPolylineLayer(const Json& value, const std::string& pointer) const
    {
        checkKeys(value, pointer, kPolylineKeys);
        PolylineLayer layer;
        const std::string positionsPointer = pointer + "/positions";
        const Json& positions = required(value, pointer, "positions");
        if (!positions.is_array() || positions.size() < 2) {
            fail(positionsPointer, "expected an array of at least two [lon, lat] or [lon, lat, height], got " +
                                       describeJson(positions));
        }
        for (std::size_t i = 0; i < positions.size(); ++i) {
            const Json& position = positions[i];
            const std::string positionPointer = positionsPointer + "/" + std::to_string(i);
            if (!position.is_array() || position.size() < 2 || position.size() > 3) {
                fail(positionPointer, "expected [lon, lat] or [lon, lat, height], got " + describeJson(position));
            }
            Geodetic3D geodetic;
            geodetic.longitude = readDegrees(position[0], positionPointer + "/0", kLongitudeRange);
            geodetic.latitude = readDegrees(position[1], positionPointer + "/1", kLatitudeRange);
            if (position.size() == 3) {
                geodetic.height = readNumber(position[2], positionPointer + "/2", kHeightRange);
            }
            layer.positions.push_back(geodetic);
        }
        if (const Json* width = member(value, "width")) {
            attempt([&] { layer.widthPixels = readNumber(*width, pointer + "/width", kPositivePixels); });
        }
        if (const Json* color = member(value, "color")) {
            attempt([&] { layer.color = readColor(*color, pointer + "/color"); });
        }
        attempt([&] { layer.path = readLinePath(value, pointer); });
        readHeightReference(value, pointer, layer.heightReference);
        return layer;
    }

    void readHeightReference(const Json& layer, const std::string& pointer, HeightReference& reference) const
    {
        if (const Json* value = member(layer, "heightReference")) {
            attempt([&] { reference = readEnum(*value, pointer + "/heightReference", kHeightReferences); });
        }
    }

    /// "granularity" and "curve" of a layer with lines.
    LinePath readLinePath(const Json& layer, const std::string& pointer) const
    {
        LinePath path;
        if (const Json* granularity = member(layer, "granularity")) {
            path.granularityRadians = readDegrees(*granularity, pointer + "/granularity", kGranularityRange);
        }
        if (const Json* curve = member(layer, "curve")) {
            path.curve = readEnum(*curve, pointer + "/curve", kCurves);
        }
        return path;
    }

    ModelLayer readModelLayer(const Json& value, const std::string& pointer) const
    {
        checkKeys(value, pointer, kModelKeys);
        ModelLayer layer;
        const Json& source = required(value, pointer, "source");
        layer.source = readPath(source, pointer + "/source");
        requireExtension(pointer + "/source", layer.source, std::array<std::string_view, 2>{".gltf", ".glb"},
                         "a .gltf or .glb file");
        layer.format = lowercase(layer.source.extension().string()) == ".glb" ? ModelLayer::Format::Glb
                                                                               : ModelLayer::Format::Gltf;
        requireFile(source, pointer + "/source", layer.source);
        attempt([&] { layer.position = readPosition(required(value, pointer, "position"), pointer + "/position"); });
        if (const Json* scale = member(value, "scale")) {
            attempt([&] {
                layer.scale = readNumber(*scale, pointer + "/scale", Range{0.0, std::numeric_limits<double>::infinity(), true});
            });
        }
        attempt([&] { layer.orientation = readOrientation(value, pointer, HeadingPitchRoll{}); });
        readHeightReference(value, pointer, layer.heightReference);
        return layer;
    }

    std::string_view _text;
    std::string _origin;
    fs::path _baseDirectory;
    SceneParseOptions _options;
    mutable int _version = kSceneFileVersion; // the file's, once read: some defaults depend on it
};

fs::path absoluteDirectory(const fs::path& directory)
{
    if (directory.is_absolute()) {
        return directory.lexically_normal();
    }
    std::error_code error;
    fs::path absolute = fs::absolute(directory.empty() ? fs::path(".") : directory, error);
    return error ? directory : absolute.lexically_normal();
}

} // namespace

namespace {

/// A fault that ends reading: thrown as a SceneFileError, or recorded when faults are collected.
/// Returns false for the latter, so that the caller gives up on the file.
bool stop(Diagnostic fault, DiagnosticList* collected)
{
    if (!collected) {
        throw SceneFileError(fault.file, fault.where, fault.line, fault.column, fault.what);
    }
    collected->add(std::move(fault));
    return false;
}

/// Parses JSON text (bounded nesting, no duplicate keys); empty when it is not JSON, the fault
/// thrown or collected.
std::optional<Json> parseJsonDocument(std::string_view text, const std::string& origin, DiagnosticList* collected)
{
    std::variant<Json, Diagnostic> parsed = detail::parseJson<Json>(text, origin, kMaxDepth);
    if (auto* fault = std::get_if<Diagnostic>(&parsed)) {
        stop(std::move(*fault), collected);
        return std::nullopt;
    }
    if (const auto duplicate = detail::findDuplicateKey(text)) {
        const detail::TextPosition position = detail::textPositionOf(text, duplicate->offset);
        const detail::TextPosition first = detail::textPositionOf(text, duplicate->firstOffset);
        const std::vector<std::string> tokens = detail::splitPointer(duplicate->pointer);
        // The document is read on (its value is the last given) when faults are collected.
        const Diagnostic fault{origin, position.line, position.column, duplicate->pointer,
                               "duplicate key " + quote(tokens.empty() ? std::string() : tokens.back()) +
                                   " (first given at line " + std::to_string(first.line) + ")"};
        stop(fault, collected);
    }
    return std::move(std::get<Json>(parsed));
}

/// The text of a file; empty when it cannot be read, the fault thrown or collected.
std::optional<std::string> readDocument(const fs::path& path, std::string_view what, DiagnosticList* collected)
{
    const std::string origin = path.string();
    try {
        resolveInSandbox(path, what);
    } catch (const Error& outside) {
        stop(Diagnostic{origin, 0, 0, "", outside.what()}, collected);
        return std::nullopt;
    }
    std::error_code error;
    if (fs::is_directory(path, error)) {
        stop({origin, 0, 0, "", "is a folder; expected " + std::string(what)}, collected);
        return std::nullopt;
    }
    std::ifstream file(path, std::ios::binary);
    if (!file) {
        const bool missing = !fs::exists(path, error);
        stop({origin, 0, 0, "", missing ? "no such file" : "cannot be opened"}, collected);
        return std::nullopt;
    }
    std::ostringstream contents;
    contents << file.rdbuf();
    if (file.bad()) {
        stop({origin, 0, 0, "", "cannot be read"}, collected);
        return std::nullopt;
    }
    return contents.str();
}

} // namespace

SceneDescription parseSceneText(std::string_view text, std::string_view originName, const fs::path& baseDirectory,
                                const SceneParseOptions& options)
{
    const std::string origin(originName);
    const std::optional<Json> root = parseJsonDocument(text, origin, options.diagnostics);
    SceneDescription scene;
    if (root) {
        const SceneReader reader(text, origin, absoluteDirectory(baseDirectory), options);
        reader.attempt([&] { scene = reader.read(*root); });
    }
    return scene;
}

std::vector<CameraKeyframe> parseCameraPathText(std::string_view text, std::string_view originName)
{
    const std::string origin(originName);
    const Json root = *parseJsonDocument(text, origin, nullptr);
    SceneParseOptions options;
    options.checkFiles = false;
    return SceneReader(text, origin, fs::path("."), options).readCameraPath(root);
}

std::vector<CameraKeyframe> parseCameraPathFile(const fs::path& path)
{
    return parseCameraPathText(*readDocument(path, "a camera path file", nullptr), path.string());
}

SceneDescription parseSceneFile(const fs::path& path, const SceneParseOptions& options)
{
    const std::optional<std::string> text = readDocument(path, "a scene file", options.diagnostics);
    if (!text) {
        return {};
    }
    const fs::path parent = path.parent_path();
    return parseSceneText(*text, path.string(), parent.empty() ? fs::path(".") : parent, options);
}

} // namespace orbis::world
