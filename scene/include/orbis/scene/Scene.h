#pragma once

#include "orbis/scene/Camera.h"
#include "orbis/scene/CommandBinner.h"
#include "orbis/scene/FrameState.h"
#include "orbis/scene/FrameStatistics.h"
#include "orbis/scene/MultiFrustum.h"

#include <orbis/core/Ellipsoid.h>

#include <glm/vec4.hpp>

#include <memory>
#include <vector>

namespace orbis {

class Context;

struct SceneOptions {
    MultiFrustumOptions multiFrustum;
    glm::vec4 background{0.0f, 0.0f, 0.0f, 1.0f};
};

/// Primitives, a camera and a sun; render() runs one frame: update the primitives that survive
/// whole-primitive culling, cull their commands against the view frustum and the ellipsoid's
/// horizon, bin the survivors into dynamic multi-frustums, and draw the frustums back to front
/// (depth cleared for each, opaque then translucent), then the overlay pass.
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

    /// Unit vector towards the Sun, Earth-fixed.
    void setSunDirection(const glm::dvec3& direction) noexcept;
    const glm::dvec3& sunDirection() const noexcept { return _sunDirection; }
    void setTime(double seconds) noexcept { _timeSeconds = seconds; }

    /// Draws one frame into the context's current framebuffer (which must exist: headless
    /// contexts have no default one). Throws orbis::Error from the renderer for bad commands.
    FrameStatistics render(Context& context);

private:
    Ellipsoid _ellipsoid;
    SceneOptions _options;
    Camera _camera;
    std::vector<std::shared_ptr<Primitive>> _primitives;
    glm::dvec3 _sunDirection{1.0, 0.0, 0.0};
    double _timeSeconds = 0.0;
    std::uint64_t _frameNumber = 0;
    CommandBinner _binner;
    CommandList _commands; ///< reused across frames
};

} // namespace orbis
