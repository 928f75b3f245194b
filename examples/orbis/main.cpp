// The orbis command: one subcommand per job, looked up in a table (kSubcommands), each a function
// from its arguments to the exit code: 0 success, 1 the job failed (an invalid scene file, ...),
// 2 the command line is wrong (a UsageError naming what, thrown by the subcommand). docs/cli.md
// describes each.
#include "../common/SceneExample.h"
#include "../common/Viewer.h"

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/Error.h>
#include <orbis/core/Math.h>
#include <orbis/renderer/Device.h>
#include <orbis/scene/CameraControllers.h>
#include <orbis/scene/SceneBuilder.h>
#include <orbis/core/TileKey.h>
#include <orbis/world/AsyncPngWriter.h>
#include <orbis/world/CsvPoints.h>
#include <orbis/world/Diagnostics.h>
#include <orbis/world/FileAccess.h>
#include <orbis/world/ImageFile.h>
#include <orbis/world/ImageryTiler.h>
#include <orbis/world/SceneData.h>
#include <orbis/world/SceneFile.h>
#include <orbis/world/TerrainHeight.h>
#include <orbis/world/TerrainSource.h>
#include <orbis/world/TerrainTiler.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <unistd.h>

namespace {

constexpr int kExitOk = 0;
constexpr int kExitFailed = 1;
constexpr int kExitUsage = 2;

using Arguments = std::span<char* const>;

/// A command line the subcommand cannot run: main prints the message and the subcommand's usage,
/// and exits with kExitUsage.
struct UsageError {
    std::string message;
};

[[gnu::format(printf, 1, 2)]] std::string format(const char* pattern, ...)
{
    std::va_list arguments;
    va_start(arguments, pattern);
    std::va_list again;
    va_copy(again, arguments);
    const int length = std::vsnprintf(nullptr, 0, pattern, arguments);
    va_end(arguments);
    std::string text(static_cast<std::size_t>(std::max(length, 0)), '\0');
    std::vsnprintf(text.data(), text.size() + 1, pattern, again);
    va_end(again);
    return text;
}

/// "unknown option "--widht" (did you mean "--width"?)".
UsageError unknownOption(std::string_view option, std::span<const std::string_view> options)
{
    return {"unknown option " + orbis::world::quote(option) + orbis::world::suggestion(option, options)};
}

/// `text` as a whole number from minimum to maximum; empty when it is anything else ("64abc", "1e3").
std::optional<std::uint32_t> parseCount(std::string_view text, std::uint32_t minimum, std::uint32_t maximum)
{
    std::uint32_t value = 0;
    const auto [rest, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || error != std::errc() || rest != text.data() + text.size() || value < minimum || value > maximum) {
        return std::nullopt;
    }
    return value;
}

/// The value of `option` as a whole number from minimum to maximum, or a UsageError saying so.
std::uint32_t countOption(std::string_view option, std::string_view value, std::uint32_t minimum, std::uint32_t maximum)
{
    const std::optional<std::uint32_t> count = parseCount(value, minimum, maximum);
    if (!count) {
        throw UsageError{format("%.*s: expected a whole number from %u to %u, got %s", static_cast<int>(option.size()),
                                option.data(), minimum, maximum, orbis::world::quote(value).c_str())};
    }
    return *count;
}

/// A progress line on stderr for a long job: rewritten in place on a terminal (ten times a second
/// at most), elsewhere, as a batch job's log wants it, a line of its own every five seconds, the
/// first after five seconds, so that a short job prints none.
class ProgressLine {
public:
    /// Shows `text` if a line is due; `last` always shows it (where an earlier line was shown).
    void show(bool last, const std::string& text)
    {
        const double elapsed = seconds();
        const bool due = elapsed >= _nextLine || (last && _shown);
        if (!due) {
            return;
        }
        _nextLine = elapsed + (_terminal ? 0.1 : 5.0);
        std::fprintf(stderr, _terminal ? "\r%s   " : "%s\n", text.c_str());
        _shown = true;
        _open = _terminal;
        if (last) {
            endLine();
        }
    }
    /// Seconds since the line was made.
    double seconds() const
    {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - _start).count();
    }
    ~ProgressLine() { endLine(); }

private:
    void endLine()
    {
        if (_open) {
            std::fputc('\n', stderr);
            _open = false;
        }
    }

    bool _terminal = isatty(fileno(stderr)) != 0;
    std::chrono::steady_clock::time_point _start = std::chrono::steady_clock::now();
    double _nextLine = _terminal ? 0.0 : 5.0;
    bool _shown = false; ///< a line was printed
    bool _open = false;  ///< the terminal's cursor is at the end of a line being rewritten
};

void printConversion(const orbis::Ellipsoid& earth, const char* name, const orbis::Geodetic3D& g)
{
    const glm::dvec3 p = earth.toCartesian(g);
    const orbis::Geodetic3D back = earth.toGeodetic3D(p);
    std::printf("%-22s lon %11.6f lat %10.6f h %12.3f m -> x %15.3f y %15.3f z %15.3f m -> "
                "lon %11.6f lat %10.6f h %12.3f m\n",
                name, orbis::toDegrees(g.longitude), orbis::toDegrees(g.latitude), g.height, p.x, p.y, p.z,
                orbis::toDegrees(back.longitude), orbis::toDegrees(back.latitude), back.height);
}

