#include <orbis/core/EarClipping.h>
#include <orbis/core/Error.h>
#include <orbis/core/Math.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <thread>

using namespace orbis;
using Catch::Matchers::Contains;
using Catch::Matchers::WithinRel;

namespace {

using Ring = std::vector<glm::dvec2>;
using Rings = std::vector<Ring>;

/// Orientation in 80-bit long double: exact for the small integers and the 1e-15 offsets here.
long double orient(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c)
{
    using Long = long double;
    return (Long(b.x) - Long(a.x)) * (Long(c.y) - Long(a.y)) - (Long(b.y) - Long(a.y)) * (Long(c.x) - Long(a.x));
}

long double ringArea(const Ring& ring)
{
    long double twice = 0.0L;
    for (std::size_t i = 0; i < ring.size(); ++i) {
        const glm::dvec2& a = ring[i];
        const glm::dvec2& b = ring[(i + 1) % ring.size()];
        using Long = long double;
        twice += Long(a.x) * Long(b.y) - Long(a.y) * Long(b.x);
    }
    return 0.5L * twice;
}

std::vector<glm::dvec2> concatenated(const Rings& rings)
{
    std::vector<glm::dvec2> all;
    for (const Ring& ring : rings) {
        all.insert(all.end(), ring.begin(), ring.end());
    }
    return all;
}

/// Every triangle strictly counter-clockwise, and together they cover the polygon's area
/// (|outer| - sum |holes|, to 1e-12 relative: rounding of the sums).
void requireCoversArea(const Rings& rings, const PolygonTriangles& result)
{
    const std::vector<glm::dvec2> all = concatenated(rings);
    long double covered = 0.0L;
    for (std::size_t t = 0; t < result.indices.size(); t += 3) {
        const long double twice = orient(all[result.indices[t]], all[result.indices[t + 1]], all[result.indices[t + 2]]);
        INFO("triangle " << t / 3);
        REQUIRE(twice > 0.0L);
        covered += 0.5L * twice;
    }
    long double expected = std::abs(ringArea(rings[0]));
    for (std::size_t r = 1; r < rings.size(); ++r) {
        expected -= std::abs(ringArea(rings[r]));
    }
    REQUIRE_THAT(static_cast<double>(covered), WithinRel(static_cast<double>(expected), 1e-12));
}

/// No two triangles overlap (their interiors are disjoint, by separating axes: an edge of one with
/// the other entirely on its outer side), and each triangle's centroid lies inside the polygon
/// (outer ring minus holes, by winding numbers). With requireCoversArea: an exact cover. For the
/// small polygons whose rings touch, where requireTriangulation's edge count does not apply.
void requireNoOverlap(const Rings& rings, const PolygonTriangles& result)
{
    const std::vector<glm::dvec2> all = concatenated(rings);
    auto corner = [&](std::size_t t, int k) { return all[result.indices[3 * t + static_cast<std::size_t>(k)]]; };
    auto separates = [&](std::size_t t, std::size_t u) {
        for (int k = 0; k < 3; ++k) {
            const glm::dvec2 a = corner(t, k);
            const glm::dvec2 b = corner(t, (k + 1) % 3);
            if (orient(a, b, corner(u, 0)) <= 0.0L && orient(a, b, corner(u, 1)) <= 0.0L &&
                orient(a, b, corner(u, 2)) <= 0.0L) {
                return true;
            }
        }
        return false;
    };
    auto winding = [](const Ring& ring, const glm::dvec2& p) {
        int w = 0;
        for (std::size_t i = 0; i < ring.size(); ++i) {
            const glm::dvec2& u = ring[i];
            const glm::dvec2& v = ring[(i + 1) % ring.size()];
            if (u.y <= p.y && v.y > p.y && orient(u, v, p) > 0.0L) {
                ++w;
            } else if (u.y > p.y && v.y <= p.y && orient(u, v, p) < 0.0L) {
                --w;
            }
        }
        return w;
    };
    for (std::size_t t = 0; t < result.triangleCount(); ++t) {
        INFO("triangle " << t);
        for (std::size_t u = t + 1; u < result.triangleCount(); ++u) {
            INFO("and triangle " << u);
            REQUIRE((separates(t, u) || separates(u, t)));
        }
        const glm::dvec2 centroid = (corner(t, 0) + corner(t, 1) + corner(t, 2)) / 3.0;
        REQUIRE(winding(rings[0], centroid) != 0);
        for (std::size_t r = 1; r < rings.size(); ++r) {
            REQUIRE(winding(rings[r], centroid) == 0);
        }
    }
}

/// The triangles form a triangulation of the rings: besides covering the area with positive
/// triangles, every edge of the rings (outer counter-clockwise, holes clockwise) is an edge of
/// exactly one triangle, in that direction, and every other edge is shared by exactly two triangles
/// in opposite directions. By a degree argument this means no gaps and no overlaps. Valid for rings
/// whose vertices are all distinct (no touching, no duplicates besides the closing one).
void requireTriangulation(const Rings& rings, const PolygonTriangles& result)
{
    requireCoversArea(rings, result);
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
    for (std::size_t t = 0; t < result.indices.size(); t += 3) {
        for (int k = 0; k < 3; ++k) {
            ++edges[{result.indices[t + static_cast<std::size_t>(k)], result.indices[t + static_cast<std::size_t>((k + 1) % 3)]}];
        }
    }
    std::uint32_t offset = 0;
    std::size_t boundary = 0;
    for (std::size_t r = 0; r < rings.size(); ++r) {
        std::size_t n = rings[r].size();
        if (n > 1 && rings[r].front() == rings[r].back()) {
            --n;
        }
        const bool ccw = ringArea(rings[r]) > 0.0L;
        const bool forward = (r == 0) == ccw;
        for (std::size_t i = 0; i < n; ++i) {
            auto from = static_cast<std::uint32_t>(offset + i);
            auto to = static_cast<std::uint32_t>(offset + (i + 1) % n);
            if (!forward) {
                std::swap(from, to);
            }
            INFO("ring " << r << " edge " << i);
            REQUIRE(edges[{from, to}] == 1);
            REQUIRE(edges[{to, from}] == 0);
            ++boundary;
        }
        offset += static_cast<std::uint32_t>(rings[r].size());
    }
    std::size_t inner = 0;
    for (const auto& [edge, count] : edges) {
        if (count == 0) {
            continue;
        }
        REQUIRE(count == 1);
        const auto reverse = edges.find({edge.second, edge.first});
        if (reverse != edges.end() && reverse->second == 1) {
            ++inner;
        }
    }
    REQUIRE(inner + boundary == 3 * result.triangleCount());
}

Ring square(double x0, double y0, double size, bool ccw = true)
{
    Ring ring = {{x0, y0}, {x0 + size, y0}, {x0 + size, y0 + size}, {x0, y0 + size}};
    if (!ccw) {
        std::reverse(ring.begin(), ring.end());
    }
    return ring;
}

} // namespace

