// Polygons on WGS84 (book section 8.2): ear clipping of every polygon of Natural Earth's
// countries-110m through its tangent plane, then subdivision to a granularity; what each step costs,
// and how the granularity trades triangles and time against the depth of the triangles below the
// surface. The data is read with the tests' small GeoJSON helper.

#include "Report.h"

#include "../tests/core/PolygonTestData.h"

#include <orbis/core/EarClipping.h>
#include <orbis/core/EllipsoidPolygon.h>
#include <orbis/core/EllipsoidTangentPlane.h>
#include <orbis/core/Tessellation.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>

#ifdef ORBIS_HAVE_EARCUT
// earcut.hpp is not part of Orbis: the build uses it only here, to compare, when configured with
// -DORBIS_EARCUT_DIR=<a folder holding mapbox/earcut.hpp>.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wnull-dereference" // in earcut.hpp once inlined
#include <mapbox/earcut.hpp>
#pragma GCC diagnostic pop
#endif

namespace orbis::bench {
namespace {

struct Polygon {
    std::string label;
    std::vector<std::vector<glm::dvec3>> rings;
    double referenceArea = 0.0; // GeographicLib, geodesic edges
};

/// All the polygons' meshes in one, for the deviation.
Mesh concatenate(const std::vector<Mesh>& meshes)
{
    Mesh all;
    for (const Mesh& mesh : meshes) {
        const auto offset = static_cast<std::uint32_t>(all.positions.size());
        all.positions.insert(all.positions.end(), mesh.positions.begin(), mesh.positions.end());
        for (const std::uint32_t index : mesh.indices) {
            all.indices.push_back(offset + index);
        }
    }
    return all;
}

/// One ring of n vertices around the origin of radius about 1: "circle" exactly round, "coast"
/// round with a wave and noise of a few percent (as a coastline at a fixed step), "star" with radii
/// random in [0.5, 1] (long thin spikes, every other vertex reflex).
std::vector<glm::dvec2> syntheticRing(const std::string& kind, int n)
{
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<glm::dvec2> ring;
    ring.reserve(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        const double angle = 2.0 * 3.141592653589793 * i / n;
        const double radius = kind == "circle" ? 1.0
                              : kind == "coast" ? 1.0 + 0.05 * std::sin(37.0 * angle) + 0.01 * unit(random)
                                                : 0.5 + 0.5 * unit(random);
        ring.emplace_back(radius * std::cos(angle), radius * std::sin(angle));
    }
    return ring;
}

/// A lake district: a wavy outer ring (as syntheticRing's "coast") of 20,000 vertices holding
/// `holes` small rings of 4 to 8 vertices, either winding, on a jittered grid (as Natural Earth's
/// and OpenStreetMap's countries hold lakes: Germany at 1:10m has 12,593 holes of 6.7 positions on
/// average).
std::vector<std::vector<glm::dvec2>> syntheticLakes(int holes)
{
    std::vector<std::vector<glm::dvec2>> rings{syntheticRing("coast", 20000)};
    std::mt19937_64 random(13);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const int side = static_cast<int>(std::ceil(std::sqrt(holes)));
    const double cell = 1.2 / side; // the grid spans [-0.6, 0.6]^2, inside the coast's 0.94
    for (int h = 0; h < holes; ++h) {
        const glm::dvec2 centre(-0.6 + cell * (h % side + 0.45 + 0.1 * unit(random)),
                                -0.6 + cell * (h / side + 0.45 + 0.1 * unit(random)));
        const int count = 4 + static_cast<int>(5 * unit(random));
        std::vector<glm::dvec2> hole;
        for (int k = 0; k < count; ++k) {
            const double angle = 2.0 * 3.141592653589793 * k / count;
            const double radius = cell * (0.2 + 0.2 * unit(random));
            hole.push_back(centre + radius * glm::dvec2(std::cos(angle), std::sin(angle)));
        }
        if (unit(random) < 0.5) {
            std::reverse(hole.begin(), hole.end());
        }
        rings.push_back(std::move(hole));
    }
    return rings;
}

Table largeRings(const Options& options)
{
    Table table;
    table.title = "Large rings and many holes: earClip beside earcut.hpp";
    const int repeats = options.quick ? 1 : 3;
    table.description =
        "One polygon, or many small ones, triangulated in the plane; best of " + std::to_string(repeats) +
        " runs. earClip checks the rings first (edges that cross or touch, through a grid of cells sized from "
        "the edges; where the grid would compare more than 32 pairs an edge, a sweep line proves the rings touch "
        "nothing instead; a strictly convex ring without holes needs no check, and one of up to 32 vertices is "
        "triangulated at once; nor does a ring without holes that is strictly star-shaped round its vertices' mean or "
        "a point of its kernel, whose ears need no search until those left span half a turn or more from that "
        "centre), joins each hole to the outer ring at a vertex it touches or by a bridge checked "
        "against the edges near it (a grid of the edges), then clips ears shortest diagonal first (by the diagonal's "
        "binary order of magnitude, first in first out within one), testing each candidate against the vertices in "
        "its bounding box that could be in its way (reflex, straight, or sharing a position; a Z-order walk, or a "
        "k-d tree, which skips the cells the triangle misses, once walks have been long often enough to pay for it) "
        "and again only when a vertex near it goes; predicates exact. earcut.hpp (mapbox, not part of Orbis; compiled in only when the build is given "
        "its folder) clips in ring order, with a Z-order walk and floating-point predicates, and does not check "
        "the rings.";
    table.columns = {"polygon", "vertices", "holes", "earClip ms", "earcut.hpp ms", "triangles (both)"};
    using Rings = std::vector<std::vector<glm::dvec2>>;
    const int n = options.quick ? 2000 : 100000;
    std::vector<std::pair<std::string, std::vector<Rings>>> cases; // a name, its polygons
    for (const std::string kind : {"circle", "coast", "star"}) {
        cases.push_back({kind, {Rings{syntheticRing(kind, n)}}});
    }
    for (const int holes : options.quick ? std::vector<int>{100} : std::vector<int>{1000, 10000}) {
        cases.push_back({"lakes", {syntheticLakes(holes)}});
    }
    // What each call costs besides the work of its vertices: many small polygons, as buildings.
    std::vector<Rings> pentagons;
    for (int k = 0; k < n / 5; ++k) {
        const glm::dvec2 at(k % 200, k / 200);
        pentagons.push_back({{at, at + glm::dvec2(0.8, 0.0), at + glm::dvec2(0.9, 0.6), at + glm::dvec2(0.4, 0.9),
                              at + glm::dvec2(0.0, 0.6)}});
    }
    cases.push_back({std::to_string(pentagons.size()) + " pentagons", pentagons});
    for (const auto& [name, polygons] : cases) {
        std::size_t vertices = 0;
        std::size_t holes = 0;
        for (const Rings& rings : polygons) {
            for (const auto& ring : rings) {
                vertices += ring.size();
            }
            holes += rings.size() - 1;
        }
        std::size_t triangles = 0;
        const double ours = nanosecondsPerItem(1, [&] {
            triangles = 0;
            for (const Rings& rings : polygons) {
                triangles += earClip(rings).triangleCount();
            }
        }, repeats);
        std::string theirs = "(not built)";
        std::string count = std::to_string(triangles);
#ifdef ORBIS_HAVE_EARCUT
        std::vector<std::vector<std::vector<std::array<double, 2>>>> theirPolygons;
        for (const Rings& rings : polygons) {
            auto& polygon = theirPolygons.emplace_back();
            for (const auto& ring : rings) {
                polygon.emplace_back();
                for (const glm::dvec2& p : ring) {
                    polygon.back().push_back({p.x, p.y});
                }
            }
        }
        std::size_t earcutTriangles = 0;
        const double earcutNs = nanosecondsPerItem(1, [&] {
            earcutTriangles = 0;
            for (const auto& polygon : theirPolygons) {
                earcutTriangles += mapbox::earcut<std::uint32_t>(polygon).size() / 3;
            }
        }, repeats);
        theirs = formatNumber(1e-6 * earcutNs, 3);
        count += " / " + std::to_string(earcutTriangles);
#endif
        table.rows.push_back({name, std::to_string(vertices), std::to_string(holes), formatNumber(1e-6 * ours, 3), theirs,
                              count});
    }
    table.notes =
        "A convex ring (the circle, the pentagons) is faster with earClip: it is known not to touch itself from its "
        "turns alone, and a small one needs no queue of ears. The coast and the star are star-shaped (the coast round "
        "its vertices' mean, the star round its kernel's centre): their rings need no check and their ears no search, where "
        "earcut searches every ear's box, which on the star, every other vertex reflex, holds many vertices. earcut "
        "joins each hole to the outer ring by a walk round the whole outer ring, the holes joined before included, so "
        "its time grows with the holes times the vertices; earClip's bridges look only at the edges near them.";
    return table;
}

std::vector<Table> run(const Options& options)
{
    const Ellipsoid earth = Ellipsoid::wgs84();
    const int repeats = options.quick ? 1 : 5;

    std::vector<Polygon> polygons;
    std::size_t vertices = 0;
    std::size_t holes = 0;
    for (const testdata::GeoPolygon& polygon : testdata::loadPolygons(testdata::naturalEarthPath("countries-110m.geojson"))) {
        Polygon p{polygon.label(), testdata::toCartesian(earth, polygon.ringsDegrees),
                  testdata::geodesicPolygonArea(polygon.ringsDegrees)};
        for (const auto& ring : p.rings) {
            vertices += ring.size();
        }
        holes += p.rings.size() - 1;
        polygons.push_back(std::move(p));
    }
    const std::string data = std::to_string(polygons.size()) + " polygons, " + std::to_string(holes) + " hole, " +
                             std::to_string(vertices) + " vertices";

    // --- What each step costs ------------------------------------------------------------------
    Table steps;
    steps.title = "Triangulating countries-110m";
    steps.description = "Natural Earth's countries at 1:110m (" + data +
                        ", Fiji, Russia and Antarctica across the antimeridian, Antarctica around the pole), "
                        "every polygon in turn; best of " + std::to_string(repeats) +
                        " runs. The plane alone: earClip on rings projected beforehand (exact orientation tests, "
                        "hole bridging, sliver flips). On the ellipsoid: earClipOnEllipsoid, which first moves the "
                        "positions to the surface, cleans the rings up and projects them.";
    steps.columns = {"step", "triangles", "ms, all polygons", "us per input vertex"};
    std::vector<std::vector<std::vector<glm::dvec2>>> projected;
    for (const Polygon& polygon : polygons) {
        std::vector<glm::dvec3> outer = polygon.rings[0];
        const EllipsoidTangentPlane plane(earth, outer);
        std::vector<std::vector<glm::dvec2>> rings;
        for (const auto& ring : polygon.rings) {
            rings.push_back(plane.projectPointsOntoPlane(ring).value_or(std::vector<glm::dvec2>{}));
        }
        projected.push_back(std::move(rings));
    }
    std::size_t planeTriangles = 0;
    const double planeNs = nanosecondsPerItem(1, [&] {
        planeTriangles = 0;
        for (const auto& rings : projected) {
            planeTriangles += earClip(rings).triangleCount();
        }
    }, repeats);
    std::size_t clippedTriangles = 0;
    const double clipNs = nanosecondsPerItem(1, [&] {
        clippedTriangles = 0;
        for (const Polygon& polygon : polygons) {
            clippedTriangles += earClipOnEllipsoid(earth, polygon.rings, polygon.label).triangleCount();
        }
    }, repeats);
    const auto perVertex = [&](double ns) { return formatNumber(1e-3 * ns / static_cast<double>(vertices), 3); };
    steps.rows.push_back({"ear clipping in the plane (earClip)", std::to_string(planeTriangles),
                          formatNumber(1e-6 * planeNs, 3), perVertex(planeNs)});
    steps.rows.push_back({"ear clipping on the ellipsoid (earClipOnEllipsoid)", std::to_string(clippedTriangles),
                          formatNumber(1e-6 * clipNs, 3), perVertex(clipNs)});

    // --- Granularity -----------------------------------------------------------------------------
    Table granularity;
    granularity.title = "Subdivision granularity on countries-110m";
    granularity.description =
        "triangulatePolygon on every polygon: ear clipping, then subdivideOnEllipsoid until no edge subtends more "
        "than the granularity at the centre. Depth: the greatest distance of a triangle's points below the "
        "surface over all polygons (maxDeviationFromEllipsoid: a barycentric grid and a compass search on every "
        "triangle, heights from the exact Ellipsoid::toGeodetic3D). Area: the greatest relative difference, over "
        "the polygons, between the sum of the mesh's geodesic triangles and GeographicLib's PolygonArea of the "
        "rings (edges along plane sections through the centre rather than geodesics, and the clean-up). Time: "
        "best of " + std::to_string(repeats) + " runs for all polygons, depth and area not measured.";
    granularity.columns = {"granularity", "vertices", "triangles", "max depth below surface", "max area difference",
                           "ms, all polygons"};
    const std::vector<double> degrees = options.quick ? std::vector<double>{5.0, 2.0}
                                                      : std::vector<double>{10.0, 5.0, 2.0, 1.0, 0.5, 0.25};
    for (const double g : degrees) {
        std::vector<Mesh> meshes;
        for (const Polygon& polygon : polygons) {
            meshes.push_back(triangulatePolygon(earth, polygon.rings, toRadians(g), polygon.label));
        }
        double worstArea = 0.0;
        for (std::size_t i = 0; i < polygons.size(); ++i) {
            if (polygons[i].referenceArea > 0.0) {
                worstArea = std::max(worstArea, std::abs(testdata::geodesicMeshArea(meshes[i]) - polygons[i].referenceArea) /
                                                    polygons[i].referenceArea);
            }
        }
        const Mesh all = concatenate(meshes);
        const double depth = maxDeviationFromEllipsoid(all, earth);
        const double ns = nanosecondsPerItem(1, [&] {
            for (const Polygon& polygon : polygons) {
                const Mesh mesh = triangulatePolygon(earth, polygon.rings, toRadians(g), polygon.label);
                doNotOptimize(mesh.indices.data());
            }
        }, repeats);
        granularity.rows.push_back({formatNumber(g, 3) + " deg", std::to_string(all.positions.size()),
                                    std::to_string(all.triangleCount()), formatLength(depth),
                                    formatNumber(worstArea, 2), formatNumber(1e-6 * ns, 3)});
    }
    granularity.notes =
        "Halving the granularity about quarters the depth for about four times the triangles: a triangle whose "
        "edges subtend at most g lies up to R g^2 / 6 below the surface (at the circumcentre of an equilateral "
        "one: 8.1 km at 5 degrees, 324 m at 1). The area difference is the plane sections' departure from the "
        "geodesics (at most e^2 L^3 / 24 R for an edge of length L), largest on long edges (W. Sahara's straight "
        "borders); it grows as finer subdivision makes the boundary follow the plane sections, and is bounded "
        "by that departure.";

    // --- A polygon too large for one tangent plane --------------------------------------------------
    Table large;
    large.title = "A polygon larger than one tangent plane takes";
    large.description =
        "A cap of 85 degrees around the south pole (a ring of 72 vertices along 5 degrees south), beyond the 80 "
        "degrees one gnomonic projection takes: split into octants by three planes through the centre, clipped "
        "piece by piece and welded; best of " + std::to_string(repeats) + " runs.";
    large.columns = {"granularity", "triangles", "ms"};
    std::vector<glm::dvec2> cap;
    for (int longitude = -180; longitude < 180; longitude += 5) {
        cap.emplace_back(longitude, -5.0);
    }
    const auto capRings = testdata::toCartesian(earth, {cap});
    for (const double g : options.quick ? std::vector<double>{5.0} : std::vector<double>{5.0, 1.0}) {
        std::size_t triangles = 0;
        const double ns = nanosecondsPerItem(1, [&] {
            triangles = triangulatePolygon(earth, capRings, toRadians(g), "cap").triangleCount();
        }, repeats);
        large.rows.push_back({formatNumber(g, 3) + " deg", std::to_string(triangles), formatNumber(1e-6 * ns, 3)});
    }
    return {steps, granularity, large, largeRings(options)};
}

const SectionRegistration registration("polygons", 40, run);

} // namespace
} // namespace orbis::bench
