// The orbis command: one subcommand per job, looked up in a table (kSubcommands), each a function
// from its arguments to the exit code: 0 success, 1 the job failed (an invalid scene file, ...),
// 2 the command line is wrong.
#include "../common/SceneExample.h"
#include "../common/Viewer.h"

#include <orbis/core/Ellipsoid.h>
#include <orbis/renderer/Device.h>
#include <orbis/scene/CameraControllers.h>
#include <orbis/scene/SceneBuilder.h>
#include <orbis/core/TileKey.h>
#include <orbis/world/ImageFile.h>
#include <orbis/world/FileAccess.h>
#include <orbis/world/ImageryTiler.h>
#include <orbis/world/SceneData.h>
#include <orbis/world/SceneFile.h>
#include <orbis/world/TerrainTiler.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <unistd.h>

namespace {

constexpr int kExitOk = 0;
constexpr int kExitFailed = 1;
constexpr int kExitUsage = 2;

using Arguments = std::span<char* const>;

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
        return kExitUsage;
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
bool confineFiles(const char* folder)
{
    try {
        orbis::world::setFileSandbox(std::filesystem::path(folder));
        return true;
    } catch (const orbis::Error& error) {
        std::fprintf(stderr, "orbis: %s\n", error.what());
        return false;
    }
}

/// Builds the scene's primitives as render does, without a GPU (polygons triangulated, billboard
/// images packed, models unfolded): what the files' readers accept but drawing them refuses. False,
/// with the message, when that fails.
bool buildsWithoutFault(const std::string& path, const orbis::world::SceneDescription& description)
{
    try {
        orbis::scene::Scene scene;
        orbis::scene::populateScene(description, scene);
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
    std::vector<std::string> scenes;
    for (std::size_t i = 0; i < arguments.size(); ++i) {
        if (std::string_view(arguments[i]) == "--sandbox" && i + 1 < arguments.size()) {
            if (!confineFiles(arguments[++i])) {
                return kExitFailed;
            }
        } else if (std::string_view(arguments[i]).starts_with("--")) {
            return kExitUsage;
        } else {
            scenes.push_back(resolveDataFile(arguments[i], "scenes"));
        }
    }
    if (scenes.empty()) {
        return kExitUsage;
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

/// A progress bar on a terminal, for flights.
void showProgress(int done, int count, double elapsedSeconds)
{
    if (count <= 1 || !isatty(fileno(stderr))) {
        return;
    }
    constexpr int kWidth = 30;
    const int filled = done * kWidth / count;
    std::fprintf(stderr, "\r[%.*s%*s] %d/%d frames, %.1f frames/s", filled, "==============================",
                 kWidth - filled, "", done, count, elapsedSeconds > 0.0 ? done / elapsedSeconds : 0.0);
    if (done == count) {
        std::fputc('\n', stderr);
    }
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

/// Reads the arguments into `parsed`; false when they are malformed.
bool parseSceneArguments(Arguments arguments, SceneArguments& parsed)
{
    for (std::size_t i = 0; i < arguments.size(); ++i) {
        const std::string_view argument = arguments[i];
        if (!argument.starts_with("--")) {
            if (parsed.scenePath) {
                return false;
            }
            parsed.scenePath = resolveDataFile(std::string(argument), "scenes");
            continue;
        }
        if (argument == "--no-wait") {
            parsed.noWait = true;
            continue;
        }
        if (i + 1 == arguments.size()) {
            return false;
        }
        const char* value = arguments[++i];
        auto count = [&](std::optional<int>& into, std::uint32_t maximum) {
            const std::optional<std::uint32_t> number = parseCount(value, 1, maximum);
            if (!number) {
                std::fprintf(stderr, "orbis: %.*s: expected a whole number from 1 to %u, got %s\n",
                             static_cast<int>(argument.size()), argument.data(), maximum,
                             orbis::world::quote(value).c_str());
                return false;
            }
            into = static_cast<int>(*number);
            return true;
        };
        if (argument == "--out") {
            parsed.output = value;
        } else if (argument == "--stats") {
            parsed.statisticsPath = value;
        } else if (argument == "--path") {
            parsed.cameraPath = resolveDataFile(value, "paths");
        } else if (argument == "--sandbox") {
            parsed.sandbox = value;
        } else if (!((argument == "--width" && count(parsed.width, 16384)) ||
                     (argument == "--height" && count(parsed.height, 16384)) ||
                     (argument == "--frames" && count(parsed.frames, 100000)) ||
                     (argument == "--max-frames" && count(parsed.maxFrames, 100000)))) {
            return false;
        }
    }
    return true;
}

/// A line now and then while render waits for tiles: on a terminal as it goes, elsewhere every
/// few seconds.
class ConvergenceProgress {
public:
    void show(int frames, const orbis::scene::FrameStatistics& statistics)
    {
        if (!statistics.tiles) {
            return;
        }
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - _start).count();
        const bool terminal = isatty(fileno(stderr)) != 0;
        if (!terminal && elapsed < _nextLine) {
            return;
        }
        _nextLine = elapsed + 5.0;
        std::fprintf(stderr, terminal ? "\rwaiting for tiles: %d frames, %zu drawn, %zu pending " :
                                        "waiting for tiles: %d frames, %zu drawn, %zu pending\n",
                     frames, statistics.tiles->drawn, statistics.tiles->pending);
        _shown = terminal;
    }
    ~ConvergenceProgress()
    {
        if (_shown) {
            std::fputc('\n', stderr);
        }
    }

private:
    std::chrono::steady_clock::time_point _start = std::chrono::steady_clock::now();
    double _nextLine = 5.0;
    bool _shown = false;
};

/// orbis render [SCENE.json] [--out PNG] [--width W] [--height H] [--stats JSON] [--max-frames N |
/// --no-wait] [--frames N --path PATH.json]: one picture of a scene file (the built-in default
/// Earth without one), rendered until its streamed tiles have converged (at most --max-frames
/// frames, 600 by default; --no-wait writes the first), or a flight along a camera path as
/// numbered PNGs, one frame each, headless. Each PNG appears whole or not at all.
int runRender(Arguments arguments)
{
    SceneArguments parsed;
    if (!parseSceneArguments(arguments, parsed)) {
        return kExitUsage;
    }
    const auto& [scenePath, outputOption, statisticsPath, cameraPath, width, height, frames, maxFrames, noWait, sandbox] =
        parsed;
    const std::string output = outputOption.value_or("orbis.png");
    if (frames.value_or(1) > 1 && !cameraPath) {
        std::fprintf(stderr, "orbis render: --frames needs a camera path (--path PATH.json)\n");
        return kExitUsage;
    }
    if (noWait && maxFrames) {
        std::fprintf(stderr, "orbis render: --no-wait writes the first frame, --max-frames waits: give one\n");
        return kExitUsage;
    }
    if (sandbox && !confineFiles(sandbox->c_str())) {
        return kExitFailed;
    }

    try {
        const orbis::world::SceneDescription description =
            scenePath ? orbis::world::parseSceneFile(*scenePath)
                      : orbis::world::parseDefaultScene(orbis::examples::dataDirectory() / "scenes");
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
        orbis::scene::populateScene(description, scene);

        std::string statisticsJson = frameCount > 1 ? "[\n" : "";
        const auto start = std::chrono::steady_clock::now();
        for (int frame = 0; frame < frameCount; ++frame) {
            orbis::scene::FrameStatistics statistics;
            if (flight) {
                const double t = frameCount > 1 ? static_cast<double>(frame) / (frameCount - 1) : 0.0;
                flight->apply(flight->keyframes().front().seconds + t * flight->duration(), scene.camera());
                statistics = scene.render(context);
            } else {
                // A still picture waits for its tiles: frames until nothing changes any more.
                ConvergenceProgress progress;
                const int limit = noWait ? 1 : maxFrames.value_or(600);
                for (int rendered = 1;; ++rendered) {
                    statistics = scene.render(context);
                    const bool converged = !statistics.tiles || statistics.tiles->converged;
                    if (converged) {
                        statistics.framesToConverge = static_cast<std::uint64_t>(rendered);
                    }
                    if (converged || rendered >= limit) {
                        break;
                    }
                    progress.show(rendered, statistics);
                }
            }
            const std::string path = framePath(output, frame, frameCount);
            orbis::world::writePng(context.readPixels(), outputs.stage(path));
            if (frame == 0 || frameCount == 1) {
                std::printf("%s: %dx%d, %s\n%s", path.c_str(), framebuffer.width(), framebuffer.height(),
                            device.info().renderer.c_str(), statistics.toText().c_str());
            }
            if (!flight && statistics.tiles) {
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
            }
            showProgress(frame + 1, frameCount,
                         std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        }
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

/// orbis view [SCENE.json] [--width W] [--height H] [--frames N --out PNG]: the scene in a window,
/// turned by dragging with the left button and zoomed with the wheel (about the Earth's centre);
/// F switches to flying (drag to look around, W A S D to move, E and Q up and down) and back;
/// Escape or closing the window ends it. Each frame is rendered offscreen, where the scene may have
/// the float depth buffer a window lacks, and copied to the window. --frames stops after N frames,
/// and --out then writes the last one as the window showed it.
int runView(Arguments arguments)
{
    SceneArguments parsed;
    if (!parseSceneArguments(arguments, parsed) || parsed.statisticsPath || parsed.cameraPath ||
        (parsed.output && !parsed.frames)) {
        return kExitUsage;
    }
    try {
        const orbis::world::SceneDescription description =
            parsed.scenePath ? orbis::world::parseSceneFile(*parsed.scenePath)
                             : orbis::world::parseDefaultScene(orbis::examples::dataDirectory() / "scenes");
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
        orbis::scene::populateScene(description, scene, build);
        orbis::examples::runViewer(device, scene, options);
        return kExitOk;
    } catch (const orbis::Error& error) {
        std::fprintf(stderr, "orbis view: %s\n", error.what());
        return kExitFailed;
    }
}

/// orbis info: the OpenGL driver the headless device gets, and its limits.
int runInfo(Arguments arguments)
{
    if (!arguments.empty()) {
        return kExitUsage;
    }
    const orbis::renderer::Device device;
    const orbis::renderer::DeviceInfo& info = device.info();
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
    std::printf("KHR_debug:        %s\n", info.khrDebug ? "yes" : "no");
    return kExitOk;
}

/// Progress of a tiling run on stderr: one line rewritten on a terminal, else a line every five
/// seconds (a batch job's log), and the last tile always.
class TilingProgressLine {
public:
    void operator()(const orbis::world::TilerProgress& progress)
    {
        const bool last = progress.done == progress.total;
        const double sinceLine = progress.seconds - _lastLine;
        if (!last && sinceLine < (_terminal ? 0.1 : 5.0)) {
            return;
        }
        _lastLine = progress.seconds;
        const auto done = static_cast<double>(progress.done);
        const auto total = static_cast<double>(progress.total);
        const double rate = progress.seconds > 0.0 ? done / progress.seconds : 0.0;
        const double left = rate > 0.0 ? (total - done) / rate : 0.0;
        std::fprintf(stderr, "%slevel %u: %zu/%zu tiles, all levels %zu/%zu (%.0f%%), %.1f tiles/s, %.0f s left%s",
                     _terminal ? "\r" : "", progress.level, progress.levelDone, progress.levelTotal, progress.done,
                     progress.total, total > 0.0 ? 100.0 * done / total : 100.0, rate, left,
                     _terminal ? (last ? "\n" : "   ") : "\n");
    }

private:
    bool _terminal = isatty(fileno(stderr)) != 0;
    double _lastLine = -1e9;
};

/// `text` as a finite number of metres, 0 or more; empty when it is anything else.
std::optional<double> parseMetres(std::string_view text)
{
    double value = 0.0;
    const auto [rest, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || error != std::errc() || rest != text.data() + text.size() || !std::isfinite(value) || value < 0.0) {
        return std::nullopt;
    }
    return value;
}

/// The options both tilers take: INPUT --out FOLDER [--levels N] [--level L [--range X0:X1]]
/// [--threads N] [--title TEXT] [--attribution TEXT]; the rest go to `other`, which returns
/// false for an option it does not know or a bad value.
struct TilingArguments {
    std::filesystem::path input;
    std::filesystem::path output;
    std::optional<std::uint32_t> levels;
    std::optional<std::uint32_t> onlyLevel;
    std::optional<std::pair<std::uint32_t, std::uint32_t>> columns;
    int threads = 0;
    std::string title;
    std::string attribution;

    template <class Other>
    bool parse(Arguments arguments, Other&& other)
    {
        for (std::size_t i = 0; i < arguments.size(); ++i) {
            const std::string_view argument = arguments[i];
            if (!argument.starts_with("--")) {
                if (!input.empty()) {
                    return false;
                }
                input = std::string(argument);
                continue;
            }
            if (other.flag(argument)) {
                continue;
            }
            if (i + 1 == arguments.size()) {
                return false;
            }
            const std::string_view value = arguments[++i];
            if (argument == "--out") {
                output = std::string(value);
            } else if (argument == "--levels") {
                levels = parseCount(value, 1, orbis::kMaximumTileLevel + 1);
                if (!levels) {
                    return false;
                }
            } else if (argument == "--level") {
                onlyLevel = parseCount(value, 0, orbis::kMaximumTileLevel);
                if (!onlyLevel) {
                    return false;
                }
            } else if (argument == "--range") {
                const std::size_t colon = value.find(':');
                const auto first = parseCount(value.substr(0, colon), 0, 0x7fffffff);
                const auto last =
                    colon == std::string_view::npos ? std::nullopt : parseCount(value.substr(colon + 1), 0, 0x7fffffff);
                if (!first || !last) {
                    return false;
                }
                columns = std::pair(*first, *last);
            } else if (argument == "--threads") {
                const auto count = parseCount(value, 1, 256);
                if (!count) {
                    return false;
                }
                threads = static_cast<int>(*count);
            } else if (argument == "--title") {
                title = std::string(value);
            } else if (argument == "--attribution") {
                attribution = std::string(value);
            } else if (!other.option(argument, value)) {
                return false;
            }
        }
        return !input.empty() && !output.empty() && (!columns || onlyLevel);
    }
};

/// orbis tile imagery INPUT --out FOLDER [--format jpg|png|webp] [--quality Q] and the common
/// options: a TMS pyramid (geographic, tilemapresource.xml) cut from an image GDAL reads.
int runTileImagery(Arguments arguments)
{
    orbis::world::ImageryTilerOptions options;
    struct Extra {
        orbis::world::ImageryTilerOptions& options;
        bool flag(std::string_view) { return false; }
        bool option(std::string_view argument, std::string_view value)
        {
            if (argument == "--format") {
                options.format = orbis::world::imageFormatFromName(value);
                return options.format != orbis::world::ImageFormat::Unknown && value.find('/') == std::string_view::npos;
            }
            if (argument == "--quality") {
                const auto quality = parseCount(value, 0, 100);
                options.quality = quality ? std::optional<int>(static_cast<int>(*quality)) : std::nullopt;
                return quality.has_value();
            }
            return false;
        }
    } extra{options};
    TilingArguments common;
    if (!common.parse(arguments, extra)) {
        return kExitUsage;
    }
    options.input = common.input;
    options.output = common.output;
    options.levels = common.levels;
    options.onlyLevel = common.onlyLevel;
    options.columns = common.columns;
    options.threads = common.threads;
    options.title = common.title;
    options.attribution = common.attribution;
    try {
        options.progress = TilingProgressLine();
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
    struct Extra {
        orbis::world::TerrainTilerOptions& options;
        bool flag(std::string_view argument)
        {
            if (argument == "--no-normals") {
                options.normals = false;
                return true;
            }
            return false;
        }
        bool option(std::string_view argument, std::string_view value)
        {
            if (argument == "--format") {
                if (value == "quantized-mesh") {
                    options.format = orbis::world::TerrainTileFormat::QuantizedMesh;
                } else if (value == "heightmap") {
                    options.format = orbis::world::TerrainTileFormat::Heightmap;
                } else {
                    return false;
                }
                return true;
            }
            if (argument == "--samples") {
                const auto samples = parseCount(value, 5, 1025);
                options.gridSize = samples ? static_cast<int>(*samples) : 0;
                return samples.has_value();
            }
            if (argument == "--gzip") {
                const auto level = parseCount(value, 0, 9);
                options.gzipLevel = level ? static_cast<int>(*level) : 0;
                return level.has_value();
            }
            if (argument == "--max-error") {
                options.maximumError = parseMetres(value);
                return options.maximumError.has_value();
            }
            if (argument == "--nodata-height") {
                double height = 0.0;
                const auto [rest, error] = std::from_chars(value.data(), value.data() + value.size(), height);
                options.noDataHeight = height;
                return !value.empty() && error == std::errc() && rest == value.data() + value.size() && std::isfinite(height);
            }
            return false;
        }
    } extra{options};
    TilingArguments common;
    if (!common.parse(arguments, extra)) {
        return kExitUsage;
    }
    options.input = common.input;
    options.output = common.output;
    options.levels = common.levels;
    options.onlyLevel = common.onlyLevel;
    options.columns = common.columns;
    options.threads = common.threads;
    options.title = common.title;
    options.attribution = common.attribution;
    try {
        options.progress = TilingProgressLine();
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
    if (arguments.size() < 2) {
        return kExitUsage;
    }
    const std::string_view kind = arguments[0];
    if (kind == "imagery") {
        return runTileImagery(arguments.subspan(1));
    }
    if (kind == "terrain") {
        return runTileTerrain(arguments.subspan(1));
    }
    return kExitUsage;
}

struct Subcommand {
    std::string_view name;
    std::string_view arguments; ///< for the usage line
    std::string_view summary;
    int (*run)(Arguments);
};

constexpr Subcommand kSubcommands[] = {
    {"demo", "", "geodetic conversions on WGS84 (the default with no subcommand)", runDemo},
    {"render",
     "[SCENE.json] [--out PNG] [--width W] [--height H] [--stats JSON] [--max-frames N | --no-wait] "
     "[--frames N --path PATH.json] [--sandbox FOLDER]",
     "render a scene file (the default Earth without one) to a PNG once its tiles have converged (at most "
     "--max-frames frames, 600 by default; --no-wait: the first frame), or a flight along a camera path to "
     "numbered PNGs, headless",
     runRender},
    {"view", "[SCENE.json] [--width W] [--height H] [--frames N [--out PNG]]",
     "show a scene file in a window (needs GLFW and a display): drag to turn, wheel to zoom, F to fly (W A S "
     "D, E Q), Escape to close",
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
    {"info", "", "the OpenGL vendor, renderer, version and limits", runInfo},
};

int usage(std::FILE* stream, int exitCode)
{
    std::fprintf(stream, "usage:\n");
    for (const Subcommand& subcommand : kSubcommands) {
        std::fprintf(stream, "  orbis %.*s %.*s\n      %.*s\n", static_cast<int>(subcommand.name.size()),
                     subcommand.name.data(), static_cast<int>(subcommand.arguments.size()),
                     subcommand.arguments.data(), static_cast<int>(subcommand.summary.size()),
                     subcommand.summary.data());
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

} // namespace

int main(int argc, char** argv)
{
    const Arguments all(argv, static_cast<std::size_t>(argc));
    const std::string_view name = all.size() > 1 ? std::string_view(all[1]) : std::string_view("demo");
    if (name == "help" || name == "--help" || name == "-h") {
        return usage(stdout, kExitOk);
    }
    for (const Subcommand& subcommand : kSubcommands) {
        if (subcommand.name == name) {
            try {
                const int exitCode = subcommand.run(all.size() > 2 ? all.subspan(2) : Arguments());
                return exitCode == kExitUsage ? usage(stderr, kExitUsage) : exitCode;
            } catch (const std::exception& error) {
                std::fprintf(stderr, "orbis %.*s: %s\n", static_cast<int>(name.size()), name.data(), error.what());
                return kExitFailed;
            }
        }
    }
    std::fprintf(stderr, "orbis: unknown command \"%.*s\"\n", static_cast<int>(name.size()), name.data());
    return usage(stderr, kExitUsage);
}
