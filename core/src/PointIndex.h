#pragma once

// The points of a set that lie in a box, as points are removed one by one: the ear clipper's way to
// find what may lie inside an ear without looking at every vertex. Internal to orbis::core.

#include <glm/common.hpp>
#include <glm/vec2.hpp>

#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace orbis::detail {

/// Points in Z order (Morton order of their coordinates quantised to 16 bits over the set's
/// bounding box), linked so that removal is O(1). A point of a box has a key between those of the
/// box's corners, so walking from a point near the box, both ways along the order, finds every
/// point of the box; that is a few steps for a small box, but can be most of the set for a box
/// across a major boundary of the order, so walks longer than about a hundred steps give way to a
/// k-d tree (built, from the points then present, once they have been long often enough to pay for
/// it), whose query takes O(sqrt(n) + k) whatever the box.
class PointIndex {
public:
    /// Empty until reset.
    PointIndex();
    ~PointIndex();

    /// Indexes points[id] for each id in ids with indexed[id] != 0 (ids index points and
    /// indexed, which must outlive the call; points the index), instead of those before, keeping
    /// their memory. The other ids are not found, but may start a walk (findIn's near).
    void reset(std::span<const glm::dvec2> points, std::span<const int> ids, std::span<const std::uint8_t> indexed);
    PointIndex(const PointIndex&) = delete;
    PointIndex& operator=(const PointIndex&) = delete;

    /// Removes the point id; nothing if it is not present.
    void remove(int id) noexcept;

    /// Calls visit(id) for points present in the counter-clockwise triangle a, b, c (closed), and
    /// maybe some others in its bounding box, in no particular order and maybe a point twice,
    /// until visit returns true; returns whether it did. near must be one of reset's ids, present
    /// or not, at or next to the triangle (the walk starts there).
    template <typename Visit>
    bool findIn(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, int near, Visit&& visit)
    {
        if (_presentCount == 0) {
            return false;
        }
        const glm::dvec2 lo = glm::min(a, glm::min(b, c));
        const glm::dvec2 hi = glm::max(a, glm::max(b, c));
        const std::uint32_t low = key(lo);
        const std::uint32_t high = key(hi);
        // From the point present at or before near in the order back, and from the one after it on.
        const int back = presentFrom(_previous, near);
        const int forward = back >= 0 ? _next[static_cast<std::size_t>(back)] : presentFrom(_next, near);
        int steps = 0;
        for (int i = back; i >= 0 && _key[static_cast<std::size_t>(i)] >= low; i = _previous[static_cast<std::size_t>(i)]) {
            if (++steps > kWalkLimit && walkTooLong()) {
                return findInTree(Triangle{{a, b, c}, lo, hi}, visit);
            }
            if (inBox(i, lo, hi) && visit(i)) {
                return true;
            }
        }
        for (int i = forward; i >= 0 && _key[static_cast<std::size_t>(i)] <= high; i = _next[static_cast<std::size_t>(i)]) {
            if (++steps > kWalkLimit && walkTooLong()) {
                return findInTree(Triangle{{a, b, c}, lo, hi}, visit);
            }
            if (inBox(i, lo, hi) && visit(i)) {
                return true;
            }
        }
        return false;
    }

private:
    static constexpr int kWalkLimit = 96;
    // The tree is built once the walks' steps beyond kWalkLimit add up to this many per point
    // present, about what building it costs: never for sets whose walks stay short on the whole
    // (a convex ring), soon for those whose walks are mostly long (a star).
    static constexpr std::size_t kTreeStepsPerPoint = 16;

    // For each step of a walk beyond kWalkLimit: whether to go on in the tree instead.
    bool walkTooLong() noexcept { return _tree || ++_stepsBeyondLimit > kTreeStepsPerPoint * _presentCount; }

    /// A query: a counter-clockwise triangle and its bounding box.
    struct Triangle {
        glm::dvec2 corners[3];
        glm::dvec2 lo, hi;

        /// Whether the box lo..hi (within the triangle's box) lies wholly outside one of the
        /// triangle's edges, by more than rounding could make up: then no point of it is in the
        /// triangle (a thin triangle's box holds far more points than the triangle).
        bool missesBox(const glm::dvec2& boxLo, const glm::dvec2& boxHi) const noexcept
        {
            for (int k = 0; k < 3; ++k) {
                const glm::dvec2& p = corners[k];
                const glm::dvec2 edge = corners[(k + 1) % 3] - p;
                // The box's corner farthest to the left of the edge (inside is left).
                const glm::dvec2 r(edge.y < 0.0 ? boxHi.x : boxLo.x, edge.x > 0.0 ? boxHi.y : boxLo.y);
                const double left = edge.x * (r.y - p.y);
                const double right = edge.y * (r.x - p.x);
                if (left - right < -1e-12 * (std::abs(left) + std::abs(right))) {
                    return true;
                }
            }
            return false;
        }
    };

    /// A static k-d tree over points, with removal; see findIn.
    class Tree {
    public:
        Tree(std::span<const glm::dvec2> points, std::span<const int> present);
        void remove(int id) noexcept;

