#include "orbis/core/SunPosition.h"

#include "orbis/core/Math.h"

#include <charconv>
#include <cmath>

namespace orbis {

glm::dvec3 sunDirectionEarthFixed(std::chrono::sys_seconds utc) noexcept
{
    // Days since J2000.0 (2000-01-01 12:00 UTC); the UT1 - UTC difference (< 1 s) is ignored.
    constexpr std::chrono::sys_seconds kJ2000{std::chrono::sys_days{std::chrono::year{2000} / 1 / 1} +
                                              std::chrono::hours{12}};
    const double days = std::chrono::duration<double, std::ratio<86400>>(utc - kJ2000).count();

    const double meanLongitude = toRadians(std::remainder(280.460 + 0.9856474 * days, 360.0));
    const double meanAnomaly = toRadians(std::remainder(357.528 + 0.9856003 * days, 360.0));
    const double eclipticLongitude =
        meanLongitude + toRadians(1.915) * std::sin(meanAnomaly) + toRadians(0.020) * std::sin(2.0 * meanAnomaly);
    const double obliquity = toRadians(23.439 - 0.0000004 * days);

    const glm::dvec3 inertial(std::cos(eclipticLongitude), std::cos(obliquity) * std::sin(eclipticLongitude),
                              std::sin(obliquity) * std::sin(eclipticLongitude));
    const double siderealAngle = toRadians(std::remainder(280.46061837 + 360.98564736629 * days, 360.0));
    const double c = std::cos(siderealAngle);
    const double s = std::sin(siderealAngle);
    return {c * inertial.x + s * inertial.y, -s * inertial.x + c * inertial.y, inertial.z};
}

std::optional<std::chrono::sys_seconds> parseUtcTime(std::string_view text) noexcept
{
    // Exactly YYYY-MM-DDTHH:MM:SSZ.
    if (text.size() != 20 || text[4] != '-' || text[7] != '-' || text[10] != 'T' || text[13] != ':' ||
        text[16] != ':' || text[19] != 'Z') {
        return std::nullopt;
    }
    auto number = [&](std::size_t at, std::size_t length, int& out) {
        const char* first = text.data() + at;
        const auto [end, error] = std::from_chars(first, first + length, out);
        return error == std::errc() && end == first + length;
    };
    int year, month, day, hour, minute, second;
    if (!number(0, 4, year) || !number(5, 2, month) || !number(8, 2, day) || !number(11, 2, hour) ||
        !number(14, 2, minute) || !number(17, 2, second)) {
        return std::nullopt;
    }
    const std::chrono::year_month_day date{std::chrono::year{year}, std::chrono::month{static_cast<unsigned>(month)},
                                           std::chrono::day{static_cast<unsigned>(day)}};
    if (!date.ok() || hour > 23 || minute > 59 || second > 60) {
        return std::nullopt;
    }
    return std::chrono::sys_days{date} + std::chrono::hours{hour} + std::chrono::minutes{minute} +
           std::chrono::seconds{second};
}

} // namespace orbis
