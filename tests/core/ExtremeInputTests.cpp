// No NaN, ever: the core's geometry on every combination of points from the centre (and
// subnormal distances) out to 1e150 m in awkward directions (the axes, the poles, a direction
// with a subnormal component), with ray directions from subnormal to 1e300 long. The hard-case
// tests of each file check the answers; this sweep checks that no combination of extremes turns
// any answer into NaN or infinity. 1e150 m: a little further, squared distances overflow
// (IntersectionTests.h and BoundingSphere.h say where).
#include <orbis/core/BoundingSphere.h>
#include <orbis/core/Ellipsoid.h>
#include <orbis/core/EllipsoidTangentPlane.h>
#include <orbis/core/EllipsoidalOccluder.h>
#include <orbis/core/EmulatedDouble.h>
#include <orbis/core/IntersectionTests.h>
#include <orbis/core/Math.h>
#include <orbis/core/Transforms.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace orbis;

namespace {

const Ellipsoid kEarth = Ellipsoid::wgs84();

std::vector<glm::dvec3> directions()
{
    return {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}, {1, 1, 1}, {-1, 2, -3}, {1e-300, 0, 1}, {0.6, 0.8, 0}};
}

/// Every direction at every magnitude: the centre, subnormal and tiny offsets, both WGS84 radii,
/// orbit, and far beyond.
std::vector<glm::dvec3> extremePoints()
{
    std::vector<glm::dvec3> points;
    for (const double magnitude : {0.0, 4.9e-324, 1e-300, 1e-12, 1e-3, 1.0, 6356752.314245, 6378137.0, 1e7, 4.2e7,
                                   1e9, 1e12, 1e20, 1e100, 1e150}) {
        for (const glm::dvec3& direction : directions()) {
            points.push_back(glm::normalize(direction) * magnitude);
        }
    }
    return points;
}

} // namespace

TEST_CASE("Geodetic conversions, normals and surface projections stay finite for extreme points", "[core][hard][extreme]")
{
    for (const glm::dvec3& p : extremePoints()) {
        INFO("p = (" << p.x << ", " << p.y << ", " << p.z << ")");
        const Geodetic3D g = kEarth.toGeodetic3D(p);
        REQUIRE(std::isfinite(g.longitude));
        REQUIRE(std::isfinite(g.latitude));
        REQUIRE(std::isfinite(g.height));
        REQUIRE(isFinite(kEarth.geodeticSurfaceNormal(p)));
        REQUIRE(isFinite(kEarth.scaleToGeodeticSurface(p)));
        REQUIRE(isFinite(kEarth.scaleToGeocentricSurface(p)));
        const glm::dmat3 enu = eastNorthUpAxes(kEarth, p);
        REQUIRE((isFinite(enu[0]) && isFinite(enu[1]) && isFinite(enu[2])));
        const ViewOrientation view = headingPitchRollToView(kEarth, p, 1.0, -0.5, 0.2);
        REQUIRE((isFinite(view.direction) && isFinite(view.up)));
        for (const glm::dvec3& direction : directions()) {
            const HeadingPitch back = viewToHeadingPitch(kEarth, p, direction);
            REQUIRE((std::isfinite(back.heading) && std::isfinite(back.pitch)));
        }
        const EmulatedDouble split = EmulatedDouble::fromDouble(p.x);
        REQUIRE((std::isfinite(split.high) && std::isfinite(split.low)));
    }
}

TEST_CASE("Ray intersections stay finite for extreme origins and direction lengths", "[core][hard][extreme][intersection]")
{
    const BoundingSphere earthSphere{glm::dvec3(0.0), kEarth.maximumRadius()};
    for (const glm::dvec3& origin : extremePoints()) {
        for (const glm::dvec3& direction : directions()) {
            for (const double length : {1.0, -1.0, 1e-300, 1e300}) {
                const Ray ray{origin, direction * length};
                INFO("origin (" << origin.x << ", " << origin.y << ", " << origin.z << "), direction ("
                                << ray.direction.x << ", " << ray.direction.y << ", " << ray.direction.z << ")");
                if (const auto hit = intersectRayEllipsoid(ray, kEarth)) {
                    REQUIRE((std::isfinite(hit->nearDistance) && std::isfinite(hit->farDistance)));
                    REQUIRE(hit->nearDistance <= hit->farDistance);
                }
                if (const auto hit = intersectRaySphere(ray, earthSphere)) {
                    REQUIRE((std::isfinite(hit->nearDistance) && std::isfinite(hit->farDistance)));
                }
            }
        }
    }
}

TEST_CASE("Curves, tangent planes and horizon culling stay finite for extreme points", "[core][hard][extreme]")
{
    const std::vector<glm::dvec3> points = extremePoints();
    for (const glm::dvec3& p : points) {
        INFO("p = (" << p.x << ", " << p.y << ", " << p.z << ")");
        const EllipsoidTangentPlane plane(kEarth, p);
        REQUIRE((isFinite(plane.origin()) && isFinite(plane.xAxis()) && isFinite(plane.yAxis()) && isFinite(plane.normal())));
        for (const double q : {0.0, 1.0, 1e7, 1e20, 1e300}) {
            REQUIRE(isFinite(plane.projectPointOntoEllipsoid({q, -q})));
        }

        const EllipsoidalOccluder occluder(kEarth, p);
        for (const glm::dvec3& direction : directions()) {
            const auto point = occluder.horizonOcclusionPoint(direction, std::span<const glm::dvec3>(points).first(24));
            REQUIRE((!point || isFinite(*point)));
        }

        for (const glm::dvec3& q : points) {
            INFO("q = (" << q.x << ", " << q.y << ", " << q.z << ")");
            if (const auto projected = plane.projectPointOntoPlane(q)) {
                REQUIRE((std::isfinite(projected->x) && std::isfinite(projected->y)));
            }
            REQUIRE(std::isfinite(plane.cosineFromNormal(q)));
            for (const glm::dvec3& c : kEarth.computeCurve(p, q, 0.25)) {
                REQUIRE(isFinite(c));
            }
            const glm::dvec3 pair[] = {p, q};
            const BoundingSphere sphere = BoundingSphere::fromPoints(pair);
            REQUIRE((isFinite(sphere.centre) && std::isfinite(sphere.radius)));
            REQUIRE(sphere.contains(p));
        }
    }
}
