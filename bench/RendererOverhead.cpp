// What the renderer layer costs: the same 10,000 small draws with mixed state issued through
// Context::draw and with raw GL (the loader's entry points, state tracked by hand), on the device
// the environment gives (Mesa llvmpipe here); and the time from process start to the first
// triangle PNG (examples/ch03_triangle).

#include "RawGlBaseline.h"
#include "Report.h"

#include <orbis/renderer/Device.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>
#include <cstdio>
#include <filesystem>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

using namespace orbis::renderer;

namespace orbis::bench {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start)
{
    return std::chrono::duration<double>(Clock::now() - start).count();
}

/// CPU time of the whole process (llvmpipe's rasteriser threads included), in seconds: less
/// disturbed than wall time when other processes share the cores.
double processCpuSeconds()
{
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

ShaderProgramDescription programDescription(int variant)
{
    ShaderProgramDescription description;
    description.name = "overhead " + std::to_string(variant);
    description.vertex = ShaderSource::fromText("overhead.vert.glsl", R"(
in vec4 position;
uniform mat4 og_modelViewProjectionMatrix;
uniform vec2 u_offset;
void main() { gl_Position = og_modelViewProjectionMatrix * position + vec4(u_offset, 0.0, 0.0); }
)");
    description.fragment = ShaderSource::fromText("overhead.frag.glsl", variant == 0 ? R"(
out vec4 fragmentColor;
uniform vec4 u_color;
void main() { fragmentColor = u_color; }
)"
                                                                                      : R"(
out vec4 fragmentColor;
uniform vec4 u_color;
void main() { fragmentColor = vec4(u_color.bgr, u_color.a * 0.5); }
)");
    return description;
}

Mesh smallQuad(double half)
{
    Mesh mesh;
    mesh.positions = {{-half, -half, 0.0}, {half, -half, 0.0}, {half, half, 0.0}, {-half, half, 0.0}};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    return mesh;
}

/// Draw i: program, array and three state switches on different periods, so that most draws
/// change something and few change everything; an offset on a 40 x 40 grid and a colour.
std::vector<BaselineDraw> mixedDraws(int count)
{
    std::vector<BaselineDraw> draws(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) {
        BaselineDraw& d = draws[static_cast<std::size_t>(i)];
        d.program = (i / 3) % 2;
        d.vertexArray = (i / 2) % 2;
        d.blending = i % 4 == 3;
        d.depthLessOrEqual = (i / 8) % 2 == 1;
        d.culling = i % 5 != 0;
        d.offset = {-0.95f + 1.9f * float(i % 40) / 40.0f, -0.95f + 1.9f * float((i / 40) % 40) / 40.0f};
        d.color = {float(i % 7) / 6.0f, float(i % 11) / 10.0f, float(i % 13) / 12.0f, 0.75f};
    }
    return draws;
}

struct Timing {
    double best = HUGE_VAL;    ///< wall clock, seconds
    double bestCpu = HUGE_VAL; ///< process CPU time, seconds
    std::uint64_t glCalls = 0;
};

double median(std::vector<double> values)
{
    std::sort(values.begin(), values.end());
    return values.empty() ? std::numeric_limits<double>::quiet_NaN() : values[values.size() / 2];
}

struct Comparison {
    Timing raw;
    Timing orbis; ///< Context::draw(command) in a loop
    Timing batch; ///< Context::draw(span of commands)
    double medianRatio = NAN;    ///< median over the pairs of Orbis wall / raw wall
    double medianCpuRatio = NAN; ///< the same for process CPU time
    double batchMedianRatio = NAN;
    double batchMedianCpuRatio = NAN;
};

