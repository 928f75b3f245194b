#pragma once

// Which segments of a set may meet, without comparing every pair: the polygon code's test for
// crossing and touching edges. Internal to orbis::core.

#include <glm/common.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace orbis::detail {

/// A uniform grid of square cells, sized from the segments: twice the median segment length, or
/// the bounding box's side over sqrt(n) if smaller (rings whose edges are long next to the ring),
/// or larger where the segments would otherwise pass through more than 8 n cells in all. Cells are
/// named by a 64-bit number, and hashed.
class SegmentGrid {
public:
    SegmentGrid(std::span<const glm::dvec2> from, std::span<const glm::dvec2> to)
    {
        glm::dvec2 lo(HUGE_VAL);
        glm::dvec2 hi(-HUGE_VAL);
        std::vector<double> lengths(from.size());
        double total = 0.0;
        for (std::size_t k = 0; k < from.size(); ++k) {
            lo = glm::min(lo, glm::min(from[k], to[k]));
            hi = glm::max(hi, glm::max(from[k], to[k]));
            const glm::dvec2 d = glm::abs(to[k] - from[k]);
            lengths[k] = std::max(d.x, d.y); // the cells a segment passes along its longer axis
            total += lengths[k];
        }
        _lo = lo;
        const double extent = std::max(hi.x - lo.x, hi.y - lo.y);
        if (!(extent > 0.0) || !std::isfinite(extent) || !std::isfinite(total)) {
            return; // one cell
        }
        const auto count = static_cast<double>(from.size());
        std::nth_element(lengths.begin(), lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2), lengths.end());
        double side = std::min(2.0 * lengths[lengths.size() / 2], extent / std::sqrt(count));
        side = std::max({side, total / (8.0 * count), extent / double{1 << 30}});
        _scale = 1.0 / side;
        _cells = static_cast<std::int64_t>(std::floor(extent * _scale)) + 1;
    }

    /// Square cells over the box lo..hi, cellsPerAxis of them along its longer side.
    SegmentGrid(const glm::dvec2& lo, const glm::dvec2& hi, std::int64_t cellsPerAxis) : _lo(lo)
    {
        const double extent = std::max(hi.x - lo.x, hi.y - lo.y);
        if (extent > 0.0 && std::isfinite(extent) && cellsPerAxis > 1) {
            _scale = static_cast<double>(cellsPerAxis) / extent;
            _cells = cellsPerAxis;
        }
    }

    /// The cells' names run from 0 to this, less one.
    std::uint64_t cellCount() const noexcept { return index(_cells - 1, _cells - 1) + 1; }

    /// Calls emit(cell) for each cell the segment a -> b passes through (with a margin for
    /// rounding), or every cell of its bounding box when that is at most 2 x 2.
    template <typename Emit>
    void cellsOf(const glm::dvec2& a, const glm::dvec2& b, Emit&& emit) const
    {
        const std::int64_t x0 = cellOn(0, std::min(a.x, b.x));
        const std::int64_t x1 = cellOn(0, std::max(a.x, b.x));
        const std::int64_t y0 = cellOn(1, std::min(a.y, b.y));
        const std::int64_t y1 = cellOn(1, std::max(a.y, b.y));
        if (x1 - x0 <= 1 && y1 - y0 <= 1) {
            for (std::int64_t x = x0; x <= x1; ++x) {
                for (std::int64_t y = y0; y <= y1; ++y) {
                    emit(index(x, y));
                }
            }
            return;
        }
        // Along the axis the segment runs more along, one slab of cells at a time; across it, the
        // cells between where the segment enters and leaves the slab.
        const int along = std::abs(b.x - a.x) >= std::abs(b.y - a.y) ? 0 : 1;
        const int across = 1 - along;
        const glm::dvec2& p = a[along] <= b[along] ? a : b;
        const glm::dvec2& q = a[along] <= b[along] ? b : a;
        const double slope = q[along] > p[along] ? (q[across] - p[across]) / (q[along] - p[along]) : 0.0;
        const double margin = roundingMargin(p, q);
        const std::int64_t first = cellOn(along, p[along]);
        const std::int64_t last = cellOn(along, q[along]);
        for (std::int64_t slab = first; slab <= last; ++slab) {
            const double start = std::max(p[along], _lo[along] + static_cast<double>(slab) / _scale);
            const double end = std::min(q[along], _lo[along] + static_cast<double>(slab + 1) / _scale);
            const double u = p[across] + slope * (start - p[along]);
            const double v = p[across] + slope * (std::max(start, end) - p[along]);
            const std::int64_t lowCell = cellOn(across, std::min(u, v) - margin);
            const std::int64_t highCell = cellOn(across, std::max(u, v) + margin);
            for (std::int64_t cell = lowCell; cell <= highCell; ++cell) {
                emit(along == 0 ? index(slab, cell) : index(cell, slab));
            }
        }
    }

    /// Calls emit(cell) for each cell of the box lo..hi.
    template <typename Emit>
    void cellsOfBox(const glm::dvec2& lo, const glm::dvec2& hi, Emit&& emit) const
    {
        for (std::int64_t y = cellOn(1, lo.y); y <= cellOn(1, hi.y); ++y) {
            for (std::int64_t x = cellOn(0, lo.x); x <= cellOn(0, hi.x); ++x) {
                emit(index(x, y));
            }
        }
    }

    /// Calls emit(cell) for the cells of the ray from p towards +x up to x = xEnd, a column of
    /// cells at a time from left to right (with a margin for rounding across), until
    /// stop(columnLeft), asked after each column, says the cells right of that column's left edge
    /// need no look.
    template <typename Emit, typename Stop>
    void cellsTowardsPlusX(const glm::dvec2& p, double xEnd, Emit&& emit, Stop&& stop) const
    {
        const double margin = roundingMargin(p, glm::dvec2(xEnd, p.y));
        const std::int64_t y0 = cellOn(1, p.y - margin);
        const std::int64_t y1 = cellOn(1, p.y + margin);
        for (std::int64_t x = cellOn(0, p.x); x <= cellOn(0, xEnd); ++x) {
            for (std::int64_t y = y0; y <= y1; ++y) {
                emit(index(x, y));
            }
            if (stop(_lo.x + static_cast<double>(x) / _scale)) {
                return;
            }
        }
    }

