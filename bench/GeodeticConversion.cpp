// Geodetic <-> Cartesian on WGS84: Orbis, the book's Newton method and GeographicLib, side by side.
// Errors are measured with an extended-precision (x87 long double) forward conversion, so the
// figure is the error of the method itself, not of the yardstick.

#include "Report.h"

#include <orbis/core/Ellipsoid.h>

#include <GeographicLib/Constants.hpp>
#include <GeographicLib/Geocentric.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <random>

namespace orbis::bench {
namespace {

constexpr long double kA = 6378137.0L;
constexpr long double kF = 1.0L / 298.257223563L;
constexpr long double kE2 = kF * (2.0L - kF);
constexpr long double kPiL = 3.141592653589793238462643383279502884L;

struct PointL {
    long double x, y, z;
};

PointL forwardExtended(long double longitude, long double latitude, long double height)
{
    const long double sinLat = std::sin(latitude);
    const long double cosLat = std::cos(latitude);
    const long double n = kA / std::sqrt(1.0L - kE2 * sinLat * sinLat);
    return {(n + height) * cosLat * std::cos(longitude), (n + height) * cosLat * std::sin(longitude),
            (n * (1.0L - kE2) + height) * sinLat};
}

double distance(const PointL& a, const glm::dvec3& b)
{
    const long double dx = a.x - b.x;
    const long double dy = a.y - b.y;
    const long double dz = a.z - b.z;
    return static_cast<double>(std::sqrt(dx * dx + dy * dy + dz * dz));
}

struct Sample {
    Geodetic3D geodetic;
    glm::dvec3 cartesian; ///< the exact position rounded to doubles
};

/// Latitudes cover the poles exactly and within 1e-12 rad, longitudes both sides of the
/// antimeridian, heights from -100 km to 100,000 km, log-spaced so that every scale is present.
std::vector<Sample> makeSamples(std::size_t count)
{
    std::mt19937_64 random(20261123);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double specialLatitudes[] = {kHalfPi, kHalfPi - 1e-12, kHalfPi - 1e-6, 0.0, 1e-12, toRadians(45.0)};
    const double specialLongitudes[] = {kPi, -kPi, kPi - 1e-12, 0.0};
    std::vector<Sample> samples;
    samples.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        double latitude = std::asin(2.0 * unit(random) - 1.0);
        double longitude = kPi * (2.0 * unit(random) - 1.0);
        if (i % 7 == 0) {
            latitude = specialLatitudes[(i / 7) % std::size(specialLatitudes)] * (i % 2 ? 1.0 : -1.0);
        }
        if (i % 11 == 0) {
            longitude = specialLongitudes[(i / 11) % std::size(specialLongitudes)];
        }
        double height = 0.0;
        const double u = unit(random);
        if (i % 5 == 0) {
            height = -1e5 * u; // down to -100 km
        } else if (i % 5 != 1) {
            height = std::pow(10.0, 8.0 * u); // 1 m to 100,000 km
        }
        const PointL p = forwardExtended(longitude, latitude, height);
        samples.push_back({{longitude, latitude, height},
                           {static_cast<double>(p.x), static_cast<double>(p.y), static_cast<double>(p.z)}});
    }
    return samples;
}

/// The bound the tests hold: 10 nm + 4e-16 of the distance from the centre.
double errorBound(const glm::dvec3& p)
{
    return 10e-9 + 4e-16 * glm::length(p);
}

struct ReverseResult {
    double maxError = 0.0;
    double maxErrorNearEarth = 0.0; ///< |height| <= 100 km
    double maxErrorOverBound = 0.0;
    double nanoseconds = 0.0;
};

template <typename Reverse>
ReverseResult measureReverse(const std::vector<Sample>& samples, Reverse reverse)
{
    ReverseResult result;
    for (const Sample& sample : samples) {
        const auto [longitude, latitude, height] = reverse(sample.cartesian);
        const double error = distance(forwardExtended(longitude, latitude, height), sample.cartesian);
        result.maxError = std::max(result.maxError, error);
        if (std::abs(sample.geodetic.height) <= 1e5) {
            result.maxErrorNearEarth = std::max(result.maxErrorNearEarth, error);
        }
        result.maxErrorOverBound = std::max(result.maxErrorOverBound, error / errorBound(sample.cartesian));
    }
    result.nanoseconds = nanosecondsPerItem(samples.size(), [&] {
        for (const Sample& sample : samples) {
            const auto g = reverse(sample.cartesian);
            doNotOptimize(g);
        }
    });
    return result;
}

struct Extended {
    long double longitude, latitude, height;
};

/// Widened explicitly: the value is exact either way, but Clang's -Wdouble-promotion asks for it.
Extended extended(double longitude, double latitude, double height)
{
    return {static_cast<long double>(longitude), static_cast<long double>(latitude), static_cast<long double>(height)};
}

std::vector<Table> run(const Options& options)
{
    const std::vector<Sample> samples = makeSamples(options.quick ? 20000 : 400000);
    const Ellipsoid earth = Ellipsoid::wgs84();
    const GeographicLib::Geocentric& geographicLib = GeographicLib::Geocentric::WGS84();
    constexpr long double degree = kPiL / 180.0L;

    auto orbisReverse = [&](const glm::dvec3& p) {
        const Geodetic3D g = earth.toGeodetic3D(p);
        return extended(g.longitude, g.latitude, g.height);
    };
    auto bookReverse = [&](const glm::dvec3& p) {
        const Geodetic3D g = earth.toGeodetic3DBook(p);
        return extended(g.longitude, g.latitude, g.height);
    };
    auto geographicLibReverse = [&](const glm::dvec3& p) {
        double latitude, longitude, height;
        geographicLib.Reverse(p.x, p.y, p.z, latitude, longitude, height);
        const Extended e = extended(longitude, latitude, height);
        return Extended{e.longitude * degree, e.latitude * degree, e.height};
    };

    Table reverse;
    reverse.title = "Cartesian to geodetic (WGS84)";
    reverse.description =
        std::to_string(samples.size()) +
        " points: latitudes uniform on the sphere plus the poles exactly and within 1e-12 rad, longitudes "
        "both sides of the antimeridian, heights from -100 km to 100,000 km. Error: distance between the "
        "input point and the position the method's answer denotes, computed in extended precision. The bound "
        "is 10 nm + 4e-16 x distance from the centre (about 13 nm on the surface).";
    reverse.columns = {"method", "max error", "max error, |h| <= 100 km", "max error / bound", "ns per point"};
    const std::pair<const char*, ReverseResult> results[] = {
        {"Orbis Ellipsoid::toGeodetic3D (Newton on the foot, Bowring start)", measureReverse(samples, orbisReverse)},
        {"Book section 2.3.3 (Ellipsoid::toGeodetic3DBook)", measureReverse(samples, bookReverse)},
        {"GeographicLib Geocentric::Reverse", measureReverse(samples, geographicLibReverse)},
    };
    for (const auto& [name, r] : results) {
        reverse.rows.push_back({name, formatLength(r.maxError), formatLength(r.maxErrorNearEarth),
                                formatNumber(r.maxErrorOverBound, 2), formatNumber(r.nanoseconds, 3)});
    }

    Table forward;
    forward.title = "Geodetic to Cartesian (WGS84)";
    forward.description = "The same points the other way: error against the extended-precision conversion.";
    forward.columns = {"method", "max error", "max error / bound", "ns per point"};
    auto measureForward = [&](const char* name, auto convert) {
        double maxError = 0.0;
        double maxOverBound = 0.0;
        for (const Sample& sample : samples) {
            const glm::dvec3 p = convert(sample.geodetic);
            const Geodetic3D& g = sample.geodetic;
            const Extended e = extended(g.longitude, g.latitude, g.height);
            const double error = distance(forwardExtended(e.longitude, e.latitude, e.height), p);
            maxError = std::max(maxError, error);
            maxOverBound = std::max(maxOverBound, error / errorBound(sample.cartesian));
        }
        const double ns = nanosecondsPerItem(samples.size(), [&] {
            for (const Sample& sample : samples) {
                const glm::dvec3 p = convert(sample.geodetic);
                doNotOptimize(p);
            }
        });
        forward.rows.push_back({name, formatLength(maxError), formatNumber(maxOverBound, 2), formatNumber(ns, 3)});
    };
    measureForward("Orbis Ellipsoid::toCartesian", [&](const Geodetic3D& g) { return earth.toCartesian(g); });
    // GeographicLib takes degrees; the conversion is part of what a caller with radians pays.
    measureForward("GeographicLib Geocentric::Forward", [&](const Geodetic3D& g) {
        glm::dvec3 p;
        geographicLib.Forward(toDegrees(g.latitude), toDegrees(g.longitude), g.height, p.x, p.y, p.z);
        return p;
    });
    return {reverse, forward};
}

const SectionRegistration registration("geodetic conversion", 10, run);

} // namespace
} // namespace orbis::bench
