#include "orbis/core/EarClipping.h"

#include "PointIndex.h"
#include "RobustPredicates.h"
#include "SegmentPairs.h"

#include "orbis/core/Error.h"
#include "orbis/core/PolygonCleanup.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <unordered_map>

namespace orbis {

namespace {

using detail::inClosedTriangle;
using detail::onSegment;
using detail::orient2d;
using detail::segmentsIntersect;

// Ears thinner than this (triangleQuality) are clipped only when no other ear is left.
constexpr double kSliverQuality = 1e-9;

// How full a triangle is: twice its area over its longest edge squared, about the sine of its
// smallest angle; 0 for one with no extent.
double triangleQuality(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) noexcept
{
    const glm::dvec2 ab = b - a;
    const glm::dvec2 bc = c - b;
    const glm::dvec2 ca = a - c;
    const double longest = std::max({glm::dot(ab, ab), glm::dot(bc, bc), glm::dot(ca, ca)});
    return longest > 0.0 ? std::abs(ab.x * bc.y - ab.y * bc.x) / longest : 0.0;
}

struct Node {
    glm::dvec2 p;
    std::uint32_t index = 0;  // output index: into the concatenated input rings
    std::uint32_t ring = 0;   // for messages
    std::uint32_t vertex = 0; // for messages: the vertex number in the input ring
    int prev = -1;
    int next = -1;
    bool removed = false;
    bool twin = false; // another vertex has its position (a touch, a bridge's copy)
};

enum class Location { Inside, Outside, Boundary };

// Whether the closed ring of n points at(k) (k taken modulo n) is strictly convex and winds once
// round: every turn goes one way (so the edges' direction turns monotonically, by less than half a
// turn at a vertex) and the edges' x changes sign twice round it. Such a ring touches nothing. The
// turns' sign (1 counter-clockwise, -1 clockwise), or 0 when it is not such a ring.
template <typename At>
int convexTurn(std::size_t n, At&& at)
{
    int turn = 0;
    int xChanges = 0;
    double firstDx = 0.0;
    double lastDx = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
        const int o = orient2d(at(k + n - 1), at(k), at(k + 1));
        if (o == 0 || (turn != 0 && o != turn)) {
            return 0;
        }
        turn = o;
        const double dx = at(k + 1).x - at(k).x;
        if (dx != 0.0) {
            if (lastDx == 0.0) {
                firstDx = dx;
            } else if ((dx > 0.0) != (lastDx > 0.0)) {
                ++xChanges;
            }
            lastDx = dx;
        }
    }
    xChanges += (firstDx > 0.0) != (lastDx > 0.0) ? 1 : 0; // round the end of the ring
    return xChanges <= 2 ? turn : 0;
}

// The quarter round a point lies in, seen from c: 0 for angles in [0, 90) degrees, 1 for [90, 180),
// 2 for [180, 270), 3 for [270, 360); -1 at c. Exact: comparisons only.
int quadrantAround(const glm::dvec2& c, const glm::dvec2& p) noexcept
{
    if (p.x > c.x && p.y >= c.y) {
        return 0;
    }
    if (p.x <= c.x && p.y > c.y) {
        return 1;
    }
    if (p.x < c.x && p.y <= c.y) {
        return 2;
    }
    return p.x >= c.x && p.y < c.y ? 3 : -1;
}

std::string describeEdge(const Node& from, const Node& to)
{
    std::ostringstream out;
    out << "the edge of ring " << from.ring << " from vertex " << from.vertex << " to vertex " << to.vertex;
    return out.str();
}

// Vertices queued by a class of priority (0 first), first in first out within a class: pushing
// and popping take constant time, where a binary heap of all the candidate ears took a quarter of
// the time of triangulating a ring. A polygon uses few of the classes: buckets are made for those.
class ClassQueue {
public:
    static constexpr std::size_t kClasses = 4096;

    bool empty() const noexcept { return _size == 0; }

    // Empties the queue, keeping its buckets' memory for the next polygon.
    void clear() noexcept
    {
        for (std::size_t b = 0; b < _bucketsUsed; ++b) {
            _bucketOf[_buckets[b].priorityClass] = 0;
            _nonEmpty[_buckets[b].priorityClass / 64] = 0;
            _buckets[b].ids.clear();
            _buckets[b].read = 0;
        }
        _bucketsUsed = 0;
        _size = 0;
    }

    void push(std::uint32_t priorityClass, int id)
    {
        std::uint16_t& number = _bucketOf[priorityClass];
        if (number == 0) {
            if (_bucketsUsed == _buckets.size()) {
                _buckets.emplace_back();
            }
            _buckets[_bucketsUsed].priorityClass = priorityClass;
            number = static_cast<std::uint16_t>(++_bucketsUsed);
        }
        Bucket& bucket = _buckets[number - 1u];
        if (bucket.ids.size() == bucket.read) {
            _nonEmpty[priorityClass / 64] |= std::uint64_t{1} << (priorityClass % 64);
        }
        bucket.ids.push_back(id);
        ++_size;
    }

    // The first id of the lowest class; the queue must not be empty.
    std::pair<std::uint32_t, int> pop()
    {
        std::size_t word = 0;
        while (_nonEmpty[word] == 0) {
            ++word;
        }
        const auto priorityClass = static_cast<std::uint32_t>(64 * word + static_cast<std::size_t>(std::countr_zero(_nonEmpty[word])));
        Bucket& bucket = _buckets[_bucketOf[priorityClass] - 1u];
        const int id = bucket.ids[bucket.read++];
        if (bucket.read == bucket.ids.size()) {
            bucket.ids.clear();
            bucket.read = 0;
            _nonEmpty[word] &= ~(std::uint64_t{1} << (priorityClass % 64));
        }
        --_size;
        return {priorityClass, id};
    }

private:
    struct Bucket {
        std::vector<int> ids;
        std::size_t read = 0;
        std::uint32_t priorityClass = 0;
    };
    std::vector<Bucket> _buckets; // the first _bucketsUsed in use
    std::size_t _bucketsUsed = 0;
    std::array<std::uint16_t, kClasses> _bucketOf{}; // per class: its bucket's number from 1, 0 for none yet
    std::array<std::uint64_t, kClasses / 64> _nonEmpty{};
    std::size_t _size = 0;
};

class EarClipper {
public:
    // One clipper serves polygon after polygon on a thread, its vectors keeping their memory: a
    // polygon of a few vertices (a building) spent most of its time in some 30 allocations.
    PolygonTriangles run(std::span<const std::vector<glm::dvec2>> rings, std::string_view name, double repairRelativeArea,
                         std::vector<LeftOutHole>* leftOutHoles)
    {
        _name = name;
        _repairRelativeArea = repairRelativeArea;
        _leftOutHoles = leftOutHoles;
        _holesLeftOut = 0;
        _outerArea = 0.0;
        _repairedArea = 0.0;
        _nodes.clear();
        _cycles.clear();
        _ringNumbers.clear();
        _ringTouchesItself = false;
        _edges.reset();
        _ringOf.clear();
        _start = -1;
        _remaining = 0;
        PolygonTriangles result;
        if (rings.size() == 1 && triangulateSmallConvex(rings[0], result)) {
            return result;
        }
        if (!prepareRings(rings, result)) {
            return result;
        }
        // A convex ring without holes touches nothing: its edges need no check (a fifth of a round
        // ring's time), and no vertex can be in an ear's way.
        const bool convex = _cycles.size() == 1 && convexTurn(_nodes.size(), [&](std::size_t k) -> const glm::dvec2& {
                                return _nodes[k % _nodes.size()].p;
                            }) != 0;
        // So does a strictly star-shaped ring without holes (starShaped), whose ears need no search
        // either.
        _starShaped = !convex && _cycles.size() == 1 && starShaped();
        const bool touchesNothing = convex || _starShaped;
        for (Split split = touchesNothing ? Split::Done : splitTouchingEdges(); split != Split::Done; split = splitTouchingEdges()) {
            if (split == Split::RepairedVertex) {
                ++result.repairedVertices;
                --result.vertexCount;
            }
        }
        for (std::size_t removed = touchesNothing ? 0 : removeInvertedLobe(); removed > 0; removed = removeInvertedLobe()) {
            result.repairedVertices += removed;
            result.vertexCount -= std::min(removed, result.vertexCount);
        }
        result.repairedArea = _repairedArea;
        if (_cycles.size() > 1) {
            indexEdges();
            checkHoles();
            bridgeHoles();
        }
        result.holeCount -= _holesLeftOut;
        _start = _cycles[0];
        clip(result.indices);
        flipSlivers(result.indices);
        return result;
    }

    // The vertices its memory holds now.
    std::size_t capacity() const noexcept { return _nodes.capacity(); }

private:
    [[noreturn]] void fail(const std::string& what) const
    {
        throw Error("polygon '" + std::string(_name) + "': " + what);
    }

    // --- Small convex rings ----------------------------------------------------------------

