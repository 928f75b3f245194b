#include "orbis/core/EllipsoidPolygon.h"

#include "RobustPredicates.h"

#include "orbis/core/EllipsoidTangentPlane.h"
#include "orbis/core/Error.h"
#include "orbis/core/PolygonCleanup.h"
#include "orbis/core/TriangleMeshSubdivision.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>
#include <optional>
#include <string>
#include <unordered_map>

namespace orbis {

namespace {

using Ring3 = std::vector<glm::dvec3>;

[[noreturn]] void fail(std::string_view name, const std::string& what)
{
    throw Error("polygon '" + std::string(name) + "': " + what);
}

/// The rings moved to the surface and cleaned up; dropped holes have no indices.
struct CleanPolygon {
    std::vector<Ring3> surface;                // per input ring, every position on the surface
    std::vector<std::vector<std::size_t>> kept; // per input ring, the vertices the clean-up kept
    std::vector<std::size_t> offsets;          // where each ring starts in the concatenation
    bool empty = false;                        // the outer ring has no area: nothing to triangulate
};

CleanPolygon cleanPolygon(const Ellipsoid& ellipsoid, std::span<const std::vector<glm::dvec3>> rings,
                          std::string_view name)
{
    if (rings.empty()) {
        fail(name, "has no rings");
    }
    CleanPolygon clean;
    std::size_t offset = 0;
    for (std::size_t r = 0; r < rings.size(); ++r) {
        Ring3 surface;
        surface.reserve(rings[r].size());
        for (std::size_t i = 0; i < rings[r].size(); ++i) {
            if (!isFinite(rings[r][i])) {
                fail(name, "vertex " + std::to_string(i) + " of ring " + std::to_string(r) + " is not finite");
            }
            surface.push_back(ellipsoid.scaleToGeodeticSurface(rings[r][i]));
        }
        clean.surface.push_back(std::move(surface));
        clean.offsets.push_back(offset);
        offset += rings[r].size();
    }
    // Positions where rings touch (one position at two places that are not neighbours in a ring)
    // stay, so that the touch stays a shared vertex (by a hash of the position: a collision only
    // keeps a vertex that could have gone).
    std::unordered_map<std::uint64_t, int> seen;
    auto key = [](const glm::dvec3& p) {
        return std::bit_cast<std::uint64_t>(p.x) * 0x9e3779b97f4a7c15ull ^ std::bit_cast<std::uint64_t>(p.y) * 0x632be59bd9b4e019ull ^
               std::bit_cast<std::uint64_t>(p.z);
    };
    for (const Ring3& ring : clean.surface) {
        for (std::size_t i = 0; i < ring.size(); ++i) {
            if (ring[i] != ring[(i + ring.size() - 1) % ring.size()]) {
                ++seen[key(ring[i])];
            }
        }
    }
    for (std::size_t r = 0; r < rings.size(); ++r) {
        const Ring3& surface = clean.surface[r];
        const auto pinned = std::make_unique<bool[]>(surface.size());
        for (std::size_t i = 0; i < surface.size(); ++i) {
            pinned[i] = seen[key(surface[i])] > 1;
        }
        std::vector<std::size_t> kept =
            cleanRing(surface, kEllipsoidCollinearToleranceRadians, std::span<const bool>(pinned.get(), surface.size()));
        if (kept.size() < 3) {
            if (r == 0) {
                clean.empty = true;
            } else {
                kept.clear(); // a hole with no area removes nothing
            }
        }
        clean.kept.push_back(std::move(kept));
    }
    if (offset > 0xffffffffu) {
        fail(name, "has more vertices than 32-bit indices can address");
    }
    return clean;
}

/// The tangent plane at the centre of the outer ring, and the widest angle of any vertex from its normal.
struct PlaneFit {
    EllipsoidTangentPlane plane;
    double widestCosine;
};

PlaneFit fitPlane(const Ellipsoid& ellipsoid, const CleanPolygon& clean)
{
    Ring3 outer;
    for (const std::size_t i : clean.kept[0]) {
        outer.push_back(clean.surface[0][i]);
    }
    PlaneFit fit{EllipsoidTangentPlane(ellipsoid, outer), 1.0};
    for (std::size_t r = 0; r < clean.kept.size(); ++r) {
        for (const std::size_t i : clean.kept[r]) {
            fit.widestCosine = std::min(fit.widestCosine, fit.plane.cosineFromNormal(clean.surface[r][i]));
        }
    }
    return fit;
}

bool fits(const PlaneFit& fit)
{
    return fit.widestCosine >= std::cos(kMaximumTangentPlaneAngleRadians);
}

/// Ear clipping in the tangent plane; indices into the concatenated input rings.
PolygonTriangles clipInPlane(const CleanPolygon& clean, const EllipsoidTangentPlane& plane, std::string_view name,
                             std::vector<LeftOutHole>* leftOutHoles)
{
    std::vector<std::vector<glm::dvec2>> rings2;
    std::vector<std::uint32_t> original;
    std::vector<std::size_t> originalRings;
    for (std::size_t r = 0; r < clean.kept.size(); ++r) {
        if (clean.kept[r].empty()) {
            continue;
        }
        originalRings.push_back(r);
        std::vector<glm::dvec2> ring;
        for (const std::size_t i : clean.kept[r]) {
            const std::optional<glm::dvec2> q = plane.projectPointOntoPlane(clean.surface[r][i]);
            if (!q) {
                fail(name, "vertex " + std::to_string(i) + " of ring " + std::to_string(r) +
                               " cannot be projected onto the polygon's tangent plane");
            }
            ring.push_back(*q);
            original.push_back(static_cast<std::uint32_t>(clean.offsets[r] + i));
        }
        rings2.push_back(std::move(ring));
    }
    const std::size_t before = leftOutHoles ? leftOutHoles->size() : 0;
    PolygonTriangles triangles = earClip(rings2, name, kSpikeRepairRelativeArea, leftOutHoles);
    for (std::uint32_t& index : triangles.indices) {
        index = original[index];
    }
    for (std::size_t h = before; leftOutHoles && h < leftOutHoles->size(); ++h) {
        (*leftOutHoles)[h].ring = originalRings[(*leftOutHoles)[h].ring];
    }
    return triangles;
}

// --- Splitting a region by planes through the centre ---------------------------------------------

/// A region of the surface as oriented rings (the region on the left of each, seen from outside):
/// outer boundaries and holes side by side, not yet told apart.
struct Region {
    std::vector<Ring3> rings;
    bool empty() const noexcept { return rings.empty(); }
};

void closeLoop(Ring3& loop, Region& into)
{
    Ring3 cleaned;
    for (const glm::dvec3& p : loop) {
        if (cleaned.empty() || cleaned.back() != p) {
            cleaned.push_back(p);
        }
    }
    while (cleaned.size() > 1 && cleaned.back() == cleaned.front()) {
        cleaned.pop_back();
    }
    if (cleaned.size() >= 3) {
        into.rings.push_back(std::move(cleaned));
    }
}

struct Crossing {
    glm::dvec3 point;
    double theta = 0.0;          // position along the cut
    double order = 0.0;          // theta measured from the widest gap between crossings
    double nudge = 0.0;          // at a vertex on the plane: where the crossing moves with the plane
    bool down = false;           // the ring leaves the + side here
    std::size_t ring = 0;
    std::size_t edge = 0;        // on the ring's edge from vertex `edge` to the next
    std::size_t nextOnRing = 0;  // the next crossing along the same ring
    std::size_t partner = 0;     // the other end of this crossing's interval along the cut
    std::vector<glm::dvec3> between; // down crossings: points along the interval, in +theta order
};

/// Splits a region by the plane through the centre with unit normal n into the part on the +n side
/// and the part on the -n side. A vertex on the plane belongs to the + side. Where a ring crosses
/// the plane, the crossing is computed once from the edge's ends (symmetrically, so both parts and
/// both orders give the same point); along the cut, the region's inside intervals run from each
/// crossing leaving the + side to the next crossing (in the direction that keeps the + side on the
/// left) entering it. Intervals wider than 90 degrees get points in between, shared by both parts.
///
/// Vertices on the plane are decided as if the plane were moved an infinitesimal distance to the
/// - side (simulation of simplicity): they are on the + side, and the crossing on an edge from one
/// of them to the - side sits at the vertex but is ordered along the cut by where it would move
/// with the plane; crossings still at one place put those leaving the + side first.
std::pair<Region, Region> splitRegion(const Ellipsoid& ellipsoid, const Region& region, const glm::dvec3& n,
                                      std::string_view name)
{
    const glm::dvec3 e1 = anyPerpendicular(n);
    const glm::dvec3 e2 = glm::cross(n, e1);
    Region plus;
    Region minus;
    std::vector<Crossing> crossings;
    for (std::size_t r = 0; r < region.rings.size(); ++r) {
        const Ring3& ring = region.rings[r];
        const std::size_t count = ring.size();
        std::vector<double> w(count);
        bool anyPlus = false;
        bool anyMinus = false;
        for (std::size_t i = 0; i < count; ++i) {
            w[i] = glm::dot(n, ring[i]);
            if (std::abs(w[i]) <= 1e-15 * glm::length(ring[i])) {
                w[i] = 0.0; // on the plane to rounding: exactly on it, for both parts alike
            }
            (w[i] >= 0.0 ? anyPlus : anyMinus) = true;
        }
        if (!anyMinus || !anyPlus) {
            (anyPlus ? plus : minus).rings.push_back(ring);
            continue;
        }
        const std::size_t first = crossings.size();
        for (std::size_t i = 0; i < count; ++i) {
            const std::size_t j = (i + 1) % count;
            if ((w[i] >= 0.0) == (w[j] >= 0.0)) {
                continue;
            }
            Crossing c;
            if (w[i] == 0.0 || w[j] == 0.0) {
                const std::size_t on = w[i] == 0.0 ? i : j;
                const std::size_t off = on == i ? j : i;
                c.point = ring[on];
                // Along the cut per unit of depth below the plane (a cotangent, so it is compared
                // with a relative tolerance: rounding makes an edge along a meridian 1e-10 off).
                c.nudge = glm::dot(glm::normalize(glm::cross(n, ring[on])), ring[off] - ring[on]) / std::abs(w[off]);
            } else {
                c.point = ellipsoid.scaleToGeocentricSurface(std::abs(w[j]) * ring[i] + std::abs(w[i]) * ring[j]);
            }
            c.theta = std::atan2(glm::dot(e2, c.point), glm::dot(e1, c.point));
            c.down = w[i] >= 0.0;
            c.ring = r;
            c.edge = i;
            crossings.push_back(std::move(c));
        }
        for (std::size_t k = first; k < crossings.size(); ++k) {
            crossings[k].nextOnRing = k + 1 < crossings.size() ? k + 1 : first;
        }
    }
    if (crossings.empty()) {
        return {std::move(plus), std::move(minus)};
    }

    // Along the cut, in +theta order (which keeps the + side on the left), measured from the
    // middle of the widest gap between crossings so that no two close crossings straddle the jump
    // from pi to -pi. Crossings within 1e-13 rad are at one place (computed from different edges,
    // one point can differ in the last bits) and are ordered by nudge, then leaving before entering,
    // so that a touch from the - side is a zero-length interval.
    std::vector<std::size_t> order(crossings.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return crossings[a].theta < crossings[b].theta; });
    double gapStart = crossings[order.back()].theta;
    double widest = crossings[order.front()].theta + kTwoPi - gapStart;
    for (std::size_t k = 0; k + 1 < order.size(); ++k) {
        const double gap = crossings[order[k + 1]].theta - crossings[order[k]].theta;
        if (gap > widest) {
            widest = gap;
            gapStart = crossings[order[k]].theta;
        }
    }
    const double cut = gapStart + 0.5 * widest;
    for (Crossing& c : crossings) {
        c.order = std::fmod(c.theta - cut + 2.0 * kTwoPi, kTwoPi);
    }
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return crossings[a].order < crossings[b].order; });
    // Runs of nearly equal keys, in place: sorted by the next key, or put leaving before entering.
    auto orderRuns = [&](std::size_t from, std::size_t to, auto close, auto then) {
        for (std::size_t k = from; k < to;) {
            std::size_t end = k + 1;
            while (end < to && close(crossings[order[end - 1]], crossings[order[end]])) {
                ++end;
            }
            then(k, end);
            k = end;
        }
    };
    auto range = [&](std::size_t from, std::size_t to) {
        return std::pair(order.begin() + static_cast<std::ptrdiff_t>(from), order.begin() + static_cast<std::ptrdiff_t>(to));
    };
    orderRuns(0, order.size(), [](const Crossing& a, const Crossing& b) { return b.order - a.order <= 1e-13; },
              [&](std::size_t from, std::size_t to) {
                  auto [begin, end] = range(from, to);
                  std::sort(begin, end, [&](std::size_t a, std::size_t b) { return crossings[a].nudge < crossings[b].nudge; });
                  orderRuns(from, to,
                            [](const Crossing& a, const Crossing& b) {
                                return b.nudge - a.nudge <= 1e-9 * std::max({1.0, std::abs(a.nudge), std::abs(b.nudge)});
                            },
                            [&](std::size_t innerFrom, std::size_t innerTo) {
                                auto [first, last] = range(innerFrom, innerTo);
                                std::stable_partition(first, last, [&](std::size_t c) { return crossings[c].down; });
                            });
              });
    const std::size_t m = order.size();
    for (std::size_t k = 0; k < m; ++k) {
        Crossing& c = crossings[order[k]];
        Crossing& next = crossings[order[(k + 1) % m]];
        if (c.down == next.down) {
            fail(name, "cannot be split along a plane through the centre: its rings cross or overlap there");
        }
        if (!c.down) {
            continue;
        }
        c.partner = order[(k + 1) % m];
        next.partner = order[k];
        double width = next.order - c.order;
        if (width < 0.0) {
            width += kTwoPi;
        }
        const int steps = static_cast<int>(std::ceil(width / kHalfPi));
        for (int s = 1; s < steps; ++s) {
            const double theta = c.theta + width * s / steps;
            c.between.push_back(ellipsoid.scaleToGeocentricSurface(std::cos(theta) * e1 + std::sin(theta) * e2));
        }
    }

    auto appendArc = [&](Ring3& loop, const Crossing& from, const Crossing& to) {
        const Ring3& ring = region.rings[from.ring];
        loop.push_back(from.point);
        std::size_t i = (from.edge + 1) % ring.size();
        while (true) {
            loop.push_back(ring[i]);
            if (i == to.edge) {
                break;
            }
            i = (i + 1) % ring.size();
        }
        loop.push_back(to.point);
    };

    // + part: arcs from entering to leaving crossings, then along the cut in +theta.
    std::vector<bool> used(crossings.size(), false);
    for (std::size_t s = 0; s < crossings.size(); ++s) {
        if (crossings[s].down || used[s]) {
            continue;
        }
        Ring3 loop;
        std::size_t u = s;
        std::size_t guard = 0;
        do {
            if (used[u] || ++guard > crossings.size()) {
                fail(name, "cannot be split along a plane through the centre: its rings cross or overlap there");
            }
            used[u] = true;
            const Crossing& cu = crossings[u];
            const Crossing& cd = crossings[cu.nextOnRing];
            appendArc(loop, cu, cd);
            loop.insert(loop.end(), cd.between.begin(), cd.between.end());
            u = cd.partner;
        } while (u != s);
        closeLoop(loop, plus);
    }
    // - part: arcs from leaving to entering crossings, then along the cut in -theta.
    std::fill(used.begin(), used.end(), false);
    for (std::size_t s = 0; s < crossings.size(); ++s) {
        if (!crossings[s].down || used[s]) {
            continue;
        }
        Ring3 loop;
        std::size_t d = s;
        std::size_t guard = 0;
        do {
            if (used[d] || ++guard > crossings.size()) {
                fail(name, "cannot be split along a plane through the centre: its rings cross or overlap there");
            }
            used[d] = true;
            const Crossing& cd = crossings[d];
            const Crossing& cu = crossings[cd.nextOnRing];
            appendArc(loop, cd, cu);
            const Crossing& back = crossings[cu.partner];
            loop.insert(loop.end(), back.between.rbegin(), back.between.rend());
            d = cu.partner;
        } while (d != s);
        closeLoop(loop, minus);
    }
    return {std::move(plus), std::move(minus)};
}