private:
    /// How far across a segment a -> b to look for the cells it passes: rounding moves the points
    /// computed along it by a few units in the last place of the coordinates, and along the cells'
    /// edges by as much (the slope across is at most 1).
    static double roundingMargin(const glm::dvec2& a, const glm::dvec2& b) noexcept
    {
        return 1e-9 * (std::abs(a.x) + std::abs(a.y) + std::abs(b.x) + std::abs(b.y));
    }

    std::int64_t cellOn(int axis, double value) const noexcept
    {
        const double scaled = std::floor((value - _lo[axis]) * _scale);
        return static_cast<std::int64_t>(std::clamp(scaled, 0.0, static_cast<double>(_cells - 1)));
    }
    std::uint64_t index(std::int64_t x, std::int64_t y) const noexcept
    {
        return static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(_cells) + static_cast<std::uint64_t>(x);
    }

    glm::dvec2 _lo{0.0};
    double _scale = 0.0;     // cells per unit
    std::int64_t _cells = 1; // per axis
};

/// True when the segments from[k] -> to[k], each from vertex fromVertex[k] to vertex toVertex[k]
/// (ids >= 0: the nodes of closed rings, where each vertex starts one segment and ends one), have
/// a position per vertex that no other vertex has, and meet only where
/// two share a vertex, there at that point alone: then no segment touches or crosses another.
/// Proved by a sweep of a vertical line across the vertices (Shamos and Hoey), comparing only
/// segments next to each other along the line: O(n log n) whatever the segments' lengths, where
/// findMeetingSegments looks at every pair whose boxes overlap (most pairs of a ring of long thin
/// spikes). False as soon as it finds anything else, without saying what: the caller looks closer.
bool meetOnlyAtSharedVertices(std::span<const glm::dvec2> from, std::span<const glm::dvec2> to,
                              std::span<const int> fromVertex, std::span<const int> toVertex);

/// What findMeetingSegments did: visit returned true (Stopped), every pair was visited
/// (Finished), or none was, for the pairs to look at were more than the limit.
enum class PairSearch { Stopped, Finished, TooManyPairs };

