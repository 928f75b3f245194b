#pragma once

#include "orbis/scene/FrameStatistics.h"
#include "orbis/scene/MultiFrustum.h"
#include "orbis/scene/SceneCommand.h"

#include <orbis/core/EllipsoidalOccluder.h>
#include <orbis/core/Frustum.h>

#include <span>
#include <vector>

namespace orbis::scene {

/// Step 4 of a frame: culls the commands against the view frustum, then the ellipsoid's
/// horizon, and bins the survivors into dynamic multi-frustums by their extent along the view
/// direction. Overlay commands are kept apart: they are drawn after every frustum.
class CommandBinner final {
public:
    explicit CommandBinner(const MultiFrustumOptions& options = {}) : _multiFrustum(options) {}

    /// Culls and bins; adds the culling counts, frustums and redundancy to statistics.
    /// cosHalfDiagonal: the cosine of the angle between the view direction and the frustum's
    /// corners, which turns a command's nearest distance into a nearest depth.
    void cullAndBin(std::span<const SceneCommand> commands, const Frustum& cullingVolume,
                    const EllipsoidalOccluder& occluder, const glm::dvec3& eye, const glm::dvec3& viewDirection,
                    double cosHalfDiagonal, FrameStatistics& statistics);

    MultiFrustum& multiFrustum() noexcept { return _multiFrustum; }
    const MultiFrustum& multiFrustum() const noexcept { return _multiFrustum; }
    /// The commands that survived culling (indices into the span given), in submission order;
    /// multiFrustum().bins() index into this list.
    const std::vector<std::uint32_t>& visible() const noexcept { return _visible; }
    /// Surviving overlay commands (indices into the span given).
    const std::vector<std::uint32_t>& overlay() const noexcept { return _overlay; }

private:
    MultiFrustum _multiFrustum;
    std::vector<std::uint32_t> _visible;
    std::vector<std::uint32_t> _overlay;
    std::vector<DepthInterval> _intervals;
};

} // namespace orbis::scene
