#include <orbis/core/TilingScheme.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using orbis::Geodetic2D;
using orbis::GeodeticExtent;
using orbis::TileKey;
using orbis::TilingScheme;

namespace {

const TilingScheme kSchemes[] = {TilingScheme::geographic(), TilingScheme::webMercator()};

} // namespace

TEST_CASE("TilingScheme counts tiles per level: two geographic roots, one Mercator root", "[core][tiles]")
{
    const TilingScheme geographic = TilingScheme::geographic();
    const TilingScheme mercator = TilingScheme::webMercator();
    CHECK(geographic.tilesX(0) == 2);
    CHECK(geographic.tilesY(0) == 1);
    CHECK(geographic.tilesX(30) == 2147483648u);
    CHECK(geographic.tilesY(30) == 1073741824u);
    CHECK(mercator.tilesX(0) == 1);
    CHECK(mercator.tilesY(0) == 1);
    CHECK(mercator.tilesX(30) == 1073741824u);
    CHECK(geographic.isValid({30, 2147483647u, 1073741823u}));
    CHECK_FALSE(geographic.isValid({30, 0, 1073741824u}));
    CHECK_FALSE(mercator.isValid({3, 8, 0}));
    CHECK_FALSE(geographic.isValid({31, 0, 0}));
}

TEST_CASE("Tile edges run exactly from -180 to 180 degrees and pole to pole (or the Mercator limit)", "[core][tiles]")
{
    for (std::uint32_t level = 0; level <= orbis::kMaximumTileLevel; ++level) {
        for (const TilingScheme& scheme : kSchemes) {
            INFO("level " << level);
            CHECK(scheme.edgeLongitude(level, 0) == -orbis::kPi);
            CHECK(scheme.edgeLongitude(level, scheme.tilesX(level)) == orbis::kPi);
            if (scheme.tilesX(level) >= 2) {
                CHECK(scheme.edgeLongitude(level, scheme.tilesX(level) / 2) == 0.0);
            }
        }
        if (level == 0) {
            continue;
        }
        const TilingScheme geographic = TilingScheme::geographic();
        CHECK(geographic.edgeLatitude(level, 0) == -orbis::kHalfPi);
        CHECK(geographic.edgeLatitude(level, geographic.tilesY(level)) == orbis::kHalfPi);
        CHECK(geographic.edgeLatitude(level, geographic.tilesY(level) / 2) == 0.0);
        const TilingScheme mercator = TilingScheme::webMercator();
        CHECK(mercator.edgeLatitude(level, 0) == mercator.coverage().north);
        CHECK(mercator.edgeLatitude(level, mercator.tilesY(level)) == mercator.coverage().south);
        CHECK(mercator.edgeLatitude(level, mercator.tilesY(level) / 2) == 0.0);
    }
    CHECK(TilingScheme::webMercator().coverage().north ==
          Approx(TilingScheme::kMaximumMercatorLatitude).epsilon(1e-15));
    CHECK(orbis::toDegrees(TilingScheme::kMaximumMercatorLatitude) == Approx(85.05112878).epsilon(1e-10));
}

TEST_CASE("Neighbouring tiles share their edges bit for bit, and children their parent's, at every level",
          "[core][tiles]")
{
    std::mt19937_64 random(20261201);
    for (const TilingScheme& scheme : kSchemes) {
        for (std::uint32_t level = 0; level < orbis::kMaximumTileLevel; ++level) {
            for (int sample = 0; sample < 200; ++sample) {
                const std::uint32_t x = static_cast<std::uint32_t>(random() % scheme.tilesX(level));
                const std::uint32_t y = static_cast<std::uint32_t>(random() % scheme.tilesY(level));
                const TileKey key{level, x, y};
                INFO("level " << level << " x " << x << " y " << y);
                const GeodeticExtent extent = scheme.tileExtent(key);
                REQUIRE(extent.west < extent.east);
                REQUIRE(extent.south < extent.north);
                if (x + 1 < scheme.tilesX(level)) {
                    CHECK(scheme.tileExtent({level, x + 1, y}).west == extent.east);
                }
                if (y + 1 < scheme.tilesY(level)) {
                    const GeodeticExtent next = scheme.tileExtent({level, x, y + 1});
                    // Rows count from the south (geographic) or from the north (Mercator).
                    if (scheme.projection() == orbis::TilingProjection::Geographic) {
                        CHECK(next.south == extent.north);
                    } else {
                        CHECK(next.north == extent.south);
                    }
                }
                GeodeticExtent union_{extent.east, extent.north, extent.west, extent.south};
                for (int child = 0; child < 4; ++child) {
                    const GeodeticExtent c = scheme.tileExtent(key.child(child));
                    union_.west = std::min(union_.west, c.west);
                    union_.east = std::max(union_.east, c.east);
                    union_.south = std::min(union_.south, c.south);
                    union_.north = std::max(union_.north, c.north);
                    CHECK(key.child(child).parent() == key);
                }
                CHECK(union_ == extent);
            }
        }
    }
}

