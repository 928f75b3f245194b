#pragma once

// What every scene example shares: arguments, a headless device, a framebuffer, one frame of a
// Scene (or a row of captioned tiles) written to a PNG, and the frame statistics printed.

#include <orbis/scene/Scene.h>
#include <orbis/world/ImageFile.h>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

namespace orbis::scene {
class BillboardCollection;
} // namespace orbis::scene
namespace orbis::world {
struct CsvPoints;
} // namespace orbis::world

namespace orbis::examples {

struct ExampleSettings {
    std::string output; ///< PNG path
    int width = 800;
    int height = 600;
};

/// Parses [--out file.png] [--width W] [--height H], builds the scene with `setup`, renders one
/// frame and writes the PNG. With --view [--frames N], shows the scene in a window instead
/// (runViewer; with --frames, the last frame shown goes to the PNG). Returns the process exit
/// code: 0, 1 for an orbis::Error, 2 for usage.
int runSceneExample(int argc, char** argv, const std::string& defaultOutput,
                    const std::function<void(scene::Scene&, const ExampleSettings&)>& setup);

/// As runSceneExample, for a scene that streams (tiles, pages): frames are rendered until the
/// statistics say the tiles converged (at most maxFrames), the last goes to the PNG, then `done`
/// runs with the context and the scene (for further pictures). No window.
int runStreamingExample(int argc, char** argv, const std::string& defaultOutput,
                        const std::function<void(scene::Scene&, const ExampleSettings&)>& setup,
                        const std::function<void(renderer::Context&, scene::Scene&, const ExampleSettings&)>& done,
                        int maxFrames = 600);

/// One tile of a side-by-side example: its pixels and the caption written over them.
struct ExampleTile {
    Image image;
    std::string caption; ///< lines split at '\n'
};

/// Parses the arguments as runSceneExample does (W x H: one tile; `defaults` where not given),
/// calls `renderTile` for tiles 0 to tileCount - 1 with a W x H framebuffer set on the context,
/// captions each tile (scaled with it, up to 13 pixels) and writes them three to a row as one PNG.
/// Returns the process exit code as runSceneExample does.
int runTiledExample(int argc, char** argv, const ExampleSettings& defaults, std::size_t tileCount,
                    const std::function<ExampleTile(renderer::Context&, std::size_t tile, const ExampleSettings&)>& renderTile);

/// The project's data/: the folder ORBIS_DATA_DIR names in the environment; else, for an installed
/// program (<prefix>/bin), the data installed with it (<prefix>/share/orbis/data); else the source
/// tree's data/.
std::filesystem::path dataDirectory();

/// The Natural Earth II TMS pyramid in data/imagery.
std::string naturalEarthPyramid();

/// The day and night Earth images of Debian's xplanet-images package.
std::string xplanetDayImage();
std::string xplanetNightImage();

/// Every point of `cities` as a billboard of `dot` in one collection, tinted the chapter 9 example's
/// amber (the bench times the same collection).
std::shared_ptr<scene::BillboardCollection> cityBillboards(const Ellipsoid& ellipsoid, const world::CsvPoints& cities,
                                                    const Image& dot);

/// A camera looking at the Earth's centre from a geodetic position.
void lookAtEarthFrom(scene::Scene& scene, const Geodetic3D& eye);

/// A streamed scene drawn until its tiles converge, at most maxFrames: the last frame's statistics
/// and how many frames it took.
struct ConvergedFrame {
    scene::FrameStatistics statistics;
    int frames = 0;
};
ConvergedFrame renderUntilTilesConverge(scene::Scene& scene, renderer::Context& context, int maxFrames = 600);

} // namespace orbis::examples
