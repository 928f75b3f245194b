#pragma once

namespace orbis {

/// The path a line on the ellipsoid follows between two consecutive positions.
enum class CurveType {
    PlaneSection, ///< the curve cut by the plane through the centre and both ends (Ellipsoid::computeCurve)
    Geodesic,     ///< the shortest path (Geodesic::computeGeodesic); ellipsoids of revolution only
};

} // namespace orbis
