#pragma once

// Packs many small images into one, so that a collection of billboards or glyphs draws with one
// texture bound. CPU only: the atlas image is uploaded by whoever draws it.

#include <orbis/core/Image.h>
#include <orbis/renderer/PixelRectangle.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace orbis::renderer {

/// Texture coordinates of a rectangle, in [0, 1]: (u0, v0) is the outer corner of its top-left
/// pixel and (u1, v1) the outer corner of its bottom-right pixel. v grows with the image's row, so
/// v = 0 is row 0, which glTexImage2D stores first: no flip is needed when the image is uploaded as is.
struct TextureRectangle {
    float u0 = 0.0f;
    float v0 = 0.0f;
    float u1 = 0.0f;
    float v1 = 0.0f;
};

/// How a TextureAtlas lays out its images.
struct TextureAtlasOptions {
    int channels = 4;    ///< channels of the atlas and of every image added (1 to 4)
    int padding = 1;     ///< empty (zero) pixels kept between two images and between an image and the edge
    int initialSize = 64; ///< width and height of the first atlas; a power of two
    int maxSize = 4096;  ///< the atlas never grows beyond this width or height; a power of two
};

/// Images packed into one atlas image with a skyline (bottom-left) packer. Images are added, never
/// removed; each keeps its index. When an image does not fit, the atlas doubles its smaller side
/// (power-of-two sizes) and keeps every placed image where it was; only when the atlas cannot grow
/// any more are all images packed again from scratch, tallest first.
///
///     TextureAtlas atlas;
///     const std::size_t marker = atlas.add(world::readImage("marker.png")).first;
///     const TextureRectangle uv = atlas.textureCoordinates(marker);
class TextureAtlas {
public:
    /// What an addition did, so a GPU copy of the atlas can be kept current cheaply.
    struct AddResult {
        std::size_t first = 0; ///< index of the first image added; the others follow in the given order
        bool resized = false;  ///< the atlas changed size (grew): every image's texture coordinates changed
        bool repacked = false; ///< images placed before moved: every pixel rectangle changed
        PixelRectangle changed; ///< the pixels that changed (the whole atlas when grown or repacked)
    };

    explicit TextureAtlas(const TextureAtlasOptions& options = {});

    /// Adds one image. Throws orbis::Error when its channel count differs from the atlas's or when
    /// it cannot fit within maxSize; the atlas is then unchanged. An empty (0-pixel) image gets an
    /// empty rectangle.
    AddResult add(const Image& image);
    /// Adds several images at once, placed tallest first for a tighter packing; their indices follow
    /// the given order. Throws like add(image), adding none of them.
    AddResult add(std::span<const Image> images);

    /// Number of images added.
    std::size_t size() const noexcept { return _rectangles.size(); }
    /// Where image `index` lies in the atlas image, without its padding.
    const PixelRectangle& rectangle(std::size_t index) const { return _rectangles.at(index); }
    /// Image `index`'s texture coordinates at the atlas's current size.
    TextureRectangle textureCoordinates(std::size_t index) const;

    /// The atlas: images at their rectangles, zeros elsewhere.
    const Image& image() const noexcept { return _image; }
    int width() const noexcept { return _image.width; }
    int height() const noexcept { return _image.height; }
    const TextureAtlasOptions& options() const noexcept { return _options; }
    /// Increases with every change to the image; a texture made from the image is current while
    /// the version it was made from equals this.
    std::uint64_t version() const noexcept { return _version; }

private:
    struct Node {
        int x;
        int y;
        int width;
    };
    /// The skyline: the top edge of the used area, as horizontal segments from left to right.
    struct Packer {
        int width = 0;
        int height = 0;
        int padding = 0;
        std::vector<Node> skyline;

        Packer(int width_, int height_, int padding_);
        bool place(int cellWidth, int cellHeight, int& x, int& y);
        void growWidth(int newWidth);
    };

    /// Places images of the given sizes, tallest first, growing the packer as needed; false when
    /// one cannot fit within maxSize. placed[i] is where sizes[i] went.
    bool placeAll(Packer& packer, const std::vector<std::pair<int, int>>& sizes,
                  std::vector<PixelRectangle>& placed) const;

    TextureAtlasOptions _options;
    Image _image;
    Packer _packer;
    std::vector<PixelRectangle> _rectangles;
    std::uint64_t _version = 0;
};

} // namespace orbis::renderer