/// Winding number test in the plane: +1 inside, -1 outside, 0 on the boundary.
int locate(const glm::dvec2& p, const std::vector<glm::dvec2>& ring)
{
    int winding = 0;
    for (std::size_t i = 0; i < ring.size(); ++i) {
        const glm::dvec2& u = ring[i];
        const glm::dvec2& v = ring[(i + 1) % ring.size()];
        if (detail::onSegment(u, v, p)) {
            return 0;
        }
        if (u.y <= p.y) {
            if (v.y > p.y && detail::orient2d(u, v, p) > 0) {
                ++winding;
            }
        } else if (v.y <= p.y && detail::orient2d(u, v, p) < 0) {
            --winding;
        }
    }
    return winding != 0 ? 1 : -1;
}

/// Positions welded when closer than a tolerance (1e-12 of the ellipsoid's largest radius, 6 um on
/// the Earth), so that pieces meeting along a cut share their vertices: the cuts are computed once
/// for both sides, but one point reached along different edges can differ in its last bits.
class WeldedPositions {
public:
    explicit WeldedPositions(double tolerance) : _tolerance(tolerance) {}

    std::uint32_t add(const glm::dvec3& p)
    {
        const Cell cell = cellOf(p);
        for (std::int64_t dx = -1; dx <= 1; ++dx) {
            for (std::int64_t dy = -1; dy <= 1; ++dy) {
                for (std::int64_t dz = -1; dz <= 1; ++dz) {
                    const auto it = _cells.find({cell.x + dx, cell.y + dy, cell.z + dz});
                    if (it == _cells.end()) {
                        continue;
                    }
                    for (const std::uint32_t i : it->second) {
                        if (glm::length(positions[i] - p) <= _tolerance) {
                            return i;
                        }
                    }
                }
            }
        }
        const auto index = static_cast<std::uint32_t>(positions.size());
        positions.push_back(p);
        _cells[cell].push_back(index);
        return index;
    }
    std::vector<glm::dvec3> positions;

private:
    struct Cell {
        std::int64_t x, y, z;
        bool operator==(const Cell&) const = default;
    };
    struct Hash {
        std::size_t operator()(const Cell& c) const noexcept
        {
            std::uint64_t h = static_cast<std::uint64_t>(c.x) * 0x9e3779b97f4a7c15ull;
            h ^= static_cast<std::uint64_t>(c.y) + 0x632be59bd9b4e019ull + (h << 6) + (h >> 2);
            h ^= static_cast<std::uint64_t>(c.z) + 0x85ebca6b27d4eb4full + (h << 6) + (h >> 2);
            return static_cast<std::size_t>(h);
        }
    };
    Cell cellOf(const glm::dvec3& p) const
    {
        return {static_cast<std::int64_t>(std::floor(p.x / _tolerance)), static_cast<std::int64_t>(std::floor(p.y / _tolerance)),
                static_cast<std::int64_t>(std::floor(p.z / _tolerance))};
    }
    double _tolerance;
    std::unordered_map<Cell, std::vector<std::uint32_t>, Hash> _cells;
};

