#include <orbis/core/SunPosition.h>

#include <orbis/core/Math.h>

#include <glm/geometric.hpp>

#include <catch2/catch.hpp>

#include <cmath>

using namespace orbis;
using Catch::Matchers::WithinAbs;

namespace {
double subsolarLatitudeDegrees(const glm::dvec3& sun)
{
    return toDegrees(std::asin(sun.z));
}
double subsolarLongitudeDegrees(const glm::dvec3& sun)
{
    return toDegrees(std::atan2(sun.y, sun.x));
}
std::chrono::sys_seconds at(const char* text)
{
    return parseUtcTime(text).value();
}
} // namespace

TEST_CASE("The Sun stands over the tropics at the solstices and the equator at the equinoxes", "[core][sun]")
{
    // Published instants (UTC): March equinox 2026-03-20 14:46, June solstice 2026-06-21 08:24,
    // December solstice 2026-12-21 20:50. 0.05 degrees covers the formulas' error.
    REQUIRE_THAT(subsolarLatitudeDegrees(sunDirectionEarthFixed(at("2026-03-20T14:46:00Z"))), WithinAbs(0.0, 0.05));
    REQUIRE_THAT(subsolarLatitudeDegrees(sunDirectionEarthFixed(at("2026-06-21T08:24:00Z"))), WithinAbs(23.436, 0.05));
    REQUIRE_THAT(subsolarLatitudeDegrees(sunDirectionEarthFixed(at("2026-12-21T20:50:00Z"))), WithinAbs(-23.436, 0.05));
}

TEST_CASE("The Sun crosses the prime meridian near noon UTC, offset by the equation of time", "[core][sun]")
{
    // Around 2026-11-03 the equation of time is +16.4 min: the Sun transits Greenwich at 11:43:36 UTC.
    const glm::dvec3 sun = sunDirectionEarthFixed(at("2026-11-03T11:43:36Z"));
    REQUIRE_THAT(subsolarLongitudeDegrees(sun), WithinAbs(0.0, 0.1));
    REQUIRE_THAT(glm::length(sun), WithinAbs(1.0, 1e-15));
    // Six hours later it stands 90 degrees further west (less 1.5 minutes of motion).
    REQUIRE_THAT(subsolarLongitudeDegrees(sunDirectionEarthFixed(at("2026-11-03T17:43:36Z"))), WithinAbs(-90.0, 0.2));
}

TEST_CASE("parseUtcTime accepts the scene-file form and rejects anything else", "[core][sun]")
{
    REQUIRE(parseUtcTime("2026-06-21T12:00:00Z").has_value());
    REQUIRE_FALSE(parseUtcTime("2026-06-21 12:00:00Z").has_value());
    REQUIRE_FALSE(parseUtcTime("2026-02-30T12:00:00Z").has_value());
    REQUIRE_FALSE(parseUtcTime("2026-06-21T24:00:00Z").has_value());
    REQUIRE_FALSE(parseUtcTime("2026-06-21T12:00:00").has_value());
    REQUIRE_FALSE(parseUtcTime("").has_value());
    REQUIRE(parseUtcTime("2000-01-01T12:00:00Z")->time_since_epoch().count() == 946728000);
}
