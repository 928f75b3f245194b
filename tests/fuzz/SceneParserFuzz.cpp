// libFuzzer target for the scene-file parser: any input either parses into a description that
// keeps the documented invariants or throws orbis::world::SceneFileError with a well-formed message.
// Each input is read as a camera path too: one that parses flies a camera that looks somewhere
// (finite directions) at every time.
// Any other exception, a crash, a sanitizer report or a broken invariant is a bug.
// Built and run by scripts/fuzz.sh (clang, -fsanitize=fuzzer,address,undefined).
#include <orbis/core/Ellipsoid.h>
#include <orbis/scene/Camera.h>
#include <orbis/scene/CameraControllers.h>
#include <orbis/world/SceneFile.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace {

void require(bool condition)
{
    if (!condition) {
        std::abort();
    }
}

bool isFiniteAngle(double radians)
{
    return std::isfinite(radians) && std::abs(radians) <= 2.0 * orbis::kPi;
}

void checkDescription(const orbis::world::SceneDescription& scene)
{
    require(scene.version >= 1 && scene.version <= orbis::world::kSceneFileVersion);
    require(scene.width >= 1 && scene.width <= 16384 && scene.height >= 1 && scene.height <= 16384);
    require(scene.camera.fieldOfViewY > 0.0 && scene.camera.fieldOfViewY < orbis::kPi);
    require(isFiniteAngle(scene.camera.position.latitude) && std::isfinite(scene.camera.position.height));
    require(std::abs(glm::length(scene.sun.directionEarthFixed) - 1.0) < 1e-12);
    require(isFiniteAngle(scene.sun.subsolarPoint.longitude) && isFiniteAngle(scene.sun.subsolarPoint.latitude));
    const orbis::scene::Camera camera = orbis::scene::makeCamera(scene.camera, orbis::Ellipsoid::wgs84());
    require(orbis::isFinite(camera.direction()) && orbis::isFinite(camera.up()) && orbis::isFinite(camera.right()));
    for (const orbis::world::LayerDescription& layer : scene.layers) {
        if (const auto* polyline = std::get_if<orbis::world::PolylineLayer>(&layer)) {
            require(polyline->positions.size() >= 2 && polyline->widthPixels > 0.0);
        } else if (const auto* model = std::get_if<orbis::world::ModelLayer>(&layer)) {
            require(model->scale > 0.0 && std::isfinite(model->scale) && model->source.is_absolute());
        } else if (const auto* points = std::get_if<orbis::world::PointsLayer>(&layer)) {
            require(points->source.is_absolute() && points->billboard.sizePixels > 0.0);
        } else if (const auto* geojson = std::get_if<orbis::world::GeoJsonLayer>(&layer)) {
            require(geojson->source.is_absolute() && (geojson->stroke || geojson->fill));
        }
    }
}

void checkError(const orbis::world::SceneFileError& error, std::string_view origin)
{
    const std::string_view what = error.what();
    require(what.starts_with(origin) && !error.reason().empty());
    require((error.line() == 0) == (error.column() == 0));
    require(error.pointer().empty() || error.pointer().front() == '/');
}

void parseOnce(std::string_view text, bool checkFiles)
{
    // Relative paths resolve against the folder the fuzzer runs in (scripts/fuzz.sh: data/scenes).
    static const std::filesystem::path base = std::filesystem::current_path();
    constexpr std::string_view kOrigin = "fuzz.json";
    std::optional<std::string> thrown;
    try {
        checkDescription(orbis::world::parseSceneText(text, kOrigin, base, orbis::world::SceneParseOptions{checkFiles}));
    } catch (const orbis::world::SceneFileError& error) {
        checkError(error, kOrigin);
        thrown = error.what();
    }
    // Collecting every fault never throws, finds a fault exactly when the throwing parse does, and
    // finds that one first.
    orbis::world::DiagnosticList faults;
    orbis::world::SceneParseOptions collecting{checkFiles};
    collecting.diagnostics = &faults;
    orbis::world::parseSceneText(text, kOrigin, base, collecting);
    require(faults.empty() == !thrown);
    require(!thrown || faults.entries().front().text() == *thrown);
    for (const orbis::world::Diagnostic& fault : faults.entries()) {
        require(fault.file == kOrigin && !fault.what.empty() && (fault.line == 0) == (fault.column == 0));
        require(fault.where.empty() || fault.where.front() == '/');
    }
}

/// The camera along a parsed path, sampled finely between each pair of keyframes.
void flyPath(std::string_view text)
{
    constexpr std::string_view kOrigin = "fuzz-path.json";
    orbis::scene::CameraPath path(orbis::Ellipsoid::wgs84());
    try {
        for (const orbis::scene::CameraPath::Keyframe& keyframe : orbis::world::parseCameraPathText(text, kOrigin)) {
            path.add(keyframe);
        }
    } catch (const orbis::world::SceneFileError& error) {
        checkError(error, kOrigin);
        return;
    }
    require(path.keyframes().size() >= 2);
    orbis::scene::Camera camera;
    const double start = path.keyframes().front().seconds;
    constexpr int kSamples = 256;
    for (int i = 0; i <= kSamples; ++i) {
        path.apply(start + path.duration() * i / kSamples, camera);
        require(orbis::isFinite(camera.direction()) && orbis::isFinite(camera.up()) && orbis::isFinite(camera.right()));
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    parseOnce(text, true);
    parseOnce(text, false);
    flyPath(text);
    return 0;
}