/// orbis demo: a few geodetic conversions on WGS84.
int runDemo(Arguments arguments)
{
    if (!arguments.empty()) {
        throw UsageError{format("demo takes no arguments, got %s", orbis::world::quote(arguments[0]).c_str())};
    }
    const orbis::Ellipsoid earth = orbis::Ellipsoid::wgs84();
    printConversion(earth, "Greenwich, sea level", orbis::Geodetic3D::fromDegrees(0.0, 51.4778, 0.0));
    printConversion(earth, "Everest summit", orbis::Geodetic3D::fromDegrees(86.925, 27.9881, 8848.86));
    printConversion(earth, "North pole", orbis::Geodetic3D::fromDegrees(0.0, 90.0, 0.0));
    printConversion(earth, "Antimeridian, GEO", orbis::Geodetic3D::fromDegrees(180.0, 0.0, 35786000.0));
    printConversion(earth, "Mariana trench", orbis::Geodetic3D::fromDegrees(142.2, 11.35, -10994.0));
    const orbis::Geodetic3D centre = earth.toGeodetic3D({0.0, 0.0, 0.0});
    std::printf("%-22s x 0 y 0 z 0 -> lon %.1f lat %.1f h %.3f m (the closest surface point is a pole)\n",
                "Earth's centre", orbis::toDegrees(centre.longitude), orbis::toDegrees(centre.latitude),
                centre.height);
    return kExitOk;
}

/// A scene or camera-path argument: the file itself when there is one or the argument has a folder
/// in it; otherwise the example of that name in the data folder's `folder` ("capitals" or
/// "capitals.json": data/scenes/capitals.json), so the installed command finds its installed data.
std::string resolveDataFile(const std::string& argument, const char* folder)
{
    const std::filesystem::path given(argument);
    std::error_code error;
    if (std::filesystem::exists(given, error) || given.has_parent_path()) {
        return argument;
    }
    const std::filesystem::path directory = orbis::examples::dataDirectory() / folder;
    for (const std::filesystem::path& candidate : {directory / given, directory / (argument + ".json")}) {
        if (std::filesystem::is_regular_file(candidate, error)) {
            return candidate.string();
        }
    }
    return argument;
}

/// --sandbox FOLDER: every file read from now on must lie in FOLDER (symbolic links followed);
/// false, with a message, when FOLDER is no folder.
bool confineFiles(const std::string& folder)
{
    try {
        orbis::world::setFileSandbox(std::filesystem::path(folder));
        return true;
    } catch (const orbis::Error& error) {
        std::fprintf(stderr, "orbis: %s\n", error.what());
        return false;
    }
}

/// A scene's warnings on stderr, naming the scene file: the first 20, then how many more.
void printWarnings(const std::string& path, const std::vector<std::string>& warnings)
{
    constexpr std::size_t kShown = 20;
    for (std::size_t i = 0; i < std::min(warnings.size(), kShown); ++i) {
        std::fprintf(stderr, "%s: warning: %s\n", path.c_str(), warnings[i].c_str());
    }
    if (warnings.size() > kShown) {
        std::fprintf(stderr, "%s: warning: %zu more warnings like these\n", path.c_str(), warnings.size() - kShown);
    }
}

/// Builds the scene's primitives as render does, without a GPU (polygons triangulated, billboard
/// images packed, models unfolded): what the files' readers accept but drawing them refuses. False,
/// with the message, when that fails.
bool buildsWithoutFault(const std::string& path, const orbis::world::SceneDescription& description)
{
    try {
        orbis::scene::Scene scene;
        printWarnings(path, orbis::scene::populateScene(description, scene));
        return true;
    } catch (const orbis::Error& error) {
        std::fprintf(stderr, "%s: %s\n", path.c_str(), error.what());
        return false;
    }
}

/// orbis validate [--sandbox FOLDER] SCENE.json...: reads each file, and the files it names, as
/// `orbis render` would, renders nothing; lists every fault of a file (world::validateSceneFile).
int runValidate(Arguments arguments)
{
    constexpr std::string_view kOptions[] = {"--sandbox"};
    std::vector<std::string> scenes;
    for (std::size_t i = 0; i < arguments.size(); ++i) {
        const std::string_view argument = arguments[i];
        if (!argument.starts_with("--")) {
            scenes.push_back(resolveDataFile(std::string(argument), "scenes"));
        } else if (argument != "--sandbox") {
            throw unknownOption(argument, kOptions);
        } else if (i + 1 == arguments.size()) {
            throw UsageError{"--sandbox needs a value"};
        } else if (!confineFiles(arguments[++i])) {
            return kExitFailed;
        }
    }
    if (scenes.empty()) {
        throw UsageError{"give the scene files to check"};
    }
    int exitCode = kExitOk;
    for (const std::string& path : scenes) {
        orbis::world::SceneDescription scene;
        const orbis::world::DiagnosticList faults = orbis::world::validateSceneFile(path, &scene);
        if (faults.empty() && !buildsWithoutFault(path, scene)) {
            exitCode = kExitFailed;
        } else if (faults.empty()) {
            std::printf("%s: ok (%zu %s)\n", path.c_str(), scene.layers.size(),
                        scene.layers.size() == 1 ? "layer" : "layers");
        } else {
            std::fprintf(stderr, "%s", faults.text().c_str());
            exitCode = kExitFailed;
        }
    }
    return exitCode;
}

/// Where frame `index` of `count` goes: the output itself for one frame, else name_0001.png etc.
std::string framePath(const std::string& output, int index, int count)
{
    if (count == 1) {
        return output;
    }
    const std::size_t dot = output.rfind('.');
    const std::size_t slash = output.rfind('/');
    const bool hasExtension = dot != std::string::npos && (slash == std::string::npos || dot > slash);
    char number[16];
    std::snprintf(number, sizeof number, "_%04d", index + 1);
    return hasExtension ? output.substr(0, dot) + number + output.substr(dot) : output + number;
}

