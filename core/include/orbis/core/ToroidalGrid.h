#pragma once

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <vector>

namespace orbis {

/// Posts [x, x + width) x [y, y + height) of a level's global post lattice.
struct GridRegion {
    std::int64_t x = 0, y = 0;
    int width = 0, height = 0;
    friend bool operator==(const GridRegion&, const GridRegion&) = default;
};

/// A rectangle of texels of a ToroidalGrid, inside 0 .. size - 1 on both axes.
struct TexelRectangle {
    int x = 0, y = 0, width = 0, height = 0;
    friend bool operator==(const TexelRectangle&, const TexelRectangle&) = default;
};

/// A size x size window on an unbounded lattice of posts, stored toroidally (book 13.5, Losasso
/// and Hoppe 2004): post (x, y) lives in texel (x mod size, y mod size), so that moving the window
/// leaves every post still in view where it was and only the L-shaped strips that came into view
/// are written.
///
/// ```
/// ToroidalGrid<float> heights(256);
/// for (const GridRegion& region : heights.moveTo(originX, originY))
///     fill(region);                          // heights.at(x, y) = ... for its posts
/// for (const TexelRectangle& r : heights.texelRectangles(region)) upload(r);
/// ```
template <typename T>
class ToroidalGrid final {
public:
    /// size: a power of two (asserted).
    explicit ToroidalGrid(int size, T initial = T{})
        : _size(size)
        , _texels(static_cast<std::size_t>(size) * static_cast<std::size_t>(size), initial)
    {
        assert(size > 0 && (size & (size - 1)) == 0);
    }

    int size() const noexcept { return _size; }
    bool placed() const noexcept { return _placed; }
    std::int64_t originX() const noexcept { return _originX; }
    std::int64_t originY() const noexcept { return _originY; }

    /// Moves the window's post 0 to (x, y). Returns the regions that came into view and must be
    /// written (at most two, an L: the columns first, then the rows not in them); the whole window
    /// at the first move, after invalidate(), or when it moved by size or more. Empty when it did
    /// not move.
    std::vector<GridRegion> moveTo(std::int64_t x, std::int64_t y)
    {
        std::vector<GridRegion> regions;
        const std::int64_t dx = x - _originX, dy = y - _originY;
        if (!_placed || dx >= _size || -dx >= _size || dy >= _size || -dy >= _size) {
            regions.push_back({x, y, _size, _size});
        } else {
            if (dx != 0) {
                const std::int64_t first = dx > 0 ? _originX + _size : x;
                regions.push_back({first, y, static_cast<int>(dx > 0 ? dx : -dx), _size});
            }
            if (dy != 0) {
                const std::int64_t first = dy > 0 ? _originY + _size : y;
                // The columns just listed are not repeated.
                const std::int64_t columnsFirst = dx > 0 ? x : _originX;
                const int columns = _size - static_cast<int>(dx > 0 ? dx : -dx);
                regions.push_back({columnsFirst, first, columns, static_cast<int>(dy > 0 ? dy : -dy)});
            }
        }
        _placed = true;
        _originX = x;
        _originY = y;
        return regions;
    }

    /// The next moveTo returns the whole window.
    void invalidate() noexcept { _placed = false; }

    /// Whether post (x, y) is inside the window.
    bool contains(std::int64_t x, std::int64_t y) const noexcept
    {
        return _placed && x >= _originX && x < _originX + _size && y >= _originY && y < _originY + _size;
    }

    /// The texel holding post (x, y) (any post; the window decides what it means).
    T& at(std::int64_t x, std::int64_t y) noexcept { return _texels[texelIndex(x, y)]; }
    const T& at(std::int64_t x, std::int64_t y) const noexcept { return _texels[texelIndex(x, y)]; }

    std::size_t texelIndex(std::int64_t x, std::int64_t y) const noexcept
    {
        const std::int64_t mask = _size - 1;
        return static_cast<std::size_t>(y & mask) * static_cast<std::size_t>(_size) + static_cast<std::size_t>(x & mask);
    }

    /// The texel rectangles a region of at most size x size posts occupies: split where it wraps,
    /// one to four.
    std::vector<TexelRectangle> texelRectangles(const GridRegion& region) const
    {
        std::vector<TexelRectangle> rectangles;
        const std::int64_t mask = _size - 1;
        const int x0 = static_cast<int>(region.x & mask), y0 = static_cast<int>(region.y & mask);
        const int widths[2] = {std::min(region.width, _size - x0), region.width - std::min(region.width, _size - x0)};
        const int heights[2] = {std::min(region.height, _size - y0), region.height - std::min(region.height, _size - y0)};
        for (int row = 0; row < 2; ++row) {
            for (int column = 0; column < 2; ++column) {
                if (widths[column] > 0 && heights[row] > 0) {
                    rectangles.push_back({column == 0 ? x0 : 0, row == 0 ? y0 : 0, widths[column], heights[row]});
                }
            }
        }
        return rectangles;
    }

    /// All texels, row by row (texel y * size + x).
    const std::vector<T>& texels() const noexcept { return _texels; }

private:
    int _size;
    bool _placed = false;
    std::int64_t _originX = 0, _originY = 0;
    std::vector<T> _texels;
};

} // namespace orbis
