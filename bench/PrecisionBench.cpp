// Book chapters 5 and 6 and the SIGGRAPH 2013 course, measured: each vertex transform's window
// error at each eye distance beside its cost per frame; whether the GPU keeps DSFUN90's two-sum;
// each depth strategy's wrongly ordered pixels and smallest resolved separation against the
// analytic minimum triangle separation, beside its cost per frame. docs/precision.md explains them;
// the full run also writes docs/precision.svg.

#include "Plot.h"
#include "PrecisionMeasurement.h"
#include "Report.h"

#include "PrecisionScenes.h"

#include <orbis/core/Transforms.h>
#include <orbis/core/SunPosition.h>
#include <orbis/renderer/Device.h>
#include <orbis/scene/MeshPrimitive.h>

#include <glm/geometric.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

using namespace orbis::renderer;
using namespace orbis::scene;

namespace orbis::bench {
namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

const VertexTransform kTransforms[] = {VertexTransform::RelativeToWorld,  VertexTransform::RelativeToCenter,
                                       VertexTransform::RelativeToEyeGpu, VertexTransform::RelativeToEyeDsfun90,
                                       VertexTransform::RelativeToEyeCpu, VertexTransform::Automatic};
const DepthStrategy kStrategies[] = {DepthStrategy::Single, DepthStrategy::MultiFrustum,
                                     DepthStrategy::LogarithmicVertex, DepthStrategy::Logarithmic,
                                     DepthStrategy::Complementary};

std::string distanceName(double meters)
{
    return meters >= 1e3 ? formatNumber(meters / 1e3, 3) + " km" : formatNumber(meters, 3) + " m";
}

/// "1 m", "10 km", "10000 km": a power of ten as an axis label.
std::string tickName(double meters)
{
    char text[32];
    std::snprintf(text, sizeof text, meters >= 1e3 ? "%.0f km" : "%.0f m", meters >= 1e3 ? meters / 1e3 : meters);
    return text;
}

// ---- Vertex transforms ------------------------------------------------------------------------

/// Milliseconds per frame of CPU (update, cull and bin) and of drawing (GPU finished), draw calls.
struct FrameCost {
    double cpuMs = 0.0;
    double drawMs = 0.0;
    std::size_t drawCalls = 0;
    std::size_t frustums = 0;
    std::uint64_t clears = 0;
    DepthStrategy strategy = DepthStrategy::MultiFrustum;
    double floatsRewritten = 0.0; ///< per frame, by CPU relative to eye
};

FrameCost frameCost(Scene& scene, Context& context, int frames, const std::function<void(int)>& move = {})
{
    scene.render(context); // compiles and uploads
    FrameCost cost;
    for (int i = 0; i < frames; ++i) {
        if (move) {
            move(i);
        }
        const FrameStatistics s = scene.render(context);
        cost.cpuMs += s.updateMilliseconds + s.cullMilliseconds;
        cost.drawMs += s.drawMilliseconds;
        cost.drawCalls = s.commandsExecuted;
        cost.frustums = s.frustums.size();
        cost.clears = s.renderer.clears;
        cost.strategy = s.depthStrategy;
    }
    cost.cpuMs /= frames;
    cost.drawMs /= frames;
    return cost;
}

/// 16 terrain-like tiles of 128 x 128 cells (266,256 vertices in all) over 40 km, the eye 300 m
/// above the middle, moving a metre each frame (so that CPU relative-to-eye rewrites every frame).
FrameCost vertexTransformCost(Context& context, VertexTransform transform, int frames)
{
    const glm::dvec3 origin = kEarth.toCartesian(Geodetic3D::fromDegrees(10.0, 45.0, 0.0));
    const glm::dmat4 frame = eastNorthUpToFixedFrame(kEarth, origin);
    Scene scene(kEarth);
    scene.setSunDirection(kEarth.geodeticSurfaceNormal(origin));
    std::vector<std::shared_ptr<MeshPrimitive>> tiles;
    constexpr int cells = 128;
    for (int tile = 0; tile < 16; ++tile) {
        const double east0 = -20e3 + 10e3 * (tile % 4);
        const double north0 = -20e3 + 10e3 * (tile / 4);
        Mesh mesh;
        for (int j = 0; j <= cells; ++j) {
            for (int i = 0; i <= cells; ++i) {
                const double e = east0 + 10e3 * i / cells;
                const double n = north0 + 10e3 * j / cells;
                mesh.positions.push_back(glm::dvec3(frame * glm::dvec4(e, n, 30.0 * std::sin(e / 700.0) * std::cos(n / 900.0), 1.0)));
                mesh.normals.push_back(glm::vec3(frame[2]));
            }
        }
        for (int j = 0; j < cells; ++j) {
            for (int i = 0; i < cells; ++i) {
                const auto a = static_cast<std::uint32_t>(j * (cells + 1) + i);
                mesh.indices.insert(mesh.indices.end(), {a, a + 1, a + cells + 2, a, a + cells + 2, a + cells + 1});
            }
        }
        tiles.push_back(
            std::make_shared<MeshPrimitive>(std::move(mesh), glm::vec4(0.4f, 0.6f, 0.3f, 1.0f), Pass::Opaque, transform));
        scene.add(tiles.back());
    }
    auto rewritten = [&] {
        double floats = 0.0;
        for (const auto& tile : tiles) {
            floats += static_cast<double>(tile->floatsRewritten());
        }
        return floats;
    };
    const glm::dvec3 eye = glm::dvec3(frame * glm::dvec4(0.0, -3000.0, 300.0, 1.0));
    const glm::dvec3 target = glm::dvec3(frame * glm::dvec4(0.0, 5000.0, 0.0, 1.0));
    scene.camera().lookAt(eye, target, glm::dvec3(frame[2]));
    scene.render(context); // uploads
    const double before = rewritten();
    FrameCost cost = frameCost(scene, context, frames, [&](int i) {
        scene.camera().lookAt(eye + static_cast<double>(i + 1) * glm::dvec3(frame[0]), target, glm::dvec3(frame[2]));
    });
    cost.floatsRewritten = (rewritten() - before) / frames; // frameCost's first frame keeps the eye
    return cost;
}

std::vector<Table> vertexTables(Context& context, const Options& options, std::vector<Series>& plot)
{
    const std::vector<double> distances = options.quick ? std::vector<double>{1.0, 1e3, 1e7}
                                                        : std::vector<double>{1, 10, 100, 1e3, 1e4, 1e5, 1e6, 1e7};
    struct Shell {
        const char* name;
        double height;
    };
    const std::vector<Shell> shells = options.quick ? std::vector<Shell>{{"surface", 0.0}}
                                                    : std::vector<Shell>{{"surface", 0.0}, {"700 km", 700e3}, {"GEO", 35786e3}};
    Table error;
    error.title = "Vertex transform: window error at each eye distance";
    error.description =
        "The GPU's window position of 81 points over the middle of the view around a point on WGS84 at (10 E, "
        "45 N), 700 km above it, or at geostationary height, read back with transform feedback from MeshPrimitive's "
        "own vertex shader, against P V p in double; the points belong to an object 200 km across whose centre is "
        "100 km to the side (PrecisionMeasurement.h: measureVertexJitter). The eye looks straight down from the "
        "distance given; 1920x1080, 45 degree vertical field of view. Each cell: worst error in pixels, and as a "
        "length across the view at the point's depth.";
    error.columns = {"transform", "target"};
    for (const double d : distances) {
        error.columns.push_back("eye " + distanceName(d));
    }
    const char* colours[] = {"#d62728", "#ff7f0e", "#bcbd22", "#2ca02c", "#1f77b4", "#9467bd"};
    std::vector<std::vector<JitterResult>> surface;
    int k = 0;
    for (const VertexTransform transform : kTransforms) {
        Series series{vertexTransformName(transform), colours[k++], transform == VertexTransform::Automatic, {}};
        surface.emplace_back();
        for (const Shell& shell : shells) {
            std::vector<std::string> row{vertexTransformName(transform), shell.name};
            for (const double d : distances) {
                const JitterResult r = measureVertexJitter(context, transform, jitterTarget(shell.height), d);
                row.push_back(std::isfinite(r.maxPixels) ? formatNumber(r.maxPixels, 2) + " px, " + formatLength(r.maxMeters)
                                                         : std::string("behind the eye"));
                if (shell.height == 0.0) {
                    series.points.emplace_back(d, r.maxPixels);
                    surface.back().push_back(r);
                }
            }
            error.rows.push_back(row);
        }
        plot.push_back(series);
    }
    error.notes = "Relative to world is off by the float spacing at the Earth's radius (0.5 m) and at GEO (4 m) whatever the "
                  "distance: tens of pixels near the eye. Relative to centre is off by 2^-24 of the object's size plus the "
                  "centre's distance: millimetres here, pixels within metres. The book's first GPU relative-to-eye (highs "
                  "split at multiples of 65536 m) keeps millimetres at any distance. DSFUN90 and CPU relative to eye are "
                  "off by 2^-24 of the distance: 1e-4 px everywhere. Automatic draws relative to centre until its predicted "
                  "error reaches half a pixel, then DSFUN90.";

    const int frames = options.quick ? 1 : 8;
    Table cost;
    cost.title = "Vertex transform: error beside cost per frame";
    cost.description =
        "Error from the table above (surface target). Cost: 16 terrain tiles of 128 x 128 cells (266,256 vertices, "
        "524,288 triangles) seen from 300 m, the eye moving 1 m per frame, 640x360 on this machine's GL (llvmpipe), "
        "average of " + std::to_string(frames) +
        " frames. CPU: primitives' update (CPU relative to eye rewrites and uploads every vertex) plus culling and "
        "binning; draw: executing the commands, GPU finished.";
    cost.columns = {"transform"};
    for (const double d : distances) {
        cost.columns.push_back("px at " + distanceName(d));
    }
    cost.columns.insert(cost.columns.end(),
                        {"CPU ms per frame", "floats rewritten per frame", "draw (GPU) ms per frame", "draw calls"});
    Framebuffer framebuffer = context.createFramebuffer(640, 360);
    context.setFramebuffer(&framebuffer);
    for (std::size_t t = 0; t < std::size(kTransforms); ++t) {
        std::vector<std::string> row{vertexTransformName(kTransforms[t])};
        for (const JitterResult& r : surface[t]) {
            row.push_back(formatNumber(r.maxPixels, 2));
        }
        const FrameCost c = vertexTransformCost(context, kTransforms[t], frames);
        row.insert(row.end(), {formatNumber(c.cpuMs, 3), formatNumber(c.floatsRewritten, 3), formatNumber(c.drawMs, 3),
                               std::to_string(c.drawCalls)});
        cost.rows.push_back(row);
    }
    context.setFramebuffer(nullptr);
    return {error, cost};
}

Table twoSumTable(Context& context, const Options& options)
{
    Table table;
    const std::size_t samples = options.quick ? 1024 : 65536;
    table.title = "DSFUN90's two-sum on this GPU";
    table.description =
        "og_emulatedDoubleSubtract on " + std::to_string(samples) +
        " random positions at Earth radius and GEO with eyes 1 m to 10,000 km away, read back with transform feedback "
        "and compared bit for bit with the CPU's relativeToEye and with the collapsed (aHigh - bHigh) + (aLow - bLow) "
        "that reassociation leaves. Where the two differ, the GPU has kept the two-sum only if it matches the first.";
    table.columns = {"compiled with", "samples where the error term matters", "GPU = two-sum", "GPU = collapsed"};
    const std::pair<TwoSumProtection, const char*> protections[] = {
        {TwoSumProtection::Unprotected, "nothing (plain GLSL)"},
        {TwoSumProtection::Precise, "precise (GL_ARB_gpu_shader5)"},
        {TwoSumProtection::OpaqueOne, "og_opaqueOne (x 1.0 from a uniform)"}};
    for (const auto& [protection, name] : protections) {
        if (protection == TwoSumProtection::Precise && !context.device().info().gpuShader5) {
            table.rows.push_back({name, "-", "no GL_ARB_gpu_shader5 on this device", "-"});
            continue;
        }
        const TwoSumSurvival s = measureTwoSumSurvival(context, protection, samples);
        table.rows.push_back({name, std::to_string(s.errorTermMatters), std::to_string(s.matchesTwoSum),
                              std::to_string(s.matchesCollapsed)});
    }
    table.notes = "Mesa's GLSL compiler folds (a - b) - a to -b unless told otherwise, so the plain two-sum loses its error "
                  "term and becomes the collapsed form; `precise` or a multiplication by a 1.0 it cannot see keeps it. "
                  "Where the error term matters it is one float spacing of the difference, so losing it costs at most "
                  "2^-24 of the distance: the collapsed form's error shows only far from the eye, where it is a "
                  "thousandth of a pixel. Orbis compiles with `precise` where the device has it, og_opaqueOne otherwise.";
    return table;
}

// ---- Depth ---------------------------------------------------------------------------------------

std::vector<Table> depthTables(Context& context, const Options& options, std::vector<Series>& plot)
{
    const std::vector<double> distances = options.quick ? std::vector<double>{10.0, 1e4, 1e7}
                                                        : std::vector<double>{1, 10, 100, 1e3, 1e4, 1e5, 1e6, 1e7, 4e7};
    // Something half a metre from the eye, and the near limit there too, so that surfaces 1 m away
    // are inside every strategy's frustum.
    ZFightingOptions zOptions;
    zOptions.size = 64;
    zOptions.nearObjectDistance = 0.5;
    zOptions.nearLimit = 0.5;

    Table wrong;
    wrong.title = "Depth: wrongly ordered pixels, surfaces 1 m apart";
    wrong.description =
        "Two parallel squares nearly facing the eye (tilted so that their distance changes by about 1.4 % across "
        "the view, sampling many depth steps), 1 m apart (4 m at 40,000 km, the float spacing there), with a small "
        "cube 0.5 m in front of the eye so that every strategy's frame spans 0.5 m to the squares; four frames, the "
        "far square larger and smaller than the near one and submitted before and after it, a pixel wrong when it "
        "shows the far square in any (PrecisionMeasurement.h: measureZFighting); 64x64, the middle 529 pixels "
        "counted. Single: near 0.5 m, far 10 million km, fixed. Offsets from the eye reach the vertex stage rounded "
        "only to float, so depth is what is measured.";
    wrong.columns = {"strategy"};
    for (const double d : distances) {
        wrong.columns.push_back(distanceName(d));
    }
    for (const DepthStrategy strategy : kStrategies) {
        std::vector<std::string> row{depthStrategyName(strategy)};
        for (const double d : distances) {
            const ZFightingResult r = measureZFighting(context, strategy, d, 1.0, zOptions);
            row.push_back(formatNumber(100.0 * r.wrongFraction, 3) + " %");
        }
        wrong.rows.push_back(row);
    }

    Table separation;
    separation.title = "Depth: smallest separation resolved, measured (analytic)";
    separation.description =
        "The smallest separation from which up no counted pixel is wrong (separations tried from the distance down, "
        + std::string(options.quick ? "2" : "4") + " per decade), against "
        "the analytic one-step separation of DepthStrategy.h (analyticMinimumSeparation): Baker's "
        "s = z^2 / (2^24 n - z) of the course notes for single (n = 0.5 m) and multi-frustum (n the near plane of the "
        "frustum holding z), z ln(f/n) 2^-24 for logarithmic, z 2^-23 for complementary. '<=' marks the float "
        "spacing at that distance: nothing smaller reaches the GPU.";
    separation.columns = wrong.columns;
    const char* colours[] = {"#d62728", "#1f77b4", "#bcbd22", "#2ca02c", "#9467bd"};
    int k = 0;
    for (const DepthStrategy strategy : kStrategies) {
        Series measured{std::string(depthStrategyName(strategy)), colours[k], false, {}};
        Series analytic{std::string(depthStrategyName(strategy)) + " (analytic)", colours[k++], true, {}};
        std::vector<std::string> row{depthStrategyName(strategy)};
        for (const double d : distances) {
            const double spacing = static_cast<double>(std::nextafter(static_cast<float>(d), 1e30f)) -
                                   static_cast<double>(static_cast<float>(d));
            const double m = measureMinimumSeparation(context, strategy, d, zOptions, options.quick ? 2 : 4);
            const double a = analyticMinimumSeparation(strategy, d, zOptions.nearLimit,
                                                       strategy == DepthStrategy::Single ? 1e10 : d);
            row.push_back((m <= spacing ? "<= " : "") + (std::isfinite(m) ? formatLength(m) : std::string("none")) +
                          " (" + (std::isfinite(a) ? formatLength(a) : std::string("none")) + ")");
            measured.points.emplace_back(d, m);
            analytic.points.emplace_back(d, std::max(a, spacing));
        }
        separation.rows.push_back(row);
        plot.push_back(measured);
        if (strategy != DepthStrategy::LogarithmicVertex) {
            plot.push_back(analytic);
        }
    }
    separation.notes =
        "A single frustum with its near plane 0.5 m out loses 1 m from about 10 km and resolves nothing finer than "
        "thousands of kilometres at 10,000 km (Baker's formula: resolving stops at z = 2^24 n). Multi-frustum keeps "
        "far/near at 1000 per frustum, so its resolution saw-tooths between 2^-24 z and 1000 2^-24 z. Logarithmic "
        "depth spreads 24 bits evenly over log distance: about z ln(far/near) 2^-24, 1e-6 z here. The per-vertex "
        "logarithm is 30 to 200 times worse: its depth is linear across each triangle. Complementary float depth "
        "gives about 2^-23 z, the float spacing of the position itself, at every distance: the best of all. "
        "Measured separations run up to three times the analytic one-step separation (rasterisation and float "
        "rounding add to it); a few are below it, which llvmpipe's depth test allows on sloped surfaces.";

    const int frames = options.quick ? 1 : 8;
    Table cost;
    cost.title = "Depth: cost per frame";
    cost.description = "examples/ch06_depth_buffer_precision's scene (an aircraft over 200 km of terrain, snow on the peaks, "
                       "the globe, a satellite 36,000 km away; about 50 m to 36,000 km), 800x600 on llvmpipe, average of " +
                       std::to_string(frames) + " frames.";
    cost.columns = {"strategy", "ran", "frustums", "depth clears", "draw calls", "CPU ms per frame",
                    "draw (GPU) ms per frame"};
    Framebuffer framebuffer = context.createFramebuffer(800, 600);
    context.setFramebuffer(&framebuffer);
    for (const DepthStrategy strategy : kAllDepthStrategies) {
        Scene scene;
        scene.setSunDirection(sunDirectionEarthFixed(*parseUtcTime("2026-03-20T08:30:00Z")));
        scene.options().depthStrategy = strategy;
        examples::buildDepthScene(scene);
        const FrameCost c = frameCost(scene, context, frames);
        cost.rows.push_back({depthStrategyName(strategy), depthStrategyName(c.strategy), std::to_string(c.frustums),
                             std::to_string(c.clears), std::to_string(c.drawCalls), formatNumber(c.cpuMs, 3),
                             formatNumber(c.drawMs, 3)});
    }
    context.setFramebuffer(nullptr);
    cost.notes = "Depth clears count the frame's first clear too. Multi-frustum repeats the commands that span two "
                 "frustums (the globe and the terrain here); logarithmic per fragment writes gl_FragDepth, which turns "
                 "off early depth testing; complementary costs nothing per fragment but needs a float depth buffer and "
                 "glClipControl. Automatic chooses complementary here.";
    return {wrong, separation, cost};
}

std::vector<Table> run(const Options& options)
{
    Device device;
    Context& context = device.context();
    std::vector<Series> vertexPlot;
    std::vector<Series> depthPlot;
    std::vector<Table> tables = vertexTables(context, options, vertexPlot);
    tables.push_back(twoSumTable(context, options));
    for (Table& table : depthTables(context, options, depthPlot)) {
        tables.push_back(std::move(table));
    }
    if (!options.quick) {
        std::ostringstream svg;
        svg << "<svg xmlns='http://www.w3.org/2000/svg' width='1200' height='600' font-family='sans-serif'>\n"
            << "<rect width='1200' height='600' fill='white'/>\n";
        vertexPlot.push_back({"1 pixel", "#999999", true, {{1.0, 1.0}, {1e7, 1.0}}});
        auto powerOfTen = [](double value) { return "1e" + std::to_string(static_cast<int>(std::lround(std::log10(value)))); };
        plotPanel(svg, 0, 0, 600, 600, "Vertex transforms: window error",
                  {"eye distance (target on the surface)", 1.0, 1e7, true, 1.0, tickName},
                  {"worst error, pixels at 1920x1080", 1e-6, 1e4, true, 1.0, powerOfTen}, vertexPlot);
        plotPanel(svg, 600, 0, 600, 600, "Depth: smallest separation resolved",
                  {"distance (something 0.5 m from the eye)", 1.0, 4e7, true, 1.0, tickName},
                  {"separation, metres", 1e-8, 1e8, true, 1.0, powerOfTen}, depthPlot);
        svg << "</svg>\n";
        const std::string path = std::string(ORBIS_SOURCE_DIR) + "/docs/precision.svg";
        std::ofstream(path) << svg.str();
        tables.back().notes += " Plotted in docs/precision.svg.";
    }
    return tables;
}

const SectionRegistration registration("precision", 80, run);

} // namespace
} // namespace orbis::bench