/// `pairs` rounds of runs, one of each path back to back (the order rotated every round), after one
/// round of warm-up. Rounds keep a change of load on the machine from favouring one path.
Comparison measure(Context& context, Framebuffer& framebuffer, std::vector<ShaderProgram*>& programs,
                   std::vector<const VertexArray*>& arrays, const std::vector<BaselineDraw>& draws,
                   const std::vector<DrawCommand>& commands, int pairs)
{
    Comparison c;
    std::vector<double> ratios;
    std::vector<double> cpuRatios;
    std::vector<double> batchRatios;
    std::vector<double> batchCpuRatios;
    ClearState clear;
    for (int pair = 0; pair <= pairs; ++pair) {
        double wall[3] = {0.0, 0.0, 0.0};
        double cpu[3] = {0.0, 0.0, 0.0};
        for (int k = 0; k < 3; ++k) {
            const int path = (k + pair) % 3; // 0: raw, 1: Orbis per command, 2: Orbis batch
            context.clear(clear, &framebuffer);
            context.finish();
            context.resetStatistics();
            const auto start = Clock::now();
            const double cpuStart = processCpuSeconds();
            if (path == 0) {
                c.raw.glCalls = drawWithRawGl(context, framebuffer, programs, arrays, draws);
            } else if (path == 1) {
                for (const DrawCommand& command : commands) {
                    context.draw(command);
                }
                context.finish();
                c.orbis.glCalls = context.statistics().glCalls;
            } else {
                context.draw(std::span<const DrawCommand>(commands), SceneState{});
                context.finish();
                c.batch.glCalls = context.statistics().glCalls;
            }
            wall[path] = secondsSince(start);
            cpu[path] = processCpuSeconds() - cpuStart;
        }
        if (pair == 0) {
            continue; // warm-up
        }
        c.raw.best = std::min(c.raw.best, wall[0]);
        c.raw.bestCpu = std::min(c.raw.bestCpu, cpu[0]);
        c.orbis.best = std::min(c.orbis.best, wall[1]);
        c.orbis.bestCpu = std::min(c.orbis.bestCpu, cpu[1]);
        c.batch.best = std::min(c.batch.best, wall[2]);
        c.batch.bestCpu = std::min(c.batch.bestCpu, cpu[2]);
        ratios.push_back(wall[1] / wall[0]);
        cpuRatios.push_back(cpu[1] / cpu[0]);
        batchRatios.push_back(wall[2] / wall[0]);
        batchCpuRatios.push_back(cpu[2] / cpu[0]);
    }
    c.medianRatio = median(ratios);
    c.medianCpuRatio = median(cpuRatios);
    c.batchMedianRatio = median(batchRatios);
    c.batchMedianCpuRatio = median(batchCpuRatios);
    return c;
}

/// Milliseconds from posix_spawn to exit of `program args`; negative when it cannot run or fails.
double launchMilliseconds(const std::string& program, const std::vector<std::string>& arguments)
{
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(program.c_str()));
    for (const std::string& a : arguments) {
        argv.push_back(const_cast<char*>(a.c_str()));
    }
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    pid_t pid = 0;
    const auto start = Clock::now();
    const int spawned = posix_spawn(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0) {
        return -1.0;
    }
    int status = 0;
    waitpid(pid, &status, 0);
    const double ms = secondsSince(start) * 1e3;
    return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? ms : -1.0;
}

