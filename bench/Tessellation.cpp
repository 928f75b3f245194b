// Globe tessellation on WGS84: for each tessellator and level, the mesh size, how far the triangles
// depart from the ellipsoid (maxDeviationFromEllipsoid: a barycentric grid and a compass search on
// every triangle, distances by the exact Ellipsoid::toGeodetic3D) and the time to build the mesh.

#include "Report.h"

#include <orbis/core/BoxTessellator.h>
#include <orbis/core/CubeMapEllipsoidTessellator.h>
#include <orbis/core/Ellipsoid.h>
#include <orbis/core/GeographicGridEllipsoidTessellator.h>
#include <orbis/core/RectangleTessellator.h>
#include <orbis/core/SubdivisionEllipsoidTessellator.h>
#include <orbis/core/SubdivisionSphereTessellator.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

namespace orbis::bench {
namespace {

/// Builds one mesh with the given attributes, without measuring its deviation.
using Build = std::function<TessellationResult(VertexAttributes, Deviation)>;

struct Row {
    std::string tessellator;
    std::string setting;
    std::size_t vertices = 0;
    std::size_t triangles = 0;
    double deviation = 0.0;
};

/// Measures one tessellation: sizes and deviation from a positions-only mesh, then the best time of
/// `repeats` builds with positions only and with normals and texture coordinates.
std::vector<std::string> measure(const std::string& tessellator, const std::string& setting, const Build& build,
                                 int repeats, std::vector<Row>& rows)
{
    const TessellationResult measured = build(VertexAttributes::Position, Deviation::Measure);
    const double positionsMs = 1e-6 * nanosecondsPerItem(1, [&] {
        const TessellationResult r = build(VertexAttributes::Position, Deviation::Skip);
        doNotOptimize(r.mesh.positions.data());
    }, repeats);
    const double allMs = 1e-6 * nanosecondsPerItem(1, [&] {
        const TessellationResult r = build(VertexAttributes::All, Deviation::Skip);
        doNotOptimize(r.mesh.positions.data());
    }, repeats);
    const Row row{tessellator, setting, measured.mesh.positions.size(), measured.mesh.triangleCount(),
                  *measured.maxDeviationMeters};
    rows.push_back(row);
    return {tessellator,
            setting,
            std::to_string(row.vertices),
            std::to_string(row.triangles),
            formatLength(row.deviation),
            formatNumber(positionsMs, 3),
            formatNumber(allMs, 3)};
}

/// For each tessellator, the triangles it would need for 1 km, extrapolated from its finest level
/// in this run: deviation falls as 1 / triangles, so deviation x triangles is its figure of merit.
std::string trianglesPerKilometre(const std::vector<Row>& rows)
{
    std::vector<const Row*> finest;
    for (const Row& row : rows) {
        if (!finest.empty() && finest.back()->tessellator == row.tessellator) {
            finest.back() = &row;
        } else {
            finest.push_back(&row);
        }
    }
    std::sort(finest.begin(), finest.end(), [](const Row* a, const Row* b) {
        return a->deviation * static_cast<double>(a->triangles) < b->deviation * static_cast<double>(b->triangles);
    });
    std::string text = "Triangles needed for a 1 km deviation, extrapolated from each tessellator's finest level here "
                       "as deviation x triangles / 1 km (deviation falls as 1 / triangles), fewest first: ";
    for (std::size_t i = 0; i < finest.size(); ++i) {
        text += (i ? "; " : "") + finest[i]->tessellator + " " +
                formatNumber(finest[i]->deviation * static_cast<double>(finest[i]->triangles) / 1000.0, 2);
    }
    return text + ".";
}

std::vector<Table> run(const Options& options)
{
    const Ellipsoid earth = Ellipsoid::wgs84();
    const double a = earth.radii().x;
    const int repeats = options.quick ? 1 : 5;
    const int maxSubdivisions = options.quick ? 4 : 8;
    const int maxStacks = options.quick ? 32 : 256;
    const int maxPartitions = options.quick ? 16 : 128;
    const std::vector<std::string> columns = {"tessellator", "setting", "vertices", "triangles",
                                              "max deviation", "ms, positions", "ms, + normals and texture coordinates"};

    Table globe;
    globe.title = "Globe tessellations of WGS84";
    globe.description =
        "Max deviation: the greatest distance between the triangles and the ellipsoid (WGS84; the subdivision "
        "sphere against the sphere of radius a = 6378137 m), from maxDeviationFromEllipsoid: every triangle "
        "sampled on a barycentric grid of 6 steps per edge plus its deepest point on the unit-sphere-scaled "
        "ellipsoid, refined by a compass search to 2^-13 of the edges, each point's distance from the exact "
        "Ellipsoid::toGeodetic3D (to about 1e-7 relative). Vertices and triangles of the positions-only mesh "
        "(texture coordinates add copies of the antimeridian and pole vertices). Times: best of " +
        std::to_string(repeats) + " builds, deviation not measured (measuring costs about 10 us per triangle).";
    globe.columns = columns;
    std::vector<Row> rows;

    for (int n = 0; n <= maxSubdivisions; ++n) {
        globe.rows.push_back(measure("subdivision sphere (R = a)", std::to_string(n) + " subdivisions",
                                     [&](VertexAttributes attributes, Deviation deviation) {
                                         return SubdivisionSphereTessellator::compute(n, a, attributes, deviation);
                                     },
                                     repeats, rows));
    }
    for (const auto& [name, projection] : {std::pair{"subdivision ellipsoid, geocentric", EllipsoidProjection::Geocentric},
                                           std::pair{"subdivision ellipsoid, geodetic", EllipsoidProjection::Geodetic}}) {
        for (int n = 0; n <= maxSubdivisions; ++n) {
            globe.rows.push_back(measure(name, std::to_string(n) + " subdivisions",
                                         [&, p = projection](VertexAttributes attributes, Deviation deviation) {
                                             return SubdivisionEllipsoidTessellator::compute(earth, n, p, attributes,
                                                                                             deviation);
                                         },
                                         repeats, rows));
        }
    }
    for (int stacks = 4; stacks <= maxStacks; stacks *= 2) {
        globe.rows.push_back(measure("geographic grid", std::to_string(2 * stacks) + " x " + std::to_string(stacks),
                                     [&](VertexAttributes attributes, Deviation deviation) {
                                         return GeographicGridEllipsoidTessellator::compute(earth, 2 * stacks, stacks,
                                                                                            attributes, deviation);
                                     },
                                     repeats, rows));
    }
    for (const auto& [name, spacing] : {std::pair{"cube map, uniform", CubeMapSpacing::Uniform},
                                        std::pair{"cube map, equal-angle", CubeMapSpacing::EqualAngle}}) {
        for (int n = 2; n <= maxPartitions; n *= 2) {
            globe.rows.push_back(measure(name, std::to_string(n) + " x " + std::to_string(n) + " per face",
                                         [&, s = spacing](VertexAttributes attributes, Deviation deviation) {
                                             return CubeMapEllipsoidTessellator::compute(
                                                 earth, n, s, EllipsoidProjection::Geocentric, attributes, deviation);
                                         },
                                         repeats, rows));
        }
    }
    globe.notes = "Halving the edges quarters the deviation for every tessellator. " + trianglesPerKilometre(rows);

    Table flat;
    flat.title = "Flat proxies on WGS84";
    flat.description =
        "The box bounding WGS84 (the proxy that GPU ray casting rasterises) and square patches of the plane "
        "tangent at 45 degrees north, 16 x 16 cells, measured as above; both lie outside the ellipsoid and "
        "depart most at their corners.";
    flat.columns = columns;
    std::vector<Row> flatRows;
    flat.rows.push_back(measure("box", "bounding WGS84",
                                [&](VertexAttributes attributes, Deviation deviation) {
                                    return BoxTessellator::compute(earth, attributes, deviation);
                                },
                                repeats, flatRows));
    for (const double side : {1e3, 10e3, 100e3, 1000e3}) {
        flat.rows.push_back(measure("tangent rectangle", formatLength(side) + " square",
                                    [&](VertexAttributes attributes, Deviation deviation) {
                                        return RectangleTessellator::compute(earth, Geodetic2D::fromDegrees(0.0, 45.0),
                                                                             {side, side}, 16, 16, attributes, deviation);
                                    },
                                    repeats, flatRows));
    }
    flat.notes = "A tangent plane departs from the surface by about d^2 / 2R at distance d from its centre.";
    return {globe, flat};
}

const SectionRegistration registration("tessellation", 30, run);

} // namespace
} // namespace orbis::bench
