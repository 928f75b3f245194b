// Virtual texturing on the globe (Mayer's thesis; the SIGGRAPH 2013 course, chapter 6): the Blue
// Marble over the Alps as one virtual texture of 256-texel pages, fed back from what the frame
// sees. Besides the view it writes the machinery: the physical texture (the slots, each a page and
// its border), the page table's finest level coloured by the level each page shows (its own or a
// coarser ancestor's), and the last feedback buffer read back (the level each pixel asks for,
// fallbacks white).
// Usage: ch_virtual_texturing [--out file.png] [--width W] [--height H]
// Writes file.png, file-physical.png, file-page-table.png and file-feedback.png.
// Data: examples::dataDirectory() (the folder ORBIS_DATA_DIR names, or data/).
#include "../common/SceneExample.h"

#include <orbis/core/Transforms.h>
#include <orbis/scene/VirtualTextureGlobe.h>
#include <orbis/world/TileSource.h>

#include <cstdio>
#include <filesystem>
#include <string>

namespace {

using namespace orbis;
using namespace orbis::scene;

/// `path` with `suffix` before its extension: "view.png" -> "view-physical.png".
std::string besides(const std::string& path, const std::string& suffix)
{
    const std::filesystem::path p(path);
    return (p.parent_path() / (p.stem().string() + suffix + p.extension().string())).string();
}

/// Each pixel `factor` times across and up: a page table of 32 x 16 entries made visible, a
/// feedback buffer at the view's size.
Image enlarged(const Image& image, int factor)
{
    Image big(image.width * factor, image.height * factor, image.channels);
    for (int y = 0; y < big.height; ++y) {
        for (int x = 0; x < big.width; ++x) {
            std::copy_n(image.pixel(x / factor, y / factor), image.channels, big.pixel(x, y));
        }
    }
    return big;
}

} // namespace

int main(int argc, char** argv)
{
    std::shared_ptr<VirtualTextureGlobe> globe;
    return examples::runStreamingExample(
        argc, argv, "ch_virtual_texturing.png",
        [&](Scene& scene, const auto&) {
            VirtualTextureGlobeOptions options;
            options.source = world::openTileSource((examples::dataDirectory() / "imagery" / "BlueMarble").string());
            options.virtualTexture.pageSize = 256;
            options.virtualTexture.border = 4;
            options.virtualTexture.physicalPages = 64;
            options.virtualTexture.feedbackDivisor = 4;
            options.loader.workerThreads = 2;
            globe = std::make_shared<VirtualTextureGlobe>(scene.ellipsoid(), options);
            scene.add(globe);
            const Ellipsoid& ellipsoid = scene.ellipsoid();
            const glm::dvec3 eye = ellipsoid.toCartesian(Geodetic3D::fromDegrees(8.0, 43.5, 300000.0));
            const ViewOrientation view = headingPitchRollToView(ellipsoid, eye, toRadians(10.0), toRadians(-35.0), 0.0);
            scene.camera().lookAt(eye, eye + view.direction * glm::length(eye), view.up);
        },
        [&](renderer::Context&, Scene&, const examples::ExampleSettings& settings) {
            const std::string physical = besides(settings.output, "-physical");
            const std::string pageTable = besides(settings.output, "-page-table");
            const std::string feedback = besides(settings.output, "-feedback");
            world::writePng(globe->physicalTextureImage(), physical);
            world::writePng(enlarged(globe->pageTableImage(), 16), pageTable);
            // A feedback pixel covers feedbackDivisor x feedbackDivisor pixels of the view.
            world::writePng(enlarged(globe->feedbackImage(), globe->options().virtualTexture.feedbackDivisor), feedback);
            std::printf("%s: the physical texture, %d slots of %d texels\n%s: the page table's level %u, 16 pixels a page\n"
                        "%s: the feedback buffer, enlarged to the view\nlevels 0 to %u coloured:",
                        physical.c_str(), globe->options().virtualTexture.physicalPages, globe->layout().slotSize(),
                        pageTable.c_str(), globe->layout().finestLevel, feedback.c_str(), globe->layout().finestLevel);
            for (std::uint32_t level = 0; level <= globe->layout().finestLevel; ++level) {
                const auto color = VirtualTextureGlobe::levelColor(level);
                std::printf(" %u #%02x%02x%02x", level, color[0], color[1], color[2]);
            }
            std::printf("; fallbacks in the feedback white\n");
        });
}
