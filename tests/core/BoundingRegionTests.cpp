#include <orbis/core/BoundingRegion.h>
#include <orbis/core/EllipsoidalOccluder.h>
#include <orbis/core/Frustum.h>
#include <orbis/core/TilingScheme.h>

#include <catch2/catch.hpp>

#include <glm/geometric.hpp>

#include <cmath>
#include <random>

using orbis::BoundingRegion;
using orbis::Ellipsoid;
using orbis::GeodeticExtent;
using orbis::TileKey;
using orbis::TilingScheme;

namespace {

/// A random tile of either scheme at a level in [0, maximumLevel], heights as given.
struct RandomTile {
    GeodeticExtent extent;
    double minimumHeight;
    double maximumHeight;
};

RandomTile randomTile(std::mt19937_64& random, std::uint32_t maximumLevel)
{
    const TilingScheme scheme = random() % 2 ? TilingScheme::geographic() : TilingScheme::webMercator();
    const std::uint32_t level = static_cast<std::uint32_t>(random() % (maximumLevel + 1));
    const TileKey key{level, static_cast<std::uint32_t>(random() % scheme.tilesX(level)),
                      static_cast<std::uint32_t>(random() % scheme.tilesY(level))};
    std::uniform_real_distribution<double> height(-11000.0, 9000.0);
    double a = height(random);
    double b = height(random);
    if (random() % 4 == 0) {
        a = b = 0.0; // imagery tiles: flat on the ellipsoid
    }
    return {scheme.tileExtent(key), std::min(a, b), std::max(a, b)};
}

/// A point of the region's volume: half of them uniformly in longitude, latitude and height, half
/// on its outer faces (an edge, at the lowest or highest height), where the volume bulges most
/// between the samples the bounds are made from.
glm::dvec3 randomPointIn(std::mt19937_64& random, const Ellipsoid& ellipsoid, const RandomTile& tile)
{
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    double u = unit(random);
    double v = unit(random);
    double w = unit(random);
    if (random() % 2) {
        (random() % 2 ? u : v) = static_cast<double>(random() % 2);
        w = static_cast<double>(random() % 2);
    }
    return ellipsoid.toCartesian(orbis::Geodetic3D(tile.extent.west + u * tile.extent.width(),
                                                   tile.extent.south + v * tile.extent.height(),
                                                   tile.minimumHeight + w * (tile.maximumHeight - tile.minimumHeight)));
}

/// True when the segment from camera to p passes through the ellipsoid's interior (p hidden).
bool segmentHitsEllipsoid(const Ellipsoid& ellipsoid, const glm::dvec3& camera, const glm::dvec3& p)
{
    const glm::dvec3 c = camera * ellipsoid.oneOverRadii();
    const glm::dvec3 d = p * ellipsoid.oneOverRadii() - c;
    // |c + t d|^2 = 1 has a root in (0, 1) strictly inside the segment.
    const double a = glm::dot(d, d);
    const double b = 2.0 * glm::dot(c, d);
    const double q = glm::dot(c, c) - 1.0;
    const double discriminant = b * b - 4.0 * a * q;
    if (discriminant <= 0.0) {
        return false;
    }
    const double t = (-b - std::sqrt(discriminant)) / (2.0 * a);
    return t > 0.0 && t < 1.0;
}

} // namespace

TEST_CASE("A region's box and sphere contain every point of the curved volume, not only the samples", "[core][tiles]")
{
    const Ellipsoid wgs84 = Ellipsoid::wgs84();
    std::mt19937_64 random(42);
    for (int tileIndex = 0; tileIndex < 400; ++tileIndex) {
        const RandomTile tile = randomTile(random, tileIndex < 40 ? 2 : 18);
        const BoundingRegion region(wgs84, tile.extent, tile.minimumHeight, tile.maximumHeight);
        for (int sample = 0; sample < 300; ++sample) {
            const glm::dvec3 p = randomPointIn(random, wgs84, tile);
            INFO("tile " << tileIndex << " west " << tile.extent.west << " south " << tile.extent.south);
            REQUIRE(region.orientedBox().contains(p));
            REQUIRE(region.boundingSphere().contains(p));
            REQUIRE(region.distanceTo(p) == 0.0);
        }
    }
}

TEST_CASE("A region's box is tight: a camera above its centre is as far as its height over the top", "[core][tiles]")
{
    const Ellipsoid wgs84 = Ellipsoid::wgs84();
    const TilingScheme scheme = TilingScheme::geographic();
    for (std::uint32_t level : {6u, 10u, 14u, 18u}) {
        const GeodeticExtent extent = scheme.tileExtent(*scheme.tileAt(orbis::Geodetic2D::fromDegrees(7.0, 46.0), level));
        const BoundingRegion region(wgs84, extent, 200.0, 4000.0);
        const glm::dvec3 eye = wgs84.toCartesian(orbis::Geodetic3D(extent.centre(), 14000.0));
        INFO("level " << level << " padding " << region.padding());
        // 10 km over the top of the tile, less the padding and the bulge of the top surface.
        CHECK(region.distanceTo(eye) <= 10000.0);
        CHECK(region.distanceTo(eye) >= 10000.0 - region.padding() - 1.0);
        CHECK(region.padding() < (level >= 10 ? 1.0 : 300.0));
    }
}