/// The files one run writes, each first under a temporary name beside it, renamed into place
/// together once all are written: a run that fails half way leaves none of them (a flight no
/// first frames, a picture no PNG without its --stats). What is not committed is removed.
class StagedOutputs {
public:
    /// Throws orbis::Error naming the file when it exists and is no regular file (a folder in the
    /// way), so that a run fails before it renders rather than when it renames.
    static void checkWritable(const std::filesystem::path& path)
    {
        std::error_code error;
        const std::filesystem::file_status status = std::filesystem::status(path, error);
        if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
            throw orbis::Error(orbis::world::cutForMessage(path.string()) + ": cannot write: it exists and is not a file");
        }
    }

    /// The temporary name to write `path` under.
    std::filesystem::path stage(const std::filesystem::path& path)
    {
        std::filesystem::path temporary = path;
        temporary += ".partial-" + std::to_string(::getpid());
        _staged.emplace_back(temporary, path);
        return temporary;
    }

    /// Renames every staged file into place; throws orbis::Error naming the first that fails.
    void commit()
    {
        for (auto& [temporary, path] : _staged) {
            std::error_code error;
            std::filesystem::rename(temporary, path, error);
            if (error) {
                throw orbis::Error(orbis::world::cutForMessage(path.string()) + ": cannot write: " + error.message());
            }
            temporary.clear();
        }
    }

    ~StagedOutputs()
    {
        for (const auto& staged : _staged) {
            if (!staged.first.empty()) {
                std::error_code ignored;
                std::filesystem::remove(staged.first, ignored);
            }
        }
    }

private:
    std::vector<std::pair<std::filesystem::path, std::filesystem::path>> _staged; // temporary, final
};

/// The command line of render and view: a scene file and options, each at most once.
struct SceneArguments {
    std::optional<std::string> scenePath;
    std::optional<std::string> output;
    std::optional<std::string> statisticsPath;
    std::optional<std::string> cameraPath;
    std::optional<int> width;
    std::optional<int> height;
    std::optional<int> frames;
    std::optional<int> maxFrames;
    bool noWait = false;
    std::optional<std::string> sandbox;
};

constexpr std::string_view kRenderOptions[] = {"--out",  "--width",      "--height",  "--stats",  "--frames",
                                               "--path", "--max-frames", "--no-wait", "--sandbox"};
constexpr std::string_view kViewOptions[] = {"--out", "--width", "--height", "--frames"};

/// Reads the arguments of render or view, which take the `accepted` options; throws UsageError
/// naming what is wrong.
SceneArguments parseSceneArguments(Arguments arguments, std::span<const std::string_view> accepted)
{
    SceneArguments parsed;
    for (std::size_t i = 0; i < arguments.size(); ++i) {
        const std::string_view argument = arguments[i];
        if (!argument.starts_with("--")) {
            if (parsed.scenePath) {
                throw UsageError{format("one scene file at a time: %s and %s", orbis::world::quote(*parsed.scenePath).c_str(),
                                        orbis::world::quote(argument).c_str())};
            }
            parsed.scenePath = resolveDataFile(std::string(argument), "scenes");
            continue;
        }
        if (std::find(std::begin(accepted), std::end(accepted), argument) == std::end(accepted)) {
            throw unknownOption(argument, accepted);
        }
        if (argument == "--no-wait") {
            parsed.noWait = true;
            continue;
        }
        if (i + 1 == arguments.size()) {
            throw UsageError{format("%s needs a value", arguments[i])};
        }
        const std::string_view value = arguments[++i];
        auto count = [&](std::uint32_t maximum) { return static_cast<int>(countOption(argument, value, 1, maximum)); };
        if (argument == "--out") {
            parsed.output = std::string(value);
        } else if (argument == "--stats") {
            parsed.statisticsPath = std::string(value);
        } else if (argument == "--path") {
            parsed.cameraPath = resolveDataFile(std::string(value), "paths");
        } else if (argument == "--sandbox") {
            parsed.sandbox = std::string(value);
        } else if (argument == "--width") {
            parsed.width = count(16384);
        } else if (argument == "--height") {
            parsed.height = count(16384);
        } else if (argument == "--frames") {
            parsed.frames = count(100000);
        } else {
            parsed.maxFrames = count(100000);
        }
    }
    return parsed;
}

orbis::world::SceneDescription readScene(const std::optional<std::string>& scenePath)
{
    return scenePath ? orbis::world::parseSceneFile(*scenePath)
                     : orbis::world::parseDefaultScene(orbis::examples::dataDirectory() / "scenes");
}

/// Renders until the scene's streamed tiles have converged, at most `limit` frames, showing
/// progress while it waits.
orbis::scene::FrameStatistics renderConverged(orbis::scene::Scene& scene, orbis::renderer::Context& context, int limit)
{
    ProgressLine progress;
    for (int rendered = 1;; ++rendered) {
        orbis::scene::FrameStatistics statistics = scene.render(context);
        const bool converged = (!statistics.tiles || statistics.tiles->converged) &&
                               (!statistics.clipmap || statistics.clipmap->converged);
        if (converged) {
            statistics.framesToConverge = static_cast<std::uint64_t>(rendered);
        }
        if (converged || rendered >= limit) {
            return statistics;
        }
        if (statistics.tiles) {
            progress.show(false, format("waiting for tiles: %d frames, %zu drawn, %zu pending", rendered,
                                        statistics.tiles->drawn, statistics.tiles->pending));
        } else {
            progress.show(false, format("waiting for the clipmap: %d frames, %zu posts and %zu tiles pending", rendered,
                                        statistics.clipmap->postsPending, statistics.clipmap->tilesPending));
        }
    }
}

/// Encoders for a flight's frames: the cores the render thread leaves, at least one, at most four.
int frameWriterThreads()
{
    const unsigned cores = std::thread::hardware_concurrency();
    return static_cast<int>(std::clamp(cores > 1 ? cores - 1 : 1U, 1U, 4U));
}

