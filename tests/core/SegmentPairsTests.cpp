// The polygon code's internal test for rings that touch nothing (core/src/SegmentPairs.h), against
// every pair of edges.

#include "../../core/src/RobustPredicates.h"
#include "../../core/src/SegmentPairs.h"

#include <catch2/catch.hpp>

#include <glm/geometric.hpp>

#include <cmath>
#include <random>
#include <vector>

using namespace orbis;

namespace {

using Ring = std::vector<glm::dvec2>;

struct Edges {
    std::vector<glm::dvec2> from, to;
    std::vector<int> fromVertex, toVertex;
};

Edges edgesOf(const std::vector<Ring>& rings)
{
    Edges edges;
    int first = 0;
    for (const Ring& ring : rings) {
        const int n = static_cast<int>(ring.size());
        for (int i = 0; i < n; ++i) {
            edges.from.push_back(ring[static_cast<std::size_t>(i)]);
            edges.to.push_back(ring[static_cast<std::size_t>((i + 1) % n)]);
            edges.fromVertex.push_back(first + i);
            edges.toVertex.push_back(first + (i + 1) % n);
        }
        first += n;
    }
    return edges;
}

/// The same question asked of every pair.
bool meetOnlyAtSharedVerticesByPairs(const Edges& e)
{
    const std::size_t n = e.from.size();
    for (std::size_t a = 0; a < n; ++a) {
        for (std::size_t b = a + 1; b < n; ++b) {
            if (e.from[a] == e.from[b]) {
                return false; // two vertices at one position
            }
            const bool aThenB = e.toVertex[a] == e.fromVertex[b];
            const bool bThenA = e.toVertex[b] == e.fromVertex[a];
            if (!aThenB && !bThenA) {
                if (detail::segmentsIntersect(e.from[a], e.to[a], e.from[b], e.to[b])) {
                    return false;
                }
                continue;
            }
            const glm::dvec2 shared = aThenB ? e.to[a] : e.to[b];
            const glm::dvec2 aOther = aThenB ? e.from[a] : e.to[a];
            const glm::dvec2 bOther = aThenB ? e.to[b] : e.from[b];
            if (detail::orient2d(shared, aOther, bOther) == 0 && glm::dot(aOther - shared, bOther - shared) > 0.0) {
                return false;
            }
        }
    }
    return true;
}

} // namespace

TEST_CASE("The sweep finds rings touching nothing exactly when every pair of edges says so", "[polygon][ear-clipping]")
{
    // Rings on a coarse lattice: vertices on edges, repeated, collinear runs folding back,
    // crossings and touches between rings, most rings failing somewhere; and star-shaped rings
    // of random radii, which touch nothing.
    const auto seed = GENERATE(take(3, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int agreedClear = 0;
    int agreedNot = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const int n = 3 + static_cast<int>(60 * unit(random));
        const bool lattice = trial % 2 == 0;
        const double grid = 2.0 + std::floor(8.0 * unit(random)); // lattice steps across
        std::vector<Ring> rings;
        for (int r = 0; r < 1 + static_cast<int>(trial % 3 == 0); ++r) {
            Ring ring;
            for (int i = 0; i < n; ++i) {
                const double angle = 6.283185307179586 * i / n + r;
                const double radius = (r == 0 ? 1.0 : 0.3) * (0.2 + unit(random));
                glm::dvec2 p(radius * std::cos(angle), radius * std::sin(angle));
                if (lattice) {
                    p = glm::round(p * grid) / grid;
                }
                ring.push_back(p);
            }
            rings.push_back(ring);
        }
        const Edges edges = edgesOf(rings);
        const bool expected = meetOnlyAtSharedVerticesByPairs(edges);
        INFO("trial " << trial);
        REQUIRE(detail::meetOnlyAtSharedVertices(edges.from, edges.to, edges.fromVertex, edges.toVertex) == expected);
        (expected ? agreedClear : agreedNot) += 1;
    }
    // Both answers were asked for often.
    CHECK(agreedClear > 100);
    CHECK(agreedNot > 100);
}

TEST_CASE("The sweep finds two edges crossing after a third between them leaves the line", "[polygon][ear-clipping]")
{
    // A ring crossing itself once (edges from (0, 0) and from (2, 2) cross at x = 5.6) and a small
    // ring lying between those edges from x = 1.5 to 4: the two become neighbours on the line only
    // when the small ring's edges leave it.
    const std::vector<Ring> rings = {{{0, 0}, {10, 2}, {10, 0}, {2, 2}}, {{1.5, 1.0}, {4, 1.2}, {2.5, 1.3}}};
    const Edges edges = edgesOf(rings);
    REQUIRE_FALSE(meetOnlyAtSharedVerticesByPairs(edges));
    CHECK_FALSE(detail::meetOnlyAtSharedVertices(edges.from, edges.to, edges.fromVertex, edges.toVertex));
    // Untwisted, the ring touches nothing.
    const std::vector<Ring> untwisted = {{{0, 0}, {10, 0}, {10, 2}, {2, 2}}, {{1.5, 1.0}, {4, 1.2}, {2.5, 1.3}}};
    const Edges clear = edgesOf(untwisted);
    REQUIRE(meetOnlyAtSharedVerticesByPairs(clear));
    CHECK(detail::meetOnlyAtSharedVertices(clear.from, clear.to, clear.fromVertex, clear.toVertex));
}