    // A small strictly convex ring (a building, a parcel; convexTurn), triangulated at once: every
    // vertex of one is an ear, so it needs neither the check of its edges nor the queue of ears. Its
    // triangles zig-zag across it from both ends (fuller than a fan's). False, with nothing done,
    // for any other ring: one not strictly convex or winding more than once round, with more than
    // kSmallPolygon vertices or a coordinate not finite, or a triangle thinner than a sliver.
    bool triangulateSmallConvex(const std::vector<glm::dvec2>& ring, PolygonTriangles& result)
    {
        std::array<std::uint32_t, kSmallPolygon> kept; // consecutive repeats and the closing vertex left out
        std::size_t n = 0;
        for (std::size_t i = 0; i < ring.size(); ++i) {
            if (!std::isfinite(ring[i].x) || !std::isfinite(ring[i].y) || n == kSmallPolygon) {
                return false;
            }
            if (n == 0 || ring[kept[n - 1]] != ring[i]) {
                kept[n++] = static_cast<std::uint32_t>(i);
            }
        }
        while (n > 1 && ring[kept[n - 1]] == ring[kept[0]]) {
            --n;
        }
        if (n < 3) {
            return false;
        }
        auto at = [&](std::size_t k) -> const glm::dvec2& { return ring[kept[k % n]]; };
        const int turn = convexTurn(n, at);
        if (turn == 0) {
            return false;
        }
        if (turn < 0) {
            std::reverse(kept.begin(), kept.begin() + static_cast<std::ptrdiff_t>(n)); // counter-clockwise
        }
        std::vector<std::uint32_t>& indices = result.indices;
        indices.reserve(3 * (n - 2));
        std::size_t low = 0;
        std::size_t high = n - 1;
        for (bool fromLow = true; high - low >= 2; fromLow = !fromLow) {
            // (low, low + 1, high), then (low, high - 1, high) with low one on: corners in the ring's
            // order, so counter-clockwise.
            const std::array<std::size_t, 3> t = fromLow ? std::array<std::size_t, 3>{low, low + 1, high}
                                                         : std::array<std::size_t, 3>{low, high - 1, high};
            if (!(triangleQuality(at(t[0]), at(t[1]), at(t[2])) >= kSliverQuality)) {
                indices.clear();
                return false;
            }
            for (const std::size_t k : t) {
                indices.push_back(kept[k]);
            }
            if (fromLow) {
                ++low;
            } else {
                --high;
            }
        }
        result.vertexCount = n;
        return true;
    }

    // --- Rings -------------------------------------------------------------------------------

    // False when the outer ring has no area: nothing to triangulate.
    bool prepareRings(std::span<const std::vector<glm::dvec2>> rings, PolygonTriangles& result)
    {
        if (rings.empty()) {
            fail("has no rings");
        }
        std::size_t total = 0;
        for (const std::vector<glm::dvec2>& ring : rings) {
            total += ring.size();
        }
        _nodes.reserve(total + total / 8); // room for the vertices that touching edges add
        std::size_t offset = 0;
        std::vector<Node>& kept = _kept;
        std::vector<glm::dvec2>& points = _keptPoints;
        for (std::size_t r = 0; r < rings.size(); ++r) {
            const std::vector<glm::dvec2>& ring = rings[r];
            kept.clear();
            kept.reserve(ring.size());
            for (std::size_t i = 0; i < ring.size(); ++i) {
                const glm::dvec2& p = ring[i];
                if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
                    fail("vertex " + std::to_string(i) + " of ring " + std::to_string(r) + " is not finite");
                }
                if (offset + i > std::numeric_limits<std::uint32_t>::max()) {
                    fail("has more vertices than 32-bit indices can address");
                }
                if (!kept.empty() && kept.back().p == p) {
                    continue;
                }
                // Written in place: a Node built aside and copied in is read back wider than it was
                // written, which stalls the copy (a fifth of a small polygon's preparation).
                Node& n = kept.emplace_back();
                n.p = p;
                n.index = static_cast<std::uint32_t>(offset + i);
                n.ring = static_cast<std::uint32_t>(r);
                n.vertex = static_cast<std::uint32_t>(i);
            }
            while (kept.size() > 1 && kept.back().p == kept.front().p) {
                kept.pop_back();
            }
            offset += ring.size();

            points.clear();
            for (const Node& n : kept) {
                points.push_back(n.p);
            }
            const double area = kept.size() >= 3 ? signedArea(points) : 0.0;
            if (r == 0 && kept.size() < 3) {
                result.vertexCount = kept.size();
                return false;
            }
            if (r == 0 && area == 0.0) {
                // All on one line, or a ring that crosses itself (validation will say so) or
                // folds back on itself (clipping will find nothing to clip).
                bool collinear = true;
                for (const Node& n : kept) {
                    collinear = collinear && orient2d(kept[0].p, kept[1].p, n.p) == 0;
                }
                if (collinear) {
                    result.vertexCount = kept.size();
                    return false;
                }
            }
            if (r == 0) {
                _outerArea = std::abs(area);
            }
            if (r != 0 && (kept.size() < 3 || area == 0.0)) {
                continue; // a hole with no area removes nothing
            }
            // Outer ring counter-clockwise, holes clockwise.
            if ((r == 0) != (area > 0.0)) {
                std::reverse(kept.begin(), kept.end());
            }
            const int first = static_cast<int>(_nodes.size());
            const int count = static_cast<int>(kept.size());
            for (int i = 0; i < count; ++i) {
                Node& n = _nodes.emplace_back(kept[static_cast<std::size_t>(i)]);
                n.prev = first + (i + count - 1) % count;
                n.next = first + (i + 1) % count;
            }
            _cycles.push_back(first);
            _ringNumbers.push_back(r);
            result.vertexCount += kept.size();
            if (r != 0) {
                ++result.holeCount;
            }
        }
        return true;
    }

    // Whether the outer ring (counter-clockwise, with no holes) is strictly star-shaped: round its
    // vertices' mean, or, for a ring of kKernelSearchVertices or more, round the centre of the
    // extreme points of its kernel (where every edge is seen counter-clockwise), found by linear
    // programming. The centre is kept in _centre. A round coast or a star is such a ring; few
    // countries are.
    bool starShaped()
    {
        glm::dvec2 sum(0.0);
        for (const Node& n : _nodes) {
            sum += n.p;
        }
        const glm::dvec2 mean = sum / static_cast<double>(_nodes.size());
        if (starShapedRound(mean)) {
            return true;
        }
        if (_nodes.size() < kKernelSearchVertices) {
            return false;
        }
        const std::optional<glm::dvec2> centre = kernelCentre(mean);
        return centre && starShapedRound(*centre);
    }

    // Whether each edge of the outer ring turns strictly counter-clockwise round c, by less than
    // half a turn, and all of them once round together (the quarters the vertices lie in, seen
    // from c, advance by four): then a ray from c meets the ring once, so it touches nothing, and
    // an ear needs no search (earBlocker). Exact; keeps c as _centre when true.
    bool starShapedRound(const glm::dvec2& c)
    {
        int quarters = 0;
        int i = _cycles[0];
        int quadrant = quadrantAround(c, pos(i));
        do {
            const int next = node(i).next;
            const int following = quadrantAround(c, pos(next));
            if (quadrant < 0 || following < 0 || orient2d(c, pos(i), pos(next)) <= 0) {
                return false;
            }
            quarters += (following - quadrant + 4) % 4; // 0 to 2: each step is less than half a turn
            quadrant = following;
            i = next;
        } while (i != _cycles[0] && quarters <= 4);
        if (quarters != 4 || i != _cycles[0]) {
            return false;
        }
        _centre = c;
        return true;
    }

