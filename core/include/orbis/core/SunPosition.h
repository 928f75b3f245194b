#pragma once

#include <glm/vec3.hpp>

#include <chrono>
#include <optional>
#include <string_view>

namespace orbis {

/// Unit vector from the Earth's centre towards the Sun, in the Earth-fixed frame (x through
/// longitude 0 on the equator, z north), at a UTC time. Low-precision formulas of the
/// Astronomical Almanac with Greenwich mean sidereal time: about 0.01 degrees from 1950 to 2050,
/// plenty for lighting a globe.
glm::dvec3 sunDirectionEarthFixed(std::chrono::sys_seconds utc) noexcept;

/// Parses "YYYY-MM-DDTHH:MM:SSZ" (UTC, the form scene files use); empty for anything else or an
/// impossible date.
std::optional<std::chrono::sys_seconds> parseUtcTime(std::string_view text) noexcept;

} // namespace orbis