/// orbis render [SCENE.json] [options]: one picture of a scene file (the built-in default Earth
/// without one), rendered until its streamed tiles have converged, or a flight along a camera path
/// as numbered PNGs, one frame each, headless; the PNGs are encoded on other threads while the
/// next frames are drawn. Each PNG appears whole or not at all. docs/cli.md has the options.
int runRender(Arguments arguments)
{
    const auto [scenePath, outputOption, statisticsPath, cameraPath, width, height, frames, maxFrames, noWait,
                sandbox] = parseSceneArguments(arguments, kRenderOptions);
    const std::string output = outputOption.value_or("orbis.png");
    if (frames && !cameraPath) {
        throw UsageError{"--frames needs a camera path (--path PATH.json): a still picture is one frame"};
    }
    if (noWait && maxFrames) {
        throw UsageError{"--no-wait writes the first frame, --max-frames waits: give one"};
    }
    if (cameraPath && (noWait || maxFrames)) {
        throw UsageError{"--no-wait and --max-frames are for still pictures; a flight draws each frame once"};
    }
    if (sandbox && !confineFiles(*sandbox)) {
        return kExitFailed;
    }

    try {
        const orbis::world::SceneDescription description = readScene(scenePath);
        std::optional<orbis::scene::CameraPath> flight;
        if (cameraPath) {
            flight.emplace(orbis::Ellipsoid::wgs84());
            for (const orbis::scene::CameraPath::Keyframe& keyframe : orbis::world::parseCameraPathFile(*cameraPath)) {
                flight->add(keyframe);
            }
        }
        const int frameCount = flight ? frames.value_or(60) : 1;
        for (int frame = 0; frame < frameCount; ++frame) {
            StagedOutputs::checkWritable(framePath(output, frame, frameCount));
        }
        if (statisticsPath) {
            StagedOutputs::checkWritable(*statisticsPath);
        }
        StagedOutputs outputs;

        orbis::renderer::Device device;
        orbis::renderer::Context& context = device.context();
        orbis::renderer::Framebuffer framebuffer =
            context.createFramebuffer(width.value_or(description.width), height.value_or(description.height));
        context.setFramebuffer(&framebuffer);
        orbis::scene::Scene scene;
        printWarnings(scenePath.value_or("the default scene"), orbis::scene::populateScene(description, scene));

        orbis::world::AsyncPngWriter writer(frameCount > 1 ? frameWriterThreads() : 1);
        std::string statisticsJson = frameCount > 1 ? "[\n" : "";
        ProgressLine progress;
        for (int frame = 0; frame < frameCount; ++frame) {
            orbis::scene::FrameStatistics statistics;
            if (flight) {
                const double t = frameCount > 1 ? static_cast<double>(frame) / (frameCount - 1) : 0.0;
                flight->apply(flight->keyframes().front().seconds + t * flight->duration(), scene.camera());
                statistics = scene.render(context);
            } else {
                statistics = renderConverged(scene, context, noWait ? 1 : maxFrames.value_or(600));
            }
            const std::string path = framePath(output, frame, frameCount);
            writer.write(context.readPixels(), outputs.stage(path));
            if (frame == 0) {
                std::printf("%s: %dx%d, %s\n%s", path.c_str(), framebuffer.width(), framebuffer.height(),
                            device.info().renderer.c_str(), statistics.toText().c_str());
            }
            if (!flight && (statistics.tiles || statistics.clipmap)) {
                if (statistics.framesToConverge) {
                    std::printf("converged after %llu frames\n",
                                static_cast<unsigned long long>(*statistics.framesToConverge));
                } else {
                    std::printf("not converged after %llu frames (%s)\n",
                                static_cast<unsigned long long>(statistics.frameNumber),
                                noWait ? "--no-wait" : "--max-frames");
                }
            }
            statisticsJson += statistics.toJson();
            if (frameCount > 1) {
                statisticsJson += frame + 1 < frameCount ? ",\n" : "]\n";
                const double seconds = progress.seconds();
                progress.show(frame + 1 == frameCount, format("%d/%d frames, %.1f frames/s", frame + 1, frameCount,
                                                              seconds > 0.0 ? (frame + 1) / seconds : 0.0));
            }
        }
        writer.finish();
        if (frameCount > 1) {
            std::printf("%d frames: %s .. %s\n", frameCount, framePath(output, 0, frameCount).c_str(),
                        framePath(output, frameCount - 1, frameCount).c_str());
        }
        if (statisticsPath) {
            orbis::world::writeFileAtomically(outputs.stage(*statisticsPath), statisticsJson);
        }
        outputs.commit();
        return kExitOk;
    } catch (const orbis::Error& error) {
        std::fprintf(stderr, "orbis render: %s\n", error.what());
        return kExitFailed;
    }
}

/// orbis view [SCENE.json] [--width W] [--height H] [--frames N [--out PNG]]: the scene in a
/// window (examples/common/Viewer.h has the controls). Each frame is rendered offscreen, where the
/// scene may have the float depth buffer a window lacks, and copied to the window. --frames stops
/// after N frames, and --out then writes the last one as the window showed it.
int runView(Arguments arguments)
{
    const SceneArguments parsed = parseSceneArguments(arguments, kViewOptions);
    if (parsed.output && !parsed.frames) {
        throw UsageError{"--out writes the last of --frames N frames: give --frames too"};
    }
    try {
        const orbis::world::SceneDescription description = readScene(parsed.scenePath);
        orbis::examples::ViewerOptions options;
        options.width = parsed.width.value_or(description.width);
        options.height = parsed.height.value_or(description.height);
        options.title = "Orbis: " + parsed.scenePath.value_or("the default Earth");
        options.frames = parsed.frames;
        options.output = parsed.output;
        orbis::renderer::Device device = orbis::examples::createViewerDevice(options);
        orbis::scene::Scene scene;
        // The viewer keeps drawing while tiles arrive: they enter whenever they are ready.
        orbis::scene::SceneBuildOptions build;
        build.loader.latencyFrames = 0;
        printWarnings(parsed.scenePath.value_or("the default scene"), orbis::scene::populateScene(description, scene, build));
        orbis::examples::runViewer(device, scene, options);
        return kExitOk;
    } catch (const orbis::Error& error) {
        std::fprintf(stderr, "orbis view: %s\n", error.what());
        return kExitFailed;
    }
}

