#include "orbis/scene/Scene.h"

#include "DepthPlan.h"

#include <orbis/core/Error.h>
#include <orbis/core/SunPosition.h>
#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>

#include <glm/geometric.hpp>

#include <cxxabi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>
#include <string>
#include <typeinfo>

namespace orbis::scene {

namespace {

/// The demangled class name of a primitive, for messages.
std::string readableTypeName(const Primitive& primitive)
{
    int status = 0;
    const char* mangled = typeid(primitive).name();
    std::unique_ptr<char, void (*)(void*)> demangled(abi::__cxa_demangle(mangled, nullptr, nullptr, &status), std::free);
    return status == 0 && demangled ? demangled.get() : mangled;
}

double millisecondsSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// Puts the context's framebuffer back however the frame ends.
struct FramebufferRestorer {
    renderer::Context& context;
    renderer::Framebuffer* framebuffer;
    ~FramebufferRestorer() { context.setFramebuffer(framebuffer); }
};

} // namespace

double FrameState::metersPerPixel(double distance) const noexcept
{
    return 2.0 * distance * camera.halfExtent(width, height).y / std::max(height, 1);
}

std::optional<HeightInterval> FrameState::groundHeights(const GeodeticExtent& extent) const
{
    std::optional<HeightInterval> heights;
    for (const Primitive* primitive : ground) {
        if (const std::optional<HeightInterval> drawn = primitive->drawnHeights(extent)) {
            heights = enclose(heights, *drawn);
        }
    }
    return heights;
}

Scene::Scene(const Ellipsoid& ellipsoid, const SceneOptions& options)
    : _ellipsoid(ellipsoid)
    , _options(options)
    , _binner(options.multiFrustum)
    , _sceneDepth(std::make_shared<renderer::Texture2D>())
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

std::optional<glm::dvec3> Scene::pickGround(const glm::dvec2& windowPosition, int width, int height) const
{
    const Ray ray = _camera.pickRay(windowPosition, width, height);
    std::optional<double> nearest;
    for (const std::shared_ptr<Primitive>& primitive : _primitives) {
        const std::optional<double> distance = primitive->pickGround(ray);
        if (distance && (!nearest || *distance < *nearest)) {
            nearest = distance;
        }
    }
    if (nearest) {
        return ray.pointAt(*nearest);
    }
    return _camera.pickEllipsoid(windowPosition, width, height, _ellipsoid);
}

double Scene::groundHeight(const Geodetic2D& position) const
{
    std::optional<double> highest;
    for (const std::shared_ptr<Primitive>& primitive : _primitives) {
        const std::optional<double> height = primitive->groundHeight(position);
        if (height && (!highest || *height > *highest)) {
            highest = height;
        }
    }
    return highest.value_or(0.0);
}

bool Scene::keepCameraAboveGround(double clearance)
{
    const Geodetic3D eye = _ellipsoid.toGeodetic3D(_camera.eye());
    const double lowest = groundHeight(Geodetic2D(eye.longitude, eye.latitude)) + clearance;
    if (!(eye.height < lowest)) {
        return false;
    }
    const glm::dvec3 lifted = _ellipsoid.toCartesian(Geodetic3D(eye.longitude, eye.latitude, lowest));
    _camera.lookAt(lifted, _camera.target() + (lifted - _camera.eye()), _camera.up());
    return true;
}

void Scene::setSunDirection(const glm::dvec3& direction) noexcept
{
    const double length = glm::length(direction);
    if (length > 0.0 && std::isfinite(length)) {
        _sunDirection = direction / length;
    }
}

void Scene::setTime(std::chrono::sys_seconds utc) noexcept
{
    setSunDirection(sunDirectionEarthFixed(utc));
}

DepthStrategy Scene::chooseDepthStrategy(renderer::Context& context, renderer::Framebuffer* target, double nearDistance,
                                         double farDistance, bool logarithmicAvailable) const
{
    const renderer::DeviceInfo& device = context.device().info();
    const DepthStrategy requested = _options.depthStrategy;
    if (requested == DepthStrategy::Automatic) {
        detail::AutoInputs inputs;
        inputs.nearDistance = nearDistance;
        inputs.farDistance = farDistance;
        inputs.complementaryAvailable = device.clipControl && target != nullptr;
        inputs.logarithmicAvailable = logarithmicAvailable;
        return detail::resolveAutomaticDepth(inputs, _options.multiFrustum);
    }
    if (requested == DepthStrategy::Complementary) {
        if (!device.clipControl) {
            throw Error("Scene: complementary depth needs glClipControl (OpenGL 4.5 or GL_ARB_clip_control) for a "
                        "0..1 clip-space depth range, and this driver (" + device.renderer + ", OpenGL " +
                        device.version + ") has neither; use DepthStrategy::Automatic, Logarithmic or MultiFrustum");
        }
        if (!target) {
            throw Error("Scene: complementary depth needs a Depth32F depth buffer, which a default (window) "
                        "framebuffer cannot be given; render into a Framebuffer");
        }
    }
    return requested;
}

renderer::Framebuffer* Scene::floatDepthTarget(renderer::Context& context, renderer::Framebuffer& target, bool stencil)
{
    // Stencil only when the frame drapes: a plain float depth costs half the memory.
    const renderer::TextureFormat format =
        stencil ? renderer::TextureFormat::Depth32FStencil8 : renderer::TextureFormat::Depth32F;
    const renderer::TextureFormat targetDepth =
        target.depthAttachment() ? target.depthAttachment()->format() : renderer::TextureFormat::RGBA8;
    if (targetDepth == format || targetDepth == renderer::TextureFormat::Depth32FStencil8) {
        return &target;
    }
    bool current = _floatDepthTarget && _floatDepthContext == &context && _floatDepth &&
                   _floatDepth->format() == format && _floatDepth->width() == target.width() &&
                   _floatDepth->height() == target.height();
    for (int i = 0; current && i < renderer::Framebuffer::kMaxColorAttachments; ++i) {
        current = _floatDepthTarget->colorAttachment(i) == target.colorAttachment(i);
    }
    if (!current) {
        _floatDepthTarget = std::make_shared<renderer::Framebuffer>(context.createFramebuffer());
        for (int i = 0; i < renderer::Framebuffer::kMaxColorAttachments; ++i) {
            _floatDepthTarget->setColorAttachment(i, target.colorAttachment(i));
        }
        _floatDepth = std::make_shared<renderer::Texture2D>(
            context.device().createTexture2D({target.width(), target.height(), format}));
        _floatDepthTarget->setDepthAttachment(_floatDepth);
        _floatDepthContext = &context;
    }
    return _floatDepthTarget.get();
}

renderer::Framebuffer* Scene::multisampleTarget(renderer::Context& context, const renderer::Framebuffer& target,
                                                int samples, bool floatDepth, bool stencil)
{
    const renderer::TextureFormat colorFormat =
        target.colorAttachment(0) ? target.colorAttachment(0)->format() : renderer::TextureFormat::RGBA8;
    const renderer::TextureFormat depthFormat =
        !floatDepth ? renderer::TextureFormat::Depth24Stencil8
                    : (stencil ? renderer::TextureFormat::Depth32FStencil8 : renderer::TextureFormat::Depth32F);
    const renderer::Framebuffer* current = _multisampleTarget.get();
    if (!current || _multisampleContext != &context || current->width() != target.width() ||
        current->height() != target.height() || current->colorAttachment(0)->samples() != samples ||
        current->colorAttachment(0)->format() != colorFormat || current->depthAttachment()->format() != depthFormat) {
        renderer::Device& device = context.device();
        _multisampleTarget = std::make_shared<renderer::Framebuffer>(context.createFramebuffer());
        _multisampleTarget->setColorAttachment(0, std::make_shared<renderer::Texture2D>(device.createTexture2D(
                                                      {target.width(), target.height(), colorFormat, false, samples})));
        _multisampleTarget->setDepthAttachment(std::make_shared<renderer::Texture2D>(
            device.createTexture2D({target.width(), target.height(), depthFormat, false, samples})));
        _multisampleContext = &context;
    }
    return _multisampleTarget.get();
}

/// What one frame looks through: its target, the camera's view, and the volume it sees.
struct Scene::FrameView {
    renderer::Framebuffer* target;
    int width;
    int height;
    double aspect;
    glm::dmat4 view;
    glm::dvec3 eye;
    glm::dvec3 viewDirection;
    Frustum cullingVolume;  ///< the whole view, from the near to the far limit
    double cosHalfDiagonal; ///< between the view direction and the frustum's corners
};

/// The depth the primitives that survived culling span by their spheres, for Automatic's first guess.
struct Scene::SurvivorDepth {
    double nearest = std::numeric_limits<double>::infinity();
    double farthest = 0.0;
    bool logarithmicAvailable = true; ///< every survivor writes logarithmic depth
};

Scene::FrameView Scene::frameView(renderer::Framebuffer* target) const
{
    const int width = target ? target->width() : 0;
    const int height = target ? target->height() : 0;
    const double aspect = height > 0 ? static_cast<double>(width) / height : 1.0;
    const MultiFrustumOptions& limits = _options.multiFrustum;
    const glm::dmat4 view = _camera.viewMatrix();
    const glm::dmat4 wholeProjection = _camera.projectionMatrix(aspect, limits.nearLimit, limits.farLimit);
    const glm::dvec2 halfExtent = _camera.halfExtent(width, height);
    return {target,
            width,
            height,
            aspect,
            view,
            _camera.eye(),
            _camera.direction(),
            Frustum::fromViewProjection(wholeProjection * view),
            1.0 / std::sqrt(1.0 + glm::dot(halfExtent, halfExtent))};
}

Scene::SurvivorDepth Scene::cullPrimitives(const FrameView& frame, FrameStatistics& statistics)
{
    // Primitives culled whole are never asked for commands, so they allocate nothing.
    const MultiFrustumOptions& limits = _options.multiFrustum;
    _survivors.clear();
    SurvivorDepth depth;
    for (const std::shared_ptr<Primitive>& primitive : _primitives) {
        const std::optional<BoundingSphere> sphere = primitive->boundingSphere();
        if (sphere && frame.cullingVolume.intersect(*sphere) == Intersect::Outside) {
            ++statistics.primitivesCulled;
            continue;
        }
        _survivors.push_back(primitive.get());
        const double centre = sphere ? glm::dot(sphere->centre - frame.eye, frame.viewDirection) : 0.0;
        depth.nearest = std::min(depth.nearest, sphere ? centre - sphere->radius : limits.nearLimit);
        depth.farthest = std::max(depth.farthest, sphere ? centre + sphere->radius : limits.farLimit);
        depth.logarithmicAvailable = depth.logarithmicAvailable && primitive->supportsLogarithmicDepth();
    }
    // The ground first, in the order added: what stands on it asks for the ground drawn this frame.
    _groundSurvivors = static_cast<std::size_t>(
        std::stable_partition(_survivors.begin(), _survivors.end(), [](const Primitive* p) { return p->drawsGround(); }) -
        _survivors.begin());
    return depth;
}

DepthStrategy Scene::startingDepthStrategy(renderer::Context& context, const FrameView& frame,
                                           const SurvivorDepth& depth) const
{
    // Automatic decides from the commands' own depth bounds, sharper than the primitives' spheres
    // (a globe bounds its depth by the eye's height and its horizon). Primitives choose their shader
    // variants in update(), so the frame starts with last frame's choice (the spheres' on the first)
    // and updates once more only when the commands call for another: never in a steady view. Any
    // choice draws correctly meanwhile: multi-frustum adds frustums as the commands need them.
    const MultiFrustumOptions& limits = _options.multiFrustum;
    const double sphereNear = std::clamp(depth.nearest, limits.nearLimit, limits.farLimit);
    const double sphereFar = std::clamp(depth.farthest, sphereNear, limits.farLimit);
    DepthStrategy strategy =
        chooseDepthStrategy(context, frame.target, sphereNear, sphereFar, depth.logarithmicAvailable);
    if (_options.depthStrategy == DepthStrategy::Automatic && _lastAutomaticDepth) {
        // Last frame's choice, while this frame can still have it (a primitive added since may not
        // write logarithmic depth).
        const bool logarithmic = *_lastAutomaticDepth == DepthStrategy::Logarithmic;
        const bool complementary = *_lastAutomaticDepth == DepthStrategy::Complementary;
        if ((!logarithmic || depth.logarithmicAvailable) &&
            (!complementary || (context.device().info().clipControl && frame.target != nullptr))) {
            strategy = *_lastAutomaticDepth;
        }
    }
    if (strategy == DepthStrategy::Logarithmic || strategy == DepthStrategy::LogarithmicVertex) {
        for (const Primitive* primitive : _survivors) {
            if (!primitive->supportsLogarithmicDepth()) {
                throw Error(std::string("Scene: logarithmic depth needs every primitive to write it, and a ") +
                            readableTypeName(*primitive) + " does not (Primitive::supportsLogarithmicDepth)");
            }
        }
    }
    return strategy;
}

detail::DepthPlan Scene::updateAndBin(FrameState& frameState, DepthStrategy strategy, const FrameView& frame,
                                      FrameStatistics& statistics, FrameStatistics& binning)
{
    const detail::DepthPlan plan = detail::DepthPlan::of(strategy, _options.multiFrustum);
    frameState.depthStrategy = plan.strategy;
    // A window's depth cannot be copied into a texture of a known format; a target's can (the
    // float depth texture of its own under complementary depth).
    const bool depthToCopy = frame.target && (plan.needsFloatDepth || frame.target->depthAttachment());
    frameState.sceneDepth = depthToCopy ? _sceneDepth.get() : nullptr;
    frameState.ground = std::span<const Primitive* const>(_survivors.data(), _groundSurvivors);
    auto start = std::chrono::steady_clock::now();
    _commands.clear();
    for (Primitive* primitive : _survivors) {
        primitive->update(frameState, _commands);
    }
    statistics.updateMilliseconds += millisecondsSince(start);
    // Cull, then bin what survives into frustums by its extent along the view direction.
    start = std::chrono::steady_clock::now();
    if (_binner.multiFrustum().options() != plan.binning) {
        _binner.multiFrustum().setOptions(plan.binning);
    }
    binning = FrameStatistics();
    _binner.cullAndBin(_commands, frame.cullingVolume, frameState.occluder, frame.eye, frame.viewDirection,
                       frame.cosHalfDiagonal, binning);
    statistics.cullMilliseconds += millisecondsSince(start);
    return plan;
}

detail::DepthPlan Scene::prepareCommands(renderer::Context& context, const FrameView& frame, const SurvivorDepth& depth,
                                         FrameStatistics& statistics)
{
    const bool automatic = _options.depthStrategy == DepthStrategy::Automatic;
    FrameState frameState{context,
                          context.device(),
                          _camera,
                          _ellipsoid,
                          frame.width,
                          frame.height,
                          _sunDirection,
                          _clockSeconds,
                          _frameNumber,
                          frame.cullingVolume,
                          EllipsoidalOccluder(_ellipsoid, frame.eye),
                          startingDepthStrategy(context, frame, depth)};
    FrameStatistics binning;
    detail::DepthPlan plan = updateAndBin(frameState, frameState.depthStrategy, frame, statistics, binning);
    if (automatic && !_commands.empty()) {
        const FrustumRange range = _binner.multiFrustum().desiredRange();
        const DepthStrategy chosen = chooseDepthStrategy(context, frame.target, range.nearDistance, range.farDistance,
                                                         depth.logarithmicAvailable);
        if (chosen != plan.strategy) {
            plan = updateAndBin(frameState, chosen, frame, statistics, binning);
        }
        _lastAutomaticDepth = plan.strategy;
    }

    statistics.primitivesUpdated = _survivors.size();
    for (const Primitive* primitive : _survivors) {
        if (const TileStatistics* tiles = primitive->tileStatistics()) {
            if (!statistics.tiles) {
                statistics.tiles = TileStatistics{};
                statistics.tiles->converged = true;
            }
            statistics.tiles->add(*tiles);
        }
        if (const ClipmapStatistics* clipmap = primitive->clipmapStatistics()) {
            statistics.clipmap = *clipmap; // one clipmap terrain per scene
        }
        if (const VirtualTextureStatistics* pages = primitive->virtualTextureStatistics()) {
            if (!statistics.virtualTexture) {
                statistics.virtualTexture = *pages;
            } else {
                statistics.virtualTexture->add(*pages);
            }
        }
    }
    statistics.depthStrategy = plan.strategy;
    statistics.depthStrategyAutomatic = automatic;
    statistics.commandsSubmitted = binning.commandsSubmitted;
    statistics.commandsCulledByFrustum = binning.commandsCulledByFrustum;
    statistics.commandsCulledByHorizon = binning.commandsCulledByHorizon;
    statistics.frustums = binning.frustums;
    statistics.frustumsReused = binning.frustumsReused;
    statistics.commandsExecutedMoreThanOnce = binning.commandsExecutedMoreThanOnce;
    if (plan.fixedRange && !statistics.frustums.empty()) {
        const MultiFrustumOptions& limits = _options.multiFrustum;
        statistics.frustums.front() = {limits.nearLimit, limits.farLimit};
    }
    return plan;
}

void Scene::copySceneDepth(renderer::Context& context)
{
    const renderer::Framebuffer* source = context.framebuffer();
    const std::shared_ptr<renderer::Texture2D>& depth = source ? source->depthAttachment() : nullptr;
    if (!depth) {
        return; // FrameState::sceneDepth was null for this frame
    }
    if (!_sceneDepth->valid() || _sceneDepthContext != &context || _sceneDepth->format() != depth->format() ||
        _sceneDepth->width() != depth->width() || _sceneDepth->height() != depth->height()) {
        *_sceneDepth = context.device().createTexture2D({depth->width(), depth->height(), depth->format()});
        _sceneDepthTarget = std::make_shared<renderer::Framebuffer>(context.createFramebuffer());
        _sceneDepthTarget->setDepthAttachment(_sceneDepth);
        _sceneDepthContext = &context;
    }
    context.copyDepth(*source, *_sceneDepthTarget);
}

void Scene::drawFrustums(renderer::Context& context, const FrameView& frame, const detail::DepthPlan& plan,
                         renderer::SceneState& sceneState, FrameStatistics& statistics)
{
    // Back to front, a depth clear per frustum, opaque before translucent.
    const std::vector<FrustumRange>& frustums = statistics.frustums;
    const auto& bins = _binner.multiFrustum().bins();
    const auto& visible = _binner.visible();
    statistics.drawCallsPerFrustum.assign(frustums.size(), 0);
    renderer::ClearState depthOnly;
    depthOnly.buffers = renderer::ClearBuffers::Depth;
    depthOnly.depth = plan.clearDepth;
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
        sceneState.projectionMatrix = plan.projection(_camera, frame.aspect, frustums[f]);
        // Where frustums overlap the nearer one owns the overlap (blended draws keep only their own).
        sceneState.ownedNearDistance = plan.ownedRanges && f > 0 ? frustums[f - 1].farDistance : 0.0;
        sceneState.ownedFarDistance = plan.ownedRanges && f + 1 < frustums.size()
                                          ? frustums[f].farDistance
                                          : std::numeric_limits<double>::infinity();
        for (const Pass pass : {Pass::Opaque, Pass::Translucent}) {
            if (pass == Pass::Translucent &&
                std::any_of(bins[f].begin(), bins[f].end(), [&](std::uint32_t binned) {
                    const SceneCommand& command = _commands[visible[binned]];
                    return command.pass == Pass::Translucent && command.readsSceneDepth;
                })) {
                copySceneDepth(context);
            }
            std::size_t drawn = 0;
            const auto drawWhere = [&](const auto& wanted) {
                for (const std::uint32_t binned : bins[f]) {
                    const SceneCommand& command = _commands[visible[binned]];
                    if (wanted(command)) {
                        context.draw(command.draw, sceneState);
                        statistics.effects |= command.tags;
                        ++drawn;
                    }
                }
            };
            const bool drapes = pass == Pass::Opaque && std::any_of(bins[f].begin(), bins[f].end(), [&](std::uint32_t binned) {
                                    return _commands[visible[binned]].pass == Pass::Draped;
                                });
            if (drapes) {
                // Draped commands colour whatever the depth holds inside their volumes: they come
                // after the ground and before the other opaque commands, which they would colour too.
                drawWhere([](const SceneCommand& command) { return command.pass == Pass::Opaque && command.ground; });
                drawWhere([](const SceneCommand& command) { return command.pass == Pass::Draped; });
                drawWhere([](const SceneCommand& command) { return command.pass == Pass::Opaque && !command.ground; });
            } else {
                drawWhere([pass](const SceneCommand& command) { return command.pass == pass; });
            }
            (pass == Pass::Opaque ? statistics.opaquePasses : statistics.translucentPasses) += drawn > 0 ? 1 : 0;
            statistics.drawCallsPerFrustum[f] += drawn;
            statistics.commandsExecuted += drawn;
        }
        depthDirty = true;
    }
}