    // The mean of the westmost, eastmost, southmost and northmost points of the outer ring's
    // kernel (the points left of every edge), which lies inside it where it has an inside; none
    // where the search finds it empty. Seidel's randomized linear programming, in floating point
    // (starShapedRound checks the answer exactly), relative to `origin`, in expected linear time.
    std::optional<glm::dvec2> kernelCentre(const glm::dvec2& origin)
    {
        std::vector<HalfPlane>& planes = _halfPlanes;
        planes.clear();
        glm::dvec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        forEachInCycle(_cycles[0], [&](int i) {
            const glm::dvec2 p = pos(i) - origin;
            const glm::dvec2 q = pos(node(i).next) - origin;
            const glm::dvec2 normal(p.y - q.y, q.x - p.x); // the edge turned a quarter to its left
            planes.push_back({normal, glm::dot(normal, p)});
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        });
        // A fixed order, so that a polygon always gets the same triangles.
        std::shuffle(planes.begin(), planes.end(), std::mt19937(static_cast<std::uint32_t>(planes.size())));
        const HalfPlane box[4] = {{{1.0, 0.0}, lo.x}, {{-1.0, 0.0}, -hi.x}, {{0.0, 1.0}, lo.y}, {{0.0, -1.0}, -hi.y}};

        // The point of the kernel within the ring's box farthest in `direction`.
        auto farthest = [&](const glm::dvec2& direction) -> std::optional<glm::dvec2> {
            glm::dvec2 x(direction.x > 0.0 ? hi.x : lo.x, direction.y > 0.0 ? hi.y : lo.y);
            for (std::size_t k = 0; k < planes.size(); ++k) {
                const HalfPlane& h = planes[k];
                if (glm::dot(h.normal, x) >= h.offset) {
                    continue;
                }
                // The best point moves onto this plane's line: the best of the line within the others.
                const double lengthSquared = glm::dot(h.normal, h.normal);
                const glm::dvec2 onLine = h.normal * (h.offset / lengthSquared);
                const glm::dvec2 along(-h.normal.y, h.normal.x);
                double low = -std::numeric_limits<double>::infinity();
                double high = std::numeric_limits<double>::infinity();
                auto limit = [&](const HalfPlane& g) {
                    const double rate = glm::dot(g.normal, along);
                    const double needed = g.offset - glm::dot(g.normal, onLine);
                    if (rate > 0.0) {
                        low = std::max(low, needed / rate);
                    } else if (rate < 0.0) {
                        high = std::min(high, needed / rate);
                    } else if (needed > 0.0) {
                        low = std::numeric_limits<double>::infinity(); // parallel, and outside it
                    }
                };
                for (const HalfPlane& g : box) {
                    limit(g);
                }
                for (std::size_t j = 0; j < k; ++j) {
                    limit(planes[j]);
                }
                if (!(low <= high)) {
                    return std::nullopt;
                }
                x = onLine + along * (glm::dot(direction, along) > 0.0 ? high : low);
            }
            return x;
        };
        glm::dvec2 sum(0.0);
        for (const glm::dvec2 direction : {glm::dvec2(-1.0, 0.0), glm::dvec2(1.0, 0.0), glm::dvec2(0.0, -1.0), glm::dvec2(0.0, 1.0)}) {
            const std::optional<glm::dvec2> x = farthest(direction);
            if (!x) {
                return std::nullopt;
            }
            sum += *x;
        }
        return origin + 0.25 * sum;
    }

    Node& node(int i) { return _nodes[static_cast<std::size_t>(i)]; }
    const Node& node(int i) const { return _nodes[static_cast<std::size_t>(i)]; }
    const glm::dvec2& pos(int i) const { return _nodes[static_cast<std::size_t>(i)].p; }

    template <typename F>
    void forEachInCycle(int start, F&& f) const
    {
        int i = start;
        do {
            f(i);
            i = node(i).next;
        } while (i != start);
    }

    // Marks x and y as twins when they have one position; whether they do.
    bool twins(int x, int y)
    {
        if (pos(x) != pos(y)) {
            return false;
        }
        node(x).twin = true;
        node(y).twin = true;
        return true;
    }

    int insertAfter(int after, const Node& copy)
    {
        Node n = copy;
        const int id = static_cast<int>(_nodes.size());
        n.prev = after;
        n.next = node(after).next;
        _nodes.push_back(n);
        node(n.next).prev = id;
        node(after).next = id;
        return id;
    }

    // --- Validation: crossing edges are errors; a vertex touching another edge is made a vertex
    // of that edge too, so that every touch is between vertices. ----------------------------------

    // What splitTouchingEdges did: Done, or it changed the rings to undo a crossing (call again).
    enum class Split { Done, RepairedVertex, LeftOutHole };

    // Throws on crossings it cannot undo.
    Split splitTouchingEdges()
    {
        std::size_t count = 0;
        for (const int cycle : _cycles) {
            forEachInCycle(cycle, [&](int) { ++count; });
        }
        // By edge, in the order of the rings: the node it starts at, the node it ends at, its cycle,
        // its ends' positions.
        std::vector<int>& edges = _edgeStarts;
        std::vector<int>& edgeEnds = _edgeEnds;
        std::vector<std::size_t>& edgeCycles = _edgeCycles;
        std::vector<glm::dvec2>& starts = _edgeStartPositions;
        std::vector<glm::dvec2>& ends = _edgeEndPositions;
        edges.clear();
        edgeEnds.clear();
        edgeCycles.clear();
        starts.clear();
        ends.clear();
        edges.reserve(count);
        edgeEnds.reserve(count);
        edgeCycles.reserve(count);
        starts.reserve(count);
        ends.reserve(count);
        for (std::size_t k = 0; k < _cycles.size(); ++k) {
            forEachInCycle(_cycles[k], [&](int i) {
                edges.push_back(i);
                edgeEnds.push_back(node(i).next);
                edgeCycles.push_back(k);
                starts.push_back(pos(i));
                ends.push_back(pos(node(i).next));
            });
        }

        std::vector<std::pair<int, int>>& touching = _touching; // an edge (by its first node), a vertex touching it
        touching.clear();
        // Vertex touches the edge from edgeFrom, given which side of the edge it is on.
        auto touches = [&](int vertex, int edgeFrom, int side) {
            const glm::dvec2& a = pos(edgeFrom);
            const glm::dvec2& b = pos(node(edgeFrom).next);
            const glm::dvec2& p = pos(vertex);
            if (side == 0 && p != a && p != b && std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) &&
                std::min(a.y, b.y) <= p.y && p.y <= std::max(a.y, b.y)) {
                touching.emplace_back(edgeFrom, vertex);
            }
        };
        Split changed = Split::Done;
        std::vector<std::pair<std::size_t, std::string>> faulty; // holes to leave out, and why
        std::vector<bool>& isFaulty = _cycleIsFaulty;
        isFaulty.assign(_cycles.size(), false);
        // Judges a pair of edges that may meet.
        auto judge = [&](std::size_t e, std::size_t f) {
            const int a = edges[e];
            const int b = edgeEnds[e];
            const int c = edges[f];
            const int d = edgeEnds[f];
            if (b == c || d == a) {
                return false; // neighbours meet at their shared vertex; folding back is a spike, harmless
            }
            const int o1 = orient2d(starts[e], ends[e], starts[f]);
            const int o2 = orient2d(starts[e], ends[e], ends[f]);
            if (o1 * o2 > 0) {
                return false; // f on one side of e's line: they do not meet (the most pairs)
            }
            if (isFaulty[edgeCycles[e]] || isFaulty[edgeCycles[f]]) {
                return false; // going anyway
            }
            const bool sharePosition = twins(a, c) | twins(a, d) | twins(b, c) | twins(b, d); // all four marked
            if (sharePosition && edgeCycles[e] == edgeCycles[f]) {
                _ringTouchesItself = true;
            }
            const int o3 = orient2d(starts[f], ends[f], starts[e]);
            const int o4 = orient2d(starts[f], ends[f], ends[e]);
            if (o1 * o2 < 0 && o3 * o4 < 0) {
                if (repairCrossing(a, c)) {
                    changed = Split::RepairedVertex;
                    return true;
                }
                const std::string crossing = describeEdge(node(a), node(b)) + " crosses " + describeEdge(node(c), node(d));
                if (_leftOutHoles && (edgeCycles[e] != 0 || edgeCycles[f] != 0)) {
                    // The hole goes, or the smaller of two holes.
                    const std::size_t hole = edgeCycles[e] == 0                           ? edgeCycles[f]
                                             : edgeCycles[f] == 0                         ? edgeCycles[e]
                                             : cycleArea(edgeCycles[e]) <= cycleArea(edgeCycles[f]) ? edgeCycles[e]
                                                                                                     : edgeCycles[f];
                    const std::size_t other = hole == edgeCycles[e] ? edgeCycles[f] : edgeCycles[e];
                    isFaulty[hole] = true;
                    faulty.emplace_back(hole, "it crosses " +
                                                  (other == 0 ? std::string("the outer ring")
                                                              : "hole ring " + std::to_string(_ringNumbers[other])) +
                                                  " (" + crossing + ")");
                    return false; // the others in the same pass: one pass more, not one a hole
                }
                fail(crossing);
            }
            touches(c, a, o1);
            touches(d, a, o2);
            touches(a, c, o3);
            touches(b, c, o4);
            return false;
        };
        // Where the grid would compare many pairs (long edges close together, as in a ring of thin
        // spikes), a sweep proves most rings touch nothing in O(n log n); what it finds is then
        // judged pair by pair after all.
        if (detail::findMeetingSegments(starts, ends, judge, 32 * count) == detail::PairSearch::TooManyPairs &&
            !detail::meetOnlyAtSharedVertices(starts, ends, edges, edgeEnds)) {
            detail::findMeetingSegments(starts, ends, judge);
        }
        if (changed != Split::Done) {
            return changed;
        }
        if (!faulty.empty()) {
            std::sort(faulty.begin(), faulty.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
            for (const auto& [hole, reason] : faulty) { // last first: the numbers before stay
                leaveOutHole(hole, reason);
            }
            return Split::LeftOutHole;
        }
        // Each edge's touching vertices in order along it, inserted after its first node.
        auto along = [&](const std::pair<int, int>& touch) {
            const glm::dvec2& a = pos(touch.first);
            return glm::dot(pos(touch.second) - a, pos(node(touch.first).next) - a);
        };
        std::sort(touching.begin(), touching.end(), [&](const auto& t, const auto& u) {
            return t.first != u.first ? t.first < u.first : along(t) < along(u);
        });
        int after = -1;
        for (std::size_t k = 0; k < touching.size(); ++k) {
            const auto [edge, vertex] = touching[k];
            if (k == 0 || touching[k - 1].first != edge) {
                after = edge;
            }
            if (pos(vertex) != pos(after)) {
                after = insertAfter(after, node(vertex));
                twins(after, vertex);
            }
        }
        _ringTouchesItself = _ringTouchesItself || !touching.empty(); // maybe: a new vertex lies at a vertex of its ring
        return Split::Done;
    }