/// orbis info: Orbis's version, the OpenGL driver the headless device gets, its limits, and the
/// capabilities the scene chooses its strategies by.
int runInfo(Arguments arguments)
{
    if (!arguments.empty()) {
        throw UsageError{format("info takes no arguments, got %s", orbis::world::quote(arguments[0]).c_str())};
    }
    orbis::renderer::Device device;
    const orbis::renderer::DeviceInfo& info = device.info();
    auto yes = [](bool value) { return value ? "yes" : "no"; };
    std::printf("orbis:            %s\n", ORBIS_VERSION);
    std::printf("backend:          %s\n", info.backendDescription.c_str());
    std::printf("vendor:           %s\n", info.vendor.c_str());
    std::printf("renderer:         %s\n", info.renderer.c_str());
    std::printf("version:          %s\n", info.version.c_str());
    std::printf("GLSL:             %s\n", info.shadingLanguageVersion.c_str());
    std::printf("max texture size: %d\n", info.maxTextureSize);
    std::printf("texture units:    %d\n", info.maxTextureUnits);
    std::printf("colour targets:   %d\n", info.maxColorAttachments);
    std::printf("vertex attributes: %d\n", info.maxVertexAttributes);
    std::printf("max anisotropy:   %g\n", static_cast<double>(info.maxAnisotropy));
    std::printf("max samples:      %d (the most a scene's \"samples\" (MSAA) gets)\n", info.maxSamples);
    std::printf("KHR_debug:        %s\n", yes(info.khrDebug));
    std::printf("capabilities the strategies depend on:\n");
    std::printf("  clip control:   %s (complementary depth in a float buffer: depth \"auto\" can pick it)\n",
                yes(info.clipControl));
    std::printf("  gpu_shader5:    %s (\"precise\" arithmetic for GPU relative-to-eye and emulated doubles)\n",
                yes(info.gpuShader5));
    std::printf("  sparse texture: %s (ARB_sparse_texture, for virtual textures' \"sparse\" path)\n", yes(info.sparseTexture));
    if (info.sparseTexture) {
        const orbis::renderer::SparsePageSize page = device.sparsePageSize(orbis::renderer::TextureFormat::RGBA8);
        std::printf("                  pages of %d x %d RGBA8 texels, textures up to %d texels a side\n", page.width,
                    page.height, info.maxSparseTextureSize);
    }
    return kExitOk;
}

/// `text` as a finite number, at least `minimum`; empty when it is anything else.
std::optional<double> parseFinite(std::string_view text, double minimum)
{
    double value = 0.0;
    const auto [rest, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || error != std::errc() || rest != text.data() + text.size() || !std::isfinite(value) ||
        value < minimum) {
        return std::nullopt;
    }
    return value;
}

/// The options both tilers take: INPUT --out FOLDER [--levels N] [--level L [--range X0:X1]]
/// [--threads N] [--title TEXT] [--attribution TEXT].
struct TilingArguments {
    std::filesystem::path input;
    std::filesystem::path output;
    std::optional<std::uint32_t> levels;
    std::optional<std::uint32_t> onlyLevel;
    std::optional<std::pair<std::uint32_t, std::uint32_t>> columns;
    int threads = 0;
    std::string title;
    std::string attribution;

    static constexpr std::string_view kOptions[] = {"--out",     "--levels", "--level",      "--range",
                                                    "--threads", "--title",  "--attribution"};

    /// Reads the arguments; the tiler's own options (`ownOptions`, flags among them taking no value)
    /// go to `own(option, value)`, which throws UsageError for a bad value. Throws UsageError naming
    /// what is wrong.
    template <class Own>
    void parse(Arguments arguments, std::span<const std::string_view> ownOptions,
               std::span<const std::string_view> ownFlags, Own&& own)
    {
        std::vector<std::string_view> accepted(std::begin(kOptions), std::end(kOptions));
        accepted.insert(accepted.end(), ownOptions.begin(), ownOptions.end());
        accepted.insert(accepted.end(), ownFlags.begin(), ownFlags.end());
        for (std::size_t i = 0; i < arguments.size(); ++i) {
            const std::string_view argument = arguments[i];
            if (!argument.starts_with("--")) {
                if (!input.empty()) {
                    throw UsageError{format("one input at a time: %s and %s", orbis::world::quote(input.string()).c_str(),
                                            orbis::world::quote(argument).c_str())};
                }
                input = std::string(argument);
                continue;
            }
            if (std::find(accepted.begin(), accepted.end(), argument) == accepted.end()) {
                throw unknownOption(argument, accepted);
            }
            if (std::find(ownFlags.begin(), ownFlags.end(), argument) != ownFlags.end()) {
                own(argument, std::string_view());
                continue;
            }
            if (i + 1 == arguments.size()) {
                throw UsageError{format("%s needs a value", arguments[i])};
            }
            const std::string_view value = arguments[++i];
            if (argument == "--out") {
                output = std::string(value);
            } else if (argument == "--levels") {
                levels = countOption(argument, value, 1, orbis::kMaximumTileLevel + 1);
            } else if (argument == "--level") {
                onlyLevel = countOption(argument, value, 0, orbis::kMaximumTileLevel);
            } else if (argument == "--range") {
                const std::size_t colon = value.find(':');
                const auto first = parseCount(value.substr(0, colon), 0, 0x7fffffff);
                const auto last =
                    colon == std::string_view::npos ? std::nullopt : parseCount(value.substr(colon + 1), 0, 0x7fffffff);
                if (!first || !last) {
                    throw UsageError{"--range: expected the first and last column as X0:X1, got " +
                                     orbis::world::quote(value)};
                }
                columns = std::pair(*first, *last);
            } else if (argument == "--threads") {
                threads = static_cast<int>(countOption(argument, value, 1, 256));
            } else if (argument == "--title") {
                title = std::string(value);
            } else if (argument == "--attribution") {
                attribution = std::string(value);
            } else {
                own(argument, value);
            }
        }
        if (input.empty() || output.empty()) {
            throw UsageError{"give the input and --out FOLDER"};
        }
        if (columns && !onlyLevel) {
            throw UsageError{"--range cuts columns of one level: give --level too"};
        }
    }

