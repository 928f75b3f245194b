#include "orbis/renderer/TextureAtlas.h"

#include "orbis/core/Error.h"

#include <algorithm>
#include <cassert>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>

namespace orbis::renderer {

namespace {

[[maybe_unused]] bool isPowerOfTwo(int n)
{
    return n > 0 && (n & (n - 1)) == 0;
}

std::string describeSize(int width, int height)
{
    return std::to_string(width) + "x" + std::to_string(height);
}

/// Copies `rectangle` of `from` to (x, y) of `to`; both have the same channel count.
void copyPixels(const Image& from, const PixelRectangle& rectangle, Image& to, int x, int y)
{
    const std::size_t rowBytes = static_cast<std::size_t>(rectangle.width) * static_cast<std::size_t>(from.channels);
    for (int row = 0; row < rectangle.height; ++row) {
        std::memcpy(to.pixel(x, y + row), from.pixel(rectangle.x, rectangle.y + row), rowBytes);
    }
}

} // namespace

TextureAtlas::Packer::Packer(int width_, int height_, int padding_)
    : width(width_), height(height_), padding(padding_), skyline{{padding_, padding_, width_ - padding_}}
{
}

bool TextureAtlas::Packer::place(int cellWidth, int cellHeight, int& x, int& y)
{
    // Bottom-left rule: the position whose top edge is lowest, then the leftmost.
    std::size_t best = skyline.size();
    int bestTop = std::numeric_limits<int>::max();
    int bestY = 0;
    for (std::size_t i = 0; i < skyline.size(); ++i) {
        const int left = skyline[i].x;
        if (left + cellWidth > width) {
            break;
        }
        int top = skyline[i].y;
        for (std::size_t j = i + 1; j < skyline.size() && skyline[j].x < left + cellWidth; ++j) {
            top = std::max(top, skyline[j].y);
        }
        if (top + cellHeight <= height && top + cellHeight < bestTop) {
            best = i;
            bestTop = top + cellHeight;
            bestY = top;
        }
    }
    if (best == skyline.size()) {
        return false;
    }
    x = skyline[best].x;
    y = bestY;

    // The cell's top becomes a new segment; the segments under it shrink or go.
    const int right = x + cellWidth;
    skyline.insert(skyline.begin() + static_cast<std::ptrdiff_t>(best), Node{x, y + cellHeight, cellWidth});
    std::size_t next = best + 1;
    while (next < skyline.size() && skyline[next].x < right) {
        const int overlap = right - skyline[next].x;
        if (overlap >= skyline[next].width) {
            skyline.erase(skyline.begin() + static_cast<std::ptrdiff_t>(next));
        } else {
            skyline[next].x += overlap;
            skyline[next].width -= overlap;
            break;
        }
    }
    // Neighbours at the same height become one segment.
    for (std::size_t i = 0; i + 1 < skyline.size();) {
        if (skyline[i].y == skyline[i + 1].y) {
            skyline[i].width += skyline[i + 1].width;
            skyline.erase(skyline.begin() + static_cast<std::ptrdiff_t>(i + 1));
        } else {
            ++i;
        }
    }
    return true;
}

void TextureAtlas::Packer::growWidth(int newWidth)
{
    // The new columns are empty: their skyline lies at the top padding.
    if (skyline.back().y == padding) {
        skyline.back().width += newWidth - width;
    } else {
        skyline.push_back({width, padding, newWidth - width});
    }
    width = newWidth;
}

TextureAtlas::TextureAtlas(const TextureAtlasOptions& options)
    : _options(options)
    , _image(options.initialSize, options.initialSize, options.channels)
    , _packer(options.initialSize, options.initialSize, options.padding)
{
    assert(options.channels >= 1 && options.channels <= 4);
    assert(options.padding >= 0 && 2 * options.padding < options.initialSize);
    assert(isPowerOfTwo(options.initialSize) && isPowerOfTwo(options.maxSize) && options.initialSize <= options.maxSize);
}

bool TextureAtlas::placeAll(Packer& packer, const std::vector<std::pair<int, int>>& sizes,
                            std::vector<PixelRectangle>& placed) const
{
    // Tallest first, then widest: a skyline packs such an order tightly.
    std::vector<std::size_t> order(sizes.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return sizes[a].second != sizes[b].second ? sizes[a].second > sizes[b].second : sizes[a].first > sizes[b].first;
    });
    placed.assign(sizes.size(), PixelRectangle{});
    const int padding = _options.padding;
    for (std::size_t index : order) {
        const auto [width, height] = sizes[index];
        if (width == 0 || height == 0) {
            continue;
        }
        int x = 0;
        int y = 0;
        while (!packer.place(width + padding, height + padding, x, y)) {
            // Grow the smaller side (the width on a tie), keeping what is placed where it is.
            const bool widthCanGrow = packer.width < _options.maxSize;
            const bool heightCanGrow = packer.height < _options.maxSize;
            if (widthCanGrow && (packer.width <= packer.height || !heightCanGrow)) {
                packer.growWidth(packer.width * 2);
            } else if (heightCanGrow) {
                packer.height *= 2;
            } else {
                return false;
            }
        }
        placed[index] = {x, y, width, height};
    }
    return true;
}