TEST_CASE("A hidden horizon occlusion point proves every point of the region hidden, even at the horizon",
          "[core][tiles]")
{
    const Ellipsoid wgs84 = Ellipsoid::wgs84();
    std::mt19937_64 random(1234);
    std::uniform_real_distribution<double> logHeight(std::log(10.0), std::log(4.0e7));
    std::uniform_real_distribution<double> azimuth(0.0, orbis::kTwoPi);
    int culled = 0;
    for (int trial = 0; trial < 1500; ++trial) {
        const RandomTile tile = randomTile(random, 14);
        const BoundingRegion region(wgs84, tile.extent, tile.minimumHeight, tile.maximumHeight);
        if (!region.horizonOcclusionPoint()) {
            continue;
        }
        // Cameras at one height on a great circle through the tile's centre, theta radians away:
        // find where the occlusion point just sinks below the horizon, the hardest place for it.
        const double height = std::exp(logHeight(random));
        const glm::dvec3 centre = glm::normalize(wgs84.toCartesian(tile.extent.centre()));
        const glm::dvec3 side = glm::normalize(glm::cross(centre, orbis::anyPerpendicular(centre)));
        const double angle = azimuth(random);
        const glm::dvec3 along = std::cos(angle) * side + std::sin(angle) * glm::cross(centre, side);
        auto cameraAt = [&](double theta) {
            const glm::dvec3 surface = wgs84.scaleToGeodeticSurface((std::cos(theta) * centre + std::sin(theta) * along) * 6.4e6);
            return surface + wgs84.geodeticSurfaceNormal(surface) * height;
        };
        auto hidden = [&](double theta) {
            return !orbis::EllipsoidalOccluder(wgs84, cameraAt(theta))
                        .isScaledSpacePointVisible(*region.horizonOcclusionPoint(), region.minimumHeight());
        };
        if (hidden(0.0) || !hidden(orbis::kPi)) {
            continue;
        }
        double visible = 0.0;
        double invisible = orbis::kPi;
        for (int step = 0; step < 50; ++step) {
            const double middle = 0.5 * (visible + invisible);
            (hidden(middle) ? invisible : visible) = middle;
        }
        const glm::dvec3 camera = cameraAt(invisible);
        ++culled;
        const Ellipsoid occluding = orbis::EllipsoidalOccluder::occludingEllipsoid(wgs84, region.minimumHeight());
        for (int sample = 0; sample < 400; ++sample) {
            const glm::dvec3 p = randomPointIn(random, wgs84, tile);
            INFO("trial " << trial << " camera height " << height);
            REQUIRE(segmentHitsEllipsoid(occluding, camera, p));
        }
    }
    CHECK(culled > 1000);
}

TEST_CASE("Regions wider than a hemisphere have no occlusion point; a polar tile has one", "[core][tiles]")
{
    const Ellipsoid wgs84 = Ellipsoid::wgs84();
    CHECK_FALSE(BoundingRegion(wgs84, TilingScheme::webMercator().tileExtent({0, 0, 0}), 0.0, 0.0).horizonOcclusionPoint());
    const BoundingRegion polar(wgs84, TilingScheme::geographic().tileExtent({3, 5, 7}), 0.0, 3000.0);
    REQUIRE(polar.horizonOcclusionPoint());
    // Seen from above the south pole, the north polar tile is below the horizon.
    const orbis::EllipsoidalOccluder southern(wgs84, {0.0, 0.0, -8.0e6});
    CHECK_FALSE(southern.isScaledSpacePointVisible(*polar.horizonOcclusionPoint(), 0.0));
    const orbis::EllipsoidalOccluder northern(wgs84, {0.0, 0.0, 8.0e6});
    CHECK(northern.isScaledSpacePointVisible(*polar.horizonOcclusionPoint(), 0.0));
}

TEST_CASE("Frustum culls oriented boxes outside any plane and keeps those crossing it", "[core][tiles]")
{
    // A frustum looking down -z from the origin, 90 degrees wide, near 1, far 100.
    const double n = 1.0;
    const double f = 100.0;
    const glm::dmat4 projection(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -(f + n) / (f - n), -1.0, 0.0, 0.0,
                                -2.0 * f * n / (f - n), 0.0);
    const orbis::Frustum frustum = orbis::Frustum::fromViewProjection(projection);
    const glm::dmat3 rotated(glm::dvec3(0.7071, 0.7071, 0.0), glm::dvec3(-0.7071, 0.7071, 0.0), glm::dvec3(0.0, 0.0, 1.0));
    const orbis::OrientedBoundingBox inside{{0.0, 0.0, -50.0}, rotated};
    const orbis::OrientedBoundingBox outside{{60.0, 0.0, -50.0}, rotated};
    const orbis::OrientedBoundingBox crossing{{50.0, 0.0, -50.0}, rotated};
    const orbis::OrientedBoundingBox flat{{0.0, 0.0, -150.0}, glm::dmat3(glm::dvec3(5, 0, 0), glm::dvec3(0, 5, 0), glm::dvec3(0.0))};
    CHECK(frustum.intersect(inside) == orbis::Intersect::Inside);
    CHECK(frustum.intersect(outside) == orbis::Intersect::Outside);
    CHECK(frustum.intersect(crossing) == orbis::Intersect::Intersecting);
    CHECK(frustum.intersect(flat) == orbis::Intersect::Outside);
    CHECK(flat.distanceSquaredTo({0.0, 0.0, -140.0}) == Approx(100.0));
    CHECK(flat.distanceSquaredTo({8.0, 0.0, -150.0}) == Approx(9.0));
    CHECK_FALSE(flat.contains({0.0, 0.0, -149.0}));
    CHECK(flat.contains({4.0, -4.0, -150.0}));
}
