#pragma once

#include "orbis/core/Ellipsoid.h"
#include "orbis/core/GeodeticExtent.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cassert>
#include <cmath>
#include <vector>

namespace orbis {

/// A regular grid of columns x rows points over a longitude-latitude extent (column 0 at the
/// west edge, row 0 at the north edge, the last ones exactly on the east and south edges), with
/// the sines and cosines computed once per row and column instead of once per point: tile meshes
/// and tile bounds are made of such grids, thousands per second while the camera moves.
class GeodeticGrid final {
public:
    GeodeticGrid(const Ellipsoid& ellipsoid, const GeodeticExtent& extent, int columns, int rows)
        : _radiiSquared(ellipsoid.radii() * ellipsoid.radii())
        , _columns(columns)
        , _cosLongitude(columns)
        , _sinLongitude(columns)
        , _cosLatitude(rows)
        , _sinLatitude(rows)
    {
        assert(columns >= 2 && rows >= 2);
        for (int i = 0; i < columns; ++i) {
            const double longitude = extent.west + extent.width() * i / (columns - 1);
            _cosLongitude[i] = std::cos(longitude);
            _sinLongitude[i] = std::sin(longitude);
        }
        for (int j = 0; j < rows; ++j) {
            const double latitude = j + 1 == rows ? extent.south : extent.north - extent.height() * j / (rows - 1);
            _cosLatitude[j] = std::cos(latitude);
            _sinLatitude[j] = std::sin(latitude);
        }
    }

    /// A grid through the given longitudes (west to east) and latitudes (north to south).
    GeodeticGrid(const Ellipsoid& ellipsoid, const std::vector<double>& longitudes, const std::vector<double>& latitudes)
        : _radiiSquared(ellipsoid.radii() * ellipsoid.radii())
        , _columns(static_cast<int>(longitudes.size()))
    {
        for (const double longitude : longitudes) {
            _cosLongitude.push_back(std::cos(longitude));
            _sinLongitude.push_back(std::sin(longitude));
        }
        for (const double latitude : latitudes) {
            _cosLatitude.push_back(std::cos(latitude));
            _sinLatitude.push_back(std::sin(latitude));
        }
    }

    int columns() const noexcept { return _columns; }
    int rows() const noexcept { return static_cast<int>(_cosLatitude.size()); }

    /// The geodetic surface normal at column i, row j.
    glm::dvec3 normal(int i, int j) const noexcept
    {
        return {_cosLatitude[j] * _cosLongitude[i], _cosLatitude[j] * _sinLongitude[i], _sinLatitude[j]};
    }

    /// The point on the surface with that normal, as Ellipsoid::toCartesian computes it.
    glm::dvec3 surface(const glm::dvec3& normal) const noexcept
    {
        const glm::dvec3 k = _radiiSquared * normal;
        return k / std::sqrt(glm::dot(k, normal));
    }

private:
    glm::dvec3 _radiiSquared;
    int _columns;
    std::vector<double> _cosLongitude;
    std::vector<double> _sinLongitude;
    std::vector<double> _cosLatitude;
    std::vector<double> _sinLatitude;
};

} // namespace orbis