    // Edges e (from node a) and f (from node c) cross with at most kTwistEdges edges between them:
    // the ring twists in a small loop, as rings simplified with straight edges in longitude and
    // latitude can once drawn with great-circle edges, or quantized ones (TopoJSON) where a step
    // back of one unit crosses the edge before. Removing one of the vertices between the crossing
    // edges undoes it, or leaves a smaller loop to undo next time round: the one whose triangle
    // with its neighbours holds least area goes, if that is at most _repairRelativeArea of the
    // outer ring's.
    static constexpr int kTwistEdges = 16;

    bool repairCrossing(int a, int c)
    {
        // The crossing edges are first -> (first's next) and last -> (last's next).
        auto edgesBetween = [&](int from, int to) {
            int steps = 0;
            for (int i = node(from).next; i != to && steps <= kTwistEdges; i = node(i).next) {
                ++steps;
            }
            return steps;
        };
        const int forward = edgesBetween(a, c);
        const int backward = edgesBetween(c, a);
        if (std::min(forward, backward) > kTwistEdges || std::min(forward, backward) < 1) {
            return false;
        }
        const int first = forward <= backward ? a : c;
        const int last = first == a ? c : a;
        auto triangleArea = [&](int x) {
            const glm::dvec2 p = pos(x) - pos(node(x).prev);
            const glm::dvec2 q = pos(node(x).next) - pos(node(x).prev);
            return 0.5 * std::abs(p.x * q.y - p.y * q.x);
        };
        int gone = -1;
        double smallest = HUGE_VAL;
        for (int i = node(first).next; i != node(last).next; i = node(i).next) {
            if (triangleArea(i) < smallest) {
                smallest = triangleArea(i);
                gone = i;
            }
        }
        if (gone < 0 || smallest > _repairRelativeArea * _outerArea) {
            return false;
        }
        _repairedArea += smallest;
        std::size_t ringSize = 0;
        forEachInCycle(gone, [&](int) { ++ringSize; });
        if (ringSize <= 3) {
            return false;
        }
        const int prev = node(gone).prev;
        const int next = node(gone).next;
        node(prev).next = next;
        node(next).prev = prev;
        for (int& start : _cycles) {
            if (start == gone) {
                start = next;
            }
        }
        return true;
    }

    // A ring that touches itself at a vertex is lobes joined there; each lobe must wind as its ring
    // does. One that winds the other way is the ring folded over itself (as quantization can fold
    // a small island, or a coast, where it comes back to a point it passed): such a lobe is cut off
    // at the touch if it holds at most _repairRelativeArea of the outer ring's area. Returns the
    // vertices removed, 0 when no lobe is inverted. Skipped unless splitTouchingEdges saw a ring
    // come back to a position (sorting every ring's positions to find out cost a sixth of the time).
    std::size_t removeInvertedLobe()
    {
        if (_repairRelativeArea <= 0.0 || !_ringTouchesItself) {
            return 0;
        }
        for (std::size_t k = 0; k < _cycles.size(); ++k) {
            std::vector<int> order;
            forEachInCycle(_cycles[k], [&](int i) { order.push_back(i); });
            std::vector<std::pair<glm::dvec2, std::size_t>> byPosition; // position, place in order
            for (std::size_t place = 0; place < order.size(); ++place) {
                byPosition.emplace_back(pos(order[place]), place);
            }
            std::sort(byPosition.begin(), byPosition.end(), [](const auto& a, const auto& b) {
                return std::tie(a.first.x, a.first.y, a.second) < std::tie(b.first.x, b.first.y, b.second);
            });
            const double ringSign = k == 0 ? 1.0 : -1.0; // the outer ring counter-clockwise, holes clockwise
            for (std::size_t r = 1; r < byPosition.size(); ++r) {
                if (byPosition[r].first != byPosition[r - 1].first) {
                    continue;
                }
                // The lobe from one visit of the position to the next.
                const std::size_t from = byPosition[r - 1].second;
                const std::size_t to = byPosition[r].second;
                std::vector<glm::dvec2> lobe;
                for (std::size_t place = from; place < to; ++place) {
                    lobe.push_back(pos(order[place]));
                }
                const double area = signedArea(lobe);
                // The lobe outside it (the rest of the ring) may be the inverted one instead.
                const double rest = signedArea(ringPositions(order)) - area;
                const bool lobeInverted = area * ringSign < 0.0;
                const bool restInverted = rest * ringSign < 0.0;
                if (lobeInverted == restInverted) {
                    continue;
                }
                const double removedArea = std::abs(lobeInverted ? area : rest);
                if (removedArea > _repairRelativeArea * _outerArea) {
                    continue;
                }
                // Keep the first visit, unlink the lobe's other vertices (or the rest's).
                const int keep = order[lobeInverted ? from : to];
                const int resume = order[lobeInverted ? to : from];
                std::size_t removed = 0;
                for (int i = node(keep).next; i != resume; i = node(i).next) {
                    ++removed;
                }
                if (order.size() - removed - 1 < 3) {
                    continue;
                }
                node(keep).next = node(resume).next;
                node(node(resume).next).prev = keep;
                _cycles[k] = keep;
                _repairedArea += removedArea;
                return removed + 1;
            }
        }
        return 0;
    }

    std::vector<glm::dvec2> ringPositions(std::span<const int> order) const
    {
        std::vector<glm::dvec2> points;
        points.reserve(order.size());
        for (const int i : order) {
            points.push_back(pos(i));
        }
        return points;
    }

    double cycleArea(std::size_t k) const
    {
        std::vector<glm::dvec2> points;
        forEachInCycle(_cycles[k], [&](int i) { points.push_back(pos(i)); });
        return std::abs(signedArea(points));
    }

    // Hole k goes (its nodes stay unlinked), listed with the reason: only with _leftOutHoles.
    void leaveOutHole(std::size_t k, const std::string& reason)
    {
        _leftOutHoles->push_back({_ringNumbers[k], reason});
        _cycles.erase(_cycles.begin() + static_cast<std::ptrdiff_t>(k));
        _ringNumbers.erase(_ringNumbers.begin() + static_cast<std::ptrdiff_t>(k));
        ++_holesLeftOut;
    }

    // --- Where points lie, through an index of the edges (made once the rings are final) -------

    // Files every edge by the cells it passes through, and each node under its ring's number (the
    // outer ring 0; holes keep theirs until bridged, then become part of ring 0). Only polygons
    // with holes need it.
    void indexEdges()
    {
        glm::dvec2 lo(HUGE_VAL);
        glm::dvec2 hi(-HUGE_VAL);
        std::size_t count = 0;
        for (const int start : _cycles) {
            forEachInCycle(start, [&](int i) {
                lo = glm::min(lo, pos(i));
                hi = glm::max(hi, pos(i));
                ++count;
            });
        }
        _edges.emplace(lo, hi, count);
        _lo = lo;
        _hi = hi;
        _ringOf.assign(_nodes.size(), -1);
        for (std::size_t k = 0; k < _cycles.size(); ++k) {
            forEachInCycle(_cycles[k], [&](int i) {
                _ringOf[static_cast<std::size_t>(i)] = static_cast<int>(k);
                indexEdge(i);
            });
        }
    }

    void indexEdge(int i) { _edges->insert(i, pos(i), pos(node(i).next)); }
    int ringOf(int i) const { return _ringOf[static_cast<std::size_t>(i)]; }