void Scene::drawOverlay(renderer::Context& context, const FrameView& frame, const detail::DepthPlan& plan,
                        renderer::SceneState& sceneState, FrameStatistics& statistics) const
{
    const auto& overlay = _binner.overlay();
    if (overlay.empty()) {
        return;
    }
    // Screen-space commands, after every frustum: the whole depth range, in the frame's depth
    // convention (a complementary frame's depth buffer is cleared to 0, which a Less test against
    // GL's convention would never pass).
    const MultiFrustumOptions& limits = _options.multiFrustum;
    sceneState.nearDistance = limits.nearLimit;
    sceneState.farDistance = limits.farLimit;
    sceneState.projectionMatrix = plan.projection(_camera, frame.aspect, {limits.nearLimit, limits.farLimit});
    sceneState.ownedNearDistance = 0.0;
    sceneState.ownedFarDistance = std::numeric_limits<double>::infinity();
    for (const std::uint32_t index : overlay) {
        context.draw(_commands[index].draw, sceneState);
        statistics.effects |= _commands[index].tags;
    }
    statistics.commandsExecuted += overlay.size();
    statistics.overlayPasses = 1;
}

void Scene::drawFrame(renderer::Context& context, const FrameView& frame, const detail::DepthPlan& plan,
                      FrameStatistics& statistics)
{
    const FramebufferRestorer restorer{context, frame.target};
    const int samples = frame.target ? std::clamp(_options.samples, 1, context.device().info().maxSamples) : 1;
    const bool drapes = std::any_of(_binner.visible().begin(), _binner.visible().end(),
                                    [&](std::uint32_t index) { return _commands[index].pass == Pass::Draped; });
    renderer::Framebuffer* multisampled =
        samples > 1 ? multisampleTarget(context, *frame.target, samples, plan.needsFloatDepth, drapes) : nullptr;
    if (multisampled) {
        context.setFramebuffer(multisampled);
    } else if (plan.needsFloatDepth) {
        context.setFramebuffer(floatDepthTarget(context, *frame.target, drapes));
    }
    const renderer::Framebuffer* drawn = context.framebuffer();
    if (drapes && drawn && (!drawn->depthAttachment() || !renderer::hasStencil(drawn->depthAttachment()->format()))) {
        throw Error(std::string("Scene: draped polygons need a stencil buffer, and the target's depth is ") +
                    (drawn->depthAttachment() ? renderer::textureFormatName(drawn->depthAttachment()->format())
                                              : "missing") +
                    "; give it Depth24Stencil8 or Depth32FStencil8");
    }
    statistics.samples = samples;
    renderer::ClearState clear;
    clear.color = _options.background;
    clear.depth = plan.clearDepth;
    context.clear(clear);

    renderer::SceneState sceneState;
    sceneState.viewMatrix = frame.view;
    sceneState.cameraEye = frame.eye;
    sceneState.viewport = {0, 0, frame.width, frame.height};
    sceneState.sunDirection = _sunDirection;
    sceneState.timeSeconds = _clockSeconds;
    sceneState.depthConvention = plan.convention;
    drawFrustums(context, frame, plan, sceneState, statistics);
    drawOverlay(context, frame, plan, sceneState, statistics);
    if (multisampled) {
        context.blit(*multisampled, frame.target); // the samples resolved into the target's colour
    }
    context.finish();
}

FrameStatistics Scene::render(renderer::Context& context)
{
    FrameStatistics statistics;
    statistics.frameNumber = ++_frameNumber;
    const FrameView frame = frameView(context.framebuffer());
    renderer::Device& device = context.device();
    const std::uint64_t compilesBefore = device.shaderCache().compiles();
    context.resetStatistics();

    // The steps of a frame as data (docs/architecture.md): cull primitives, update the survivors into
    // commands and bin them, then draw the bins.
    auto phase = std::chrono::steady_clock::now();
    const SurvivorDepth depth = cullPrimitives(frame, statistics);
    statistics.updateMilliseconds = millisecondsSince(phase);
    const detail::DepthPlan plan = prepareCommands(context, frame, depth, statistics);

    phase = std::chrono::steady_clock::now();
    drawFrame(context, frame, plan, statistics);
    statistics.drawMilliseconds = millisecondsSince(phase);
    statistics.programsCompiled = device.shaderCache().compiles() - compilesBefore;
    statistics.renderer = context.statistics();
    return statistics;
}

} // namespace orbis::scene