/// Triangulates the part of a region inside one octant in the octant's tangent plane.
void clipOctant(const Ellipsoid& ellipsoid, const Region& region, const glm::dvec3& centre, std::string_view name,
                WeldedPositions& welded, std::vector<std::uint32_t>& indices)
{
    const std::string pieceName = std::string(name) + " (its piece in the octant around " +
                                  std::to_string(toDegrees(std::atan2(centre.y, centre.x))) + " E, " +
                                  std::to_string(toDegrees(std::asin(std::clamp(centre.z, -1.0, 1.0)))) + " N)";
    const EllipsoidTangentPlane plane(ellipsoid, ellipsoid.scaleToGeocentricSurface(centre));
    struct Ring2 {
        std::vector<glm::dvec2> points;
        const Ring3* positions;
        double area;
    };
    std::vector<Ring2> outers;
    std::vector<Ring2> holes;
    for (const Ring3& ring : region.rings) {
        const std::optional<std::vector<glm::dvec2>> points = plane.projectPointsOntoPlane(ring);
        if (!points) {
            fail(pieceName, "a vertex of the piece cannot be projected onto the octant's tangent plane");
        }
        // Loops with no area (a ring running along the cut and back) are dropped whole: they hold
        // nothing, and their vertices lie on the boundary of the piece on the other side.
        glm::dvec2 lo(HUGE_VAL);
        glm::dvec2 hi(-HUGE_VAL);
        for (const glm::dvec2& q : *points) {
            lo = glm::min(lo, q);
            hi = glm::max(hi, q);
        }
        const glm::dvec2 extent = hi - lo;
        const double area = signedArea(*points);
        if (std::abs(area) <= 1e-12 * glm::dot(extent, extent)) {
            continue;
        }
        (area > 0.0 ? outers : holes).push_back({*points, &ring, area});
    }
    std::vector<std::vector<std::size_t>> holesOf(outers.size());
    for (std::size_t h = 0; h < holes.size(); ++h) {
        std::optional<std::size_t> best;
        for (std::size_t o = 0; o < outers.size(); ++o) {
            // The first vertex of the hole not on this outer ring's boundary decides.
            for (const glm::dvec2& p : holes[h].points) {
                const int where = locate(p, outers[o].points);
                if (where != 0) {
                    if (where > 0 && (!best || outers[o].area < outers[*best].area)) {
                        best = o;
                    }
                    break;
                }
            }
        }
        if (!best) {
            fail(pieceName, "a hole lies outside the outer ring");
        }
        holesOf[*best].push_back(h);
    }
    for (std::size_t o = 0; o < outers.size(); ++o) {
        std::vector<std::vector<glm::dvec2>> rings2{outers[o].points};
        std::vector<const glm::dvec3*> positions;
        for (const glm::dvec3& p : *outers[o].positions) {
            positions.push_back(&p);
        }
        for (const std::size_t h : holesOf[o]) {
            rings2.push_back(holes[h].points);
            for (const glm::dvec3& p : *holes[h].positions) {
                positions.push_back(&p);
            }
        }
        const PolygonTriangles triangles = earClip(rings2, pieceName);
        for (std::size_t t = 0; t < triangles.indices.size(); t += 3) {
            const std::uint32_t a = welded.add(*positions[triangles.indices[t]]);
            const std::uint32_t b = welded.add(*positions[triangles.indices[t + 1]]);
            const std::uint32_t c = welded.add(*positions[triangles.indices[t + 2]]);
            if (a != b && b != c && c != a) { // welding can close up a sliver along a cut
                indices.insert(indices.end(), {a, b, c});
            }
        }
    }
}

