#include "orbis/scene/CommandBinner.h"

#include <glm/geometric.hpp>

#include <algorithm>

namespace orbis::scene {

void CommandBinner::cullAndBin(std::span<const SceneCommand> commands, const Frustum& cullingVolume,
                               const EllipsoidalOccluder& occluder, const glm::dvec3& eye,
                               const glm::dvec3& viewDirection, double cosHalfDiagonal,
                               FrameStatistics& statistics)
{
    const MultiFrustumOptions& limits = _multiFrustum.options();
    _visible.clear();
    _overlay.clear();
    _intervals.clear();
    statistics.commandsSubmitted += commands.size();
    for (std::uint32_t i = 0; i < commands.size(); ++i) {
        const SceneCommand& command = commands[i];
        if (command.boundingSphere && cullingVolume.intersect(*command.boundingSphere) == Intersect::Outside) {
            ++statistics.commandsCulledByFrustum;
            continue;
        }
        if (command.horizonOcclusionPoint && !occluder.isScaledSpacePointVisible(*command.horizonOcclusionPoint)) {
            ++statistics.commandsCulledByHorizon;
            continue;
        }
        if (command.pass == Pass::Overlay) {
            _overlay.push_back(i);
            continue;
        }
        _visible.push_back(i);
        DepthInterval interval{limits.nearLimit, limits.farLimit};
        if (command.boundingSphere) {
            const double distance = glm::dot(command.boundingSphere->centre - eye, viewDirection);
            interval = {distance - command.boundingSphere->radius, distance + command.boundingSphere->radius};
        }
        // Within the view, depth lies between distance x cos(half diagonal) and distance.
        interval.nearDistance = std::max(interval.nearDistance, command.nearestDistance * cosHalfDiagonal);
        interval.farDistance = std::min(interval.farDistance, command.farthestDistance);
        _intervals.push_back(interval);
    }
    _multiFrustum.bin(_intervals);
    statistics.frustums = _multiFrustum.frustums();
    statistics.frustumsReused = _multiFrustum.reused();
    statistics.commandsExecutedMoreThanOnce = _multiFrustum.commandsInSeveralFrustums();
}

} // namespace orbis::scene
