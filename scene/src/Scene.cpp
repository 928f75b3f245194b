#include "orbis/scene/Scene.h"

#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace orbis {

namespace {

double millisecondsSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

double FrameState::metersPerPixel(double distance) const noexcept
{
    return 2.0 * distance * std::tan(0.5 * camera.fieldOfViewY()) / std::max(height, 1);
}

Scene::Scene(const Ellipsoid& ellipsoid, const SceneOptions& options)
    : _ellipsoid(ellipsoid)
    , _options(options)
    , _binner(options.multiFrustum)
{
}

void Scene::add(std::shared_ptr<Primitive> primitive)
{
    if (primitive) {
        _primitives.push_back(std::move(primitive));
    }
}

void Scene::remove(const Primitive* primitive)
{
    std::erase_if(_primitives, [&](const std::shared_ptr<Primitive>& p) { return p.get() == primitive; });
}

void Scene::setSunDirection(const glm::dvec3& direction) noexcept
{
    const double length = glm::length(direction);
    if (length > 0.0 && std::isfinite(length)) {
        _sunDirection = direction / length;
    }
}

FrameStatistics Scene::render(Context& context)
{
    FrameStatistics statistics;
    statistics.frameNumber = ++_frameNumber;
    Framebuffer* target = context.framebuffer();
    const int width = target ? target->width() : 0;
    const int height = target ? target->height() : 0;
    const double aspect = height > 0 ? static_cast<double>(width) / height : 1.0;

    if (_binner.multiFrustum().options() != _options.multiFrustum) {
        _binner.multiFrustum().setOptions(_options.multiFrustum);
    }
    const MultiFrustumOptions& limits = _options.multiFrustum;
    const glm::dmat4 view = _camera.viewMatrix();
    const glm::dmat4 wholeProjection = _camera.projectionMatrix(aspect, limits.nearLimit, limits.farLimit);

    Device& device = context.device();
    const std::uint64_t compilesBefore = device.shaderCache().compiles();
    context.resetStatistics();

    FrameState frameState{context,
                          device,
                          _camera,
                          _ellipsoid,
                          width,
                          height,
                          _sunDirection,
                          _timeSeconds,
                          _frameNumber,
                          Frustum::fromViewProjection(wholeProjection * view),
                          EllipsoidalOccluder(_ellipsoid, _camera.eye())};

    // Update: primitives culled whole are never asked for commands, so they allocate nothing.
    auto phase = std::chrono::steady_clock::now();
    _commands.clear();
    for (const std::shared_ptr<Primitive>& primitive : _primitives) {
        const std::optional<BoundingSphere> sphere = primitive->boundingSphere();
        if (sphere && frameState.cullingVolume.intersect(*sphere) == Intersect::Outside) {
            ++statistics.primitivesCulled;
            continue;
        }
        primitive->update(frameState, _commands);
        ++statistics.primitivesUpdated;
    }
    statistics.updateMilliseconds = millisecondsSince(phase);

    // Cull, then bin what survives into frustums by its extent along the view direction.
    phase = std::chrono::steady_clock::now();
    const glm::dvec3 eye = _camera.eye();
    const double tanHalfY = std::tan(0.5 * _camera.fieldOfViewY());
    const double cosHalfDiagonal = 1.0 / std::sqrt(1.0 + tanHalfY * tanHalfY * (1.0 + aspect * aspect));
    _binner.cullAndBin(_commands, frameState.cullingVolume, frameState.occluder, eye, _camera.direction(),
                       cosHalfDiagonal, statistics);
    statistics.cullMilliseconds = millisecondsSince(phase);

    // Draw: back to front, a depth clear per frustum, opaque before translucent.
    phase = std::chrono::steady_clock::now();
    ClearState clear;
    clear.color = _options.background;
    context.clear(clear);

    SceneState sceneState;
    sceneState.viewMatrix = view;
    sceneState.cameraEye = eye;
    sceneState.viewport = {0, 0, width, height};
    sceneState.sunDirection = _sunDirection;
    sceneState.timeSeconds = _timeSeconds;

    const auto& frustums = _binner.multiFrustum().frustums();
    const auto& bins = _binner.multiFrustum().bins();
    const auto& visible = _binner.visible();
    statistics.drawCallsPerFrustum.assign(frustums.size(), 0);
    ClearState depthOnly;
    depthOnly.buffers = ClearBuffers::Depth;
    bool depthDirty = false;
    for (std::size_t f = frustums.size(); f-- > 0;) {
        if (bins[f].empty()) {
            continue;
        }
        if (depthDirty) {
            context.clear(depthOnly);
        }
        sceneState.nearDistance = frustums[f].nearDistance;
        sceneState.farDistance = frustums[f].farDistance;
        sceneState.projectionMatrix =
            _camera.projectionMatrix(aspect, frustums[f].nearDistance, frustums[f].farDistance);
        for (const Pass pass : {Pass::Opaque, Pass::Translucent}) {
            std::size_t drawn = 0;
            for (const std::uint32_t binned : bins[f]) {
                const DrawCommand& command = _commands[visible[binned]];
                if (command.pass == pass) {
                    context.draw(command, sceneState);
                    ++drawn;
                }
            }
            (pass == Pass::Opaque ? statistics.opaquePasses : statistics.translucentPasses) += drawn > 0 ? 1 : 0;
            statistics.drawCallsPerFrustum[f] += drawn;
            statistics.commandsExecuted += drawn;
        }
        depthDirty = true;
    }
    const auto& overlay = _binner.overlay();
    if (!overlay.empty()) {
        // Screen-space commands: the whole depth range, after every frustum.
        sceneState.nearDistance = limits.nearLimit;
        sceneState.farDistance = limits.farLimit;
        sceneState.projectionMatrix = wholeProjection;
        for (const std::uint32_t index : overlay) {
            context.draw(_commands[index], sceneState);
        }
        statistics.commandsExecuted += overlay.size();
        statistics.overlayPasses = 1;
    }
    context.finish();
    statistics.drawMilliseconds = millisecondsSince(phase);
    statistics.programsCompiled = device.shaderCache().compiles() - compilesBefore;
    statistics.renderer = context.statistics();
    return statistics;
}

} // namespace orbis