    // The winding numbers about p of the rings (by their numbers in _ringOf) whose edges meet a ray
    // from p to the nearest side of the rings' bounding box, and whether p lies on each. The plane
    // is turned (exactly, by quarter turns, which keep orientations) so that the ray runs towards
    // +x; the edges that count for a winding number then meet it (Sunday's rule: upward edges with
    // p to their left, downward ones with p to their right).
    struct RingWinding {
        int ring = 0;
        int winding = 0;
        bool boundary = false;
    };
    void windingsAt(const glm::dvec2& p, std::vector<RingWinding>& windings)
    {
        windings.clear();
        const double room[4] = {_hi.x - p.x, _hi.y - p.y, p.x - _lo.x, p.y - _lo.y}; // +x, +y, -x, -y
        const int quarter = static_cast<int>(std::min_element(room, room + 4) - room);
        const glm::dvec2 end = quarter == 0 ? glm::dvec2(_hi.x, p.y)
                               : quarter == 1 ? glm::dvec2(p.x, _hi.y)
                               : quarter == 2 ? glm::dvec2(_lo.x, p.y)
                                              : glm::dvec2(p.x, _lo.y);
        const auto turn = [quarter](const glm::dvec2& q) {
            return quarter == 0 ? q : quarter == 1 ? glm::dvec2(q.y, -q.x) : quarter == 2 ? -q : glm::dvec2(-q.y, q.x);
        };
        const glm::dvec2 t = turn(p);
        _edges->forEachNear(p, glm::max(_lo, glm::min(_hi, end)), [&](int i) {
            if (ringOf(i) < 0) {
                return;
            }
            const glm::dvec2 u = turn(pos(i));
            const glm::dvec2 v = turn(pos(node(i).next));
            int step = 0;
            if (u.y <= t.y) {
                step = v.y > t.y && orient2d(u, v, t) > 0 ? 1 : 0;
            } else if (v.y <= t.y && orient2d(u, v, t) < 0) {
                step = -1;
            }
            const bool boundary = onSegment(u, v, t);
            if (step == 0 && !boundary) {
                return;
            }
            auto found = std::find_if(windings.begin(), windings.end(), [&](const RingWinding& w) { return w.ring == ringOf(i); });
            if (found == windings.end()) {
                windings.push_back({ringOf(i), 0, false});
                found = windings.end() - 1;
            }
            found->winding += step;
            found->boundary = found->boundary || boundary;
        });
    }

    // Where p lies against ring `ring`, or against all the rings together when ring < 0.
    Location locate(const glm::dvec2& p, int ring = -1)
    {
        windingsAt(p, _windings);
        int winding = 0;
        for (const RingWinding& w : _windings) {
            if (ring < 0 || w.ring == ring) {
                if (w.boundary) {
                    return Location::Boundary;
                }
                winding += w.winding;
            }
        }
        return winding != 0 ? Location::Inside : Location::Outside;
    }

    // Where ring number `ring` lies against ring `other`: by its first vertex that is not on the
    // other's boundary.
    std::optional<Location> ringAgainst(int ring, int other)
    {
        std::optional<Location> found;
        forEachInCycle(_cycles[static_cast<std::size_t>(ring)], [&](int i) {
            if (!found) {
                const Location l = locate(pos(i), other);
                if (l != Location::Boundary) {
                    found = l;
                }
            }
        });
        return found;
    }

    void checkHoles()
    {
        std::vector<RingWinding> around;
        std::vector<std::pair<std::size_t, std::string>> faulty; // holes and why, left out at the end
        for (std::size_t k = 1; k < _cycles.size(); ++k) {
            const int hole = static_cast<int>(k);
            // Where the hole lies against another ring: by the winding number about its first
            // vertex, unless that vertex is on the other's boundary (then its other vertices tell).
            windingsAt(pos(_cycles[k]), around);
            const auto against = [&](int other) -> std::optional<Location> {
                const auto w = std::find_if(around.begin(), around.end(), [&](const RingWinding& x) { return x.ring == other; });
                if (w == around.end()) {
                    return Location::Outside;
                }
                // The winding test counts a hole's clockwise turn as -1: inside means nonzero.
                return w->boundary ? ringAgainst(hole, other) : (w->winding != 0 ? Location::Inside : Location::Outside);
            };
            const std::optional<Location> l = against(0);
            if (!l || *l == Location::Outside) {
                faulty.emplace_back(k, "lies outside the outer ring (or on it)");
                continue;
            }
            for (const RingWinding& w : around) {
                if (w.ring == 0 || w.ring == hole) {
                    continue;
                }
                const std::optional<Location> inside = against(w.ring);
                if (inside && *inside == Location::Inside) {
                    faulty.emplace_back(k, "lies inside hole ring " + std::to_string(_ringNumbers[static_cast<std::size_t>(w.ring)]));
                    break;
                }
            }
        }
        if (faulty.empty()) {
            return;
        }
        if (!_leftOutHoles) {
            fail("hole ring " + std::to_string(_ringNumbers[faulty[0].first]) + " " + faulty[0].second);
        }
        for (auto it = faulty.rbegin(); it != faulty.rend(); ++it) { // last first: the numbers before stay
            leaveOutHole(it->first, "it " + it->second);
        }
        indexEdges();
    }

    // --- Holes: bridges from each hole's rightmost vertex to a visible vertex -------------------

    // True when direction b -> t leaves b into the polygon's interior, strictly.
    bool locallyInside(int b, const glm::dvec2& t) const
    {
        const glm::dvec2& a = pos(node(b).prev);
        const glm::dvec2& p = pos(b);
        const glm::dvec2& c = pos(node(b).next);
        const int turn = orient2d(a, p, c);
        if (turn > 0) {
            return orient2d(a, p, t) > 0 && orient2d(p, c, t) > 0;
        }
        if (turn < 0) {
            return orient2d(a, p, t) > 0 || orient2d(p, c, t) > 0;
        }
        if (glm::dot(p - a, c - p) > 0.0) {
            return orient2d(a, p, t) > 0; // straight through
        }
        return false; // a spike tip or a zero-length edge: no interior to speak of
    }

    bool bridgeIsValid(int m, int p)
    {
        const glm::dvec2 mp = pos(m);
        const glm::dvec2 pp = pos(p);
        if (mp == pp || !locallyInside(p, mp) || !locallyInside(m, pp)) {
            return false;
        }
        bool valid = true;
        _edges->forEachNear(mp, pp, [&](int i) {
            if (!valid || ringOf(i) < 0) {
                return;
            }
            const glm::dvec2& u = pos(i);
            const glm::dvec2& v = pos(node(i).next);
            if (!segmentsIntersect(mp, pp, u, v)) {
                return;
            }
            const bool uAt = u == mp || u == pp;
            const bool vAt = v == mp || v == pp;
            if (uAt == vAt) {
                valid = false; // crosses, or runs along the bridge
                return;
            }
            // The edge leaves one end of the bridge: fine unless it runs along it.
            const glm::dvec2& end = uAt ? u : v;
            const glm::dvec2& other = uAt ? v : u;
            const glm::dvec2& far = end == mp ? pp : mp;
            if (onSegment(mp, pp, other) || onSegment(end, other, far)) {
                valid = false;
            }
        });
        // The bridge crosses nothing, so it is inside or outside as a whole: test its midpoint
        // against every ring (this settles the places where rings touch).
        return valid && locate(0.5 * (mp + pp)) == Location::Inside;
    }

    void bridgeHoles()
    {
        std::vector<std::pair<int, std::size_t>> holes; // rightmost node, cycle
        for (std::size_t k = 1; k < _cycles.size(); ++k) {
            int rightmost = _cycles[k];
            forEachInCycle(_cycles[k], [&](int i) {
                const glm::dvec2& p = pos(i);
                const glm::dvec2& best = pos(rightmost);
                if (p.x > best.x || (p.x == best.x && p.y < best.y)) {
                    rightmost = i;
                }
            });
            holes.emplace_back(rightmost, k);
        }
        std::sort(holes.begin(), holes.end(), [&](const auto& a, const auto& b) { return pos(a.first).x > pos(b.first).x; });

        for (const auto& [m, k] : holes) {
            // A hole touching the rings joined so far at a vertex is joined there: bridged
            // elsewhere, both of the ring's passes through that point would claim the angle between
            // the hole's edges and the other ring's, and no ear could be found round it.
            if (mergeAtTouch(m)) {
                continue;
            }
            const int p = findBridge(m);
            if (p < 0) {
                const std::string why = "cannot be joined to the outer ring (no vertex in sight; do rings overlap?)";
                if (!_leftOutHoles) {
                    fail("hole ring " + std::to_string(_ringNumbers[k]) + " " + why);
                }
                // Its edges no longer count (ring -1), so that later bridges may pass where it was.
                _leftOutHoles->push_back({_ringNumbers[k], "it " + why});
                ++_holesLeftOut;
                forEachInCycle(m, [&](int i) { _ringOf[static_cast<std::size_t>(i)] = -1; });
                continue;
            }
            joinOuterRing(m);
            // Splice: p -> m -> ...hole... -> m' -> p' -> (p's old next).
            const int pNext = node(p).next;
            const int mPrev = node(m).prev;
            const int m2 = copyNode(m);
            const int p2 = copyNode(p);
            node(p).next = m;
            node(m).prev = p;
            node(mPrev).next = m2;
            node(m2).prev = mPrev;
            node(m2).next = p2;
            node(p2).prev = m2;
            node(p2).next = pNext;
            node(pNext).prev = p2;
            for (const int moved : {p, m2, p2}) { // mPrev's edge ends at m's copy: still in its cells
                indexEdge(moved);
            }
        }
    }

