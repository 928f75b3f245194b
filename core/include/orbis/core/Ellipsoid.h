#pragma once

#include "orbis/core/Geodetic.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <vector>

namespace orbis {

/// An ellipsoid centred at the origin with semi-axes radii() along x, y and z (metres).
///
/// Geodetic conversions are exact to a few units in the last place for ellipsoids of revolution
/// (radii().x == radii().y, as every Earth model); triaxial ellipsoids use an iterative foot-point
/// search of the same accuracy but slower.
///
/// Points with more than one closest surface point (the centre, and points on the equatorial
/// plane deep inside) take the northern one, as GeographicLib does: the centre converts to
/// latitude +90 degrees, longitude 0 and height minus the polar radius.
class Ellipsoid final {
public:
    /// radii must be positive and finite (asserted).
    explicit Ellipsoid(const glm::dvec3& radii) noexcept;
    Ellipsoid(double x, double y, double z) noexcept : Ellipsoid(glm::dvec3(x, y, z)) {}

    /// WGS84: a = 6378137 m, 1/f = 298.257223563.
    static Ellipsoid wgs84() noexcept;
    /// WGS84 divided by its equatorial radius, so that x = y = 1.
    static Ellipsoid scaledWgs84() noexcept;
    static Ellipsoid unitSphere() noexcept;

    const glm::dvec3& radii() const noexcept { return _radii; }
    const glm::dvec3& radiiSquared() const noexcept { return _radiiSquared; }
    const glm::dvec3& oneOverRadii() const noexcept { return _oneOverRadii; }
    const glm::dvec3& oneOverRadiiSquared() const noexcept { return _oneOverRadiiSquared; }
    double minimumRadius() const noexcept;
    double maximumRadius() const noexcept;
    /// True when the x and y radii are equal (an ellipsoid of revolution about z).
    bool isSpheroid() const noexcept { return _radii.x == _radii.y; }

    /// Unit vector from the centre through p; +z for the centre itself.
    static glm::dvec3 geocentricSurfaceNormal(const glm::dvec3& p) noexcept;
    /// Unit normal of the ellipsoid's level surface through p (exact on the surface); +z for the centre.
    glm::dvec3 geodeticSurfaceNormal(const glm::dvec3& p) const noexcept;
    /// Unit normal at a geodetic position (depends only on longitude and latitude).
    static glm::dvec3 geodeticSurfaceNormal(const Geodetic3D& g) noexcept;
    static glm::dvec3 geodeticSurfaceNormal(const Geodetic2D& g) noexcept;

    glm::dvec3 toCartesian(const Geodetic3D& g) const noexcept;
    glm::dvec3 toCartesian(const Geodetic2D& g) const noexcept;

    /// Geodetic longitude (-pi, pi], latitude [-pi/2, pi/2] and height of p. Longitude is 0 on the
    /// z axis. Never NaN for finite p.
    Geodetic3D toGeodetic3D(const glm::dvec3& p) const noexcept;
    Geodetic2D toGeodetic2D(const glm::dvec3& p) const noexcept;
    /// The book's conversion (section 2.3.3: Newton's method for the surface point, latitude by
    /// asin, height by distance), kept as the baseline of the accuracy-versus-time report. Errors
    /// reach millimetres near the poles; the centre gives the north pole.
    Geodetic3D toGeodetic3DBook(const glm::dvec3& p) const noexcept;

    /// The closest point on the surface to p (the foot of p's geodetic normal); the north pole
    /// for the centre.
    glm::dvec3 scaleToGeodeticSurface(const glm::dvec3& p) const noexcept;
    /// The point where the ray from the centre through p meets the surface; the north pole for
    /// the centre.
    glm::dvec3 scaleToGeocentricSurface(const glm::dvec3& p) const noexcept;

    /// Points along the curve where the plane through the centre, start and stop cuts the
    /// surface (book section 2.4), spaced at most granularityRadians apart as seen from the
    /// centre. Starts with start and ends with stop exactly; identical points give both;
    /// antipodal points take the plane through the z axis (through the x axis for the poles).
    /// granularityRadians is clamped to at least 1e-6 so that the result stays bounded.
    std::vector<glm::dvec3> computeCurve(const glm::dvec3& start, const glm::dvec3& stop,
                                         double granularityRadians) const;

    friend bool operator==(const Ellipsoid& a, const Ellipsoid& b) noexcept { return a._radii == b._radii; }

private:
    struct Foot {
        glm::dvec3 surface;
        glm::dvec3 normal;
        double height;
    };
    /// The foot of the normal in the meridian plane of a spheroid, first quadrant (rho, |z| >= 0).
    struct MeridianFoot {
        glm::dvec2 foot;
        glm::dvec2 normal;
        double height;
    };
    MeridianFoot footInMeridianPlane(double rho, double zAbs) const noexcept;
    Foot footOfNormal(const glm::dvec3& p) const noexcept;
    Foot footOfNormalSpheroid(const glm::dvec3& p) const noexcept;
    Foot footOfNormalTriaxial(const glm::dvec3& p) const noexcept;

    glm::dvec3 _radii;
    glm::dvec3 _radiiSquared;
    glm::dvec3 _oneOverRadii;
    glm::dvec3 _oneOverRadiiSquared;
};

} // namespace orbis
