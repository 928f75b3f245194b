#include <orbis/core/Frustum.h>
#include <orbis/core/Math.h>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace orbis;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {

struct Camera {
    glm::dvec3 eye;
    glm::dvec3 target;
    glm::dvec3 up;
    double fovy;
    double aspect;
    double nearDistance;
    double farDistance;

    glm::dmat4 view() const { return glm::lookAt(eye, target, up); }
    glm::dmat4 projection() const { return glm::perspective(fovy, aspect, nearDistance, farDistance); }
    glm::dvec3 forward() const { return glm::normalize(target - eye); }
};

/// World-space corner of the clip volume at NDC (x, y, z), each -1 or 1.
glm::dvec3 corner(const glm::dmat4& viewProjection, double x, double y, double z)
{
    const glm::dvec4 p = glm::inverse(viewProjection) * glm::dvec4(x, y, z, 1.0);
    return glm::dvec3(p) / p.w;
}

} // namespace

TEST_CASE("Frustum planes pass through the clip volume's corners and face inwards", "[core][geometry][frustum]")
{
    // A camera 20,000 km from the Earth's centre, so that the plane distances are large.
    const Camera camera{{2e7, 1e6, -3e6}, {0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, toRadians(50.0), 1.5, 10.0, 4e7};
    const glm::dmat4 viewProjection = camera.projection() * camera.view();
    const Frustum frustum = Frustum::fromViewProjection(viewProjection);

    // Each corner lies on the three planes of its sides. Tolerance: 1e-9 of the corner's distance
    // from the origin, the rounding of inverting a matrix with entries from 1e-8 to 2e7.
    const Frustum::Side xSides[] = {Frustum::Left, Frustum::Right};
    const Frustum::Side ySides[] = {Frustum::Bottom, Frustum::Top};
    const Frustum::Side zSides[] = {Frustum::Near, Frustum::Far};
    for (int i = 0; i < 8; ++i) {
        const int ix = i & 1, iy = (i >> 1) & 1, iz = (i >> 2) & 1;
        const glm::dvec3 c = corner(viewProjection, ix ? 1.0 : -1.0, iy ? 1.0 : -1.0, iz ? 1.0 : -1.0);
        const double tolerance = 1e-9 * glm::length(c);
        INFO("corner " << i);
        REQUIRE(std::abs(frustum.plane(xSides[ix]).signedDistance(c)) <= tolerance);
        REQUIRE(std::abs(frustum.plane(ySides[iy]).signedDistance(c)) <= tolerance);
        REQUIRE(std::abs(frustum.plane(zSides[iz]).signedDistance(c)) <= tolerance);
        for (const Plane& plane : frustum.planes()) {
            REQUIRE_THAT(glm::length(plane.normal), WithinRel(1.0, 1e-15));
            REQUIRE(plane.signedDistance(c) >= -tolerance);
        }
    }
    REQUIRE(frustum.contains(camera.eye + 1000.0 * camera.forward()));
    REQUIRE_FALSE(frustum.contains(camera.eye + 5.0 * camera.forward()));  // before the near plane
    REQUIRE_FALSE(frustum.contains(camera.eye - 1000.0 * camera.forward())); // behind the camera
    REQUIRE_FALSE(frustum.contains(camera.eye + 5e7 * camera.forward()));   // beyond the far plane
    // The near plane faces forward; the far plane backward.
    REQUIRE_THAT(glm::dot(frustum.plane(Frustum::Near).normal, camera.forward()), WithinRel(1.0, 1e-12));
    REQUIRE_THAT(glm::dot(frustum.plane(Frustum::Far).normal, camera.forward()), WithinRel(-1.0, 1e-12));
}

TEST_CASE("Frustum classifies spheres as inside, intersecting or outside", "[core][geometry][frustum]")
{
    const Camera camera{{0.0, 0.0, 0.0}, {0.0, 0.0, -1.0}, {0.0, 1.0, 0.0}, toRadians(60.0), 1.0, 1.0, 1000.0};
    const Frustum frustum = Frustum::fromViewProjection(camera.projection() * camera.view());
    // The side planes are at 30 degrees from the -z axis; at depth 100 the half-width is 57.7.
    REQUIRE(frustum.intersect({{0.0, 0.0, -100.0}, 10.0}) == Intersect::Inside);
    REQUIRE(frustum.intersect({{57.7, 0.0, -100.0}, 10.0}) == Intersect::Intersecting);  // right plane
    REQUIRE(frustum.intersect({{0.0, -57.7, -100.0}, 10.0}) == Intersect::Intersecting); // bottom plane
    REQUIRE(frustum.intersect({{100.0, 0.0, -100.0}, 10.0}) == Intersect::Outside);     // beyond the right
    REQUIRE(frustum.intersect({{-100.0, 0.0, -100.0}, 10.0}) == Intersect::Outside);
    REQUIRE(frustum.intersect({{0.0, 100.0, -100.0}, 10.0}) == Intersect::Outside);
    REQUIRE(frustum.intersect({{0.0, 0.0, 20.0}, 10.0}) == Intersect::Outside);     // behind
    REQUIRE(frustum.intersect({{0.0, 0.0, -0.5}, 0.25}) == Intersect::Outside);     // before near
    REQUIRE(frustum.intersect({{0.0, 0.0, -1.0}, 0.25}) == Intersect::Intersecting); // on near
    REQUIRE(frustum.intersect({{0.0, 0.0, -1200.0}, 100.0}) == Intersect::Outside);  // beyond far
    REQUIRE(frustum.intersect({{0.0, 0.0, -1000.0}, 1.0}) == Intersect::Intersecting);
    REQUIRE(frustum.intersect({{0.0, 0.0, 0.0}, 1e4}) == Intersect::Intersecting);    // around it all
}

TEST_CASE("Frustum sees the whole Earth from orbit and culls a sphere behind the camera", "[core][geometry][frustum]")
{
    // From 3 Earth radii the Earth subtends asin(1/3) = 19.5 degrees: inside a 60-degree view.
    const double radius = 6378137.0;
    const Camera camera{{3.0 * radius, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, toRadians(60.0), 1.0, 1.0, 1e8};
    const Frustum frustum = Frustum::fromViewProjection(camera.projection() * camera.view());
    REQUIRE(frustum.intersect({{0.0, 0.0, 0.0}, radius}) == Intersect::Inside);
    REQUIRE(frustum.intersect({{4.0 * radius, 0.0, 0.0}, radius}) == Intersect::Outside);
    // 53 degrees off the view axis, 5.7 degrees across: wholly right of the 30-degree side plane.
    REQUIRE(frustum.intersect({{0.0, 4.0 * radius, 0.0}, 0.5 * radius}) == Intersect::Outside);
    // 33.7 degrees off the axis and 8 degrees across: it straddles the side plane.
    REQUIRE(frustum.intersect({{0.0, 2.0 * radius, 0.0}, 0.5 * radius}) == Intersect::Intersecting);
}

TEST_CASE("Frustum of an infinite projection has a far plane that contains everything", "[core][geometry][frustum]")
{
    const glm::dmat4 projection = glm::infinitePerspective(toRadians(45.0), 1.0, 1.0);
    const Frustum frustum = Frustum::fromViewProjection(projection);
    const Plane& far = frustum.plane(Frustum::Far);
    REQUIRE(far.normal == glm::dvec3(0.0));
    REQUIRE(far.distance == std::numeric_limits<double>::infinity());
    REQUIRE(frustum.intersect({{0.0, 0.0, -1e300}, 1.0}) == Intersect::Inside);
    REQUIRE(frustum.intersect({{0.0, 0.0, 10.0}, 1.0}) == Intersect::Outside);
    REQUIRE(frustum.contains({0.0, 0.0, -1e30}));
    for (const Plane& plane : frustum.planes()) {
        REQUIRE_FALSE(std::isnan(plane.signedDistance({1.0, 2.0, -3.0})));
    }
}

TEST_CASE("Frustum of an orthographic projection is a box", "[core][geometry][frustum]")
{
    const Frustum frustum = Frustum::fromViewProjection(glm::ortho(-2.0, 2.0, -1.0, 1.0, 0.5, 10.0));
    REQUIRE(frustum.plane(Frustum::Left).normal == glm::dvec3(1.0, 0.0, 0.0));
    REQUIRE(frustum.plane(Frustum::Left).distance == 2.0);
    REQUIRE(frustum.plane(Frustum::Top).normal == glm::dvec3(0.0, -1.0, 0.0));
    REQUIRE(frustum.plane(Frustum::Top).distance == 1.0);
    // The eye looks down -z: near is z = -0.5, far z = -10.
    REQUIRE_THAT(frustum.plane(Frustum::Near).signedDistance({0.0, 0.0, -0.5}), WithinAbs(0.0, 1e-15));
    REQUIRE_THAT(frustum.plane(Frustum::Far).signedDistance({0.0, 0.0, -10.0}), WithinAbs(0.0, 1e-14));
    REQUIRE(frustum.contains({1.9, -0.9, -9.9}));
    REQUIRE_FALSE(frustum.contains({2.1, 0.0, -5.0}));
}
