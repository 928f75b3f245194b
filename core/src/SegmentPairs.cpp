#include "SegmentPairs.h"

#include "RadixSort.h"
#include "RobustPredicates.h"

#include <glm/geometric.hpp>

#include <bit>

namespace orbis::detail {

namespace {

/// The sweep's order of points: by x, then by y (a line turned a hair clockwise from vertical).
bool sweepsFirst(const glm::dvec2& a, const glm::dvec2& b) noexcept
{
    return a.x < b.x || (a.x == b.x && a.y < b.y);
}

/// Bits of a double that sort as the double does (-0 as +0).
std::uint64_t orderedBits(double value) noexcept
{
    const auto bits = std::bit_cast<std::uint64_t>(value + 0.0);
    return (bits >> 63) != 0 ? ~bits : bits | (std::uint64_t{1} << 63);
}

struct Vertex {
    std::uint64_t key;
    std::uint32_t segment;
};

} // namespace

bool meetOnlyAtSharedVertices(std::span<const glm::dvec2> from, std::span<const glm::dvec2> to,
                              std::span<const int> fromVertex, std::span<const int> toVertex)
{
    const std::size_t count = from.size();
    // Each segment's ends in the sweep's order, and the segment ending at each vertex.
    std::vector<glm::dvec2> first(count), last(count);
    std::vector<std::uint32_t> ending(static_cast<std::size_t>(*std::max_element(toVertex.begin(), toVertex.end())) + 1);
    for (std::size_t k = 0; k < count; ++k) {
        if (from[k] == to[k]) {
            return false;
        }
        const bool forward = sweepsFirst(from[k], to[k]);
        first[k] = forward ? from[k] : to[k];
        last[k] = forward ? to[k] : from[k];
        ending[static_cast<std::size_t>(toVertex[k])] = static_cast<std::uint32_t>(k);
    }
    // The vertices in the sweep's order, each as the segment starting there: by x in a radix
    // sort (a comparison sort's branches on the coordinates took most of the sweep's time), then
    // by y where x is the same.
    std::vector<Vertex> vertices(count);
    for (std::size_t k = 0; k < count; ++k) {
        vertices[k] = {orderedBits(from[k].x), static_cast<std::uint32_t>(k)};
    }
    std::vector<Vertex> scratch(vertices.size());
    radixSort(vertices, scratch, [](const Vertex& v) { return v.key; });
    for (std::size_t run = 0; run < count;) {
        std::size_t end = run + 1;
        while (end < count && vertices[end].key == vertices[run].key) {
            ++end;
        }
        if (end - run > 1) {
            std::sort(vertices.begin() + static_cast<std::ptrdiff_t>(run), vertices.begin() + static_cast<std::ptrdiff_t>(end),
                      [&](const Vertex& a, const Vertex& b) { return from[a.segment].y < from[b.segment].y; });
        }
        run = end;
    }

    // The segments the line crosses, from below to above. Only a segment joining the line is
    // compared with those there, at its first end; until a first meeting of two segments, the
    // order of those on the line does not change.
    auto below = [&](std::uint32_t a, std::uint32_t b) {
        if (a == b) {
            return false;
        }
        const bool aLater = !sweepsFirst(first[a], first[b]);
        const std::uint32_t earlier = aLater ? b : a;
        const std::uint32_t later = aLater ? a : b;
        // Two joining the line at one vertex (equal, which the exact test would take long to say):
        // by where they go.
        int side = first[later] == first[earlier] ? 0 : orient2d(first[earlier], last[earlier], first[later]);
        if (side == 0) {
            side = orient2d(first[earlier], last[earlier], last[later]);
        }
        if (side == 0) {
            return a < b; // on one line: the meeting is found when they are compared as neighbours
        }
        return aLater ? side < 0 : side > 0;
    };
    std::vector<std::uint32_t> line; // sorted by below: a line crosses few segments of most rings
    auto place = [&](std::uint32_t segment) {
        return std::lower_bound(line.begin(), line.end(), segment, below);
    };

    // Whether two segments meet anywhere but at a vertex they share.
    auto meet = [&](std::uint32_t a, std::uint32_t b) {
        const bool aThenB = toVertex[a] == fromVertex[b];
        if (!aThenB && toVertex[b] != fromVertex[a]) {
            return segmentsIntersect(from[a], to[a], from[b], to[b]);
        }
        // Neighbours along a ring: a problem only where one folds back along the other.
        const glm::dvec2& shared = aThenB ? to[a] : to[b];
        const glm::dvec2& aOther = aThenB ? from[a] : to[a];
        const glm::dvec2& bOther = aThenB ? to[b] : from[b];
        return orient2d(shared, aOther, bOther) == 0 && glm::dot(aOther - shared, bOther - shared) > 0.0;
    };

    for (std::size_t v = 0; v < count; ++v) {
        if (v > 0 && from[vertices[v - 1].segment] == from[vertices[v].segment]) {
            return false; // two vertices at one position
        }
        // The segment arriving here and the one leaving: those whose last end this is leave the
        // line before those whose first end it is join it.
        const std::uint32_t leaving = vertices[v].segment;
        const std::uint32_t arriving = ending[static_cast<std::size_t>(fromVertex[leaving])];
        const glm::dvec2& here = from[leaving];
        for (const std::uint32_t segment : {arriving, leaving}) {
            if (last[segment] != here) {
                continue;
            }
            const auto at = place(segment);
            if (at == line.end() || *at != segment) {
                return false; // the order on the line broke: segments met unseen
            }
            if (at != line.begin() && at + 1 != line.end() && meet(*(at - 1), *(at + 1))) {
                return false;
            }
            line.erase(at);
        }
        for (const std::uint32_t segment : {arriving, leaving}) {
            if (first[segment] != here) {
                continue;
            }
            const auto at = line.insert(place(segment), segment);
            if ((at != line.begin() && meet(*(at - 1), segment)) || (at + 1 != line.end() && meet(segment, *(at + 1)))) {
                return false;
            }
        }
    }
    return true;
}

} // namespace orbis::detail
