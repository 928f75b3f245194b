#pragma once

// What the polygon tests and the polygons bench section need from the data, and nothing more
// (a GeoJSON loader proper is later work): the Polygon and MultiPolygon features of a
// FeatureCollection as rings of (longitude, latitude) in degrees, and areas on WGS84 by
// GeographicLib, independent of Orbis.

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/Mesh.h>

#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/PolygonArea.hpp>

// GCC's -Wnull-dereference fires inside nlohmann/json once inlined at -O3 (a false positive in
// the library's iterator code); silence it for that header only.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wnull-dereference"
#include <nlohmann/json.hpp>
#pragma GCC diagnostic pop

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace orbis::testdata {

/// One polygon of a feature: its name, which part of a MultiPolygon it is, and its rings (outer
/// first) of (longitude, latitude) degrees as the file has them (GeoJSON rings repeat their first
/// vertex at the end).
struct GeoPolygon {
    std::string name;
    std::size_t part = 0;
    std::vector<std::vector<glm::dvec2>> ringsDegrees;

    /// "Russia, part 9" for messages.
    std::string label() const { return name + ", part " + std::to_string(part); }
};

/// Path of a file in the repository's data/natural-earth folder.
inline std::string naturalEarthPath(const std::string& file)
{
    return std::string(ORBIS_SOURCE_DIR) + "/data/natural-earth/" + file;
}

/// Every polygon of every Polygon or MultiPolygon feature of a GeoJSON FeatureCollection, named by
/// the feature's "name" property. Throws std::runtime_error when the file cannot be read.
inline std::vector<GeoPolygon> loadPolygons(const std::string& path)
{
    std::ifstream in(path);
    if (!in) {
        throw std::runtime_error("cannot read " + path);
    }
    const nlohmann::json collection = nlohmann::json::parse(in);
    std::vector<GeoPolygon> polygons;
    auto readPolygon = [](const nlohmann::json& rings) {
        std::vector<std::vector<glm::dvec2>> result;
        for (const nlohmann::json& ring : rings) {
            std::vector<glm::dvec2> points;
            for (const nlohmann::json& position : ring) {
                points.emplace_back(position.at(0).get<double>(), position.at(1).get<double>());
            }
            result.push_back(std::move(points));
        }
        return result;
    };
    for (const nlohmann::json& feature : collection.at("features")) {
        const nlohmann::json& geometry = feature.at("geometry");
        if (geometry.is_null()) {
            continue;
        }
        const std::string name = feature.at("properties").value("name", std::string("unnamed"));
        const std::string type = geometry.at("type").get<std::string>();
        if (type == "Polygon") {
            polygons.push_back({name, 0, readPolygon(geometry.at("coordinates"))});
        } else if (type == "MultiPolygon") {
            std::size_t part = 0;
            for (const nlohmann::json& rings : geometry.at("coordinates")) {
                polygons.push_back({name, part++, readPolygon(rings)});
            }
        }
    }
    return polygons;
}

/// The rings as positions on the ellipsoid.
inline std::vector<std::vector<glm::dvec3>> toCartesian(const Ellipsoid& ellipsoid,
                                                        const std::vector<std::vector<glm::dvec2>>& ringsDegrees)
{
    std::vector<std::vector<glm::dvec3>> rings;
    for (const std::vector<glm::dvec2>& ring : ringsDegrees) {
        std::vector<glm::dvec3> positions;
        for (const glm::dvec2& p : ring) {
            positions.push_back(ellipsoid.toCartesian(Geodetic2D::fromDegrees(p.x, p.y)));
        }
        rings.push_back(std::move(positions));
    }
    return rings;
}

/// GeographicLib's signed area (m^2) of a ring of (longitude, latitude) degrees on WGS84, geodesic
/// edges: positive when counter-clockwise, in (-A/2, A/2] for the Earth's area A, so its magnitude
/// is the area of the smaller region the ring bounds. A closing duplicate vertex adds nothing.
inline double geodesicRingArea(const std::vector<glm::dvec2>& ringDegrees)
{
    GeographicLib::PolygonArea polygon(GeographicLib::Geodesic::WGS84());
    for (const glm::dvec2& p : ringDegrees) {
        polygon.AddPoint(p.y, p.x);
    }
    double perimeter = 0.0;
    double area = 0.0;
    polygon.Compute(false, true, perimeter, area);
    return area;
}

/// The area of a polygon as GeographicLib has it: the outer ring's smaller region less the holes'.
inline double geodesicPolygonArea(const std::vector<std::vector<glm::dvec2>>& ringsDegrees)
{
    double area = 0.0;
    for (std::size_t r = 0; r < ringsDegrees.size(); ++r) {
        area += (r == 0 ? 1.0 : -1.0) * std::abs(geodesicRingArea(ringsDegrees[r]));
    }
    return area;
}

/// A bound on the area between a polygon's geodesic edges (GeographicLib's) and its edges as Orbis
/// draws them, the curves cut by planes through the centre, on WGS84. Between a geodesic of length
/// L and that curve lies at most e^2 L^3 / (24 R) (measured with GeographicLib: 0.0417 e^2 L^3 / R
/// for L up to 10 degrees, 0.0432 at 40 degrees); the bound takes 0.05 per edge, twice over: once for
/// the edge and once for the chords of its subdivision.
inline double planeSectionAreaBound(const std::vector<std::vector<glm::dvec2>>& ringsDegrees)
{
    const GeographicLib::Geodesic& geodesic = GeographicLib::Geodesic::WGS84();
    const double e2 = geodesic.EquatorialRadius() > 0 ? geodesic.Flattening() * (2.0 - geodesic.Flattening()) : 0.0;
    const double radius = geodesic.EquatorialRadius();
    double bound = 0.0;
    for (const std::vector<glm::dvec2>& ring : ringsDegrees) {
        for (std::size_t i = 0; i + 1 < ring.size(); ++i) {
            double length = 0.0;
            geodesic.Inverse(ring[i].y, ring[i].x, ring[i + 1].y, ring[i + 1].x, length);
            bound += 2.0 * 0.05 * e2 * length * length * length / radius;
        }
    }
    return bound;
}

/// The sum of the signed areas of a WGS84 mesh's triangles, each taken as the geodesic triangle
/// through its corners (corners converted by GeographicLib, not Orbis). Neighbours share the
/// geodesic along their common edge, so inner edges cancel: for a triangulation of a polygon
/// whose edges are geodesics, the sum is the polygon's area to rounding.
inline double geodesicMeshArea(const Mesh& mesh)
{
    const GeographicLib::Geocentric& earth = GeographicLib::Geocentric::WGS84();
    std::vector<glm::dvec2> latLon;
    latLon.reserve(mesh.positions.size());
    for (const glm::dvec3& p : mesh.positions) {
        double latitude, longitude, height;
        earth.Reverse(p.x, p.y, p.z, latitude, longitude, height);
        latLon.emplace_back(latitude, longitude);
    }
    double sum = 0.0;
    GeographicLib::PolygonArea triangle(GeographicLib::Geodesic::WGS84());
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        triangle.Clear();
        for (int k = 0; k < 3; ++k) {
            const glm::dvec2& q = latLon[mesh.indices[t + static_cast<std::size_t>(k)]];
            triangle.AddPoint(q.x, q.y);
        }
        double perimeter = 0.0;
        double area = 0.0;
        triangle.Compute(false, true, perimeter, area);
        sum += area;
    }
    return sum;
}

} // namespace orbis::testdata