        /// Calls visit(id) for the points present in the triangle's box whose k-d cell the
        /// triangle may meet, until visit returns true.
        template <typename Visit>
        bool findIn(const Triangle& triangle, Visit&& visit) const
        {
            const glm::dvec2& lo = triangle.lo;
            const glm::dvec2& hi = triangle.hi;
            struct Range {
                int first, last, axis;
                glm::dvec2 cellLo, cellHi; // the subtree's cell, within the triangle's box
            };
            Range stack[96]; // the depth is at most log2(n) + 1
            int top = 0;
            if (!_ids.empty()) {
                stack[top++] = {0, static_cast<int>(_ids.size()) - 1, 0, lo, hi};
            }
            while (top > 0) {
                const Range range = stack[--top];
                if (triangle.missesBox(range.cellLo, range.cellHi)) {
                    continue;
                }
                if (range.last - range.first < kLeafSize) {
                    if (_count[static_cast<std::size_t>(range.first)] == 0) {
                        continue;
                    }
                    for (int slot = range.first; slot <= range.last; ++slot) {
                        if (present(slot) && inBox(slot, lo, hi) && visit(_ids[static_cast<std::size_t>(slot)])) {
                            return true;
                        }
                    }
                    continue;
                }
                const int middle = range.first + (range.last - range.first) / 2;
                if (_count[static_cast<std::size_t>(middle)] == 0) {
                    continue;
                }
                if (present(middle) && inBox(middle, lo, hi) && visit(_ids[static_cast<std::size_t>(middle)])) {
                    return true;
                }
                const double split = _points[static_cast<std::size_t>(middle)][range.axis];
                if (lo[range.axis] <= split) {
                    glm::dvec2 cellHi = range.cellHi;
                    cellHi[range.axis] = std::min(cellHi[range.axis], split);
                    stack[top++] = {range.first, middle - 1, 1 - range.axis, range.cellLo, cellHi};
                }
                if (hi[range.axis] >= split) {
                    glm::dvec2 cellLo = range.cellLo;
                    cellLo[range.axis] = std::max(cellLo[range.axis], split);
                    stack[top++] = {middle + 1, range.last, 1 - range.axis, cellLo, range.cellHi};
                }
            }
            return false;
        }

    private:
        static constexpr int kLeafSize = 8;
        bool present(int slot) const noexcept { return _present[static_cast<std::size_t>(slot)] != 0; }
        bool inBox(int slot, const glm::dvec2& lo, const glm::dvec2& hi) const noexcept
        {
            const glm::dvec2& p = _points[static_cast<std::size_t>(slot)];
            return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y;
        }

        std::vector<glm::dvec2> _points; // in tree order: each subtree's median at its middle slot
        std::vector<int> _ids;           // in tree order
        std::vector<std::uint8_t> _present;
        // Points present per subtree: at its middle slot, or at its first slot for a leaf (no
        // inner subtree has that slot as its middle).
        std::vector<std::int32_t> _count;
        std::vector<int> _slotOf; // by id; -1 for ids not in the tree
    };

    template <typename Visit>
    bool findInTree(const Triangle& triangle, Visit&& visit)
    {
        if (!_tree) {
            buildTree();
        }
        return _tree->findIn(triangle, visit);
    }
    void buildTree();

    std::uint32_t key(const glm::dvec2& p) const noexcept;
    /// id when present; otherwise the first point present following links (_previous or _next)
    /// from it, -1 for none, the links on the way pointed straight at it (an absent point's links
    /// lead to the points that were present next to it when it left, or was left out).
    int presentFrom(std::vector<int>& links, int id) noexcept
    {
        int found = id;
        while (found >= 0 && _present[static_cast<std::size_t>(found)] == 0) {
            found = links[static_cast<std::size_t>(found)];
        }
        for (int i = id; i != found;) {
            const int following = links[static_cast<std::size_t>(i)];
            links[static_cast<std::size_t>(i)] = found;
            i = following;
        }
        return found;
    }
    bool inBox(int id, const glm::dvec2& lo, const glm::dvec2& hi) const noexcept
    {
        const glm::dvec2& p = _points[static_cast<std::size_t>(id)];
        return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y;
    }

    std::span<const glm::dvec2> _points;
    glm::dvec2 _origin{0.0};
    glm::dvec2 _scale{0.0};
    std::vector<std::uint32_t> _key; // by id
    // By id: the point present before in Z order, -1 for none; for a point not present, the one
    // present before it when it left, or was left out (see presentFrom).
    std::vector<int> _previous;
    std::vector<int> _next;
    std::vector<std::uint8_t> _present; // by id
    std::vector<std::uint64_t> _order; // reset's, kept for its memory
    std::vector<std::uint64_t> _orderScratch;
    std::size_t _presentCount = 0;
    std::size_t _stepsBeyondLimit = 0; // by all walks
    std::unique_ptr<Tree> _tree;
};

} // namespace orbis::detail