    /// Copies the common options into a tiler's options.
    template <class Options>
    void apply(Options& options) const
    {
        options.input = input;
        options.output = output;
        options.levels = levels;
        options.onlyLevel = onlyLevel;
        options.columns = columns;
        options.threads = threads;
        options.title = title;
        options.attribution = attribution;
    }
};

/// A tiler's progress on a ProgressLine.
std::function<void(const orbis::world::TilerProgress&)> tilingProgress()
{
    return [line = std::make_shared<ProgressLine>()](const orbis::world::TilerProgress& progress) {
        const auto done = static_cast<double>(progress.done);
        const auto total = static_cast<double>(progress.total);
        const double rate = progress.seconds > 0.0 ? done / progress.seconds : 0.0;
        const double left = rate > 0.0 ? (total - done) / rate : 0.0;
        line->show(progress.done == progress.total,
                   format("level %u: %zu/%zu tiles, all levels %zu/%zu (%.0f%%), %.1f tiles/s, %.0f s left",
                          progress.level, progress.levelDone, progress.levelTotal, progress.done, progress.total,
                          total > 0.0 ? 100.0 * done / total : 100.0, rate, left));
    };
}

/// orbis tile imagery INPUT --out FOLDER [--format jpg|png|webp] [--quality Q] and the common
/// options: a TMS pyramid (geographic, tilemapresource.xml) cut from an image GDAL reads.
int runTileImagery(Arguments arguments)
{
    orbis::world::ImageryTilerOptions options;
    constexpr std::string_view kOwnOptions[] = {"--format", "--quality"};
    TilingArguments common;
    common.parse(arguments, kOwnOptions, {}, [&](std::string_view argument, std::string_view value) {
        if (argument == "--format") {
            options.format = orbis::world::imageFormatFromName(value);
            if (options.format == orbis::world::ImageFormat::Unknown || value.find('/') != std::string_view::npos) {
                throw UsageError{"--format: expected \"jpg\", \"png\" or \"webp\", got " + orbis::world::quote(value)};
            }
        } else {
            options.quality = static_cast<int>(countOption(argument, value, 0, 100));
        }
    });
    common.apply(options);
    try {
        options.progress = tilingProgress();
        orbis::world::ImageryTiler tiler(options);
        const orbis::world::TilerSummary summary = tiler.run();
        std::printf("%s: %zu tiles written, %zu empty skipped, levels 0-%u, %.1f s (%.1f tiles/s)\n",
                    options.output.c_str(), summary.tilesWritten, summary.tilesEmpty, summary.levelCount - 1,
                    summary.seconds,
                    summary.seconds > 0.0 ? static_cast<double>(summary.tilesWritten + summary.tilesEmpty) / summary.seconds
                                          : 0.0);
        return kExitOk;
    } catch (const orbis::Error& error) {
        std::fprintf(stderr, "orbis tile: %s\n", error.what());
        return kExitFailed;
    }
}

/// orbis tile terrain DEM --out FOLDER [--format quantized-mesh|heightmap] [--samples N]
/// [--max-error METRES] [--no-normals] [--gzip LEVEL] [--nodata-height METRES] and the common
/// options: a terrain tile set with layer.json cut from a DEM GDAL reads.
int runTileTerrain(Arguments arguments)
{
    orbis::world::TerrainTilerOptions options;
    constexpr std::string_view kOwnOptions[] = {"--format", "--samples", "--gzip", "--max-error", "--nodata-height"};
    constexpr std::string_view kOwnFlags[] = {"--no-normals"};
    TilingArguments common;
    common.parse(arguments, kOwnOptions, kOwnFlags, [&](std::string_view argument, std::string_view value) {
        if (argument == "--no-normals") {
            options.normals = false;
        } else if (argument == "--format") {
            if (value == "quantized-mesh") {
                options.format = orbis::world::TerrainTileFormat::QuantizedMesh;
            } else if (value == "heightmap") {
                options.format = orbis::world::TerrainTileFormat::Heightmap;
            } else {
                throw UsageError{"--format: expected \"quantized-mesh\" or \"heightmap\", got " +
                                 orbis::world::quote(value)};
            }
        } else if (argument == "--samples") {
            options.gridSize = static_cast<int>(countOption(argument, value, 5, 1025));
        } else if (argument == "--gzip") {
            options.gzipLevel = static_cast<int>(countOption(argument, value, 0, 9));
        } else {
            const bool error = argument == "--max-error";
            const std::optional<double> metres = parseFinite(value, error ? 0.0 : -1e300);
            if (!metres) {
                throw UsageError{format("%.*s: expected a finite number of metres%s, got %s",
                                        static_cast<int>(argument.size()), argument.data(), error ? ", 0 or more" : "",
                                        orbis::world::quote(value).c_str())};
            }
            if (error) {
                options.maximumError = *metres;
            } else {
                options.noDataHeight = *metres;
            }
        }
    });
    common.apply(options);
    try {
        options.progress = tilingProgress();
        orbis::world::TerrainTiler tiler(options);
        const orbis::world::TerrainTilerSummary summary = tiler.run();
        std::string errors;
        for (std::uint32_t level = 0; level < summary.levelCount; ++level) {
            if (summary.maximumErrors[level] > 0.0 || !options.onlyLevel || *options.onlyLevel == level) {
                char text[48];
                std::snprintf(text, sizeof text, "%s%u: %.2f m", errors.empty() ? "" : ", ", level,
                              summary.maximumErrors[level]);
                errors += text;
            }
        }
        std::printf("%s: %zu tiles written (%.1f MB), levels 0-%u, %.1f s (%.1f tiles/s, %.2f MB/s); largest error by "
                    "level: %s\n",
                    options.output.c_str(), summary.tilesWritten, static_cast<double>(summary.bytesWritten) / 1e6,
                    summary.levelCount - 1, summary.seconds,
                    summary.seconds > 0.0 ? static_cast<double>(summary.tilesWritten) / summary.seconds : 0.0,
                    summary.seconds > 0.0 ? static_cast<double>(summary.bytesWritten) / 1e6 / summary.seconds : 0.0,
                    errors.c_str());
        return kExitOk;
    } catch (const orbis::Error& error) {
        std::fprintf(stderr, "orbis tile: %s\n", error.what());
        return kExitFailed;
    }
}