TextureAtlas::AddResult TextureAtlas::add(const Image& image)
{
    return add(std::span<const Image>(&image, 1));
}

TextureAtlas::AddResult TextureAtlas::add(std::span<const Image> images)
{
    AddResult result;
    result.first = _rectangles.size();
    if (images.empty()) {
        return result;
    }
    const int padding = _options.padding;
    const int largest = _options.maxSize - 2 * padding;
    std::vector<std::pair<int, int>> sizes;
    sizes.reserve(images.size());
    for (std::size_t i = 0; i < images.size(); ++i) {
        const Image& image = images[i];
        if (image.width > 0 && image.height > 0 && image.channels != _options.channels) {
            throw Error("texture atlas: image " + std::to_string(result.first + i) + " has " +
                        std::to_string(image.channels) + " channels, the atlas " + std::to_string(_options.channels));
        }
        if (image.width > largest || image.height > largest) {
            throw Error("texture atlas: image " + std::to_string(result.first + i) + " (" +
                        describeSize(image.width, image.height) + ") cannot fit in the maximum atlas size " +
                        describeSize(_options.maxSize, _options.maxSize) + " with " + std::to_string(padding) +
                        " px padding");
        }
        sizes.emplace_back(image.width, image.height);
    }

    // First try: place the new images around the old ones, growing the atlas as needed.
    Packer packer = _packer;
    std::vector<PixelRectangle> placed;
    std::vector<PixelRectangle> moved; // where the old images go when everything is packed again
    if (!placeAll(packer, sizes, placed)) {
        // The atlas is as large as it may be: pack everything again from scratch.
        std::vector<std::pair<int, int>> all;
        all.reserve(_rectangles.size() + sizes.size());
        for (const PixelRectangle& r : _rectangles) {
            all.emplace_back(r.width, r.height);
        }
        all.insert(all.end(), sizes.begin(), sizes.end());
        packer = Packer(_options.initialSize, _options.initialSize, padding);
        std::vector<PixelRectangle> allPlaced;
        if (!placeAll(packer, all, allPlaced)) {
            throw Error("texture atlas: " + std::to_string(images.size()) + " more image(s) do not fit beside the " +
                        std::to_string(_rectangles.size()) + " already packed within the maximum size " +
                        describeSize(_options.maxSize, _options.maxSize));
        }
        moved.assign(allPlaced.begin(), allPlaced.begin() + static_cast<std::ptrdiff_t>(_rectangles.size()));
        placed.assign(allPlaced.begin() + static_cast<std::ptrdiff_t>(_rectangles.size()), allPlaced.end());
        result.repacked = true;
    }

    // Commit: a new image when the size changed or images moved, then the new images' pixels.
    result.resized = packer.width != _image.width || packer.height != _image.height;
    if (result.resized || result.repacked) {
        Image larger(packer.width, packer.height, _options.channels);
        for (std::size_t i = 0; i < _rectangles.size(); ++i) {
            const PixelRectangle& to = result.repacked ? moved[i] : _rectangles[i];
            copyPixels(_image, _rectangles[i], larger, to.x, to.y);
        }
        _image = std::move(larger);
        if (result.repacked) {
            _rectangles = std::move(moved);
        }
        result.changed = {0, 0, _image.width, _image.height};
    }
    int left = _image.width;
    int top = _image.height;
    int right = 0;
    int bottom = 0;
    for (std::size_t i = 0; i < images.size(); ++i) {
        const PixelRectangle& r = placed[i];
        if (r.width == 0 || r.height == 0) {
            continue;
        }
        copyPixels(images[i], {0, 0, r.width, r.height}, _image, r.x, r.y);
        left = std::min(left, r.x);
        top = std::min(top, r.y);
        right = std::max(right, r.x + r.width);
        bottom = std::max(bottom, r.y + r.height);
    }
    if (!result.resized && !result.repacked && right > left) {
        result.changed = {left, top, right - left, bottom - top};
    }
    _rectangles.insert(_rectangles.end(), placed.begin(), placed.end());
    _packer = std::move(packer);
    ++_version;
    return result;
}

TextureRectangle TextureAtlas::textureCoordinates(std::size_t index) const
{
    const PixelRectangle& r = _rectangles.at(index);
    const double width = _image.width;
    const double height = _image.height;
    return {static_cast<float>(r.x / width), static_cast<float>(r.y / height),
            static_cast<float>((r.x + r.width) / width), static_cast<float>((r.y + r.height) / height)};
}

} // namespace orbis::renderer
