#pragma once

#include "orbis/core/Image.h"

#include <vector>

namespace orbis {

/// The next mipmap level of an image: half its width and height (rounded down, at least 1), each
/// texel the rounded mean of the texels it covers (2 x 2, or 3 along an odd edge): the box filter
/// glGenerateMipmap uses, computed where the caller likes (a loader's worker thread), not on the
/// GPU's driver thread, where a software rasteriser takes ten times a JPEG's decoding for it.
Image halveImage(const Image& image);

/// Levels 1, 2, ... of the image down to 1 x 1, each halveImage of the one before. Empty for a
/// 1 x 1 image.
std::vector<Image> mipmapChain(const Image& image);

} // namespace orbis