    // The hole whose node is `hole` becomes part of the outer ring (ring 0 in _ringOf).
    void joinOuterRing(int hole)
    {
        forEachInCycle(hole, [&](int i) { _ringOf[static_cast<std::size_t>(i)] = 0; });
    }

    // A copy of node i, of the outer ring, not yet linked.
    int copyNode(int i)
    {
        const int copy = static_cast<int>(_nodes.size());
        _nodes.push_back(node(i));
        _ringOf.push_back(0);
        twins(i, copy);
        return copy;
    }

    // Where the hole touches the outer cycle at a vertex, joins it there, with no bridge (p -> hole
    // from h's next round to h -> p's next), at the pass of the outer cycle through that point
    // whose wedge the hole's edges there leave into. Whether it did.
    bool mergeAtTouch(int hole)
    {
        int touchP = -1;
        int touchH = -1;
        forEachInCycle(hole, [&](int h) {
            if (touchP >= 0 || !node(h).twin) { // a vertex no other has touches nothing
                return;
            }
            _edges->forEachInBox(pos(h), pos(h), [&](int p) {
                if (touchP < 0 && ringOf(p) == 0 && pos(p) == pos(h) && locallyInside(p, pos(node(h).next)) &&
                    locallyInside(p, pos(node(h).prev))) {
                    touchP = p;
                    touchH = h;
                }
            });
        });
        if (touchP < 0) {
            return false;
        }
        joinOuterRing(hole);
        const int pNext = node(touchP).next;
        const int hNext = node(touchH).next;
        node(touchP).next = hNext;
        node(hNext).prev = touchP;
        node(touchH).next = pNext;
        node(pNext).prev = touchH;
        indexEdge(touchP); // the two swap edges
        indexEdge(touchH);
        return true;
    }

    int findBridge(int m)
    {
        const glm::dvec2 mp = pos(m);
        // Eberly's candidate: the nearest edge of the outer cycle hit by the ray from m towards
        // +x, its endpoint of larger x, or the reflex vertex inside the triangle (m, hit, endpoint)
        // closest in angle to the ray.
        int candidate = -1;
        double bestX = HUGE_VAL;
        _edges->forEachTowardsPlusX(mp, std::max(_hi.x, mp.x), [&](int i) {
            const glm::dvec2& u = pos(i);
            const glm::dvec2& v = pos(node(i).next);
            if (ringOf(i) != 0 || (u.y > mp.y && v.y > mp.y) || (u.y < mp.y && v.y < mp.y)) {
                return;
            }
            double x;
            int end;
            if (u.y == v.y) {
                x = std::min(u.x, v.x);
                end = u.x <= v.x ? i : node(i).next;
                if (x < mp.x) {
                    x = std::max(u.x, v.x);
                    end = u.x <= v.x ? node(i).next : i;
                }
            } else {
                x = u.x + (mp.y - u.y) * (v.x - u.x) / (v.y - u.y);
                end = u.x >= v.x ? i : node(i).next;
                if (u.y == mp.y) {
                    end = i;
                } else if (v.y == mp.y) {
                    end = node(i).next;
                }
            }
            if (x >= mp.x && x < bestX) {
                bestX = x;
                candidate = end;
            }
        }, [&](double columnLeft) { return bestX < columnLeft; }); // what lies right of this column is farther
        if (candidate >= 0 && pos(candidate).y != mp.y) {
            const glm::dvec2 hit(bestX, mp.y);
            const glm::dvec2 end = pos(candidate);
            const bool ccw = orient2d(mp, hit, end) > 0;
            const glm::dvec2 a = mp;
            const glm::dvec2 b = ccw ? hit : end;
            const glm::dvec2 c = ccw ? end : hit;
            double bestCos = -2.0;
            double bestDistance = HUGE_VAL;
            const int hidden = candidate;
            _edges->forEachInBox(glm::min(a, glm::min(b, c)), glm::max(a, glm::max(b, c)), [&](int i) {
                const glm::dvec2& q = pos(i);
                if (ringOf(i) != 0 || i == hidden || q == mp || !inClosedTriangle(a, b, c, q)) {
                    return;
                }
                if (orient2d(pos(node(i).prev), q, pos(node(i).next)) >= 0) {
                    return; // only reflex vertices can hide the candidate
                }
                const double distance = glm::length(q - mp);
                const double cosine = (q.x - mp.x) / distance;
                if (cosine > bestCos || (cosine == bestCos && distance < bestDistance)) {
                    bestCos = cosine;
                    bestDistance = distance;
                    candidate = i;
                }
            });
        }
        if (candidate >= 0) {
            // Of the copies of a vertex that bridges made, the one whose wedge holds m.
            const glm::dvec2 cp = pos(candidate);
            std::vector<int> copies;
            _edges->forEachInBox(cp, cp, [&](int i) {
                if (ringOf(i) == 0 && pos(i) == cp) {
                    copies.push_back(i);
                }
            });
            std::sort(copies.begin(), copies.end()); // as they were made: the same choice on every machine
            for (const int i : copies) {
                if (bridgeIsValid(m, i)) {
                    return i;
                }
            }
        }
        // Fallback: every vertex of the outer cycle, nearest first.
        std::vector<std::pair<double, int>> byDistance;
        forEachInCycle(_cycles[0], [&](int i) {
            const glm::dvec2 d = pos(i) - mp;
            byDistance.emplace_back(glm::dot(d, d), i);
        });
        std::sort(byDistance.begin(), byDistance.end());
        for (const auto& [distance, i] : byDistance) {
            if (bridgeIsValid(m, i)) {
                return i;
            }
        }
        return -1;
    }

    // --- Ear clipping ---------------------------------------------------------------------------

    // Strictly inside the angle at corner x of a counter-clockwise triangle whose next corner is y
    // and previous corner is z.
    static bool inOpenWedge(const glm::dvec2& x, const glm::dvec2& y, const glm::dvec2& z, const glm::dvec2& q)
    {
        return orient2d(x, y, q) > 0 && orient2d(x, z, q) < 0;
    }

    bool edgesEnter(int other, const glm::dvec2& x, const glm::dvec2& y, const glm::dvec2& z) const
    {
        return inOpenWedge(x, y, z, pos(node(other).prev)) || inOpenWedge(x, y, z, pos(node(other).next));
    }

    // Ears thinner than kSliverQuality are clipped only when no other ear is left.
    bool isSliver(int b) const
    {
        return triangleQuality(pos(node(b).prev), pos(b), pos(node(b).next)) < kSliverQuality;
    }

    static constexpr int kEar = -1;
    static constexpr int kNotConvex = -2; // or an edge next to the ear enters it: b's neighbours decide

    // kEar when b is an ear; otherwise kNotConvex, or a vertex that is in the way (inside the
    // triangle, or at one of its corners with an edge entering it): b stays no ear while that
    // vertex and its neighbours stay.
    int earBlocker(int b)
    {
        const int a = node(b).prev;
        const int c = node(b).next;
        const glm::dvec2& pa = pos(a);
        const glm::dvec2& pb = pos(b);
        const glm::dvec2& pc = pos(c);
        if (orient2d(pa, pb, pc) <= 0) {
            return kNotConvex;
        }
        if (_starShaped) {
            // The ear lies in the wedge from the centre between a and c, if that is less than half a
            // turn, and every other vertex outside it: the angles round the centre increase along
            // the ring. Clipping it leaves the ring star-shaped. A wider wedge waits for a or c to go.
            return orient2d(_centre, pa, pc) > 0 ? kEar : kNotConvex;
        }
        if (_indexed && !node(b).twin) {
            _index.remove(b); // turned convex: in no ear's way from now on (mayBlockEars)
        }
        // The edges on either side of the ear must not enter it.
        if (inOpenWedge(pa, pb, pc, pos(node(a).prev)) || inOpenWedge(pc, pa, pb, pos(node(c).next))) {
            return kNotConvex;
        }
        int blocker = kEar;
        forEachVertexIn(pa, pb, pc, b, [&](int i) {
            if (i == a || i == b || i == c) {
                return false;
            }
            const glm::dvec2& q = pos(i);
            const bool inTheWay = q == pa   ? edgesEnter(i, pa, pb, pc)
                                  : q == pb ? edgesEnter(i, pb, pc, pa)
                                  : q == pc ? edgesEnter(i, pc, pa, pb)
                                            : inClosedTriangle(pa, pb, pc, q);
            if (inTheWay) {
                blocker = i;
            }
            return inTheWay;
        });
        return blocker;
    }

    // Whether vertex i may be in the way of an ear: a strictly convex vertex that shares its
    // position with no other never is alone. If one lies in an ear's closed triangle (not at a
    // corner: only a twin can be there), then a vertex lies strictly inside it (the boundary does
    // not cross the ear's edges, and i's own edges cannot leave the side of the diagonal the ear is
    // on without a vertex there or i being reflex), and the one farthest from the diagonal has the
    // ear's side of its line through it inside the polygon: it is reflex or straight (O'Rourke,
    // Computational Geometry in C, 1.2). A vertex only becomes more convex as ears go.
    bool mayBlockEars(int i) const
    {
        return node(i).twin || orient2d(pos(node(i).prev), pos(i), pos(node(i).next)) <= 0;
    }

