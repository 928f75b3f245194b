#include <orbis/core/ClipmapLayout.h>
#include <orbis/core/ClipmapUpsampling.h>
#include <orbis/core/ToroidalGrid.h>

#include <catch2/catch.hpp>

#include <map>
#include <random>
#include <set>
#include <utility>

using namespace orbis;

namespace {

constexpr ClipmapTrim kTrims[] = {ClipmapTrim::SouthWest, ClipmapTrim::SouthEast, ClipmapTrim::NorthWest,
                                  ClipmapTrim::NorthEast};

struct Post {
    std::int64_t x, y;
    auto operator<=>(const Post&) const = default;
};

/// Twice the signed area of a triangle of lattice posts.
std::int64_t doubleArea(Post a, Post b, Post c)
{
    return (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
}

Post latticePost(const ClipmapBlockLayout& layout, std::uint32_t index)
{
    return {static_cast<std::int64_t>(index % static_cast<std::uint32_t>(layout.posts())),
            static_cast<std::int64_t>(index / static_cast<std::uint32_t>(layout.posts()))};
}

/// How many times each unit quad of the level is covered by the pieces' triangles of positive
/// area (in halves: a covered quad counts 2), checking that every triangle is counter-clockwise
/// and either half a quad or degenerate on the outer boundary.
std::vector<int> quadCoverage(const ClipmapBlockLayout& layout, const std::vector<ClipmapPiece>& pieces,
                              std::size_t& degenerates)
{
    const int n = layout.posts();
    std::vector<int> halves(static_cast<std::size_t>(n - 1) * static_cast<std::size_t>(n - 1), 0);
    for (const ClipmapPiece& piece : pieces) {
        for (std::size_t i = piece.firstIndex; i < piece.firstIndex + piece.indexCount; i += 3) {
            const Post a = latticePost(layout, layout.indices()[i]);
            const Post b = latticePost(layout, layout.indices()[i + 1]);
            const Post c = latticePost(layout, layout.indices()[i + 2]);
            for (const Post p : {a, b, c}) {
                REQUIRE(p.x >= piece.minimumX);
                REQUIRE(p.x <= piece.maximumX);
                REQUIRE(p.y >= piece.minimumY);
                REQUIRE(p.y <= piece.maximumY);
            }
            const std::int64_t area = doubleArea(a, b, c);
            if (area == 0) {
                // Only the outer ring's degenerates, all three posts on one side.
                const bool onSide = (a.y == 0 && b.y == 0 && c.y == 0) || (a.y == n - 1 && b.y == n - 1 && c.y == n - 1) ||
                                    (a.x == 0 && b.x == 0 && c.x == 0) || (a.x == n - 1 && b.x == n - 1 && c.x == n - 1);
                REQUIRE(onSide);
                ++degenerates;
                continue;
            }
            REQUIRE(area == 1); // counter-clockwise half quad
            const std::int64_t qx = std::min({a.x, b.x, c.x}), qy = std::min({a.y, b.y, c.y});
            REQUIRE(std::max({a.x, b.x, c.x}) == qx + 1);
            REQUIRE(std::max({a.y, b.y, c.y}) == qy + 1);
            ++halves[static_cast<std::size_t>(qy) * static_cast<std::size_t>(n - 1) + static_cast<std::size_t>(qx)];
        }
    }
    return halves;
}

/// The fine level's origin in this level's posts for a trim (ClipmapBlockLayout::trimFor inverted).
std::pair<int, int> fineOrigin(ClipmapTrim trim, int m)
{
    const bool west = trim == ClipmapTrim::SouthWest || trim == ClipmapTrim::NorthWest;
    const bool south = trim == ClipmapTrim::SouthWest || trim == ClipmapTrim::SouthEast;
    return {west ? m : m - 1, south ? m : m - 1};
}

} // namespace

TEST_CASE("Clipmap rings and the finer level cover every quad of a level exactly once", "[core][clipmap]")
{
    for (const int n : {7, 15, 31, 63, 255}) {
        INFO("n = " << n);
        const ClipmapBlockLayout layout(n);
        const int m = layout.blockPosts();
        for (const ClipmapTrim trim : kTrims) {
            std::size_t degenerates = 0;
            const std::vector<int> halves = quadCoverage(layout, layout.ring(trim), degenerates);
            CHECK(degenerates == 2 * static_cast<std::size_t>(n - 1));
            CHECK(ClipmapBlockLayout::trimFor(fineOrigin(trim, m).first, fineOrigin(trim, m).second, m) == trim);
            const auto [fx, fy] = fineOrigin(trim, m);
            // The finer level spans 2m - 1 quads of this level from its origin.
            for (int y = 0; y < n - 1; ++y) {
                for (int x = 0; x < n - 1; ++x) {
                    const bool underFine = x >= fx && x < fx + 2 * m - 1 && y >= fy && y < fy + 2 * m - 1;
                    INFO("quad " << x << ", " << y);
                    REQUIRE(halves[static_cast<std::size_t>(y) * static_cast<std::size_t>(n - 1) + static_cast<std::size_t>(x)] ==
                            (underFine ? 0 : 2));
                }
            }
        }
        // The finest level: the south-west ring and the interior cover everything.
        std::vector<ClipmapPiece> whole = layout.ring(ClipmapTrim::SouthWest);
        whole.push_back(layout.interior());
        std::size_t degenerates = 0;
        for (const int half : quadCoverage(layout, whole, degenerates)) {
            REQUIRE(half == 2);
        }
    }
}

TEST_CASE("Clipmap pieces are listed once each, in angular order, and tile the index buffer", "[core][clipmap]")
{
    const ClipmapBlockLayout layout(63);
    std::size_t expectedFirst = 0;
    for (const ClipmapTrim trim : kTrims) {
        const std::vector<ClipmapPiece>& ring = layout.ring(trim);
        CHECK(ring.size() == 12 + 4 + 2);
        double previous = -4.0;
        for (const ClipmapPiece& piece : ring) {
            CHECK(piece.firstIndex == expectedFirst);
            expectedFirst += piece.indexCount;
            const double angle = std::atan2(0.5 * (piece.minimumY + piece.maximumY) - 31.0,
                                            0.5 * (piece.minimumX + piece.maximumX) - 31.0);
            CHECK(angle >= previous);
            previous = angle;
        }
    }
    CHECK(layout.interior().firstIndex == expectedFirst);
    CHECK(layout.interior().firstIndex + layout.interior().indexCount == layout.indices().size());
}

TEST_CASE("Clipmap origins nest every level on post m - 1 or m of the next coarser", "[core][clipmap]")
{
    const unsigned seed = 14;
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> position(-1.0e9, 1.0e9);
    INFO("seed " << seed);
    for (const int n : {15, 255}) {
        const int m = (n + 1) / 4;
        for (int trial = 0; trial < 200; ++trial) {
            const double cx = trial < 100 ? position(random) : position(random) * 1e-6;
            const double cy = trial < 100 ? position(random) : position(random) * 1e-6;
            const std::vector<std::int64_t> origins = clipmapOrigins(cx, cy, 8, n);
            REQUIRE(origins.size() == 16);
            // The viewer within a post of level 0's centre.
            CHECK(std::abs(static_cast<double>(origins[0]) + 0.5 * (n - 1) - cx) <= 1.0);
            CHECK(std::abs(static_cast<double>(origins[1]) + 0.5 * (n - 1) - cy) <= 1.0);
            for (std::size_t level = 0; level < 8; ++level) {
                CHECK(origins[2 * level] % 2 == 0);
                CHECK(origins[2 * level + 1] % 2 == 0);
                if (level > 0) {
                    for (std::size_t axis = 0; axis < 2; ++axis) {
                        const std::int64_t offset = origins[2 * (level - 1) + axis] / 2 - origins[2 * level + axis];
                        CHECK((offset == m - 1 || offset == m));
                    }
                }
            }
        }
    }
}

TEST_CASE("Nested clipmap levels share every edge: the degenerate ring closes each T-junction", "[core][clipmap]")
{
    const unsigned seed = 2004;
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> position(-5000.0, 5000.0);
    INFO("seed " << seed);
    for (const int n : {7, 15, 31, 63}) {
        const ClipmapBlockLayout layout(n);
        const int m = layout.blockPosts();
        const int levels = 4;
        for (int trial = 0; trial < 6; ++trial) {
            INFO("n = " << n << ", trial " << trial);
            const std::vector<std::int64_t> origins = clipmapOrigins(position(random), position(random), levels, n);
            // Directed edges in finest-level units, counted.
            std::map<std::pair<Post, Post>, int> edges;
            std::set<std::pair<Post, Post>> coarsestLongEdges;
            for (int level = 0; level < levels; ++level) {
                std::vector<ClipmapPiece> pieces;
                if (level == 0) {
                    pieces = layout.ring(ClipmapTrim::SouthWest);
                    pieces.push_back(layout.interior());
                    // With the interior drawn, level 0 has no finer level; the trim is its own.
                } else {
                    const int fx = static_cast<int>(origins[2 * (level - 1)] / 2 - origins[2 * level]);
                    const int fy = static_cast<int>(origins[2 * (level - 1) + 1] / 2 - origins[2 * level + 1]);
                    pieces = layout.ring(ClipmapBlockLayout::trimFor(fx, fy, m));
                }
                const std::int64_t scale = std::int64_t{1} << level;
                auto global = [&](std::uint32_t index) {
                    const Post p = latticePost(layout, index);
                    return Post{(origins[2 * level] + p.x) * scale, (origins[2 * level + 1] + p.y) * scale};
                };
                for (const ClipmapPiece& piece : pieces) {
                    for (std::size_t i = piece.firstIndex; i < piece.firstIndex + piece.indexCount; i += 3) {
                        const Post a = global(layout.indices()[i]), b = global(layout.indices()[i + 1]),
                                   c = global(layout.indices()[i + 2]);
                        ++edges[{a, b}];
                        ++edges[{b, c}];
                        ++edges[{c, a}];
                        if (level == levels - 1 && doubleArea(a, b, c) == 0) {
                            coarsestLongEdges.insert({a, b}); // (a, c, b): a to c is the long edge
                        }
                    }
                }
            }
            std::size_t unmatched = 0;
            for (const auto& [edge, count] : edges) {
                REQUIRE(count == 1);
                if (!edges.contains({edge.second, edge.first})) {
                    ++unmatched;
                    // Only the coarsest level's outline is open.
                    REQUIRE(coarsestLongEdges.contains(edge));
                }
            }
            CHECK(unmatched == 2 * static_cast<std::size_t>(n - 1));
        }
    }
}

TEST_CASE("Toroidal updates after a sequence of moves equal a fresh build bit for bit", "[core][clipmap]")
{
    const unsigned seed = 1305;
    std::mt19937 random(seed);
    INFO("seed " << seed);
    // A value no two posts share, as a float, so that a texel written for the wrong post shows.
    auto value = [](std::int64_t x, std::int64_t y) {
        return static_cast<float>(static_cast<double>(x) * 1.7320508 + static_cast<double>(y) * 0.001 + 1e-7 * static_cast<double>(x * y % 997));
    };
    auto fill = [&](ToroidalGrid<float>& grid, const GridRegion& region) {
        for (std::int64_t y = region.y; y < region.y + region.height; ++y) {
            for (std::int64_t x = region.x; x < region.x + region.width; ++x) {
                grid.at(x, y) = value(x, y);
            }
        }
    };
    std::uniform_int_distribution<int> step(-40, 40);
    for (const int size : {16, 64}) {
        ToroidalGrid<float> moved(size, -1.0f);
        std::int64_t x = -1000003, y = 77;
        std::size_t partialMoves = 0;
        for (int move = 0; move < 300; ++move) {
            const std::int64_t oldX = x, oldY = y;
            const bool wasPlaced = moved.placed();
            x += move % 50 == 49 ? 5 * size : step(random) % (size / 2 + 1);
            y += step(random) % (size / 2 + 1);
            const std::vector<GridRegion> regions = moved.moveTo(x, y);
            // The regions are exactly the posts of the new window that were not in the old one.
            std::set<Post> written;
            for (const GridRegion& region : regions) {
                for (std::int64_t py = region.y; py < region.y + region.height; ++py) {
                    for (std::int64_t px = region.x; px < region.x + region.width; ++px) {
                        REQUIRE(written.insert({px, py}).second);
                        REQUIRE(moved.contains(px, py));
                    }
                }
                // Each region's texel rectangles cover its posts' texels exactly.
                std::size_t texels = 0;
                std::set<std::size_t> texelSet;
                for (const TexelRectangle& r : moved.texelRectangles(region)) {
                    REQUIRE(r.x >= 0);
                    REQUIRE(r.y >= 0);
                    REQUIRE(r.x + r.width <= size);
                    REQUIRE(r.y + r.height <= size);
                    texels += static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height);
                    for (int ty = r.y; ty < r.y + r.height; ++ty)
                        for (int tx = r.x; tx < r.x + r.width; ++tx) texelSet.insert(static_cast<std::size_t>(ty * size + tx));
                }
                CHECK(texels == static_cast<std::size_t>(region.width) * static_cast<std::size_t>(region.height));
                CHECK(texelSet.size() == texels);
                fill(moved, region);
            }
            const bool overlapsOld = wasPlaced && std::abs(x - oldX) < size && std::abs(y - oldY) < size;
            if (overlapsOld) {
                const std::size_t stayed = static_cast<std::size_t>(size - std::abs(x - oldX)) *
                                           static_cast<std::size_t>(size - std::abs(y - oldY));
                CHECK(written.size() == static_cast<std::size_t>(size) * static_cast<std::size_t>(size) - stayed);
                partialMoves += written.size() < static_cast<std::size_t>(size * size) ? 1 : 0;
            } else {
                CHECK(written.size() == static_cast<std::size_t>(size) * static_cast<std::size_t>(size));
            }
        }
        CHECK(partialMoves > 200);
        ToroidalGrid<float> fresh(size, -1.0f);
        for (const GridRegion& region : fresh.moveTo(x, y)) {
            fill(fresh, region);
        }
        CHECK(fresh.texels() == moved.texels());
        CHECK(moved.moveTo(x, y).empty());
    }
}

