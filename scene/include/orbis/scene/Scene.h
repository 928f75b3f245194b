#pragma once

#include "orbis/scene/Camera.h"
#include "orbis/scene/CommandBinner.h"
#include "orbis/scene/DepthStrategy.h"
#include "orbis/scene/FrameState.h"
#include "orbis/scene/FrameStatistics.h"
#include "orbis/scene/MultiFrustum.h"

#include <orbis/core/Ellipsoid.h>

#include <glm/vec4.hpp>

#include <chrono>
#include <memory>
#include <optional>
#include <vector>

namespace orbis::renderer {
class Context;
class Framebuffer;
struct SceneState;
class Texture2D;
} // namespace orbis::renderer

namespace orbis::scene {

namespace detail {
struct DepthPlan; // scene/src/DepthPlan.h
} // namespace detail

struct SceneOptions {
    /// The near and far limits of every strategy; the ratio and overlap of MultiFrustum.
    MultiFrustumOptions multiFrustum;
    /// How depth is resolved (docs/precision.md compares them); Automatic picks per frame.
    DepthStrategy depthStrategy = DepthStrategy::Automatic;
    glm::vec4 background{0.0f, 0.0f, 0.0f, 1.0f};
    /// Samples per pixel (MSAA): above 1 the frame is drawn into a multisampled target of the
    /// scene's own (at most the device's maximum) and resolved into the target's colour attachment
    /// 0, whose depth attachment is then left as it was. A window's framebuffer is drawn as it is.
    int samples = 1;
};

/// Primitives, a camera and a sun; render() runs one frame: cull primitives whole, update the
/// survivors for the frame's depth strategy, cull their commands against the view frustum and the
/// ellipsoid's horizon, bin them into frustums (one, or the dynamic multi-frustums), draw the
/// frustums back to front (depth cleared for each, opaque then translucent), then the overlay pass.
/// DepthStrategy::Automatic decides by the commands' depth range; it starts a frame with last
/// frame's choice and updates the primitives again only when the commands call for another.
///
/// Complementary depth needs a Depth32F depth buffer: when the target's depth attachment is not one,
/// the scene draws into the target's colour textures with a float depth texture of its own (made
/// once per size, no copy), and the target's own depth attachment is left as it was. A context
/// without glClipControl, or a default (window) framebuffer, cannot have it: Automatic then passes
/// over it, and asking for it throws orbis::Error saying why. A frame with draped commands
/// (Pass::Draped) needs a stencil buffer: the scene's own depth textures then have one, and a
/// target whose depth has none (Depth24, Depth32F under other strategies) throws.
///
/// ```
/// Scene scene;
/// scene.add(std::make_shared<Globe>(...));
/// scene.camera().lookAt(eye, target, up);
/// FrameStatistics statistics = scene.render(context); // into context.framebuffer()
/// ```
class Scene final {
public:
    explicit Scene(const Ellipsoid& ellipsoid = Ellipsoid::wgs84(), const SceneOptions& options = {});

    const Ellipsoid& ellipsoid() const noexcept { return _ellipsoid; }
    Camera& camera() noexcept { return _camera; }
    const Camera& camera() const noexcept { return _camera; }
    SceneOptions& options() noexcept { return _options; }

    void add(std::shared_ptr<Primitive> primitive);
    /// Removes a primitive added before; no effect for one that is not in the scene.
    void remove(const Primitive* primitive);
    const std::vector<std::shared_ptr<Primitive>>& primitives() const noexcept { return _primitives; }

    /// Unit vector towards the Sun, Earth-fixed; a zero or non-finite direction is ignored.
    void setSunDirection(const glm::dvec3& direction) noexcept;
    const glm::dvec3& sunDirection() const noexcept { return _sunDirection; }
    /// Places the Sun where it is at a UTC time (sunDirectionEarthFixed), as a scene file's "time"
    /// does.
    void setTime(std::chrono::sys_seconds utc) noexcept;
    /// The shaders' clock (og_time, seconds, sent as a float: wrap long-running clocks); it moves
    /// nothing in the sky.
    void setClockSeconds(double seconds) noexcept { _clockSeconds = seconds; }
    double clockSeconds() const noexcept { return _clockSeconds; }

    /// Where the ray through a window position (Camera::pickRay) first meets the ground drawn in
    /// the last frame (the terrain of a TiledGlobe), or else the ellipsoid; empty when it meets
    /// neither.
    std::optional<glm::dvec3> pickGround(const glm::dvec2& windowPosition, int width, int height) const;
    /// The height above the ellipsoid of the ground drawn in the last frame at a point (the
    /// highest of the primitives that are ground there), 0 where none is.
    double groundHeight(const Geodetic2D& position) const;
    /// Lifts the eye straight up, keeping where it looks, when it is less than `clearance`
    /// metres above the ground (groundHeight): the camera does not go under the terrain. True
    /// when it moved the camera.
    bool keepCameraAboveGround(double clearance);

