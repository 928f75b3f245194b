#include <orbis/scene/ImageryCoverage.h>

#include <catch2/catch.hpp>

#include <random>

using namespace orbis;
using namespace orbis::scene;

TEST_CASE("Geographic imagery of 256-pixel tiles matches the quadtree's level one for one", "[scene][tiles]")
{
    const Ellipsoid wgs84 = Ellipsoid::wgs84();
    const TilingScheme geographic = TilingScheme::geographic();
    const ImageryTiling tiling{geographic, 0, 4, 256, 256, GeodeticExtent::maximum()};
    for (std::uint32_t level = 0; level <= 8; ++level) {
        const GeodeticExtent extent = geographic.tileExtent({level, 0, 0});
        INFO("level " << level);
        CHECK(imageryLevelFor(tiling, wgs84, extent, geographic.geometricError(wgs84, level, 64)) == std::min(level, 4u));
        // A geometric error a little smaller than the texel asks for the next level.
        CHECK(imageryLevelFor(tiling, wgs84, extent, 0.9 * geographic.geometricError(wgs84, level, 64)) ==
              std::min(level + 1, 4u));
        if (level <= 4) {
            const TileKey key{level, geographic.tilesX(level) - 1, geographic.tilesY(level) / 2};
            CHECK(imageryTilesOver(tiling, level, geographic.tileExtent(key)) == std::vector<TileKey>{key});
        }
    }
}

TEST_CASE("Web Mercator imagery over geographic tiles: a finer level at the equator, coarser towards the poles",
          "[scene][tiles]")
{
    const Ellipsoid wgs84 = Ellipsoid::wgs84();
    const TilingScheme geographic = TilingScheme::geographic();
    const ImageryTiling tiling{TilingScheme::webMercator(), 0, 18, 256, 256, GeodeticExtent::maximum()};
    const std::uint32_t level = 8;
    const double error = geographic.geometricError(wgs84, level, 64);
    const TileKey equatorial = *geographic.tileAt(Geodetic2D::fromDegrees(10.0, 0.1), level);
    const TileKey arctic = *geographic.tileAt(Geodetic2D::fromDegrees(10.0, 80.5), level);
    CHECK(imageryLevelFor(tiling, wgs84, geographic.tileExtent(equatorial), error) == level + 1);
    CHECK(imageryLevelFor(tiling, wgs84, geographic.tileExtent(arctic), error) == level - 1);

    // The Mercator tiles found cover the surface tile exactly: their overlaps add up to it.
    for (const TileKey& surface : {equatorial, arctic}) {
        const GeodeticExtent extent = geographic.tileExtent(surface);
        const std::uint32_t imageryLevel = imageryLevelFor(tiling, wgs84, extent, error);
        const std::vector<TileKey> keys = imageryTilesOver(tiling, imageryLevel, extent);
        REQUIRE(!keys.empty());
        CHECK(keys.size() <= 4);
        double area = 0.0;
        for (const TileKey& key : keys) {
            const auto placement = placeImagery(tiling.scheme.tileExtent(key), extent);
            REQUIRE(placement);
            const glm::dvec4 r = placement->tileRectangle;
            area += (r.z - r.x) * (r.w - r.y);
        }
        CHECK(area == Approx(1.0).epsilon(1e-12));
    }
    // Beyond the Mercator limit there is nothing.
    const TileKey polar{level, 3, geographic.tilesY(level) - 1};
    CHECK(imageryTilesOver(tiling, 5, geographic.tileExtent(polar)).empty());
}

TEST_CASE("placeImagery maps surface texture coordinates onto the imagery's, and clips to a rectangle",
          "[scene][tiles]")
{
    const TilingScheme geographic = TilingScheme::geographic();
    const GeodeticExtent surface = geographic.tileExtent({6, 70, 40});
    const GeodeticExtent imagery = geographic.tileExtent({4, 17, 10});
    const auto placement = placeImagery(imagery, surface);
    REQUIRE(placement);
    std::mt19937_64 random(3);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < 100; ++i) {
        const glm::dvec2 uv(unit(random), unit(random));
        const double longitude = surface.west + uv.x * (surface.east - surface.west);
        const double latitude = surface.south + uv.y * (surface.north - surface.south);
        const glm::dvec2 expected((longitude - imagery.west) / (imagery.east - imagery.west),
                                  (latitude - imagery.south) / (imagery.north - imagery.south));
        const glm::dvec2 mapped = placement->translation + placement->scale * uv;
        CHECK(mapped.x == Approx(expected.x).epsilon(1e-12));
        CHECK(mapped.y == Approx(expected.y).epsilon(1e-12));
    }
    CHECK(placement->tileRectangle == glm::dvec4(0.0, 0.0, 1.0, 1.0));

    // A layer rectangle across the antimeridian keeps the part of a tile next to it.
    const GeodeticExtent acrossDateLine = GeodeticExtent::fromDegrees(170.0, -10.0, -170.0, 10.0);
    const GeodeticExtent west = geographic.tileExtent({1, 0, 0}); // 180W..90W, 90S..0
    const auto clipped = placeImagery(west, west, acrossDateLine);
    REQUIRE(clipped);
    CHECK(clipped->tileRectangle.x == 0.0);
    CHECK(clipped->tileRectangle.z == Approx(10.0 / 90.0));
    CHECK(clipped->tileRectangle.y == Approx(80.0 / 90.0));
    CHECK(clipped->tileRectangle.w == 1.0);
    CHECK_FALSE(placeImagery(west, west, GeodeticExtent::fromDegrees(0.0, -10.0, 20.0, 10.0)));
}