    // Calls visit(i) for vertices left in the counter-clockwise triangle a, b, c (and maybe some
    // others in its box) that may be in its way (mayBlockEars), until it returns true. near: a vertex
    // left, at or next to the triangle.
    template <typename Visit>
    void forEachVertexIn(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, int near, Visit&& visit)
    {
        if (_indexed) {
            _index.findIn(a, b, c, near, visit);
            return;
        }
        const glm::dvec2 lo = glm::min(a, glm::min(b, c));
        const glm::dvec2 hi = glm::max(a, glm::max(b, c));
        for (int i = node(near).next; i != near; i = node(i).next) {
            const glm::dvec2& q = pos(i);
            if (q.x >= lo.x && q.x <= hi.x && q.y >= lo.y && q.y <= hi.y && visit(i)) {
                return;
            }
        }
    }

    // --- The order of clipping: a queue of candidate ears, shortest diagonal first ------------
    //
    // Whether b is an ear depends on b's neighbours, theirs (the edges next to the ear), and the
    // vertices in the triangle. So a vertex is tested again only when one of those changes: when a
    // vertex within two steps of it goes, or the vertex found in its way goes or gets new
    // neighbours. Short diagonals first keep the triangles small, so each test looks at few
    // vertices, and make fuller triangles than clipping round the ring.

    // Slivers last, then by the binary order of magnitude of the squared diagonal: the class of
    // the queue, in the high half of the key; the vertex in the low half.
    std::uint64_t priority(int b) const
    {
        const glm::dvec2 diagonal = pos(node(b).next) - pos(node(b).prev);
        const double squared = std::min(glm::dot(diagonal, diagonal), std::numeric_limits<double>::max());
        const std::uint64_t magnitude = std::bit_cast<std::uint64_t>(squared) >> 52; // the biased exponent
        const std::uint64_t priorityClass = (std::uint64_t{isSliver(b)} << 11) | magnitude;
        return (priorityClass << 32) | static_cast<std::uint32_t>(b);
    }

    // Queues b unless it is queued already with the same priority (an older entry is left to be
    // skipped when it comes up).
    void enqueue(int b)
    {
        const auto i = static_cast<std::size_t>(b);
        if (node(b).removed) {
            return;
        }
        const std::uint64_t key = priority(b);
        if (_queued[i] == key) {
            return;
        }
        _queued[i] = key;
        _queue.push(static_cast<std::uint32_t>(key >> 32), b);
    }

    // The vertices waiting on v are tested again.
    void wake(int v)
    {
        std::vector<int>& waiting = _waiting[static_cast<std::size_t>(v)];
        for (const int b : waiting) {
            enqueue(b);
        }
        waiting.clear();
    }

    void unlink(int b)
    {
        const int a = node(b).prev;
        const int c = node(b).next;
        node(a).next = c;
        node(c).prev = a;
        node(b).removed = true;
        if (_start == b) {
            _start = c;
        }
        --_remaining;
        if (_indexed) {
            _index.remove(b);
        }
        enqueue(a); // new diagonals
        enqueue(c);
        for (const int beyond : {node(a).prev, node(c).next}) { // the same diagonal, a new edge next to the ear
            if (_queued[static_cast<std::size_t>(beyond)] == kNotQueued) {
                enqueue(beyond);
            }
        }
        for (const int moved : {b, a, c}) {
            wake(moved);
        }
    }

    // A vertex that bounds no area: the end of a zero-length edge, or the tip of a spike (the
    // ring comes straight back, its neighbours on one side of it on one line).
    bool boundsNoArea(int b) const
    {
        const glm::dvec2& pa = pos(node(b).prev);
        const glm::dvec2& pb = pos(b);
        const glm::dvec2& pc = pos(node(b).next);
        return pa == pb || pb == pc || (orient2d(pa, pb, pc) == 0 && glm::dot(pb - pa, pc - pb) <= 0.0);
    }

    // Removes the vertices that bound no area among the given ones and those that become so.
    void removeNoArea(std::vector<int>& work)
    {
        while (!work.empty() && _remaining >= 3) {
            const int b = work.back();
            work.pop_back();
            if (node(b).removed || !boundsNoArea(b)) {
                continue;
            }
            work.push_back(node(b).prev);
            work.push_back(node(b).next);
            unlink(b);
        }
    }

    // Removes vertices that bound no area: ends of zero-length edges, tips of spikes; with
    // straightToo, also vertices in the middle of a straight run. True when any went.
    bool removeDegenerate(bool straightToo)
    {
        bool removed = false;
        int i = _start;
        std::size_t steps = _remaining;
        while (steps-- > 0 && _remaining >= 3) {
            const int a = node(i).prev;
            const int c = node(i).next;
            const glm::dvec2& pa = pos(a);
            const glm::dvec2& pb = pos(i);
            const glm::dvec2& pc = pos(c);
            if (orient2d(pa, pb, pc) == 0 &&
                (pa == pb || pb == pc || pa == pc || glm::dot(pb - pa, pc - pb) <= 0.0 || straightToo)) {
                unlink(i);
                removed = true;
                if (straightToo) {
                    return true;
                }
            }
            i = c;
        }
        return removed;
    }

    // Indexes the vertices that may be in ears' way (mayBlockEars) among those given, the ring
    // left; a small polygon's ears are tested against all its vertices: cheaper than indexing them.
    void indexVertices(const std::vector<int>& vertices)
    {
        _indexed = vertices.size() > kSmallPolygon;
        if (!_indexed) {
            return;
        }
        _positions.clear();
        for (const Node& n : _nodes) {
            _positions.push_back(n.p);
        }
        _mayBlock.assign(_nodes.size(), 0);
        for (const int i : vertices) {
            _mayBlock[static_cast<std::size_t>(i)] = mayBlockEars(i);
        }
        _index.reset(_positions, vertices, _mayBlock);
    }

    void clip(std::vector<std::uint32_t>& indices)
    {
        std::vector<int>& all = _cycleOrder;
        all.clear();
        forEachInCycle(_start, [&](int i) { all.push_back(i); });
        _remaining = all.size();
        _indexed = false;
        if (!_starShaped) {
            indexVertices(all);
        }
        _queue.clear();
        _queued.assign(_nodes.size(), kNotQueued);
        if (_waiting.size() < _nodes.size()) {
            _waiting.resize(_nodes.size());
        }
        for (std::size_t i = 0; i < _nodes.size(); ++i) {
            _waiting[i].clear();
        }
        indices.reserve(3 * _remaining);
        std::vector<int>& work = _work;
        work = all;
        removeNoArea(work);
        for (const int i : all) {
            enqueue(i);
        }
        auto emit = [&](int a, int b, int c) {
            indices.push_back(node(a).index);
            indices.push_back(node(b).index);
            indices.push_back(node(c).index);
        };

        while (_remaining > 3) {
            if (_queue.empty() && _starShaped) {
                // Every convex vertex left spans half a turn or more round the centre: the rest is
                // clipped as any ring is.
                _starShaped = false;
                all.clear();
                forEachInCycle(_start, [&](int i) { all.push_back(i); });
                indexVertices(all);
                for (const int i : all) {
                    enqueue(i);
                }
                continue;
            }
            if (_queue.empty()) {
                // No ear anywhere: vertices that bound no area are in the way.
                if (!removeDegenerate(false) && !removeDegenerate(true)) {
                    fail("no ear found among the " + std::to_string(_remaining) +
                         " vertices left (do rings overlap or cross?)");
                }
                continue;
            }
            const auto [priorityClass, b] = _queue.pop();
            const std::uint64_t key = (std::uint64_t{priorityClass} << 32) | static_cast<std::uint32_t>(b);
            if (node(b).removed || _queued[static_cast<std::size_t>(b)] != key) {
                continue; // superseded
            }
            _queued[static_cast<std::size_t>(b)] = kNotQueued;
            const int blocker = earBlocker(b);
            if (blocker >= 0) {
                _waiting[static_cast<std::size_t>(blocker)].push_back(b);
            }
            if (blocker != kEar) {
                continue;
            }
            const int a = node(b).prev;
            const int c = node(b).next;
            emit(a, b, c);
            unlink(b);
            work.assign({a, c});
            removeNoArea(work);
        }
        if (_remaining == 3) {
            const int a = node(_start).prev;
            const int c = node(_start).next;
            const int turn = orient2d(pos(a), pos(_start), pos(c));
            if (turn > 0) {
                emit(a, _start, c);
            } else if (turn < 0) {
                fail("the last triangle is clockwise (do rings overlap or cross?)");
            }
        }
    }