/// Three orthonormal plane normals: the axes turned by the first of 16 fixed rotations, or the one
/// whose planes keep farthest from the region's vertices if none keeps 1e-6 rad away.
std::array<glm::dvec3, 3> cuttingFrame(const Region& region)
{
    std::array<glm::dvec3, 3> best{glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)};
    double bestClearance = -1.0;
    for (int k = 0; k < 16; ++k) {
        // Rodrigues' rotation about an axis and by an angle that follow no pattern of the data.
        const glm::dvec3 axis = glm::normalize(glm::dvec3(std::sin(1.0 + 2.3 * k), std::cos(0.7 + 1.9 * k), 0.5 + std::sin(0.3 * k)));
        const double angle = 0.4 + 0.37 * k;
        std::array<glm::dvec3, 3> frame;
        for (int i = 0; i < 3; ++i) {
            glm::dvec3 e(0.0);
            e[i] = 1.0;
            frame[static_cast<std::size_t>(i)] = std::cos(angle) * e + std::sin(angle) * glm::cross(axis, e) +
                                                 (1.0 - std::cos(angle)) * glm::dot(axis, e) * axis;
        }
        double clearance = 1.0;
        for (const Ring3& ring : region.rings) {
            for (const glm::dvec3& p : ring) {
                const glm::dvec3 u = glm::normalize(p);
                for (const glm::dvec3& n : frame) {
                    clearance = std::min(clearance, std::abs(glm::dot(n, u)));
                }
            }
        }
        if (clearance > bestClearance) {
            bestClearance = clearance;
            best = frame;
        }
        if (clearance >= 1e-6) {
            break;
        }
    }
    return best;
}