std::vector<Table> run(const Options& options)
{
    const int drawCount = 10000;
    const int pairs = options.quick ? 5 : 21;

    Device device;
    Context& context = device.context();
    Framebuffer framebuffer = context.createFramebuffer(256, 256);
    context.setFramebuffer(&framebuffer);
    ShaderProgram program0 = device.createShaderProgram(programDescription(0));
    ShaderProgram program1 = device.createShaderProgram(programDescription(1));
    const VertexArray quad0 = context.createVertexArray(smallQuad(0.015), program0); // 4 x 4 pixels
    const VertexArray quad1 = context.createVertexArray(smallQuad(0.025), program0); // 6 x 6 pixels
    std::vector<ShaderProgram*> programs = {&program0, &program1};
    std::vector<const VertexArray*> arrays = {&quad0, &quad1};

    auto commandsFor = [&](const std::vector<BaselineDraw>& draws) {
        std::vector<DrawCommand> commands(draws.size());
        for (std::size_t i = 0; i < draws.size(); ++i) {
            DrawCommand& c = commands[i];
            c.vertexArray = arrays[static_cast<std::size_t>(draws[i].vertexArray)];
            c.shaderProgram = programs[static_cast<std::size_t>(draws[i].program)];
            c.renderState = baselineRenderState(draws[i]);
            c.uniforms.set("u_offset", draws[i].offset);
            c.uniforms.set("u_color", draws[i].color);
            c.debugName = "overhead";
        }
        return commands;
    };

    const std::vector<BaselineDraw> mixed = mixedDraws(drawCount);
    const std::vector<BaselineDraw> same(static_cast<std::size_t>(drawCount), mixed[1]);
    const Comparison mixedComparison = measure(context, framebuffer, programs, arrays, mixed, commandsFor(mixed), pairs);
    const Comparison sameComparison = measure(context, framebuffer, programs, arrays, same, commandsFor(same), pairs);

    // The statistics of one mixed run through Orbis.
    const std::vector<DrawCommand> mixedCommands = commandsFor(mixed);
    context.resetStatistics();
    for (const DrawCommand& command : mixedCommands) {
        context.draw(command);
    }
    context.finish();
    const RenderStatistics statistics = context.statistics();

    Table overhead;
    overhead.title = "Renderer overhead against raw GL";
    overhead.description =
        std::to_string(drawCount) + " indexed draws of 4 x 4 and 6 x 6 pixel quads into a 256 x 256 RGBA8 + "
        "depth-stencil framebuffer on " + device.info().renderer + " (" + device.info().backendDescription +
        "). Mixed: two programs, two vertex arrays, blending, depth function and culling switching on periods "
        "of 2 to 16 draws, two uniforms (vec2, vec4) new every draw. Raw GL calls the loader's entry points "
        "directly and tracks state and uniform values by hand; Orbis executes prebuilt DrawCommands (" +
        std::to_string(sizeof(DrawCommand)) + " bytes each, uniforms inline), one Context::draw call per command or one call for the whole list; it also computes "
        "og_modelViewProjectionMatrix in double and finds it unchanged. Both end with glFinish; "
        "" + std::to_string(pairs) + " pairs of runs, the two paths back to back in each (order swapped every "
        "pair). Wall: elapsed time; CPU: the process's CPU time, the rasteriser's threads included, which other "
        "processes on the machine disturb less. Times are the best run of each path; the ratios are the "
        "median over the pairs of the ratio within each pair.";
    overhead.columns = {"draws",           "path",      "wall ms", "wall ns per draw", "CPU ns per draw", "GL calls per draw",
                        "Orbis / raw, wall", "Orbis / raw, CPU"};
    auto rows = [&](const char* draws, const Comparison& c) {
        overhead.rows.push_back({draws, "raw GL", formatNumber(c.raw.best * 1e3, 3),
                                 formatNumber(c.raw.best * 1e9 / drawCount, 3),
                                 formatNumber(c.raw.bestCpu * 1e9 / drawCount, 3),
                                 formatNumber(double(c.raw.glCalls) / drawCount, 3), "1", "1"});
        overhead.rows.push_back({draws, "Orbis Context::draw(command), in a loop", formatNumber(c.orbis.best * 1e3, 3),
                                 formatNumber(c.orbis.best * 1e9 / drawCount, 3),
                                 formatNumber(c.orbis.bestCpu * 1e9 / drawCount, 3),
                                 formatNumber(double(c.orbis.glCalls) / drawCount, 3),
                                 formatNumber(c.medianRatio, 3), formatNumber(c.medianCpuRatio, 3)});
        overhead.rows.push_back({draws, "Orbis Context::draw(commands)", formatNumber(c.batch.best * 1e3, 3),
                                 formatNumber(c.batch.best * 1e9 / drawCount, 3),
                                 formatNumber(c.batch.bestCpu * 1e9 / drawCount, 3),
                                 formatNumber(double(c.batch.glCalls) / drawCount, 3),
                                 formatNumber(c.batchMedianRatio, 3), formatNumber(c.batchMedianCpuRatio, 3)});
    };
    rows("mixed state", mixedComparison);
    rows("one command repeated", sameComparison);
    overhead.notes = "Orbis per draw in the mixed run: " +
                     formatNumber(double(statistics.stateChangesMade) / drawCount, 3) + " render-state changes made, " +
                     formatNumber(double(statistics.stateChangesAvoided) / drawCount, 3) + " avoided; " +
                     formatNumber(double(statistics.uniformUploads) / drawCount, 3) + " uniform uploads, " +
                     formatNumber(double(statistics.uniformUploadsAvoided) / drawCount, 3) +
                     " avoided. The overhead per draw is the difference of the two ns-per-draw columns.";

    Table launch;
    launch.title = "Time to the first triangle PNG";
    const std::filesystem::path triangle =
        std::filesystem::read_symlink("/proc/self/exe").parent_path() / "ch03_triangle";
    const std::string png =
        (std::filesystem::temp_directory_path() / ("orbis-bench-triangle-" + std::to_string(getpid()) + ".png"))
            .string();
    launch.description = "Wall-clock time from posix_spawn of build/bin/ch03_triangle to its exit: process start, "
                         "device creation, shader compilation, one 256 x 256 draw, read-back, PNG written. " +
                         std::to_string(options.quick ? 3 : 9) + " launches per backend.";
    launch.columns = {"backend", "median ms", "best ms"};
    for (const char* backend : {"egl", "osmesa"}) {
        std::vector<double> times;
        for (int i = 0; i < (options.quick ? 3 : 9); ++i) {
            const double ms = launchMilliseconds(triangle.string(), {png, "--backend", backend});
            if (ms >= 0.0) {
                times.push_back(ms);
            }
        }
        if (times.empty()) {
            launch.rows.push_back({backend, "did not run", "-"});
            continue;
        }
        std::sort(times.begin(), times.end());
        launch.rows.push_back({backend, formatNumber(times[times.size() / 2], 3), formatNumber(times.front(), 3)});
    }
    std::filesystem::remove(png);
    return {overhead, launch};
}

const SectionRegistration registration("renderer overhead", 50, run);

} // namespace
} // namespace orbis::bench
