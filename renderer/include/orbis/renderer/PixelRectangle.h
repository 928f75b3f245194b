#pragma once

namespace orbis::renderer {

/// A rectangle of whole pixels. Which corner (x, y) is depends on where it is used, and each use
/// says so: the bottom-left pixel for GL's viewport, scissor and texture regions, the top-left one
/// for images and atlases (rows counted from the top as in Image).
struct PixelRectangle {
    int x = 0;
    int y = 0;
    int width = 0;
    int height = 0;

    friend constexpr bool operator==(const PixelRectangle&, const PixelRectangle&) = default;
};

} // namespace orbis::renderer
