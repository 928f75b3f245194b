#pragma once

#include <cstdint>

namespace orbis::world {

/// The built-in markers a billboard can be drawn with instead of an image (a scene file's
/// billboard "shape"; scene::billboardShapeImage draws them).
enum class BillboardShape : std::uint8_t {
    Dot,    ///< a disc with an anti-aliased edge
    Square, ///< a filled square, edges on whole pixels
};

} // namespace orbis::world
