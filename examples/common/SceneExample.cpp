#include "SceneExample.h"

#include "PrecisionScenes.h"
#include "Viewer.h"

#include <orbis/core/Error.h>
#include <orbis/core/SunPosition.h>
#include <orbis/renderer/Device.h>
#include <orbis/scene/BillboardCollection.h>
#include <orbis/world/CsvPoints.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <optional>
#include <vector>

using namespace orbis::world;
using namespace orbis::renderer;
using namespace orbis::scene;

namespace orbis::examples {

namespace {

struct Arguments {
    ExampleSettings settings;
    bool view = false;         ///< --view: in a window instead of a PNG
    std::optional<int> frames; ///< --frames N with --view: stop after N, the last one to the PNG
};

/// [--out file.png] [--width W] [--height H], and with `viewable` [--view [--frames N]], over
/// `defaults`; empty (the usage printed) when the arguments are wrong.
std::optional<Arguments> parseArguments(int argc, char** argv, const ExampleSettings& defaults, bool viewable)
{
    Arguments arguments{defaults, false, std::nullopt};
    ExampleSettings& settings = arguments.settings;
    bool valid = true;
    for (int i = 1; i < argc && valid; ++i) {
        const bool hasValue = i + 1 < argc;
        if (std::strcmp(argv[i], "--out") == 0 && hasValue) {
            settings.output = argv[++i];
        } else if (std::strcmp(argv[i], "--width") == 0 && hasValue) {
            settings.width = std::atoi(argv[++i]);
        } else if (std::strcmp(argv[i], "--height") == 0 && hasValue) {
            settings.height = std::atoi(argv[++i]);
        } else if (viewable && std::strcmp(argv[i], "--view") == 0) {
            arguments.view = true;
        } else if (viewable && std::strcmp(argv[i], "--frames") == 0 && hasValue) {
            arguments.frames = std::atoi(argv[++i]);
            valid = *arguments.frames >= 1;
        } else {
            valid = false;
        }
    }
    if (!valid || (arguments.frames && !arguments.view)) {
        std::fprintf(stderr, "usage: %s [--out file.png] [--width W] [--height H]%s\n", argv[0],
                     viewable ? " [--view [--frames N]]" : "");
        return std::nullopt;
    }
    return arguments;
}

/// Parses the arguments (parseArguments, no --view), then runs `body` with a headless device's
/// context and a framebuffer of the parsed size (not yet set on the context). Returns the process
/// exit code: 0, 1 for an orbis::Error (printed), 2 for usage (printed).
int runWithFramebuffer(int argc, char** argv, const ExampleSettings& defaults,
                       const std::function<void(Context&, Framebuffer&, const ExampleSettings&)>& body)
{
    const std::optional<Arguments> parsed = parseArguments(argc, argv, defaults, false);
    if (!parsed) {
        return 2;
    }
    const ExampleSettings& settings = parsed->settings;
    try {
        Device device;
        Context& context = device.context();
        Framebuffer framebuffer = context.createFramebuffer(settings.width, settings.height);
        body(context, framebuffer, settings);
        return 0;
    } catch (const Error& error) {
        std::fprintf(stderr, "%s: %s\n", argv[0], error.what());
        return 1;
    }
}

} // namespace

int runSceneExample(int argc, char** argv, const std::string& defaultOutput,
                    const std::function<void(Scene&, const ExampleSettings&)>& setup)
{
    ExampleSettings defaults;
    defaults.output = defaultOutput;
    auto makeScene = [&](const ExampleSettings& settings) {
        auto scene = std::make_unique<Scene>();
        scene->setSunDirection(sunDirectionEarthFixed(*parseUtcTime("2026-03-20T12:00:00Z")));
        setup(*scene, settings);
        return scene;
    };
    const std::optional<Arguments> parsed = parseArguments(argc, argv, defaults, true);
    if (!parsed) {
        return 2;
    }
    if (parsed->view) {
        try {
            ViewerOptions options;
            options.width = parsed->settings.width;
            options.height = parsed->settings.height;
            options.title = argv[0];
            options.frames = parsed->frames;
            if (parsed->frames) {
                options.output = parsed->settings.output;
            }
            Device device = createViewerDevice(options);
            runViewer(device, *makeScene(parsed->settings), options);
            return 0;
        } catch (const Error& error) {
            std::fprintf(stderr, "%s: %s\n", argv[0], error.what());
            return 1;
        }
    }
    auto render = [&](Context& context, Framebuffer& framebuffer, const ExampleSettings& settings) {
        context.setFramebuffer(&framebuffer);
        const std::unique_ptr<Scene> scene = makeScene(settings);
        const FrameStatistics statistics = scene->render(context);
        writePng(context.readPixels(), settings.output);
        std::printf("%s: %dx%d\n%s", settings.output.c_str(), settings.width, settings.height,
                    statistics.toText().c_str());
    };
    return runWithFramebuffer(argc, argv, defaults, render);
}

int runStreamingExample(int argc, char** argv, const std::string& defaultOutput,
                        const std::function<void(Scene&, const ExampleSettings&)>& setup,
                        const std::function<void(Context&, Scene&, const ExampleSettings&)>& done, int maxFrames)
{
    ExampleSettings defaults;
    defaults.output = defaultOutput;
    auto render = [&](Context& context, Framebuffer& framebuffer, const ExampleSettings& settings) {
        context.setFramebuffer(&framebuffer);
        Scene scene;
        scene.setSunDirection(sunDirectionEarthFixed(*parseUtcTime("2026-03-20T12:00:00Z")));
        setup(scene, settings);
        FrameStatistics statistics;
        int frames = 0;
        do {
            statistics = scene.render(context);
            ++frames;
        } while (statistics.tiles && !statistics.tiles->converged && frames < maxFrames);
        writePng(context.readPixels(), settings.output);
        std::printf("%s: %dx%d after %d frames\n%s", settings.output.c_str(), settings.width, settings.height, frames,
                    statistics.toText().c_str());
        done(context, scene, settings);
    };
    return runWithFramebuffer(argc, argv, defaults, render);
}

int runTiledExample(int argc, char** argv, const ExampleSettings& defaults, std::size_t tileCount,
                    const std::function<ExampleTile(Context&, std::size_t tile, const ExampleSettings&)>& renderTile)
{
    auto render = [&](Context& context, Framebuffer& framebuffer, const ExampleSettings& settings) {
        const float width = static_cast<float>(settings.width);
        const float height = static_cast<float>(settings.height);
        const float captionSize = std::clamp(std::min(width / 25.0f, height / 18.0f), 6.5f, 13.0f);
        std::vector<Image> tiles;
        for (std::size_t i = 0; i < tileCount; ++i) {
            context.setFramebuffer(&framebuffer); // again for each tile, whatever the last one left set
            ExampleTile tile = renderTile(context, i, settings);
            drawCaption(tile.image, 4, 3, tile.caption, captionSize);
            tiles.push_back(std::move(tile.image));
        }
        context.setFramebuffer(nullptr);
        writePng(composeTiles(tiles, 3), settings.output);
        std::printf("%s: %d tiles of %dx%d\n", settings.output.c_str(), static_cast<int>(tiles.size()),
                    settings.width, settings.height);
    };
    return runWithFramebuffer(argc, argv, defaults, render);
}

std::filesystem::path dataDirectory()
{
    if (const char* fromEnvironment = std::getenv("ORBIS_DATA_DIR"); fromEnvironment && *fromEnvironment) {
        return fromEnvironment;
    }
    // An installed program finds the data installed with it; one in the build tree, the source's.
    std::error_code error;
    const std::filesystem::path program = std::filesystem::read_symlink("/proc/self/exe", error);
    if (!error) {
        const std::filesystem::path installed = program.parent_path() / ORBIS_INSTALLED_DATA_FROM_BINDIR;
        if (std::filesystem::is_directory(installed, error)) {
            return installed.lexically_normal();
        }
    }
    return ORBIS_DATA_DIR;
}

std::string naturalEarthPyramid()
{
    return (dataDirectory() / "imagery" / "NaturalEarthII").string();
}

std::string xplanetDayImage()
{
    return "/usr/share/xplanet/images/earth.jpg";
}

std::string xplanetNightImage()
{
    return "/usr/share/xplanet/images/night.jpg";
}

std::shared_ptr<BillboardCollection> cityBillboards(const Ellipsoid& ellipsoid, const CsvPoints& cities,
                                                    const Image& dot)
{
    auto billboards = std::make_shared<BillboardCollection>();
    const std::size_t image = billboards->addImage(dot);
    billboards->reserve(cities.size());
    for (const Geodetic3D& position : cities.positions) {
        Billboard b;
        b.position = ellipsoid.toCartesian(position);
        b.image = image;
        b.color = {1.0f, 0.8f, 0.3f, 0.6f};
        billboards->add(b);
    }
    return billboards;
}

void lookAtEarthFrom(Scene& scene, const Geodetic3D& eye)
{
    scene.camera().lookAt(scene.ellipsoid().toCartesian(eye), glm::dvec3(0.0), glm::dvec3(0.0, 0.0, 1.0));
}

ConvergedFrame renderUntilTilesConverge(Scene& scene, renderer::Context& context, int maxFrames)
{
    ConvergedFrame frame;
    while (frame.frames < maxFrames && !(frame.statistics.tiles && frame.statistics.tiles->converged)) {
        frame.statistics = scene.render(context);
        ++frame.frames;
    }
    return frame;
}

} // namespace orbis::examples
