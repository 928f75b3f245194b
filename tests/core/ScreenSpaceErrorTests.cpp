#include <orbis/core/Math.h>
#include <orbis/core/ScreenSpaceError.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>

using namespace orbis;
using Catch::Matchers::WithinRel;

TEST_CASE("screenSpaceError follows the book's equation 12.1", "[core][geometry][sse]")
{
    // 1 m of error 1 km away on a 1920-pixel, 60-degree view: 1920 / (2000 tan 30 deg) = 1.6628 px.
    // Tolerance: 4 ulp, the rounding of one tangent and three operations.
    const double expected = 1920.0 / (2000.0 * std::tan(toRadians(30.0)));
    REQUIRE_THAT(screenSpaceError(1.0, 1000.0, 1920.0, toRadians(60.0)), WithinRel(expected, 1e-15));
    REQUIRE_THAT(expected, WithinRel(1.66277, 1e-5));
    // Linear in the error and the width, inverse in the distance (exact: powers of two).
    const double base = screenSpaceError(3.0, 500.0, 1000.0, 1.0);
    REQUIRE(screenSpaceError(6.0, 500.0, 1000.0, 1.0) == 2.0 * base);
    REQUIRE(screenSpaceError(3.0, 1000.0, 1000.0, 1.0) == 0.5 * base);
    REQUIRE(screenSpaceError(3.0, 500.0, 2000.0, 1.0) == 2.0 * base);
    // A 90-degree view: tan 45 deg = 1, so rho = epsilon x / 2d.
    REQUIRE_THAT(screenSpaceError(10.0, 100.0, 800.0, kHalfPi), WithinRel(40.0, 1e-15));
}

TEST_CASE("screenSpaceError edge cases are documented values, never NaN", "[core][geometry][sse][hard]")
{
    const double infinity = std::numeric_limits<double>::infinity();
    // The viewer touches the volume: refine.
    REQUIRE(screenSpaceError(1.0, 0.0, 1920.0, 1.0) == infinity);
    REQUIRE(screenSpaceError(1.0, -5.0, 1920.0, 1.0) == infinity);
    // No error, or no pixels: nothing to see, even at distance 0.
    REQUIRE(screenSpaceError(0.0, 0.0, 1920.0, 1.0) == 0.0);
    REQUIRE(screenSpaceError(0.0, 10.0, 1920.0, 1.0) == 0.0);
    REQUIRE(screenSpaceError(-1.0, 10.0, 1920.0, 1.0) == 0.0);
    REQUIRE(screenSpaceError(1.0, 10.0, 0.0, 1.0) == 0.0);
    // Overflow and underflow of the factors.
    REQUIRE(screenSpaceError(1e300, 1e-300, 1e10, 1.0) == infinity);
    REQUIRE(screenSpaceError(1e-300, 1e300, 1.0, 1.0) == 0.0);
    // Products that overflow while the quotient does not: 1e300 * 1e10 / (2 * 1e300 * tan 0.5).
    REQUIRE_THAT(screenSpaceError(1e300, 1e300, 1e10, 1.0), WithinRel(1e10 / (2.0 * std::tan(0.5)), 1e-12));

    const auto seed = GENERATE(take(1, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < 100000; ++i) {
        const double error = std::pow(10.0, 600.0 * unit(random) - 300.0) * (i % 7 == 0 ? 0.0 : 1.0);
        const double distance = std::pow(10.0, 600.0 * unit(random) - 300.0) * (i % 11 == 0 ? 0.0 : 1.0);
        const double width = std::pow(10.0, 20.0 * unit(random) - 10.0);
        const double fov = kPi * unit(random) * (1.0 - 1e-12) + 1e-12;
        const double rho = screenSpaceError(error, distance, width, fov);
        INFO("i " << i << " " << error << " " << distance << " " << width << " " << fov);
        REQUIRE_FALSE(std::isnan(rho));
        REQUIRE(rho >= 0.0);
    }
}
