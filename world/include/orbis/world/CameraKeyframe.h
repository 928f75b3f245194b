#pragma once

#include <orbis/core/Geodetic.h>

namespace orbis::world {

/// One keyframe of a camera path file (`orbis render --path`, docs/scene-format.md): where the eye
/// is and what it looks at, at a time. The scene's CameraPath flies through them.
struct CameraKeyframe {
    double seconds;    ///< from the start of the path
    Geodetic3D eye;    ///< radians, metres
    Geodetic3D target; ///< radians, metres
};

} // namespace orbis::world