    /// Draws one frame into the context's current framebuffer (which must exist: headless
    /// contexts have no default one). Throws orbis::Error from the renderer for bad commands, and
    /// for a depth strategy the context, target or primitives cannot have (named in the message).
    FrameStatistics render(renderer::Context& context);

private:
    /// The frame's strategy: the one asked for, checked, or Automatic's choice.
    DepthStrategy chooseDepthStrategy(renderer::Context& context, renderer::Framebuffer* target, double nearDistance,
                                      double farDistance, bool logarithmicAvailable) const;
    /// The target's colour textures with a float depth texture, with stencil when the frame drapes
    /// (Pass::Draped): the target itself when its depth is already such a texture.
    renderer::Framebuffer* floatDepthTarget(renderer::Context& context, renderer::Framebuffer& target, bool stencil);
    /// A multisampled framebuffer of the target's size and colour format, `samples` per pixel,
    /// with a Depth32F (floatDepth; Depth32FStencil8 with stencil) or Depth24Stencil8 depth texture;
    /// made again when any changes.
    renderer::Framebuffer* multisampleTarget(renderer::Context& context, const renderer::Framebuffer& target,
                                             int samples, bool floatDepth, bool stencil);

    // The steps of render(), in order (Scene.cpp).
    struct FrameView;
    struct SurvivorDepth;
    FrameView frameView(renderer::Framebuffer* target) const;
    /// Culls primitives whole by their spheres; the survivors go to _survivors.
    SurvivorDepth cullPrimitives(const FrameView& frame, FrameStatistics& statistics);
    /// Last frame's choice under Automatic while it still fits, else chooseDepthStrategy's.
    DepthStrategy startingDepthStrategy(renderer::Context& context, const FrameView& frame,
                                        const SurvivorDepth& depth) const;
    /// The survivors' commands under a strategy, culled and binned into _commands and _binner.
    detail::DepthPlan updateAndBin(FrameState& frameState, DepthStrategy strategy, const FrameView& frame,
                                   FrameStatistics& statistics, FrameStatistics& binning);
    /// updateAndBin, again when Automatic's choice changes with the commands; the statistics filled.
    detail::DepthPlan prepareCommands(renderer::Context& context, const FrameView& frame, const SurvivorDepth& depth,
                                      FrameStatistics& statistics);
    void drawFrame(renderer::Context& context, const FrameView& frame, const detail::DepthPlan& plan,
                   FrameStatistics& statistics);
    void drawFrustums(renderer::Context& context, const FrameView& frame, const detail::DepthPlan& plan,
                      renderer::SceneState& sceneState, FrameStatistics& statistics);
    /// Copies the depth of the framebuffer being drawn into _sceneDepth (FrameState::sceneDepth).
    void copySceneDepth(renderer::Context& context);
    void drawOverlay(renderer::Context& context, const FrameView& frame, const detail::DepthPlan& plan,
                     renderer::SceneState& sceneState, FrameStatistics& statistics) const;

    Ellipsoid _ellipsoid;
    SceneOptions _options;
    Camera _camera;
    std::vector<std::shared_ptr<Primitive>> _primitives;
    glm::dvec3 _sunDirection{1.0, 0.0, 0.0};
    double _clockSeconds = 0.0;
    std::uint64_t _frameNumber = 0;
    CommandBinner _binner;
    CommandList _commands; ///< reused across frames
    std::vector<Primitive*> _survivors; ///< reused across frames, those that draw the ground first
    std::size_t _groundSurvivors = 0;   ///< how many survivors draw the ground
    std::optional<DepthStrategy> _lastAutomaticDepth; ///< Automatic's choice last frame
    std::shared_ptr<renderer::Framebuffer> _floatDepthTarget;
    std::shared_ptr<renderer::Texture2D> _floatDepth;
    const renderer::Context* _floatDepthContext = nullptr;
    /// FrameState::sceneDepth: one object for the scene's life (commands point at it), its GL
    /// texture made again when the target's depth changes format or size.
    std::shared_ptr<renderer::Texture2D> _sceneDepth;
    std::shared_ptr<renderer::Framebuffer> _multisampleTarget;
    const renderer::Context* _multisampleContext = nullptr;
    std::shared_ptr<renderer::Framebuffer> _sceneDepthTarget;
    const renderer::Context* _sceneDepthContext = nullptr;
};

} // namespace orbis::scene
