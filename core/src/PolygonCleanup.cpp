#include "orbis/core/PolygonCleanup.h"

#include "orbis/core/Ellipsoid.h"
#include "orbis/core/Math.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace orbis {

namespace {

// Removes vertices from a circular list until none is a duplicate of its successor and none is
// near-collinear with its neighbours. Geometry supplies duplicate(a, b) and collinear(a, b, c).
// Each removal re-examines only the neighbours, so the whole clean-up is linear in practice.
template <typename Geometry>
std::vector<std::size_t> cleanCircularList(std::size_t count, const Geometry& geometry)
{
    if (count == 0) {
        return {};
    }
    std::vector<std::size_t> next(count);
    std::vector<std::size_t> prev(count);
    std::vector<bool> alive(count, true);
    for (std::size_t i = 0; i < count; ++i) {
        next[i] = (i + 1) % count;
        prev[i] = (i + count - 1) % count;
    }
    std::size_t size = count;
    auto remove = [&](std::size_t i) {
        alive[i] = false;
        next[prev[i]] = next[i];
        prev[next[i]] = prev[i];
        --size;
    };

    // Pass 1: duplicates, keeping the first of each run; vertex 0 is never removed here, so the
    // closing duplicate of a GeoJSON ring is the one that goes.
    for (std::size_t i = 0; i < count; ++i) {
        while (alive[i] && size > 1 && next[i] > i && geometry.duplicate(i, next[i])) {
            remove(next[i]);
        }
    }
    while (size > 1 && geometry.duplicate(prev[0], 0)) {
        remove(prev[0]);
    }

    // Pass 2: near-collinear vertices and spike tips, with a work list of vertices to re-examine.
    std::vector<std::size_t> work;
    for (std::size_t i = count; i-- > 0;) {
        if (alive[i]) {
            work.push_back(i);
        }
    }
    while (!work.empty() && size >= 3) {
        const std::size_t b = work.back();
        work.pop_back();
        if (!alive[b]) {
            continue;
        }
        const std::size_t a = prev[b];
        const std::size_t c = next[b];
        // Of two duplicates, the later vertex goes (the first of the ring stays first).
        if (geometry.duplicate(a, b) || geometry.duplicate(b, c)) {
            const std::size_t other = geometry.duplicate(a, b) ? a : c;
            const std::size_t gone = std::max(other, b);
            const std::size_t stay = gone == b ? other : b;
            remove(gone);
            work.push_back(prev[stay]);
            work.push_back(next[stay]);
            work.push_back(stay);
            continue;
        }
        if (geometry.keep(b)) {
            continue;
        }
        if (geometry.duplicate(a, c) || geometry.collinear(a, b, c)) {
            remove(b);
            work.push_back(a);
            work.push_back(c);
        }
    }
    // Fewer than 3 left: whatever remains after duplicate removal, for the caller to judge.
    std::vector<std::size_t> kept;
    kept.reserve(size);
    for (std::size_t i = 0; i < count; ++i) {
        if (alive[i]) {
            kept.push_back(i);
        }
    }
    return kept;
}

struct PlanarGeometry {
    std::span<const glm::dvec2> ring;
    double tolerance; // absolute, in the ring's units

    static bool keep(std::size_t) noexcept { return false; }
    bool duplicate(std::size_t a, std::size_t b) const noexcept
    {
        const glm::dvec2 d = ring[b] - ring[a];
        return std::abs(d.x) <= tolerance && std::abs(d.y) <= tolerance && glm::length(d) <= tolerance;
    }
    bool collinear(std::size_t a, std::size_t b, std::size_t c) const noexcept
    {
        const glm::dvec2 ac = ring[c] - ring[a];
        const glm::dvec2 ab = ring[b] - ring[a];
        const double length = glm::length(ac);
        const double cross = ac.x * ab.y - ac.y * ab.x;
        // Distance of b from the line through a and c, without dividing by a tiny length.
        return std::abs(cross) <= tolerance * length;
    }
};

struct EllipsoidGeometry {
    std::vector<glm::dvec3> directions;
    double tolerance; // sine of the angle
    std::span<const bool> pinned;

    bool keep(std::size_t i) const noexcept { return i < pinned.size() && pinned[i]; }
    bool duplicate(std::size_t a, std::size_t b) const noexcept
    {
        const glm::dvec3& u = directions[a];
        const glm::dvec3& v = directions[b];
        return glm::dot(u, v) > 0.0 && glm::length(glm::cross(u, v)) <= kEllipsoidDuplicateToleranceRadians;
    }
    bool collinear(std::size_t a, std::size_t b, std::size_t c) const noexcept
    {
        const glm::dvec3& u = directions[a];
        const glm::dvec3& v = directions[b];
        const glm::dvec3& w = directions[c];
        const glm::dvec3 normal = glm::cross(u, w);
        const double length = glm::length(normal);
        if (length <= kEllipsoidDuplicateToleranceRadians) {
            // a and c are (nearly) antipodal: no plane through them; b is what decides the path.
            return false;
        }
        if (std::abs(glm::dot(v, normal)) > tolerance * length) {
            return false;
        }
        // On the curve through a and c: b goes if the path a -> b -> c turns back at b (a spike),
        // or if it runs straight on and the short way from a to c passes b (less than half a turn).
        const bool straight = glm::dot(glm::cross(u, v), glm::cross(v, w)) > 0.0;
        return !straight || std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v)) +
                                    std::atan2(glm::length(glm::cross(v, w)), glm::dot(v, w)) <
                                kPi - kEllipsoidDuplicateToleranceRadians;
    }
};

} // namespace

