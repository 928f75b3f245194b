#include "orbis/core/EllipsoidPolygon.h"

#include "RobustPredicates.h"

#include "orbis/core/EllipsoidTangentPlane.h"
#include "orbis/core/Error.h"
#include "orbis/core/PolygonCleanup.h"
#include "orbis/core/TriangleMeshSubdivision.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
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
        std::vector<std::size_t> kept = cleanRing(surface);
        if (kept.size() < 3) {
            if (r == 0) {
                clean.empty = true;
            } else {
                kept.clear(); // a hole with no area removes nothing
            }
        }
        clean.surface.push_back(std::move(surface));
        clean.kept.push_back(std::move(kept));
        clean.offsets.push_back(offset);
        offset += rings[r].size();
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
PolygonTriangles clipInPlane(const CleanPolygon& clean, const EllipsoidTangentPlane& plane, std::string_view name)
{
    std::vector<std::vector<glm::dvec2>> rings2;
    std::vector<std::uint32_t> original;
    for (std::size_t r = 0; r < clean.kept.size(); ++r) {
        if (clean.kept[r].empty()) {
            continue;
        }
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
    PolygonTriangles triangles = earClip(rings2, name);
    for (std::uint32_t& index : triangles.indices) {
        index = original[index];
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
            if (w[i] == 0.0) {
                c.point = ring[i];
            } else if (w[j] == 0.0) {
                c.point = ring[j];
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

    // Along the cut, in +theta order (which keeps the + side on the left); at one place, a ring
    // leaving the + side comes before one entering it, so that a touch from the - side is a
    // zero-length interval.
    std::vector<std::size_t> order(crossings.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        const Crossing& ca = crossings[a];
        const Crossing& cb = crossings[b];
        return ca.theta != cb.theta ? ca.theta < cb.theta : (ca.down && !cb.down);
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
        double width = next.theta - c.theta;
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

/// Positions welded by exact equality, so that pieces meeting along a cut share their vertices.
class WeldedPositions {
public:
    std::uint32_t add(const glm::dvec3& p)
    {
        const Key key{std::bit_cast<std::uint64_t>(p.x), std::bit_cast<std::uint64_t>(p.y),
                      std::bit_cast<std::uint64_t>(p.z)};
        const auto [it, inserted] = _index.try_emplace(key, static_cast<std::uint32_t>(positions.size()));
        if (inserted) {
            positions.push_back(p);
        }
        return it->second;
    }
    std::vector<glm::dvec3> positions;

private:
    struct Key {
        std::uint64_t x, y, z;
        bool operator==(const Key&) const = default;
    };
    struct Hash {
        std::size_t operator()(const Key& k) const noexcept
        {
            std::uint64_t h = k.x * 0x9e3779b97f4a7c15ull;
            h ^= (k.y + 0x632be59bd9b4e019ull + (h << 6) + (h >> 2));
            h ^= (k.z + 0x85ebca6b27d4eb4full + (h << 6) + (h >> 2));
            return static_cast<std::size_t>(h);
        }
    };
    std::unordered_map<Key, std::uint32_t, Hash> _index;
};

/// Triangulates the part of a region inside one octant in the octant's tangent plane.
void clipOctant(const Ellipsoid& ellipsoid, const Region& region, const glm::dvec3& signs, std::string_view name,
                WeldedPositions& welded, std::vector<std::uint32_t>& indices)
{
    std::string pieceName = std::string(name) + " (its piece in octant ";
    for (int axis = 0; axis < 3; ++axis) {
        pieceName += signs[axis] > 0.0 ? '+' : '-';
        pieceName += static_cast<char>('x' + axis);
    }
    pieceName += ")";

    const EllipsoidTangentPlane plane(ellipsoid, ellipsoid.scaleToGeocentricSurface(signs));
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
        const double area = signedArea(*points);
        if (area > 0.0) {
            outers.push_back({*points, &ring, area});
        } else if (area < 0.0) {
            holes.push_back({*points, &ring, area});
        }
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
        for (const std::uint32_t index : triangles.indices) {
            indices.push_back(welded.add(*positions[index]));
        }
    }
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

    std::vector<std::pair<glm::dvec3, Region>> pieces{{glm::dvec3(0.0), std::move(region)}};
    for (int axis = 0; axis < 3; ++axis) {
        glm::dvec3 normal(0.0);
        normal[axis] = 1.0;
        std::vector<std::pair<glm::dvec3, Region>> next;
        for (auto& [signs, piece] : pieces) {
            auto [plus, minus] = splitRegion(ellipsoid, piece, normal, name);
            glm::dvec3 plusSigns = signs;
            glm::dvec3 minusSigns = signs;
            plusSigns[axis] = 1.0;
            minusSigns[axis] = -1.0;
            if (!plus.empty()) {
                next.emplace_back(plusSigns, std::move(plus));
            }
            if (!minus.empty()) {
                next.emplace_back(minusSigns, std::move(minus));
            }
        }
        pieces = std::move(next);
    }

    WeldedPositions welded;
    std::vector<std::uint32_t> indices;
    for (const auto& [signs, piece] : pieces) {
        clipOctant(ellipsoid, piece, signs, name, welded, indices);
    }
    return subdivideOnEllipsoid(ellipsoid, welded.positions, indices, granularityRadians);
}

} // namespace

PolygonTriangles earClipOnEllipsoid(const Ellipsoid& ellipsoid, std::span<const std::vector<glm::dvec3>> rings,
                                    std::string_view name)
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
    return clipInPlane(clean, fit.plane, name);
}

Mesh triangulatePolygon(const Ellipsoid& ellipsoid, std::span<const std::vector<glm::dvec3>> rings,
                        double granularityRadians, std::string_view name)
{
    const CleanPolygon clean = cleanPolygon(ellipsoid, rings, name);
    if (clean.empty) {
        return Mesh{};
    }
    const PlaneFit fit = fitPlane(ellipsoid, clean);
    if (!fits(fit)) {
        return triangulateBySplitting(ellipsoid, clean, granularityRadians, name);
    }
    const PolygonTriangles triangles = clipInPlane(clean, fit.plane, name);
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