/// orbis tile imagery|terrain ...
int runTile(Arguments arguments)
{
    const std::string_view kind = arguments.empty() ? std::string_view() : std::string_view(arguments[0]);
    if (kind == "imagery") {
        return runTileImagery(arguments.subspan(1));
    }
    if (kind == "terrain") {
        return runTileTerrain(arguments.subspan(1));
    }
    throw UsageError{"what to tile: \"imagery\" or \"terrain\", got " + (kind.empty() ? "nothing" : orbis::world::quote(kind))};
}

/// orbis height TERRAIN (LON LAT ... | --points FILE.csv) [--format NAME]: the most-detailed height
/// of each point (degrees), one line each in the input's order, in metres; "nodata" where the
/// terrain has none (then exit status 1, after every line).
int runHeight(Arguments arguments)
{
    std::string terrain;
    std::vector<orbis::Geodetic2D> points;
    std::optional<std::filesystem::path> csv;
    orbis::world::TerrainSourceOptions options;
    std::vector<double> numbers;
    constexpr std::string_view kOptions[] = {"--points", "--format"};
    for (std::size_t i = 0; i < arguments.size(); ++i) {
        const std::string_view argument = arguments[i];
        if (argument == "--points" || argument == "--format") {
            if (i + 1 == arguments.size()) {
                throw UsageError{format("%s needs a value", arguments[i])};
            }
            const std::string value = arguments[++i];
            if (argument == "--points") {
                csv = value;
            } else {
                options.format = value;
            }
        } else if (terrain.empty()) {
            if (argument.starts_with("--")) {
                throw unknownOption(argument, kOptions);
            }
            terrain = std::string(argument);
        } else if (const auto number = parseFinite(argument, -1e300)) {
            numbers.push_back(*number);
        } else if (argument.starts_with("--")) {
            throw unknownOption(argument, kOptions);
        } else {
            throw UsageError{"expected a longitude or latitude in degrees, got " + orbis::world::quote(argument)};
        }
    }
    if (terrain.empty()) {
        throw UsageError{"give the terrain source, then the points"};
    }
    if (numbers.empty() == !csv) {
        throw UsageError{csv ? "give the points either on the command line or with --points, not both"
                             : "give the points: LON LAT pairs or --points FILE.csv"};
    }
    if (numbers.size() % 2 != 0) {
        throw UsageError{format("a longitude without its latitude (%zu numbers)", numbers.size())};
    }
    for (std::size_t i = 1; i < numbers.size(); i += 2) {
        if (!(std::abs(numbers[i]) <= 90.0)) {
            throw UsageError{format("latitude %g is not within -90 to 90 degrees", numbers[i])};
        }
    }
    try {
        if (csv) {
            orbis::world::CsvPointsOptions columns;
            columns.longitudeColumn.clear(); // the first column named lon, lng, long or longitude
            columns.latitudeColumn.clear();
            columns.propertyColumns = std::vector<std::string>();
            for (const orbis::Geodetic3D& position : orbis::world::loadCsvPoints(*csv, columns).positions) {
                points.push_back({position.longitude, position.latitude});
            }
        }
        for (std::size_t i = 0; i < numbers.size(); i += 2) {
            points.push_back({orbis::toRadians(numbers[i]), orbis::toRadians(numbers[i + 1])});
        }
        const auto source = orbis::world::openTerrainSource(terrain, options);
        orbis::world::TerrainHeightQuery query(*source);
        int exitCode = kExitOk;
        for (const orbis::Geodetic2D& point : points) {
            if (const auto height = query.at(point)) {
                std::printf("%.3f\n", height->height);
            } else {
                std::printf("nodata\n");
                exitCode = kExitFailed;
            }
        }
        return exitCode;
    } catch (const orbis::Error& error) {
        std::fflush(stdout);
        std::fprintf(stderr, "orbis height: %s\n", error.what());
        return kExitFailed;
    }
}

struct Subcommand {
    std::string_view name;
    std::string_view arguments; ///< for the usage line
    std::string_view summary;
    int (*run)(Arguments);
};