std::vector<std::size_t> cleanRing(std::span<const glm::dvec2> ring, double relativeTolerance)
{
    glm::dvec2 lo(HUGE_VAL);
    glm::dvec2 hi(-HUGE_VAL);
    for (const glm::dvec2& p : ring) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const double extent = ring.empty() ? 0.0 : glm::length(hi - lo);
    const double tolerance = std::isfinite(extent) ? std::max(relativeTolerance, 0.0) * extent : 0.0;
    return cleanCircularList(ring.size(), PlanarGeometry{ring, tolerance});
}

std::vector<std::size_t> cleanRing(std::span<const glm::dvec3> ring, double toleranceRadians,
                                   std::span<const bool> keep)
{
    EllipsoidGeometry geometry;
    geometry.pinned = keep;
    geometry.directions.reserve(ring.size());
    for (const glm::dvec3& p : ring) {
        geometry.directions.push_back(Ellipsoid::geocentricSurfaceNormal(p));
    }
    geometry.tolerance = std::sin(std::clamp(toleranceRadians, 0.0, kHalfPi));
    return cleanCircularList(ring.size(), geometry);
}

double signedArea(std::span<const glm::dvec2> ring) noexcept
{
    if (ring.size() < 3) {
        return 0.0;
    }
    const glm::dvec2 origin = ring[0];
    double twice = 0.0;
    for (std::size_t i = 1; i + 1 < ring.size(); ++i) {
        const glm::dvec2 a = ring[i] - origin;
        const glm::dvec2 b = ring[i + 1] - origin;
        twice += a.x * b.y - a.y * b.x;
    }
    return 0.5 * twice;
}

std::optional<Winding> winding(std::span<const glm::dvec2> ring) noexcept
{
    const double area = signedArea(ring);
    if (area == 0.0 || !std::isfinite(area)) {
        return std::nullopt;
    }
    return area > 0.0 ? Winding::CounterClockwise : Winding::Clockwise;
}

bool setWinding(std::span<glm::dvec2> ring, Winding wanted) noexcept
{
    const std::optional<Winding> current = winding(std::span<const glm::dvec2>(ring));
    if (!current) {
        return false;
    }
    if (*current != wanted) {
        std::reverse(ring.begin(), ring.end());
    }
    return true;
}

namespace {

// The sum of the signed solid angles of the triangles (d, vi, vi+1) over every edge of the ring,
// by Van Oosterom and Strackee's formula tan(omega / 2) = d . (vi x vj) / (1 + d.vi + vi.vj + vj.d).
// Their boundaries add up to the ring, so the sum is the area on the ring's left, modulo 4 pi. The
// apex d must not be antipodal to any vertex (the arc from d to it would be undefined): of 26
// directions (axes, face diagonals, corners of a cube) it is the one farthest from all antipodes.
double fanSolidAngle(std::span<const glm::dvec3> ring) noexcept
{
    if (ring.size() < 3) {
        return 0.0;
    }
    std::vector<glm::dvec3> directions;
    directions.reserve(ring.size());
    for (const glm::dvec3& p : ring) {
        directions.push_back(Ellipsoid::geocentricSurfaceNormal(p));
    }
    glm::dvec3 apex(0.0, 0.0, 1.0);
    double bestMargin = -1.0;
    for (int x = -1; x <= 1; ++x) {
        for (int y = -1; y <= 1; ++y) {
            for (int z = -1; z <= 1; ++z) {
                if (x == 0 && y == 0 && z == 0) {
                    continue;
                }
                const glm::dvec3 d = glm::normalize(glm::dvec3(x, y, z));
                double margin = 2.0;
                for (const glm::dvec3& u : directions) {
                    margin = std::min(margin, 1.0 + glm::dot(d, u));
                }
                if (margin > bestMargin) {
                    bestMargin = margin;
                    apex = d;
                }
            }
        }
    }
    double sum = 0.0;
    for (std::size_t i = 0; i < directions.size(); ++i) {
        const glm::dvec3& ui = directions[i];
        const glm::dvec3& uj = directions[(i + 1) % directions.size()];
        const double numerator = glm::dot(apex, glm::cross(ui, uj));
        const double denominator = 1.0 + glm::dot(apex, ui) + glm::dot(ui, uj) + glm::dot(uj, apex);
        sum += 2.0 * std::atan2(numerator, denominator);
    }
    return sum;
}

} // namespace

double leftSolidAngle(std::span<const glm::dvec3> ring) noexcept
{
    const double sum = fanSolidAngle(ring);
    double left = std::fmod(sum, 2.0 * kTwoPi);
    if (left < 0.0) {
        left += 2.0 * kTwoPi;
    }
    return left >= 2.0 * kTwoPi ? 0.0 : left;
}

std::optional<Winding> winding(std::span<const glm::dvec3> ring) noexcept
{
    if (ring.size() < 3) {
        return std::nullopt;
    }
    const double sum = fanSolidAngle(ring);
    if (sum == 0.0) {
        return std::nullopt;
    }
    const double left = leftSolidAngle(ring);
    if (std::abs(left - kTwoPi) <= 1e-9) {
        return std::nullopt;
    }
    return left < kTwoPi ? Winding::CounterClockwise : Winding::Clockwise;
}

bool setWinding(std::span<glm::dvec3> ring, Winding wanted) noexcept
{
    const std::optional<Winding> current = winding(std::span<const glm::dvec3>(ring));
    if (!current) {
        return false;
    }
    if (*current != wanted) {
        std::reverse(ring.begin(), ring.end());
    }
    return true;
}

} // namespace orbis
