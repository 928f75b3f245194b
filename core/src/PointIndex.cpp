#include "PointIndex.h"

#include "RadixSort.h"

#include <glm/common.hpp>

#include <algorithm>
#include <cmath>

namespace orbis::detail {

namespace {

// Spreads the 16 bits of v to the even bits of the result.
std::uint32_t spread(std::uint32_t v) noexcept
{
    v = (v | (v << 8)) & 0x00ff00ffu;
    v = (v | (v << 4)) & 0x0f0f0f0fu;
    v = (v | (v << 2)) & 0x33333333u;
    v = (v | (v << 1)) & 0x55555555u;
    return v;
}

} // namespace

PointIndex::PointIndex() = default;

void PointIndex::reset(std::span<const glm::dvec2> points, std::span<const int> ids, std::span<const std::uint8_t> indexed)
{
    _points = points;
    _presentCount = 0;
    _stepsBeyondLimit = 0;
    _tree.reset();
    _present.assign(points.size(), 0);
    if (std::none_of(ids.begin(), ids.end(), [&](int id) { return indexed[static_cast<std::size_t>(id)] != 0; })) {
        return; // nothing to find (a convex ring's ears): no order to build
    }
    glm::dvec2 lo(HUGE_VAL);
    glm::dvec2 hi(-HUGE_VAL);
    for (const int id : ids) {
        lo = glm::min(lo, points[static_cast<std::size_t>(id)]);
        hi = glm::max(hi, points[static_cast<std::size_t>(id)]);
    }
    _origin = lo;
    for (int axis = 0; axis < 2; ++axis) {
        const double extent = hi[axis] - lo[axis];
        _scale[axis] = extent > 0.0 && std::isfinite(extent) ? 65535.0 / extent : 0.0;
    }
    _key.assign(points.size(), 0);
    _previous.assign(points.size(), -1);
    _next.assign(points.size(), -1);
    std::vector<std::uint64_t>& order = _order; // key, then id
    order.clear();
    for (const int id : ids) {
        const auto i = static_cast<std::size_t>(id);
        _key[i] = key(points[i]);
        if (indexed[i] != 0) {
            _present[i] = 1;
            ++_presentCount;
        }
        order.push_back((std::uint64_t{_key[i]} << 32) | static_cast<std::uint32_t>(id));
    }
    radixSort(order, _orderScratch, [](std::uint64_t entry) { return entry; }, 32); // by key; ties as given
    // Each point linked to the points present before and after it.
    int before = -1;
    for (const std::uint64_t entry : order) {
        const auto id = static_cast<std::size_t>(entry & 0xffffffffu);
        _previous[id] = before;
        if (_present[id] != 0) {
            before = static_cast<int>(id);
        }
    }
    int after = -1;
    for (auto entry = order.rbegin(); entry != order.rend(); ++entry) {
        const auto id = static_cast<std::size_t>(*entry & 0xffffffffu);
        _next[id] = after;
        if (_present[id] != 0) {
            after = static_cast<int>(id);
        }
    }
}

PointIndex::~PointIndex() = default;

std::uint32_t PointIndex::key(const glm::dvec2& p) const noexcept
{
    // Quantised monotonically (a larger coordinate never gets a smaller cell), so that a box's
    // points have keys between its corners' keys; coordinates outside the set's box are clamped.
    auto cell = [&](int axis) {
        const double scaled = std::floor((p[axis] - _origin[axis]) * _scale[axis]);
        return static_cast<std::uint32_t>(std::clamp(scaled, 0.0, 65535.0));
    };
    return (spread(cell(0)) << 1) | spread(cell(1));
}

void PointIndex::remove(int id) noexcept
{
    const auto i = static_cast<std::size_t>(id);
    if (id < 0 || i >= _present.size() || _present[i] == 0) {
        return;
    }
    _present[i] = 0;
    --_presentCount;
    if (_tree) {
        _tree->remove(id);
    }
    const int before = _previous[i];
    const int after = _next[i];
    if (before >= 0) {
        _next[static_cast<std::size_t>(before)] = after;
    }
    if (after >= 0) {
        _previous[static_cast<std::size_t>(after)] = before;
    }
    // Its own links stay: walks that start from it follow them to the points present (presentFrom).
}

void PointIndex::buildTree()
{
    std::vector<int> present;
    for (std::size_t id = 0; id < _present.size(); ++id) {
        if (_present[id] != 0) {
            present.push_back(static_cast<int>(id));
        }
    }
    _tree = std::make_unique<Tree>(_points, present);
}

namespace {

struct Entry {
    glm::dvec2 point;
    int id;
};

} // namespace

PointIndex::Tree::Tree(std::span<const glm::dvec2> points, std::span<const int> present)
{
    std::vector<Entry> entries;
    entries.reserve(present.size());
    int largest = -1;
    for (const int id : present) {
        entries.push_back({points[static_cast<std::size_t>(id)], id});
        largest = std::max(largest, id);
    }
    _count.assign(entries.size(), 0);
    // Each subtree's middle slot gets the median along the subtree's axis, smaller ones before it.
    auto build = [&](auto&& self, int first, int last, int axis) -> void {
        if (last - first < kLeafSize) {
            _count[static_cast<std::size_t>(first)] = last - first + 1;
            return;
        }
        const int middle = first + (last - first) / 2;
        _count[static_cast<std::size_t>(middle)] = last - first + 1;
        std::nth_element(entries.begin() + first, entries.begin() + middle, entries.begin() + last + 1,
                         [axis](const Entry& a, const Entry& b) { return a.point[axis] < b.point[axis]; });
        self(self, first, middle - 1, 1 - axis);
        self(self, middle + 1, last, 1 - axis);
    };
    if (!entries.empty()) {
        build(build, 0, static_cast<int>(entries.size()) - 1, 0);
    }
    _slotOf.assign(static_cast<std::size_t>(largest + 1), -1);
    for (std::size_t slot = 0; slot < entries.size(); ++slot) {
        _points.push_back(entries[slot].point);
        _ids.push_back(entries[slot].id);
        _slotOf[static_cast<std::size_t>(entries[slot].id)] = static_cast<int>(slot);
    }
    _present.assign(entries.size(), 1);
}

void PointIndex::Tree::remove(int id) noexcept
{
    if (id < 0 || static_cast<std::size_t>(id) >= _slotOf.size() || _slotOf[static_cast<std::size_t>(id)] < 0) {
        return;
    }
    const int slot = _slotOf[static_cast<std::size_t>(id)];
    if (!present(slot)) {
        return;
    }
    _present[static_cast<std::size_t>(slot)] = 0;
    int first = 0;
    int last = static_cast<int>(_ids.size()) - 1;
    while (true) {
        if (last - first < kLeafSize) {
            --_count[static_cast<std::size_t>(first)];
            return;
        }
        const int middle = first + (last - first) / 2;
        --_count[static_cast<std::size_t>(middle)];
        if (slot == middle) {
            return;
        }
        if (slot < middle) {
            last = middle - 1;
        } else {
            first = middle + 1;
        }
    }
}

} // namespace orbis::detail
