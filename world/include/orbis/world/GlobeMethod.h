#pragma once

namespace orbis::world {

/// How the globe is drawn.
enum class GlobeMethod {
    RayCast,     ///< a bounding box whose fragments cast rays at the ellipsoid (book section 4.3)
    Tessellated, ///< a mesh from a core tessellator, relative to the eye on the GPU
};

} // namespace orbis::world