/// Calls visit(i, j), i < j, once for every pair of the segments from[k] -> to[k] that share a
/// point, and for some pairs that come close; stops when visit returns true. The segments go into
/// a SegmentGrid, each into the cells it passes through, so the work is about the number of
/// segments plus, per cell, the square of the segments in it: linear for rings whose edges are
/// about equally long, whatever the shape; where the pairs sharing a cell are more than pairLimit
/// (long edges close together: a ring of thin spikes), it visits none.
template <typename Visit>
PairSearch findMeetingSegments(std::span<const glm::dvec2> from, std::span<const glm::dvec2> to, Visit&& visit,
                               std::size_t pairLimit = std::numeric_limits<std::size_t>::max())
{
    const std::size_t count = from.size();
    if (count < 2) {
        return PairSearch::Finished;
    }
    // Whether segment j's bounding box meets the box lo..hi.
    auto meets = [&](const glm::dvec2& lo, const glm::dvec2& hi, std::size_t j) {
        const glm::dvec2 otherLo = glm::min(from[j], to[j]);
        const glm::dvec2 otherHi = glm::max(from[j], to[j]);
        return otherLo.x <= hi.x && otherHi.x >= lo.x && otherLo.y <= hi.y && otherHi.y >= lo.y;
    };
    if (count <= 32) {
        // Few segments (a building's ring): every pair costs less than making the grid.
        for (std::size_t i = 0; i < count; ++i) {
            const glm::dvec2 lo = glm::min(from[i], to[i]);
            const glm::dvec2 hi = glm::max(from[i], to[i]);
            for (std::size_t j = i + 1; j < count; ++j) {
                if (meets(lo, hi, j) && visit(i, j)) {
                    return PairSearch::Stopped;
                }
            }
        }
        return PairSearch::Finished;
    }
    const SegmentGrid grid(from, to);
    // Segments by cell, through a hash of the cell into 2^k buckets (a bucket may hold several
    // cells: only more pairs to look at), counted and placed; and each segment's buckets.
    std::vector<std::uint32_t> buckets; // per segment, in order
    std::vector<std::uint32_t> bucketsStart(count + 1, 0);
    buckets.reserve(2 * count);
    std::size_t bucketCount = 1;
    while (bucketCount < 2 * count) {
        bucketCount *= 2;
    }
    const auto bucketOf = [&](std::uint64_t cell) {
        return static_cast<std::uint32_t>(((cell * 0x9e3779b97f4a7c15ull) >> 32) & (bucketCount - 1));
    };
    for (std::size_t k = 0; k < count; ++k) {
        grid.cellsOf(from[k], to[k], [&](std::uint64_t cell) { buckets.push_back(bucketOf(cell)); });
        bucketsStart[k + 1] = static_cast<std::uint32_t>(buckets.size());
    }
    std::vector<std::uint32_t> start(bucketCount + 1, 0); // per bucket, into segments
    for (const std::uint32_t bucket : buckets) {
        ++start[bucket + 1];
    }
    std::size_t pairs = 0;
    for (std::size_t bucket = 1; bucket <= bucketCount; ++bucket) {
        const std::size_t inBucket = start[bucket];
        pairs += inBucket * (inBucket - 1) / 2; // 0 for an empty bucket too (unsigned)
        start[bucket] += start[bucket - 1];
    }
    if (pairs > pairLimit) {
        return PairSearch::TooManyPairs;
    }
    // Each bucket's segments in increasing order, and where each segment stands in its buckets.
    std::vector<std::uint32_t> segments(buckets.size());
    std::vector<std::uint32_t> placed(buckets.size()); // per entry of buckets
    {
        std::vector<std::uint32_t> filled(start.begin(), start.end() - 1);
        for (std::size_t k = 0; k < count; ++k) {
            for (std::uint32_t b = bucketsStart[k]; b < bucketsStart[k + 1]; ++b) {
                placed[b] = filled[buckets[b]]++;
                segments[placed[b]] = static_cast<std::uint32_t>(k);
            }
        }
    }

    // Each pair once: segment i meets those after it in its buckets, and the last i that met j is
    // remembered.
    std::vector<std::size_t> metLast(count, static_cast<std::size_t>(-1));
    for (std::size_t i = 0; i < count; ++i) {
        const glm::dvec2 lo = glm::min(from[i], to[i]);
        const glm::dvec2 hi = glm::max(from[i], to[i]);
        for (std::uint32_t b = bucketsStart[i]; b < bucketsStart[i + 1]; ++b) {
            for (std::uint32_t s = placed[b] + 1; s < start[buckets[b] + 1]; ++s) {
                const std::size_t j = segments[s];
                if (j <= i || metLast[j] == i) {
                    continue;
                }
                metLast[j] = i;
                if (meets(lo, hi, j) && visit(i, j)) {
                    return PairSearch::Stopped;
                }
            }
        }
    }
    return PairSearch::Finished;
}