Mesh triangulateBySplitting(const Ellipsoid& ellipsoid, const CleanPolygon& clean, double granularityRadians,
                            std::string_view name)
{
    // Orient: the outer ring counter-clockwise around the smaller region it bounds, holes clockwise.
    Region region;
    for (std::size_t r = 0; r < clean.kept.size(); ++r) {
        if (clean.kept[r].empty()) {
            continue;
        }
        Ring3 ring;
        for (const std::size_t i : clean.kept[r]) {
            ring.push_back(clean.surface[r][i]);
        }
        const std::optional<Winding> turn = winding(std::span<const glm::dvec3>(ring));
        if (!turn) {
            fail(name, "ring " + std::to_string(r) +
                           " divides the ellipsoid into two halves of equal area: which one it bounds is ambiguous");
        }
        if ((*turn == Winding::CounterClockwise) != (r == 0)) {
            std::reverse(ring.begin(), ring.end());
        }
        region.rings.push_back(std::move(ring));
    }

    // The cutting planes: three orthogonal ones, turned so that no vertex lies on or near any of
    // them (data often has vertices on the meridians 0, 90, 180 and on the equator, and a vertex
    // on a cut makes degenerate, zero-width pieces). Of a fixed series of frames, the one whose
    // planes keep farthest from every vertex.
    const std::array<glm::dvec3, 3> frame = cuttingFrame(region);
    std::vector<std::pair<glm::dvec3, Region>> pieces{{glm::dvec3(0.0), std::move(region)}};
    for (int axis = 0; axis < 3; ++axis) {
        const glm::dvec3& normal = frame[static_cast<std::size_t>(axis)];
        std::vector<std::pair<glm::dvec3, Region>> next;
        for (auto& [centre, piece] : pieces) {
            auto [plus, minus] = splitRegion(ellipsoid, piece, normal, name);
            if (!plus.empty()) {
                next.emplace_back(centre + normal, std::move(plus));
            }
            if (!minus.empty()) {
                next.emplace_back(centre - normal, std::move(minus));
            }
        }
        pieces = std::move(next);
    }

    WeldedPositions welded(1e-12 * ellipsoid.maximumRadius());
    std::vector<std::uint32_t> indices;
    for (const auto& [centre, piece] : pieces) {
        clipOctant(ellipsoid, piece, glm::normalize(centre), name, welded, indices);
    }
    return subdivideOnEllipsoid(ellipsoid, welded.positions, indices, granularityRadians);
}

} // namespace