constexpr Subcommand kSubcommands[] = {
    {"render",
     "[SCENE.json] [--out PNG] [--width W] [--height H] [--stats JSON] [--max-frames N | --no-wait] "
     "[--path PATH.json [--frames N]] [--sandbox FOLDER]",
     "render a scene file (the default Earth without one) to a PNG (orbis.png) once its tiles have converged "
     "(at most --max-frames frames, 600 by default; --no-wait: the first frame); with --path, a flight along "
     "a camera path to numbered PNGs (PNG_0001.png ...), --frames of them (60 by default), headless; "
     "--sandbox: refuse to read files outside FOLDER",
     runRender},
    {"view", "[SCENE.json] [--width W] [--height H] [--frames N [--out PNG]]",
     "show a scene file in a window (needs GLFW and a display): drag to turn, wheel to zoom, F to fly (W A S "
     "D, E Q), H to fly home, Escape to close; the title shows the tiles pending; --frames N stops after N "
     "frames, --out writes the last",
     runView},
    {"validate", "[--sandbox FOLDER] SCENE.json...",
     "check scene files and the files they name without rendering, listing every fault (see docs/scene-format.md)",
     runValidate},
    {"tile", "imagery INPUT --out FOLDER [--levels N] [--format jpg|png|webp] [--quality Q] [--level L [--range X0:X1]] "
             "[--threads N] [--title TEXT] [--attribution TEXT]",
     "cut an image GDAL reads (GeoTIFF in any CRS, or a plain whole-globe JPEG/PNG) into a geographic TMS "
     "pyramid; --level/--range cut one level's columns X0 to X1, for splitting a job across machines",
     runTile},
    {"tile", "terrain DEM --out FOLDER [--format quantized-mesh|heightmap] [--levels N] [--level L [--range X0:X1]] "
             "[--samples N] [--max-error METRES] [--no-normals] [--gzip 0-9] [--nodata-height METRES] [--threads N] "
             "[--title TEXT] [--attribution TEXT]",
     "cut a DEM GDAL reads (GeoTIFF in any CRS, nodata, 0..360 longitudes) into quantized-mesh or heightmap-1.0 "
     "tiles with layer.json (availability, each tile's measured geometric error); --max-error: the quantized-mesh "
     "tolerance at level 0, halved per level (see docs/terrain.md)",
     runTile},
    {"height", "TERRAIN (LON LAT [LON LAT ...] | --points FILE.csv) [--format NAME]",
     "print the most-detailed height of each point (degrees; a CSV's lon and lat columns) in metres, one line "
     "each in input order, from a terrain source (layer.json folder or URL, MBTiles, PNG height pyramid, .hgt, "
     "any DEM GDAL reads); a point on a tile edge gives the same value from either tile",
     runHeight},
    {"info", "", "the Orbis version, the OpenGL driver, its limits and the capabilities the scene's strategies use",
     runInfo},
    {"demo", "", "geodetic conversions on WGS84", runDemo},
    {"help", "[COMMAND]", "this text, or one command's (also: orbis COMMAND --help)", nullptr},
};

void printUsageLine(std::FILE* stream, const Subcommand& subcommand)
{
    std::fprintf(stream, "  orbis %.*s%s%.*s\n      %.*s\n", static_cast<int>(subcommand.name.size()),
                 subcommand.name.data(), subcommand.arguments.empty() ? "" : " ",
                 static_cast<int>(subcommand.arguments.size()), subcommand.arguments.data(),
                 static_cast<int>(subcommand.summary.size()), subcommand.summary.data());
}

int usage(std::FILE* stream, int exitCode)
{
    std::fprintf(stream, "orbis %s: virtual-globe rendering from scene files (docs/cli.md)\nusage:\n", ORBIS_VERSION);
    for (const Subcommand& subcommand : kSubcommands) {
        printUsageLine(stream, subcommand);
    }
    const std::filesystem::path data = orbis::examples::dataDirectory();
    std::fprintf(stream, "SCENE.json and PATH.json may name an example in %s (scenes/, paths/):",
                 data.string().c_str());
    std::error_code error;
    std::vector<std::string> examples;
    for (const char* folder : {"scenes", "paths"}) {
        for (const auto& entry : std::filesystem::directory_iterator(data / folder, error)) {
            if (entry.path().extension() == ".json") {
                examples.push_back(entry.path().stem().string());
            }
        }
    }
    std::sort(examples.begin(), examples.end());
    for (const std::string& example : examples) {
        std::fprintf(stream, " %s", example.c_str());
    }
    std::fprintf(stream, "\nexit codes: 0 success, 1 failure (e.g. an invalid scene file), 2 usage\n");
    return exitCode;
}

int commandUsage(std::FILE* stream, const Subcommand& subcommand, int exitCode)
{
    std::fprintf(stream, "usage:\n");
    for (const Subcommand& form : kSubcommands) { // tile has two forms
        if (form.name == subcommand.name) {
            printUsageLine(stream, form);
        }
    }
    std::fprintf(stream, "(orbis help: every command; docs/cli.md: the options in full)\n");
    return exitCode;
}

const Subcommand* findSubcommand(std::string_view name)
{
    for (const Subcommand& subcommand : kSubcommands) {
        if (subcommand.name == name) {
            return &subcommand;
        }
    }
    return nullptr;
}

bool asksForHelp(std::string_view argument)
{
    return argument == "--help" || argument == "-h";
}

/// "unknown command "rnder" (did you mean "render"?)".
int unknownCommand(std::string_view name)
{
    std::vector<std::string_view> names;
    for (const Subcommand& subcommand : kSubcommands) {
        if (std::find(names.begin(), names.end(), subcommand.name) == names.end()) {
            names.push_back(subcommand.name);
        }
    }
    std::fprintf(stderr, "orbis: unknown command %s%s\n", orbis::world::quote(name).c_str(),
                 orbis::world::suggestion(name, names).c_str());
    return usage(stderr, kExitUsage);
}

} // namespace

int main(int argc, char** argv)
{
    const Arguments all(argv, static_cast<std::size_t>(argc));
    if (all.size() < 2 || asksForHelp(all[1])) {
        return usage(stdout, kExitOk);
    }
    const std::string_view name = all[1];
    const Arguments arguments = all.subspan(2);
    if (name == "help") {
        if (arguments.empty()) {
            return usage(stdout, kExitOk);
        }
        const Subcommand* subcommand = findSubcommand(arguments[0]);
        return subcommand ? commandUsage(stdout, *subcommand, kExitOk) : unknownCommand(arguments[0]);
    }
    const Subcommand* subcommand = findSubcommand(name);
    if (!subcommand) {
        return unknownCommand(name);
    }
    if (std::any_of(arguments.begin(), arguments.end(), asksForHelp)) {
        return commandUsage(stdout, *subcommand, kExitOk);
    }
    try {
        return subcommand->run(arguments);
    } catch (const UsageError& error) {
        std::fprintf(stderr, "orbis %.*s: %s\n", static_cast<int>(name.size()), name.data(), error.message.c_str());
        return commandUsage(stderr, *subcommand, kExitUsage);
    } catch (const std::exception& error) {
        std::fprintf(stderr, "orbis %.*s: %s\n", static_cast<int>(name.size()), name.data(), error.what());
        return kExitFailed;
    }
}
