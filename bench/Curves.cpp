// Curves on WGS84: the book's plane-section curve (Ellipsoid::computeCurve) against the true
// geodesic (orbis::Geodesic, GeographicLib), and what computeCurve's granularity costs and buys.

#include "Report.h"

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/Geodesic.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace orbis::bench {
namespace {

struct CityPair {
    const char* name;
    Geodetic2D a;
    Geodetic2D b;
};

// Longitude, latitude in degrees.
const CityPair kPairs[] = {
    {"Paris - Rouen (short)", Geodetic2D::fromDegrees(2.3522, 48.8566), Geodetic2D::fromDegrees(1.0993, 49.4431)},
    {"Paris - Madrid (medium)", Geodetic2D::fromDegrees(2.3522, 48.8566), Geodetic2D::fromDegrees(-3.7038, 40.4168)},
    {"London - Tokyo (long)", Geodetic2D::fromDegrees(-0.1278, 51.5074), Geodetic2D::fromDegrees(139.6917, 35.6895)},
    {"Madrid - Wellington (near-antipodal)", Geodetic2D::fromDegrees(-3.7038, 40.4168),
     Geodetic2D::fromDegrees(174.7762, -41.2865)},
    {"equator, 0.5 deg short of antipodal", Geodetic2D::fromDegrees(0.0, 0.0), Geodetic2D::fromDegrees(179.5, 0.0)},
};

double polylineLength(const std::vector<glm::dvec3>& points)
{
    double length = 0.0;
    for (std::size_t i = 1; i < points.size(); ++i) {
        length += glm::distance(points[i - 1], points[i]);
    }
    return length;
}

/// Length of the plane-section curve: chord sums at two granularities, Richardson-extrapolated
/// (the chord sum's error falls as the square of the step), good to far below a millimetre.
double planeSectionLength(const Ellipsoid& ellipsoid, const glm::dvec3& a, const glm::dvec3& b, double granularity)
{
    const double coarse = polylineLength(ellipsoid.computeCurve(a, b, 2.0 * granularity));
    const double fine = polylineLength(ellipsoid.computeCurve(a, b, granularity));
    return fine + (fine - coarse) / 3.0;
}

/// Largest distance from a point of the geodesic to the plane-section curve. Each geodesic point
/// is projected onto the section's plane and scaled from the centre onto the surface, which
/// gives a curve point at angle t0 in the plane; golden-section search then finds the nearest
/// curve point within the angles whose distance could beat that one's.
double maxSeparation(const Ellipsoid& ellipsoid, const std::vector<glm::dvec3>& section,
                     const std::vector<glm::dvec3>& geodesic)
{
    const glm::dvec3 u = glm::normalize(section.front());
    const glm::dvec3 normal = glm::normalize(glm::cross(u, section[section.size() / 2]));
    const glm::dvec3 v = glm::cross(normal, u);
    auto curvePoint = [&](double t) { return ellipsoid.scaleToGeocentricSurface(std::cos(t) * u + std::sin(t) * v); };
    double largest = 0.0;
    for (const glm::dvec3& g : geodesic) {
        const double t0 = std::atan2(glm::dot(g, v), glm::dot(g, u));
        const double d0 = glm::distance(g, curvePoint(t0));
        // A curve point more than 2 d0 / b in angle from t0 is farther than d0 from g.
        const double window = 2.0 * d0 / ellipsoid.minimumRadius();
        double lo = t0 - window;
        double hi = t0 + window;
        const double ratio = 0.5 * (std::sqrt(5.0) - 1.0);
        for (int i = 0; i < 80 && hi - lo > 1e-13; ++i) {
            const double m1 = hi - ratio * (hi - lo);
            const double m2 = lo + ratio * (hi - lo);
            if (glm::distance(g, curvePoint(m1)) < glm::distance(g, curvePoint(m2))) {
                hi = m2;
            } else {
                lo = m1;
            }
        }
        largest = std::max(largest, std::min(d0, glm::distance(g, curvePoint(0.5 * (lo + hi)))));
    }
    return largest;
}

/// Deepest point below the surface of the straight segments between consecutive points, sampled
/// at 16 steps per segment (the midpoint included, where a symmetric chord dips most).
double maxChordSag(const Ellipsoid& ellipsoid, const std::vector<glm::dvec3>& points)
{
    double deepest = 0.0;
    for (std::size_t i = 1; i < points.size(); ++i) {
        for (int k = 1; k < 16; ++k) {
            const glm::dvec3 q = glm::mix(points[i - 1], points[i], k / 16.0);
            deepest = std::max(deepest, -ellipsoid.toGeodetic3D(q).height);
        }
    }
    return deepest;
}

std::vector<Table> run(const Options& options)
{
    const Ellipsoid earth = Ellipsoid::wgs84();
    const Geodesic geodesic(earth);

    Table versus;
    versus.title = "Plane-section curve versus geodesic (WGS84)";
    versus.description =
        "The book's curve (Ellipsoid::computeCurve: where the plane through the centre and both ends cuts the "
        "ellipsoid) against the shortest path (Geodesic, GeographicLib). Lengths: the geodesic's from "
        "GeographicLib, the section's from chord sums at 1e-4 and 2e-4 rad, extrapolated. Separation: the largest "
        "distance from a geodesic point (every 1e-3 rad of arc) to its nearest point of the section curve.";
    versus.columns = {"pair", "geodesic length", "section - geodesic length", "max separation"};
    for (const CityPair& pair : kPairs) {
        const glm::dvec3 a = earth.toCartesian(pair.a);
        const glm::dvec3 b = earth.toCartesian(pair.b);
        const double geodesicLength = geodesic.distance(pair.a, pair.b);
        const double sectionLength = planeSectionLength(earth, a, b, 1e-4);
        const double separation =
            maxSeparation(earth, earth.computeCurve(a, b, 1e-3), geodesic.computeGeodesic(pair.a, pair.b, 1e-3));
        versus.rows.push_back({pair.name, formatLength(geodesicLength), formatLength(sectionLength - geodesicLength),
                               formatLength(separation)});
    }
    versus.notes =
        "The section is longer than the geodesic by a second-order amount (micrometres to metres) while the "
        "two stay apart by under a metre over 100 km, tens of metres over 1000 km and kilometres over 10,000 km: "
        "fine for drawing, not for measuring. Near the antipode the geodesic takes another route altogether, "
        "hundreds to thousands of kilometres from the section.";

    Table granularity;
    const CityPair& longPair = kPairs[2];
    granularity.title = "computeCurve granularity: points, chord sag and time (WGS84, " + std::string(longPair.name) + ")";
    granularity.description =
        "Sag: how far the straight segments between consecutive points dip below the ellipsoid, sampled 16 times "
        "per segment with Ellipsoid::toGeodetic3D. The sphere estimate a(1 - cos(g/2)) is given beside it. Time: "
        "best of several runs, per curve; computeGeodesic at the same granularity for comparison.";
    granularity.columns = {"granularity", "points", "max chord sag", "a(1 - cos(g/2))", "computeCurve time",
                           "computeGeodesic time", "geodesic max chord sag"};
    const glm::dvec3 a = earth.toCartesian(longPair.a);
    const glm::dvec3 b = earth.toCartesian(longPair.b);
    const int curvesPerRun = options.quick ? 3 : 30;
    const int repeats = options.quick ? 3 : 7;
    for (const double degrees : {0.1, 0.5, 1.0, 5.0}) {
        const double g = toRadians(degrees);
        const std::vector<glm::dvec3> section = earth.computeCurve(a, b, g);
        const std::vector<glm::dvec3> path = geodesic.computeGeodesic(longPair.a, longPair.b, g);
        const double sectionNs = nanosecondsPerItem(
            static_cast<std::size_t>(curvesPerRun),
            [&] {
                for (int i = 0; i < curvesPerRun; ++i) {
                    const std::vector<glm::dvec3> curve = earth.computeCurve(a, b, g);
                    doNotOptimize(curve.data());
                }
            },
            repeats);
        const double geodesicNs = nanosecondsPerItem(
            static_cast<std::size_t>(curvesPerRun),
            [&] {
                for (int i = 0; i < curvesPerRun; ++i) {
                    const std::vector<glm::dvec3> curve = geodesic.computeGeodesic(longPair.a, longPair.b, g);
                    doNotOptimize(curve.data());
                }
            },
            repeats);
        granularity.rows.push_back({formatNumber(degrees, 2) + " deg", std::to_string(section.size()),
                                    formatLength(maxChordSag(earth, section)),
                                    formatLength(earth.radii().x * (1.0 - std::cos(0.5 * g))),
                                    formatNumber(sectionNs / 1e3, 3) + " µs", formatNumber(geodesicNs / 1e3, 3) + " µs",
                                    formatLength(maxChordSag(earth, path))});
    }
    granularity.notes = "Sag grows as the square of the granularity: a polyline drawn from these points needs a "
                        "depth offset or a finer granularity to stay above terrain at height zero.";
    return {versus, granularity};
}

const SectionRegistration registration("curves", 15, run);

} // namespace
} // namespace orbis::bench