PolygonTriangles earClipOnEllipsoid(const Ellipsoid& ellipsoid, std::span<const std::vector<glm::dvec3>> rings,
                                    std::string_view name, std::vector<LeftOutHole>* leftOutHoles)
{
    const CleanPolygon clean = cleanPolygon(ellipsoid, rings, name);
    if (clean.empty) {
        PolygonTriangles none;
        none.vertexCount = clean.kept[0].size();
        return none;
    }
    const PlaneFit fit = fitPlane(ellipsoid, clean);
    if (!fits(fit)) {
        char degrees[32];
        std::snprintf(degrees, sizeof degrees, "%.1f", toDegrees(std::acos(std::clamp(fit.widestCosine, -1.0, 1.0))));
        fail(name, std::string("a vertex lies ") + degrees +
                       " degrees from the centre of the polygon, beyond the 80 that one tangent plane can take "
                       "(triangulatePolygon splits such polygons)");
    }
    return clipInPlane(clean, fit.plane, name, leftOutHoles);
}

Mesh triangulatePolygon(const Ellipsoid& ellipsoid, std::span<const std::vector<glm::dvec3>> rings,
                        double granularityRadians, std::string_view name, std::vector<LeftOutHole>* leftOutHoles)
{
    const CleanPolygon clean = cleanPolygon(ellipsoid, rings, name);
    if (clean.empty) {
        return Mesh{};
    }
    const PlaneFit fit = fitPlane(ellipsoid, clean);
    if (!fits(fit)) {
        return triangulateBySplitting(ellipsoid, clean, granularityRadians, name);
    }
    const PolygonTriangles triangles = clipInPlane(clean, fit.plane, name, leftOutHoles);
    // Only the vertices used, in order of first use.
    std::vector<glm::dvec3> positions;
    std::unordered_map<std::uint32_t, std::uint32_t> compact;
    std::vector<std::uint32_t> indices;
    indices.reserve(triangles.indices.size());
    for (const std::uint32_t index : triangles.indices) {
        const auto [it, inserted] = compact.try_emplace(index, static_cast<std::uint32_t>(positions.size()));
        if (inserted) {
            const std::size_t r = static_cast<std::size_t>(
                std::upper_bound(clean.offsets.begin(), clean.offsets.end(), std::size_t{index}) - clean.offsets.begin() - 1);
            positions.push_back(clean.surface[r][index - clean.offsets[r]]);
        }
        indices.push_back(it->second);
    }
    return subdivideOnEllipsoid(ellipsoid, positions, indices, granularityRadians);
}

} // namespace orbis