TEST_CASE("The four-point filter reproduces a quadratic surface exactly at the new posts", "[core][clipmap]")
{
    // A quadratic in the coarse posts' numbers; the finer post (x, y) lies at (x / 2, y / 2).
    auto quadratic = [](double X, double Y) { return 3.0 - 2.0 * X + 0.5 * Y + 0.25 * X * X - 0.75 * X * Y + 0.125 * Y * Y; };
    auto coarse = [&](std::int64_t X, std::int64_t Y) { return quadratic(static_cast<double>(X), static_cast<double>(Y)); };
    std::size_t newPosts = 0;
    for (std::int64_t y = -9; y <= 9; ++y) {
        for (std::int64_t x = -9; x <= 9; ++x) {
            const double expected = quadratic(0.5 * static_cast<double>(x), 0.5 * static_cast<double>(y));
            // Exact in binary: every term is a multiple of 2^-6 of small integers.
            REQUIRE(fourPointUpsample(coarse, x, y) == expected);
            newPosts += ((x | y) & 1) != 0 ? 1 : 0;
        }
    }
    CHECK(newPosts == 19 * 19 - 9 * 9);
    // A cubic along a row too; bilinear interpolation would miss both by the curvature.
    auto cubic = [](std::int64_t X, std::int64_t) { const double t = static_cast<double>(X); return t * t * t - 4.0 * t; };
    CHECK(fourPointUpsample(cubic, 3, 0) == Approx(1.5 * 1.5 * 1.5 - 6.0).margin(1e-12));
    CHECK(0.5 * (coarse(0, 0) + coarse(1, 0)) != quadratic(0.5, 0.0));
}