    // Ear clipping has to cut slivers where vertices are collinear but for rounding (as when
    // positions on one great circle are projected onto a plane). Where a sliver's longest edge is
    // shared with another triangle and the two form a convex quadrilateral, flipping that edge gives
    // two fuller triangles; the triangulation stays one of the same polygon.
    void flipSlivers(std::vector<std::uint32_t>& indices)
    {
        std::uint32_t largest = 0;
        for (const Node& n : _nodes) {
            largest = std::max(largest, n.index);
        }
        std::vector<glm::dvec2>& where = _byOutputIndex;
        where.resize(std::size_t{largest} + 1);
        for (const Node& n : _nodes) {
            where[n.index] = n.p;
        }
        auto at = [&](std::uint32_t i) -> const glm::dvec2& { return where[i]; };
        auto quality = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) { return triangleQuality(at(a), at(b), at(c)); };
        const std::size_t count = indices.size() / 3;
        auto corner = [&](std::size_t t, std::size_t k) -> std::uint32_t& { return indices[3 * t + k % 3]; };
        auto isSliverTriangle = [&](std::size_t t) { return quality(corner(t, 0), corner(t, 1), corner(t, 2)) < kSliverQuality; };
        bool anySliver = false;
        for (std::size_t t = 0; t < count && !anySliver; ++t) {
            anySliver = isSliverTriangle(t);
        }
        if (!anySliver) {
            return;
        }

        // Half-edge 3t + k runs from corner k of triangle t to corner k + 1; its twin is the one
        // running back, where each direction occurs once (rings that touch give an edge twice:
        // those are left alone).
        constexpr std::size_t kNone = static_cast<std::size_t>(-1);
        auto key = [&](std::size_t h) { return (std::uint64_t{indices[h]} << 32) | indices[h - h % 3 + (h % 3 + 1) % 3]; };
        std::vector<std::pair<std::uint64_t, std::size_t>> sorted;
        sorted.reserve(indices.size());
        for (std::size_t h = 0; h < indices.size(); ++h) {
            sorted.emplace_back(key(h), h);
        }
        std::sort(sorted.begin(), sorted.end());
        auto unique = [&](std::uint64_t k) -> std::size_t {
            const auto it = std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(k, std::size_t{0}));
            if (it == sorted.end() || it->first != k || (it + 1 != sorted.end() && (it + 1)->first == k)) {
                return kNone;
            }
            return it->second;
        };
        std::vector<std::size_t> twin(indices.size(), kNone);
        for (std::size_t h = 0; h < indices.size(); ++h) {
            const std::uint64_t k = key(h);
            if (unique(k) == h) {
                twin[h] = unique((k << 32) | (k >> 32));
            }
        }

        for (int round = 0; round < 4; ++round) {
            bool flipped = false;
            for (std::size_t t = 0; t < count; ++t) {
                const double q = quality(corner(t, 0), corner(t, 1), corner(t, 2));
                if (q >= kSliverQuality) {
                    continue;
                }
                std::size_t k = 0; // the longest edge, from corner k to corner k + 1
                double longest = -1.0;
                for (std::size_t j = 0; j < 3; ++j) {
                    const glm::dvec2 d = at(corner(t, j + 1)) - at(corner(t, j));
                    if (glm::dot(d, d) > longest) {
                        longest = glm::dot(d, d);
                        k = j;
                    }
                }
                const std::size_t across = twin[3 * t + k];
                if (across == kNone) {
                    continue;
                }
                const std::size_t t2 = across / 3;
                const std::size_t k2 = across % 3; // t2 runs v -> u -> x from corner k2
                const std::uint32_t u = corner(t, k);
                const std::uint32_t v = corner(t, k + 1);
                const std::uint32_t w = corner(t, k + 2);
                const std::uint32_t x = corner(t2, k2 + 2);
                if (x == u || x == v || x == w || orient2d(at(u), at(x), at(w)) <= 0 ||
                    orient2d(at(x), at(v), at(w)) <= 0 ||
                    std::min(quality(u, x, w), quality(x, v, w)) <= std::min(q, quality(corner(t2, 0), corner(t2, 1), corner(t2, 2)))) {
                    continue;
                }
                // The outer half-edges' twins, then the two new triangles (u, x, w) and (x, v, w).
                const std::size_t ux = twin[3 * t2 + (k2 + 1) % 3];
                const std::size_t xv = twin[3 * t2 + (k2 + 2) % 3];
                const std::size_t vw = twin[3 * t + (k + 1) % 3];
                const std::size_t wu = twin[3 * t + (k + 2) % 3];
                corner(t, 0) = u;
                corner(t, 1) = x;
                corner(t, 2) = w;
                corner(t2, 0) = x;
                corner(t2, 1) = v;
                corner(t2, 2) = w;
                const std::size_t newTwins[6] = {ux, 3 * t2 + 2, wu, xv, vw, 3 * t + 1};
                for (std::size_t j = 0; j < 6; ++j) {
                    const std::size_t h = j < 3 ? 3 * t + j : 3 * t2 + (j - 3);
                    twin[h] = newTwins[j];
                    if (newTwins[j] != kNone) {
                        twin[newTwins[j]] = h;
                    }
                }
                flipped = true;
            }
            if (!flipped) {
                break;
            }
        }
    }

    std::string_view _name;
    double _repairRelativeArea = 0.0;
    std::vector<LeftOutHole>* _leftOutHoles = nullptr; // null: faulty holes throw
    std::size_t _holesLeftOut = 0;
    double _outerArea = 0.0;
    double _repairedArea = 0.0;
    std::vector<Node> _nodes;
    std::vector<int> _cycles; // the first node of each ring kept: the outer ring first
    std::vector<std::size_t> _ringNumbers; // per cycle: its ring's index in the input
    bool _ringTouchesItself = false;       // a ring visits a position twice (or may): it has lobes
    // For polygons with holes, from the holes' check on (indexEdges):
    std::optional<detail::SegmentIndex> _edges; // every edge, by the node it starts at
    std::vector<int> _ringOf;                   // per node: its ring's number in _cycles, -1 if unlinked
    glm::dvec2 _lo{0.0}, _hi{0.0};              // the vertices' bounding box
    std::vector<RingWinding> _windings;         // locate's, kept to spare allocations
    int _start = -1;
    std::size_t _remaining = 0;
    // While clipping:
    std::vector<glm::dvec2> _positions;       // by node, for the index
    static constexpr std::size_t kSmallPolygon = 32;
    bool _indexed = false;     // whether _index is in use
    // The outer ring, alone, is strictly star-shaped round _centre (starShaped): until the clipping
    // finds no ear that way.
    bool _starShaped = false;
    glm::dvec2 _centre{0.0};
    static constexpr std::size_t kKernelSearchVertices = 256;
    detail::PointIndex _index; // the vertices left that may be in an ear's way
    std::vector<std::uint8_t> _mayBlock; // by node, when the clipping starts
    ClassQueue _queue;
    static constexpr std::uint64_t kNotQueued = ~std::uint64_t{0}; // no priority: no magnitude is that large
    std::vector<std::uint64_t> _queued;       // per vertex: the priority it is queued with
    std::vector<std::vector<int>> _waiting;   // per vertex: vertices it is in the way of
    // Working lists of single steps, members only to keep their memory between polygons:
    std::vector<Node> _kept;                         // prepareRings: a ring's vertices
    std::vector<glm::dvec2> _keptPoints;             // and their positions
    std::vector<int> _edgeStarts, _edgeEnds;         // splitTouchingEdges: by edge
    std::vector<std::size_t> _edgeCycles;
    std::vector<glm::dvec2> _edgeStartPositions, _edgeEndPositions;
    std::vector<std::pair<int, int>> _touching;
    std::vector<bool> _cycleIsFaulty;
    std::vector<int> _cycleOrder, _work;             // clip
    std::vector<glm::dvec2> _byOutputIndex;          // flipSlivers
    struct HalfPlane {
        glm::dvec2 normal; // inside: dot(normal, x) >= offset
        double offset;
    };
    std::vector<HalfPlane> _halfPlanes; // kernelCentre
};

} // namespace

PolygonTriangles earClip(std::span<const std::vector<glm::dvec2>> rings, std::string_view name,
                         double repairRelativeArea, std::vector<LeftOutHole>* leftOutHoles)
{
    // Memory kept for the next polygon is bounded: a clipper that grew beyond this many vertices
    // (some 16 MB) is let go.
    constexpr std::size_t kKeptVertices = std::size_t{1} << 16;
    thread_local std::unique_ptr<EarClipper> clipper;
    if (!clipper) {
        clipper = std::make_unique<EarClipper>();
    }
    struct Release {
        std::unique_ptr<EarClipper>& clipper;
        ~Release()
        {
            if (clipper->capacity() > kKeptVertices) {
                clipper.reset();
            }
        }
    } release{clipper};
    return clipper->run(rings, name, std::max(repairRelativeArea, 0.0), leftOutHoles);
}

} // namespace orbis