/// Segments, named by ids, filed by the cells of a uniform grid that they pass through (about one
/// segment to a cell where they spread evenly), so that the segments that may meet a segment or a
/// box are found without looking at all of them, as segments are added. An id filed again (its
/// segment moved) stays under its old cells too: a query reports it there as well, and the caller
/// judges its segment as it is now.
class SegmentIndex {
public:
    /// For segments within the box lo..hi, about `expected` of them.
    SegmentIndex(const glm::dvec2& lo, const glm::dvec2& hi, std::size_t expected)
        : _grid(lo, hi, static_cast<std::int64_t>(std::ceil(std::sqrt(static_cast<double>(expected))))),
          _cells(static_cast<std::size_t>(_grid.cellCount()))
    {
    }

    void insert(int id, const glm::dvec2& a, const glm::dvec2& b)
    {
        if (static_cast<std::size_t>(id) >= _seen.size()) {
            _seen.resize(static_cast<std::size_t>(id) + 1, 0);
        }
        _grid.cellsOf(a, b, [&](std::uint64_t cell) {
            std::vector<int>& ids = _cells[static_cast<std::size_t>(cell)];
            if (ids.empty() || ids.back() != id) {
                ids.push_back(id);
            }
        });
    }

    /// Calls visit(id) once for each id filed under a cell that the segment a -> b passes through:
    /// every segment that meets it, and some near it.
    template <typename Visit>
    void forEachNear(const glm::dvec2& a, const glm::dvec2& b, Visit&& visit)
    {
        beginQuery();
        _grid.cellsOf(a, b, [&](std::uint64_t cell) { visitCell(cell, visit); });
    }

    /// Calls visit(id) once for each id filed under a cell of the box lo..hi: every segment with a
    /// point in the box, and some near it.
    template <typename Visit>
    void forEachInBox(const glm::dvec2& lo, const glm::dvec2& hi, Visit&& visit)
    {
        beginQuery();
        _grid.cellsOfBox(lo, hi, [&](std::uint64_t cell) { visitCell(cell, visit); });
    }

    /// Calls visit(id) once for each id filed under the cells of the ray from p towards +x up to
    /// x = xEnd, left to right, until stop(x) after a column of cells says nothing right of x
    /// matters (see SegmentGrid::cellsTowardsPlusX).
    template <typename Visit, typename Stop>
    void forEachTowardsPlusX(const glm::dvec2& p, double xEnd, Visit&& visit, Stop&& stop)
    {
        beginQuery();
        _grid.cellsTowardsPlusX(p, xEnd, [&](std::uint64_t cell) { visitCell(cell, visit); }, stop);
    }

private:
    void beginQuery()
    {
        if (++_query == 0) { // wrapped: forget every earlier query's marks
            std::fill(_seen.begin(), _seen.end(), 0);
            _query = 1;
        }
    }

    template <typename Visit>
    void visitCell(std::uint64_t cell, Visit& visit)
    {
        for (const int id : _cells[static_cast<std::size_t>(cell)]) {
            std::uint32_t& seen = _seen[static_cast<std::size_t>(id)];
            if (seen != _query) {
                seen = _query;
                visit(id);
            }
        }
    }

    SegmentGrid _grid;
    std::vector<std::vector<int>> _cells;
    std::vector<std::uint32_t> _seen; // per id: the last query that visited it
    std::uint32_t _query = 0;
};

} // namespace orbis::detail
