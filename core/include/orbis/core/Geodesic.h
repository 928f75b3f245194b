#pragma once

#include "orbis/core/Ellipsoid.h"
#include "orbis/core/Geodetic.h"

#include <glm/vec3.hpp>

#include <memory>
#include <vector>

namespace orbis {

/// Geodesics, the shortest paths along the surface, of an ellipsoid of revolution, solved with
/// GeographicLib (Karney's algorithms, accurate to about 15 nm on WGS84). Beside the book's
/// Ellipsoid::computeCurve (the plane section through the centre), which equals the geodesic on
/// a sphere only.
///
/// ```
/// const Geodesic geodesic(Ellipsoid::wgs84());
/// double meters = geodesic.distance(Geodetic2D::fromDegrees(-73.8, 40.6), Geodetic2D::fromDegrees(-0.5, 51.6));
/// std::vector<glm::dvec3> path = geodesic.computeGeodesic(a, b, toRadians(1.0));
/// ```
///
/// Exactly antipodal points have several shortest paths (infinitely many on a sphere);
/// GeographicLib takes the meridian over the pole of a's hemisphere (start azimuth 0, or 180
/// when a is south of the equator), and from one pole to the other the meridian of a's
/// longitude. computeCurve takes the same meridian plane but always heads north, so the two
/// coincide there only when a is not south of the equator. Nearly antipodal points on an oblate ellipsoid are
/// joined by paths far from the plane section (0.5 degrees short of antipodal on the equator,
/// the geodesic leaves the equator at 56 degrees azimuth). Identical points give a distance of
/// 0 and a path of the point twice. Latitudes are clamped to [-pi/2, pi/2]; any longitude is
/// accepted. Finite input never gives NaN.
///
/// Flattening up to 1/50 in magnitude (every Earth and planet model) uses GeographicLib's
/// series (Geodesic); more eccentric spheroids use its elliptic-integral solution
/// (GeodesicExact), slower but accurate for flattenings from -99 to 0.99.
class Geodesic final {
public:
    /// ellipsoid must be a spheroid, radii().x == radii().y (asserted); the z radius may be the
    /// smaller (oblate) or the larger (prolate).
    explicit Geodesic(const Ellipsoid& ellipsoid);
    ~Geodesic();
    Geodesic(const Geodesic& other);
    Geodesic& operator=(const Geodesic& other);
    Geodesic(Geodesic&& other) noexcept;
    Geodesic& operator=(Geodesic&& other) noexcept;

    const Ellipsoid& ellipsoid() const noexcept { return _ellipsoid; }

    /// Length of the shortest path from a to b along the surface (metres); 0 for identical points.
    double distance(const Geodetic2D& a, const Geodetic2D& b) const noexcept;

    /// Points along the shortest path from a to b, on the surface (Cartesian, metres), evenly
    /// spaced at most granularityRadians apart in arc on GeographicLib's auxiliary sphere: on a
    /// sphere that is the angle seen from the centre, as computeCurve's granularity, so both give
    /// the same points; on WGS84 the angle seen from the centre may exceed it by 0.4%. Starts
    /// with toCartesian(a) and ends with toCartesian(b) exactly; identical points give both.
    /// granularityRadians is clamped to at least 1e-6, as in computeCurve.
    std::vector<glm::dvec3> computeGeodesic(const Geodetic2D& a, const Geodetic2D& b,
                                            double granularityRadians) const;

    /// Points along the shortest path from a to b as computeGeodesic, evenly spaced at most
    /// maxSegmentMeters apart along the path (an arc length, not a chord). maxSegmentMeters is
    /// clamped to at least 1e-6 of the equatorial radius (6.4 m on WGS84).
    std::vector<glm::dvec3> computeGeodesicBySegmentLength(const Geodetic2D& a, const Geodetic2D& b,
                                                           double maxSegmentMeters) const;

private:
    struct Solver; ///< GeographicLib's solver, kept out of this header
    Ellipsoid _ellipsoid;
    std::unique_ptr<const Solver> _solver;
};

} // namespace orbis
