#pragma once

#include <string>

// Scenes for tests: a framebuffer-backed frame, flat squares as small meshes (cubes for markers
// and satellites: BoxTessellator::cube).

#include <orbis/scene/MeshPrimitive.h>
#include <orbis/scene/Scene.h>
#include <orbis/world/ImageFile.h>

namespace orbis::test {

/// A flat square, halfSize metres from its centre to each side, in the local horizontal plane of a
/// geodetic position (heights along the normal), counter-clockwise seen from above.
Mesh horizontalSquare(const Ellipsoid& ellipsoid, const Geodetic3D& centre, double halfSize);

/// Renders one frame of the scene into a new width x height framebuffer of the shared device.
struct RenderedFrame {
    scene::FrameStatistics statistics;
    Image image;
};
RenderedFrame renderFrame(scene::Scene& scene, int width, int height);

/// Where a world position lands in an image rendered with renderFrame (x from the left, y from the top).
glm::ivec2 projectToPixel(const scene::Scene& scene, const glm::dvec3& position, int width, int height);

/// Puts the camera at a geodetic position looking along a heading and pitch (degrees), without roll.
void placeCamera(scene::Scene& scene, const Geodetic3D& position, double headingDegrees, double pitchDegrees);

/// Renders until the frame statistics say the tiles converged, at most maxFrames; the last frame.
RenderedFrame renderUntilTilesConverge(scene::Scene& scene, int width, int height, int maxFrames);

/// A path in the project's data/ folder.
inline std::string dataPath(const std::string& relative)
{
    return std::string(ORBIS_SOURCE_DIR) + "/data/" + relative;
}

} // namespace orbis::test