TEST_CASE("tileAt finds the tile whose extent holds the point, edges going east and north", "[core][tiles]")
{
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> longitude(-orbis::kPi, orbis::kPi);
    for (const TilingScheme& scheme : kSchemes) {
        const GeodeticExtent coverage = scheme.coverage();
        std::uniform_real_distribution<double> latitude(coverage.south, coverage.north);
        for (std::uint32_t level : {0u, 1u, 5u, 12u, 22u, 30u}) {
            for (int sample = 0; sample < 2000; ++sample) {
                const Geodetic2D g{longitude(random), latitude(random)};
                const auto key = scheme.tileAt(g, level);
                REQUIRE(key);
                const GeodeticExtent extent = scheme.tileExtent(*key);
                INFO("level " << level << " lon " << g.longitude << " lat " << g.latitude);
                CHECK(g.longitude >= extent.west);
                CHECK(g.longitude < extent.east);
                CHECK(g.latitude >= extent.south);
                CHECK(g.latitude <= extent.north);
                const glm::dvec2 uv = scheme.positionInTile(*key, g);
                CHECK(uv.x >= 0.0);
                CHECK(uv.x <= 1.0);
                CHECK(uv.y >= -1e-9);
                CHECK(uv.y <= 1.0 + 1e-9);
            }
            // A point exactly on a tile's west edge belongs to that tile.
            const TileKey some{level, scheme.tilesX(level) / 3, scheme.tilesY(level) / 3};
            const GeodeticExtent extent = scheme.tileExtent(some);
            const double middle = scheme.projection() == orbis::TilingProjection::Geographic
                                      ? 0.5 * (extent.south + extent.north)
                                      : TilingScheme::mercatorLatitude(
                                            0.5 * (TilingScheme::mercatorY(extent.south) +
                                                   TilingScheme::mercatorY(extent.north)));
            CHECK(scheme.tileAt({extent.west, middle}, level) == some);
        }
    }
}

TEST_CASE("tileAt at the poles, the antimeridian and beyond the Mercator limit", "[core][tiles]")
{
    const TilingScheme geographic = TilingScheme::geographic();
    // 180 degrees east is the antimeridian, the first column's west edge.
    CHECK(geographic.tileAt({orbis::kPi, 0.0}, 3) == TileKey{3, 0, 4});
    CHECK(geographic.tileAt({-orbis::kPi, 0.0}, 3) == TileKey{3, 0, 4});
    CHECK(geographic.tileAt({3.0 * orbis::kPi - 1e-12, 0.0}, 3) == TileKey{3, 15, 4});
    CHECK(geographic.tileAt({0.0, orbis::kHalfPi}, 4) == TileKey{4, 16, 15});
    CHECK(geographic.tileAt({-1e-9, -orbis::kHalfPi}, 4) == TileKey{4, 15, 0});
    CHECK_FALSE(geographic.tileAt({std::nan(""), 0.0}, 4));
    CHECK_FALSE(geographic.tileAt({0.0, orbis::kHalfPi + 1e-9}, 4));

    const TilingScheme mercator = TilingScheme::webMercator();
    CHECK(mercator.tileAt({0.0, mercator.coverage().north}, 5) == TileKey{5, 16, 0});
    CHECK(mercator.tileAt({0.0, mercator.coverage().south}, 5) == TileKey{5, 16, 31});
    CHECK_FALSE(mercator.tileAt({0.0, orbis::toRadians(86.0)}, 5));
    // Paris at level 12 of the XYZ scheme, as every web map names it.
    CHECK(mercator.tileAt(Geodetic2D::fromDegrees(2.3522, 48.8566), 12) == TileKey{12, 2074, 1409});
}

TEST_CASE("positionInTile handles a tile at the antimeridian from either side", "[core][tiles]")
{
    const TilingScheme geographic = TilingScheme::geographic();
    const TileKey last{2, 7, 1};
    CHECK(geographic.positionInTile(last, {orbis::kPi, 0.0}).x == Approx(1.0));
    CHECK(geographic.positionInTile(last, {-orbis::kPi, 0.0}).x == Approx(1.0));
    CHECK(geographic.positionInTile(last, {orbis::kPi - orbis::kPi / 8, 0.0}).x == Approx(0.5));
    const TilingScheme mercator = TilingScheme::webMercator();
    const glm::dvec2 equator = mercator.positionInTile({1, 0, 0}, {-orbis::kHalfPi, 0.0});
    CHECK(equator.x == Approx(0.5));
    CHECK(equator.y == Approx(0.0).margin(1e-15));
}

TEST_CASE("geometricError halves per level from a quarter of the equator over the root samples", "[core][tiles]")
{
    const orbis::Ellipsoid wgs84 = orbis::Ellipsoid::wgs84();
    const TilingScheme geographic = TilingScheme::geographic();
    CHECK(geographic.geometricError(wgs84, 0) == Approx(6378137.0 * orbis::kTwoPi / 4.0 / 130.0));
    CHECK(geographic.geometricError(wgs84, 0) == Approx(77067.34).epsilon(1e-6));
    CHECK(geographic.geometricError(wgs84, 17) < 1.0);
    CHECK(geographic.geometricError(wgs84, 16) > 1.0);
    CHECK(geographic.geometricError(wgs84, 7) == geographic.geometricError(wgs84, 6) / 2.0);
    CHECK(TilingScheme::webMercator().geometricError(wgs84, 0) == 2.0 * geographic.geometricError(wgs84, 0));
}