TEST_CASE("earClip triangulates a square given clockwise and closed, with indices into the input", "[polygon][ear-clipping]")
{
    const Rings rings = {{{0, 0}, {0, 2}, {3, 2}, {3, 0}, {0, 0}}};
    const PolygonTriangles result = earClip(rings);
    REQUIRE(result.vertexCount == 4);
    REQUIRE(result.holeCount == 0);
    REQUIRE(result.triangleCount() == 2);
    for (const std::uint32_t index : result.indices) {
        REQUIRE(index < 4); // never the closing duplicate, index 4
    }
    requireTriangulation(rings, result);
}

TEST_CASE("earClip triangulates convex rings without checking their edges, and only them", "[polygon][ear-clipping]")
{
    // Random convex rings of 3 to 80 vertices (up to 32 triangulated at once), either way round,
    // closed or not, some with a vertex repeated: n - 2 triangles covering the ring, indices into
    // the input.
    const auto seed = GENERATE(take(100, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const int n = 3 + static_cast<int>(78 * unit(random));
    std::vector<double> angles(static_cast<std::size_t>(n));
    for (double& angle : angles) {
        angle = kTwoPi * unit(random);
    }
    std::sort(angles.begin(), angles.end());
    if (unit(random) < 0.5) {
        std::reverse(angles.begin(), angles.end());
    }
    const bool repeat = unit(random) < 0.3;
    Ring ring;
    for (std::size_t k = 0; k < angles.size(); ++k) {
        const glm::dvec2 p(3.0 + 2.0 * std::cos(angles[k]), -1.0 + 1.5 * std::sin(angles[k])); // on an ellipse: convex
        ring.push_back(p);
        if (repeat && k == 1) {
            ring.push_back(p);
        }
    }
    if (unit(random) < 0.5) {
        ring.push_back(ring.front());
    }
    const Rings rings{ring};
    const PolygonTriangles result = earClip(rings);
    REQUIRE(result.vertexCount == static_cast<std::size_t>(n));
    REQUIRE(result.triangleCount() == static_cast<std::size_t>(n - 2));
    if (repeat) {
        requireCoversArea(rings, result);
        requireNoOverlap(rings, result);
    } else {
        requireTriangulation(rings, result);
    }

    // Every turn one way, but round twice: a pentagram crosses itself, and so does a ring of 101
    // vertices round twice (past the small rings, where a convex ring's edges go unchecked).
    for (const int points : {5, 101}) {
        Ring twice;
        for (int k = 0; k < points; ++k) {
            const double angle = 2.0 * kTwoPi * k / points;
            twice.push_back({std::cos(angle), std::sin(angle)});
        }
        REQUIRE_THROWS_WITH(earClip(Rings{twice}, "twice round"), Contains("polygon 'twice round'") && Contains("crosses"));
    }
    // A straight vertex stays a vertex.
    const Rings straight{{{0, 0}, {1, 0}, {2, 0}, {2, 1}, {0, 1}}};
    const PolygonTriangles kept = earClip(straight);
    REQUIRE(kept.triangleCount() == 3);
    requireTriangulation(straight, kept);
}

TEST_CASE("earClip triangulates concave polygons into n - 2 triangles", "[polygon][ear-clipping]")
{
    SECTION("a comb")
    {
        // Five teeth 0.5 wide with slots 1.5 wide and 4 deep between them.
        Ring comb = {{0, 0}, {10, 0}, {10, 5}};
        for (int slot = 4; slot >= 0; --slot) {
            comb.push_back({2.0 * slot + 1.75, 5});
            comb.push_back({2.0 * slot + 1.75, 1});
            comb.push_back({2.0 * slot + 0.25, 1});
            comb.push_back({2.0 * slot + 0.25, 5});
        }
        comb.push_back({0, 5});
        const PolygonTriangles result = earClip(Rings{comb});
        REQUIRE(result.triangleCount() == comb.size() - 2);
        requireTriangulation(Rings{comb}, result);
    }
    SECTION("a spiral")
    {
        Ring outward;
        Ring inward;
        for (int i = 0; i <= 60; ++i) {
            const double angle = 0.25 * i;
            const double radius = 1.0 + 0.3 * angle;
            outward.push_back({(radius + 0.5) * std::cos(angle), (radius + 0.5) * std::sin(angle)});
            inward.push_back({radius * std::cos(angle), radius * std::sin(angle)});
        }
        Ring spiral = inward;
        spiral.insert(spiral.end(), outward.rbegin(), outward.rend());
        const PolygonTriangles result = earClip(Rings{spiral});
        REQUIRE(result.triangleCount() == spiral.size() - 2);
        requireTriangulation(Rings{spiral}, result);
    }
    SECTION("random star-shaped polygons")
    {
        const auto seed = GENERATE(take(3, random(0u, 1000000u)));
        INFO("seed " << seed);
        std::mt19937_64 random(seed);
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        for (int trial = 0; trial < 50; ++trial) {
            const int n = 3 + static_cast<int>(200 * unit(random));
            Ring star;
            for (int i = 0; i < n; ++i) {
                const double angle = kTwoPi * i / n;
                const double radius = 0.05 + unit(random);
                star.push_back({radius * std::cos(angle), radius * std::sin(angle)});
            }
            const PolygonTriangles result = earClip(Rings{star});
            REQUIRE(result.triangleCount() == star.size() - 2);
            requireTriangulation(Rings{star}, result);
        }
    }
}

TEST_CASE("earClip keeps collinear and near-collinear vertices and triangulates them exactly", "[polygon][ear-clipping]")
{
    SECTION("vertices along straight edges")
    {
        // A 4 x 4 square with the points of a unit grid along its sides: 16 vertices, half of them
        // with an angle of exactly 180 degrees.
        Ring ring;
        for (int i = 0; i < 4; ++i) ring.push_back({i, 0});
        for (int i = 0; i < 4; ++i) ring.push_back({4, i});
        for (int i = 4; i > 0; --i) ring.push_back({i, 4});
        for (int i = 4; i > 0; --i) ring.push_back({0, i});
        const PolygonTriangles result = earClip(Rings{ring});
        REQUIRE(result.triangleCount() == 14);
        requireTriangulation(Rings{ring}, result);
    }
    SECTION("a zigzag of 1e-15 along an edge")
    {
        // Orientation tests of such vertices in doubles get the sign wrong; the exact ones do not.
        Ring ring;
        for (int i = 0; i <= 20; ++i) {
            ring.push_back({0.1 * i, (i % 2 ? 1e-15 : 0.0)});
        }
        ring.push_back({2, 1});
        ring.push_back({0, 1});
        const PolygonTriangles result = earClip(Rings{ring}, "zigzag", 0.0);
        REQUIRE(result.triangleCount() == ring.size() - 2);
        requireTriangulation(Rings{ring}, result);
    }
    SECTION("a reflex vertex on the diagonals of the convex corners' ears")
    {
        // (2, 2) lies on the diagonals (0, 0)-(4, 4) and (4, 0)-(0, 4) of the ears at (4, 0) and (0, 0).
        const Ring ring = {{0, 0}, {4, 0}, {4, 4}, {3, 4}, {2, 2}, {1, 4}, {0, 4}};
        const PolygonTriangles result = earClip(Rings{ring});
        REQUIRE(result.triangleCount() == 5);
        requireTriangulation(Rings{ring}, result);
    }
}

TEST_CASE("earClip bridges holes: n + 2h - 2 triangles covering the area between the rings", "[polygon][ear-clipping]")
{
    SECTION("one hole, given counter-clockwise")
    {
        const Rings rings = {square(0, 0, 10), square(3, 3, 4)};
        const PolygonTriangles result = earClip(rings);
        REQUIRE(result.holeCount == 1);
        REQUIRE(result.triangleCount() == 8 + 2 - 2);
        requireTriangulation(rings, result);
    }
    SECTION("holes in a column sharing their rightmost x, behind a reflex vertex of the outer ring")
    {
        // The outer ring has a notch from the right whose tip (6, 5) hides the right side from
        // the holes' rightmost vertices.
        const Rings rings = {{{0, 0}, {10, 0}, {10, 4.5}, {6, 5}, {10, 5.5}, {10, 10}, {0, 10}},
                             square(1, 1, 2, false),
                             square(1, 4, 2, false),
                             square(1, 7, 2, true)};
        const PolygonTriangles result = earClip(rings);
        REQUIRE(result.holeCount == 3);
        REQUIRE(result.triangleCount() == 7 + 12 + 2 * 3 - 2);
        requireTriangulation(rings, result);
    }
    SECTION("a grid of jittered holes")
    {
        const auto seed = GENERATE(take(3, random(0u, 1000000u)));
        INFO("seed " << seed);
        std::mt19937_64 random(seed);
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        Rings rings = {square(0, 0, 20)};
        std::size_t n = 4;
        for (int i = 0; i < 6; ++i) {
            for (int j = 0; j < 6; ++j) {
                // A hole of 3 to 8 vertices inside cell (i, j), either winding.
                const int count = 3 + static_cast<int>(6 * unit(random));
                const glm::dvec2 centre(3.0 * i + 2.5 + 0.5 * unit(random), 3.0 * j + 2.5 + 0.5 * unit(random));
                Ring hole;
                for (int k = 0; k < count; ++k) {
                    const double angle = kTwoPi * k / count;
                    const double radius = 0.5 + 0.7 * unit(random);
                    hole.push_back(centre + radius * glm::dvec2(std::cos(angle), std::sin(angle)));
                }
                if (unit(random) < 0.5) {
                    std::reverse(hole.begin(), hole.end());
                }
                n += hole.size();
                rings.push_back(hole);
            }
        }
        const PolygonTriangles result = earClip(rings);
        REQUIRE(result.holeCount == 36);
        REQUIRE(result.triangleCount() == n + 2 * 36 - 2);
        requireTriangulation(rings, result);
    }
}

TEST_CASE("earClip joins a thousand holes to a wavy outer ring, each bridge checked against the edges near it",
          "[polygon][ear-clipping]")
{
    // As a country's lakes: many small holes, of 4 to 8 vertices and either winding, on a jittered
    // grid inside a coast-like ring. Most bridges end on holes bridged before (the nearest vertex
    // to the right), so the edges' index must follow every splice. (Its time, and earcut's, is in
    // the benchmark: orbis_bench --only polygons.)
    std::mt19937_64 random(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    Ring coast;
    for (int i = 0; i < 2000; ++i) {
        const double angle = kTwoPi * i / 2000;
        const double radius = 1.0 + 0.05 * std::sin(37.0 * angle) + 0.01 * unit(random);
        coast.push_back({radius * std::cos(angle), radius * std::sin(angle)});
    }
    Rings rings = {coast};
    std::size_t n = coast.size();
    const int side = 32;
    const double cell = 1.2 / side;
    for (int h = 0; h < side * side; ++h) {
        const glm::dvec2 centre(-0.6 + cell * (h % side + 0.45 + 0.1 * unit(random)),
                                -0.6 + cell * (h / side + 0.45 + 0.1 * unit(random)));
        const int count = 4 + static_cast<int>(5 * unit(random));
        Ring hole;
        for (int k = 0; k < count; ++k) {
            const double angle = kTwoPi * k / count;
            hole.push_back(centre + cell * (0.2 + 0.2 * unit(random)) * glm::dvec2(std::cos(angle), std::sin(angle)));
        }
        if (unit(random) < 0.5) {
            std::reverse(hole.begin(), hole.end());
        }
        n += hole.size();
        rings.push_back(hole);
    }
    const PolygonTriangles result = earClip(rings);
    REQUIRE(result.holeCount == side * side);
    REQUIRE(result.triangleCount() == n + 2 * side * side - 2);
    requireTriangulation(rings, result);

    SECTION("a hole outside the outer ring, or inside another hole, is named")
    {
        Rings outside = rings;
        outside.push_back(square(2, 2, 0.1, false));
        REQUIRE_THROWS_WITH(earClip(outside), Contains("hole ring 1025 lies outside the outer ring"));
        Rings nested = rings;
        const glm::dvec2 inFirst = -glm::dvec2(0.6) + cell * glm::dvec2(0.5); // within 0.07 cells of hole 1's centre
        nested.push_back({inFirst, inFirst + glm::dvec2(1e-4, 0), inFirst + glm::dvec2(1e-4), inFirst + glm::dvec2(0, 1e-4)});
        REQUIRE_THROWS_WITH(earClip(nested), Contains("hole ring 1025 lies inside hole ring 1"));
    }
}

TEST_CASE("earClip leaves out faulty holes when asked, naming each, and triangulates the rest", "[polygon][ear-clipping]")
{
    // A 10 x 10 square with a good hole at (1, 1), and one faulty hole at a time.
    const Ring outer = square(0, 0, 10);
    const Ring good = square(1, 1, 2, false);
    struct Case {
        const char* what;
        Ring faulty;
        std::size_t leftOut; // the ring expected to go
        const char* reason;
    };
    const Case cases[] = {
        {"outside the outer ring", square(20, 20, 1), 2, "it lies outside the outer ring"},
        {"inside the good hole", square(1.5, 1.5, 0.5), 2, "it lies inside hole ring 1"},
        {"crossing the good hole, and larger", square(2, 2, 3), 1, "it crosses hole ring 2"},
        {"crossing the outer ring", square(8, 4, 4), 2, "it crosses the outer ring"},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        const Rings rings = {outer, good, c.faulty};
        REQUIRE_THROWS_AS(earClip(rings), Error); // by default they throw
        std::vector<LeftOutHole> leftOut;
        const PolygonTriangles result = earClip(rings, "lakes", kSpikeRepairRelativeArea, &leftOut);
        REQUIRE(leftOut.size() == 1);
        CHECK(leftOut[0].ring == c.leftOut);
        CHECK_THAT(leftOut[0].reason, Contains(c.reason));
        CHECK(result.holeCount == 1);
        Rings kept = rings;
        kept.erase(kept.begin() + static_cast<std::ptrdiff_t>(c.leftOut));
        requireTriangulation(kept, result.indices.empty() ? result : [&] {
            // The indices count the rings given: renumber those after the left-out ring.
            PolygonTriangles renumbered = result;
            const auto from = static_cast<std::uint32_t>(4 * c.leftOut);
            for (std::uint32_t& index : renumbered.indices) {
                REQUIRE((index < from || index >= from + 4));
                index = index < from ? index : index - 4;
            }
            return renumbered;
        }());
    }
    SECTION("the outer ring crossing itself still throws")
    {
        std::vector<LeftOutHole> leftOut;
        const Rings bowtie = {{{0, 0}, {10, 10}, {10, 0}, {0, 10}}, good};
        REQUIRE_THROWS_WITH(earClip(bowtie, "bowtie", kSpikeRepairRelativeArea, &leftOut), Contains("crosses"));
    }
}

TEST_CASE("earClip gives no triangles for rings with no area, and drops such holes", "[polygon][ear-clipping]")
{
    const PolygonTriangles point = earClip(Rings{{{1, 1}, {1, 1}, {1, 1}, {1, 1}}});
    REQUIRE(point.indices.empty());
    REQUIRE(point.vertexCount == 1);
    REQUIRE(earClip(Rings{{{0, 0}, {1, 1}}}).indices.empty());
    REQUIRE(earClip(Rings{{{0, 0}, {1, 1}, {2, 2}, {3, 3}}}).indices.empty()); // collinear
    REQUIRE(earClip(Rings{Ring{}}).indices.empty());

    const Rings withFlatHole = {square(0, 0, 4), {{1, 1}, {2, 2}, {3, 3}}, {{1, 1}, {1, 1}}};
    const PolygonTriangles result = earClip(withFlatHole);
    REQUIRE(result.holeCount == 0);
    REQUIRE(result.triangleCount() == 2);
}

TEST_CASE("earClip removes repeated vertices", "[polygon][ear-clipping]")
{
    const Rings rings = {{{0, 0}, {0, 0}, {2, 0}, {2, 0}, {2, 0}, {2, 2}, {0, 2}, {0, 0}, {0, 0}}};
    const PolygonTriangles result = earClip(rings);
    REQUIRE(result.vertexCount == 4);
    REQUIRE(result.triangleCount() == 2);
    requireCoversArea(rings, result);
}

TEST_CASE("earClip triangulates rings that touch themselves or each other", "[polygon][ear-clipping]")
{
    SECTION("two lobes of one ring meeting at a vertex: two triangles fewer than n - 2")
    {
        const Rings rings = {{{0, 0}, {2, 1}, {1, 2.5}, {0, 0}, {-2, -1}, {-1, -2}}};
        const PolygonTriangles result = earClip(rings);
        REQUIRE(result.triangleCount() == 2);
        requireCoversArea(rings, result);
        requireNoOverlap(rings, result);
    }
    SECTION("a ring whose vertex touches its own edge")
    {
        // The notch's tip (2, 0) lies on the bottom edge: two regions joined at a point.
        const Rings rings = {{{0, 0}, {4, 0}, {4, 3}, {3, 3}, {2, 0}, {1, 3}, {0, 3}}};
        const PolygonTriangles result = earClip(rings);
        requireCoversArea(rings, result);
        requireNoOverlap(rings, result);
    }
    SECTION("a hole touching the outer ring at a vertex and at an edge")
    {
        const Rings rings = {square(0, 0, 4), {{0, 0}, {1, 2}, {2, 1}}, {{4, 2}, {3, 1.5}, {3, 2.5}}};
        const PolygonTriangles result = earClip(rings);
        REQUIRE(result.holeCount == 2);
        requireCoversArea(rings, result);
        requireNoOverlap(rings, result);
    }
    SECTION("two holes touching at a vertex")
    {
        const Rings rings = {square(0, 0, 6), {{1, 1}, {3, 3}, {1, 3}}, {{3, 3}, {5, 3}, {5, 5}}};
        const PolygonTriangles result = earClip(rings);
        requireCoversArea(rings, result);
        requireNoOverlap(rings, result);
    }
}

TEST_CASE("earClip repairs a spike whose tip has twisted over its neighbour, within its limit", "[polygon][ear-clipping]")
{
    // A long thin spike down to (1.0001, -10); the edge into it from (0, 0) to (1.0002, 1e-5)
    // crosses the spike's return edge from the tip to (1, 2e-5). The spike holds 1e-3, 2e-5 of the
    // polygon's area.
    const Rings rings = {{{-5, 5}, {-5, 0}, {0, 0}, {1.0002, 1e-5}, {1.0001, -10}, {1, 2e-5}, {5, 0}, {5, 5}}};
    REQUIRE_THROWS_AS(earClip(rings, "twisted", 0.0), Error);
    const PolygonTriangles result = earClip(rings, "twisted");
    REQUIRE(result.repairedVertices == 1);
    REQUIRE(result.vertexCount == 7);
    REQUIRE(result.triangleCount() == 5);
    REQUIRE(result.repairedArea > 0.0);
    REQUIRE(result.repairedArea < 1e-4 * 50.0);
    for (const std::uint32_t index : result.indices) {
        REQUIRE(index != 4); // the tip is gone
    }
}

TEST_CASE("earClip cuts off a small lobe folded over at a vertex the ring passes twice", "[polygon][ear-clipping]")
{
    // A square whose ring, at (10, 10), runs round a little clockwise loop and comes back: as
    // quantized coasts fold where they return to a point. The loop holds 0.5% of the area.
    const Rings rings = {{{0, 0}, {10, 0}, {10, 10}, {10, 11}, {11, 11}, {10, 10}, {0, 10}}};
    REQUIRE_THROWS_AS(earClip(rings, "folded", 0.0), Error);
    const PolygonTriangles result = earClip(rings, "folded");
    REQUIRE(result.repairedVertices == 3);
    REQUIRE(result.repairedArea == 0.5);
    REQUIRE(result.triangleCount() == 2);
    double covered = 0.0;
    const std::vector<glm::dvec2> all = concatenated(rings);
    for (std::size_t t = 0; t < result.indices.size(); t += 3) {
        covered += 0.5 * static_cast<double>(orient(all[result.indices[t]], all[result.indices[t + 1]], all[result.indices[t + 2]]));
    }
    REQUIRE(covered == 100.0);
}

TEST_CASE("earClip reports bad input with the polygon's name", "[polygon][ear-clipping]")
{
    REQUIRE_THROWS_WITH(earClip(Rings{{{0, 0}, {3, 3}, {3, 0}, {0, 2}}}, "bow tie"),
                        Contains("polygon 'bow tie'") && Contains("crosses"));
    // A symmetric bow tie has no signed area, but it is no line either.
    REQUIRE_THROWS_WITH(earClip(Rings{{{0, 0}, {2, 2}, {2, 0}, {0, 2}}}, "bow tie"), Contains("crosses"));
    REQUIRE_THROWS_WITH(earClip(Rings{{{0, 0}, {4, 0}, {4, 4}, {2, -1}, {0, 4}}}, "crossing"),
                        Contains("crosses"));
    REQUIRE_THROWS_WITH(earClip(Rings{square(0, 0, 1), square(5, 5, 1)}, "island"),
                        Contains("polygon 'island'") && Contains("hole ring 1 lies outside"));
    REQUIRE_THROWS_WITH(earClip(Rings{square(0, 0, 10), square(1, 1, 5), square(2, 2, 1)}, "nested"),
                        Contains("hole ring 2 lies inside hole ring 1"));
    REQUIRE_THROWS_WITH(earClip(Rings{square(0, 0, 10), square(1, 1, 5), square(4, 4, 5)}, "overlapping"),
                        Contains("crosses"));
    const double nan = std::numeric_limits<double>::quiet_NaN();
    REQUIRE_THROWS_WITH(earClip(Rings{{{0, 0}, {1, nan}, {1, 1}}}, "nan"),
                        Contains("polygon 'nan'") && Contains("vertex 1 of ring 0 is not finite"));
    REQUIRE_THROWS_WITH(earClip(Rings{}, "empty"), Contains("has no rings"));
}

TEST_CASE("earClip handles thousands of vertices", "[polygon][ear-clipping]")
{
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    Ring star;
    const int n = 5000;
    for (int i = 0; i < n; ++i) {
        const double angle = kTwoPi * i / n;
        const double radius = 1.0 + 0.5 * unit(random);
        star.push_back({radius * std::cos(angle), radius * std::sin(angle)});
    }
    const PolygonTriangles result = earClip(Rings{star});
    REQUIRE(result.triangleCount() == n - 2);
    requireCoversArea(Rings{star}, result);
}

TEST_CASE("earClip gives the same triangles whatever it triangulated before, on any thread", "[polygon][ear-clipping]")
{
    // The clipper keeps its memory between polygons on a thread (and lets it go after one larger
    // than it keeps): nothing of one polygon may leak into the next, a polygon that threw included.
    std::mt19937_64 random(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    auto star = [&](int n, double x) {
        Ring ring;
        for (int i = 0; i < n; ++i) {
            const double angle = kTwoPi * i / n;
            const double radius = 0.5 + unit(random);
            ring.push_back({x + radius * std::cos(angle), radius * std::sin(angle)});
        }
        return ring;
    };
    const std::vector<Rings> polygons = {
        {star(7, 0.0)},
        {star(32, 10.0)},  // the most vertices tested against all the others
        {star(33, 20.0)},  // the fewest indexed
        {square(0, 0, 10), square(2, 2, 2, false), square(6, 6, 2, false)},
        {star(70000, 0.0)}, // more than a clipper keeps memory for
        {star(500, -5.0)},
    };
    const Rings crossing = {{{0, 0}, {2, 2}, {2, 0}, {0, 2}}};
    auto indices = [](const Rings& rings) { return earClip(rings).indices; };
    std::vector<std::vector<std::uint32_t>> alone;
    for (const Rings& rings : polygons) {
        alone.push_back(indices(rings));
        requireCoversArea(rings, earClip(rings));
    }
    for (std::size_t k = polygons.size(); k-- > 0;) {
        REQUIRE_THROWS_AS(earClip(crossing), Error);
        REQUIRE(indices(polygons[k]) == alone[k]);
    }
    std::vector<std::vector<std::vector<std::uint32_t>>> byThread(2);
    std::vector<std::thread> threads;
    for (auto& results : byThread) {
        threads.emplace_back([&polygons, &results, &indices] {
            for (const Rings& rings : polygons) {
                results.push_back(indices(rings));
            }
        });
    }
    for (std::thread& thread : threads) {
        thread.join();
    }
    for (const auto& results : byThread) {
        REQUIRE(results == alone);
    }
}

TEST_CASE("earClip triangulates rings of 100,000 vertices, round, wavy and spiky", "[polygon][ear-clipping][large]")
{
    // Each shape stresses a different part: a circle, all convex, makes ears that grow if taken
    // round the ring; a wavy coast is what real data looks like; a star of random radii has long
    // spikes and every other vertex reflex, so each ear has many vertices near it. (The time each
    // takes is in the benchmark: orbis_bench --only polygons.)
    const int n = 100000;
    std::mt19937_64 random(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (const char* shape : {"circle", "coast", "star"}) {
        INFO(shape);
        Ring ring;
        for (int i = 0; i < n; ++i) {
            const double angle = kTwoPi * i / n;
            const double radius = shape[0] == 'c' && shape[1] == 'i' ? 1.0
                                  : shape[0] == 'c'                  ? 1.0 + 0.05 * std::sin(37.0 * angle) + 0.01 * unit(random)
                                                                     : 0.5 + 0.5 * unit(random);
            ring.push_back({radius * std::cos(angle), radius * std::sin(angle)});
        }
        const PolygonTriangles result = earClip(Rings{ring});
        REQUIRE(result.triangleCount() == n - 2);
        requireTriangulation(Rings{ring}, result);
    }
}

TEST_CASE("earClip triangulates star-shaped rings, and what is left of them when no ear spans less than half a turn",
          "[polygon][ear-clipping]")
{
    // Rings strictly star-shaped round a centre (their vertices' mean, or for rings of 256
    // vertices or more, a point of their kernel found by linear programming) are clipped without
    // searching for vertices in an ear's way (an ear's wedge from the centre holds no other vertex)
    // until every convex vertex left spans half a turn or more; the rest is clipped as any ring
    // is. Rings symmetric through their centre (so that the mean is the centre) with random radii;
    // stars of up to 2,000 spikes of random length, longer on one side, whose kernel is too small
    // to hold the mean; and triangles whose edges are dented in and out a little, whose corners
    // span more than half a turn, so the second part always has work.
    const auto seed = GENERATE(take(100, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const glm::dvec2 centre(20.0 * unit(random) - 10.0, 20.0 * unit(random) - 10.0);
    Ring ring;
    if (seed % 3 == 0) {
        const int half = 17 + static_cast<int>(200 * unit(random));
        std::vector<double> angles;
        for (int k = 0; k < half; ++k) {
            angles.push_back(0.5 * kTwoPi * (k + 0.8 * unit(random)) / half);
        }
        Ring first;
        for (const double angle : angles) {
            const double radius = 0.2 + 0.8 * unit(random);
            first.push_back(radius * glm::dvec2(std::cos(angle), std::sin(angle)));
        }
        for (const glm::dvec2& p : first) {
            ring.push_back(centre + p);
        }
        for (const glm::dvec2& p : first) {
            ring.push_back(centre - p);
        }
    } else if (seed % 3 == 1) {
        const int n = 256 + static_cast<int>(1800 * unit(random));
        for (int k = 0; k < n; ++k) {
            const double angle = kTwoPi * k / n;
            // Longer spikes eastwards: the mean lies well east of the centre, outside the kernel.
            const double radius = 0.5 + 0.5 * unit(random) + 0.4 * std::cos(angle);
            ring.push_back(centre + radius * glm::dvec2(std::cos(angle), std::sin(angle)));
        }
    } else {
        const int perEdge = 12 + static_cast<int>(60 * unit(random));
        for (int corner = 0; corner < 3; ++corner) {
            const double a0 = kTwoPi * (corner / 3.0 + 0.25);
            const double a1 = a0 + kTwoPi / 3;
            const glm::dvec2 from(std::cos(a0), std::sin(a0));
            const glm::dvec2 to(std::cos(a1), std::sin(a1));
            ring.push_back(centre + from);
            for (int k = 1; k < perEdge; ++k) {
                const double t = static_cast<double>(k) / perEdge;
                // In towards the centre by up to 3% of the way: reflex and convex vertices mixed.
                ring.push_back(centre + (1.0 - 0.03 * unit(random)) * (from + t * (to - from)));
            }
        }
    }
    if (unit(random) < 0.5) {
        std::reverse(ring.begin(), ring.end());
    }
    const PolygonTriangles result = earClip(Rings{ring});
    REQUIRE(result.triangleCount() == ring.size() - 2);
    requireTriangulation(Rings{ring}, result);
}

TEST_CASE("earClip triangulates random lattice polygons with collinear runs, pinches and holes", "[polygon][ear-clipping]")
{
    // A random set of cells of a 10 x 10 grid (or, for every other seed, of a 24 x 24 one, whose
    // rings have more vertices than earClip tests small polygons' ears against without an index),
    // grown from the centre; its boundary traced along unit edges, so every lattice point on it is
    // a vertex (runs of collinear vertices), cells touching at a corner only make rings touch
    // themselves or each other there, and enclosed empty cells make holes. At a vertex with two ways
    // out the trace turns right, so rings touch rather than cross.
    const auto seed = GENERATE(take(200, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const bool large = seed % 2 == 1;
    const int size = large ? 24 : 10;
    std::vector<std::vector<bool>> cell(size, std::vector<bool>(size, false));
    cell[size / 2][size / 2] = true;
    const int cells = large ? 60 + static_cast<int>(200 * unit(random)) : 5 + static_cast<int>(40 * unit(random));
    for (int placed = 1; placed < cells;) {
        const int x = static_cast<int>(size * unit(random));
        const int y = static_cast<int>(size * unit(random));
        const bool nextToOne = (x > 0 && cell[x - 1][y]) || (x + 1 < size && cell[x + 1][y]) ||
                               (y > 0 && cell[x][y - 1]) || (y + 1 < size && cell[x][y + 1]) ||
                               (unit(random) < 0.2 && x > 0 && y > 0 && cell[x - 1][y - 1]);
        if (!cell[x][y] && nextToOne) {
            cell[x][y] = true;
            ++placed;
        }
    }
    // Boundary edges: cell edges, counter-clockwise around each cell, whose reverse is no cell's.
    std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> out; // from vertex -> to vertices
    auto filled = [&](int x, int y) { return x >= 0 && y >= 0 && x < size && y < size && cell[x][y]; };
    for (int x = 0; x < size; ++x) {
        for (int y = 0; y < size; ++y) {
            if (!cell[x][y]) {
                continue;
            }
            if (!filled(x, y - 1)) out[{x, y}].push_back({x + 1, y});
            if (!filled(x + 1, y)) out[{x + 1, y}].push_back({x + 1, y + 1});
            if (!filled(x, y + 1)) out[{x + 1, y + 1}].push_back({x, y + 1});
            if (!filled(x - 1, y)) out[{x, y + 1}].push_back({x, y});
        }
    }
    Rings loops;
    while (!out.empty()) {
        auto start = out.begin()->first;
        Ring loop;
        std::pair<int, int> at = start;
        std::pair<int, int> from = {start.first, start.second};
        bool first = true;
        while (first || at != start || !out.count(at)) {
            auto it = out.find(at);
            if (it == out.end()) {
                break;
            }
            std::vector<std::pair<int, int>>& ways = it->second;
            std::size_t pick = 0;
            if (ways.size() > 1 && !first) {
                // The rightmost turn: the smallest cross product with the incoming direction.
                const int dx = at.first - from.first;
                const int dy = at.second - from.second;
                int best = 3;
                for (std::size_t k = 0; k < ways.size(); ++k) {
                    const int ex = ways[k].first - at.first;
                    const int ey = ways[k].second - at.second;
                    const int turn = dx * ey - dy * ex;
                    if (turn < best) {
                        best = turn;
                        pick = k;
                    }
                }
            }
            loop.push_back({at.first, at.second});
            const std::pair<int, int> to = ways[pick];
            ways.erase(ways.begin() + static_cast<std::ptrdiff_t>(pick));
            if (ways.empty()) {
                out.erase(it);
            }
            from = at;
            at = to;
            first = false;
            if (at == start && !out.count(at)) {
                break;
            }
        }
        loops.push_back(loop);
    }
    // One outer loop (counter-clockwise) and holes, or the set fell apart into several: skip.
    Rings rings;
    for (const Ring& loop : loops) {
        if (ringArea(loop) > 0.0L) {
            rings.insert(rings.begin(), loop);
        } else {
            rings.push_back(loop);
        }
    }
    if (rings.size() > 1 && ringArea(rings[1]) > 0.0L) {
        return;
    }
    const PolygonTriangles result = earClip(rings, "lattice");
    requireCoversArea(rings, result);
    requireNoOverlap(rings, result);
    // Conforming: no vertex lies inside a triangle's edge (a T-junction, which would crack once
    // the triangles are subdivided and lifted onto the ellipsoid).
    const std::vector<glm::dvec2> all = concatenated(rings);
    for (std::size_t t = 0; t < result.triangleCount(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const glm::dvec2 a = all[result.indices[3 * t + static_cast<std::size_t>(k)]];
            const glm::dvec2 b = all[result.indices[3 * t + static_cast<std::size_t>((k + 1) % 3)]];
            for (const glm::dvec2& p : all) {
                const bool inside = p != a && p != b && orient(a, b, p) == 0.0L && (p.x - a.x) * (p.x - b.x) + (p.y - a.y) * (p.y - b.y) < 0.0;
                INFO("triangle " << t << " edge " << k << " holds vertex (" << p.x << ", " << p.y << ")");
                REQUIRE_FALSE(inside);
            }
        }
    }
}
