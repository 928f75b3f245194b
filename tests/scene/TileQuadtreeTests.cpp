#include <orbis/scene/Camera.h>
#include <orbis/scene/TileQuadtree.h>

#include <orbis/core/Geodetic.h>
#include <orbis/core/IntersectionTests.h>
#include <orbis/core/TileMesh.h>
#include <orbis/core/Transforms.h>

#include <catch2/catch.hpp>

#include <glm/geometric.hpp>

#include <cmath>
#include <random>
#include <set>
#include <tuple>
#include <map>
#include <optional>

using namespace orbis;
using namespace orbis::scene;

namespace {

constexpr int kWidth = 1920;
constexpr int kHeight = 1080;

/// A random camera: log-uniform height from 100 m to 40,000 km, looking anywhere from straight
/// down to well above the horizon.
Camera randomCamera(std::mt19937_64& random, const Ellipsoid& ellipsoid)
{
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double height = std::exp(std::log(100.0) + unit(random) * (std::log(4.0e7) - std::log(100.0)));
    const Geodetic3D position(kPi * (2.0 * unit(random) - 1.0), std::asin(2.0 * unit(random) - 1.0), height);
    const glm::dvec3 eye = ellipsoid.toCartesian(position);
    const double heading = kTwoPi * unit(random);
    const double pitch = -kHalfPi + unit(random) * (kHalfPi + 0.3);
    const ViewOrientation view = headingPitchRollToView(ellipsoid, eye, heading, pitch, 0.0);
    return Camera(eye, eye + view.direction * 1000.0, view.up, toRadians(60.0));
}

TileView viewOf(const Camera& camera, const Ellipsoid& ellipsoid)
{
    TileView view;
    view.eye = camera.eye();
    view.direction = camera.direction();
    const double height = std::max(1.0, ellipsoid.toGeodetic3D(camera.eye()).height);
    const double farDistance = 2.0 * glm::length(camera.eye()) + 1e7;
    view.frustum = Frustum::fromViewProjection(
        camera.projectionMatrix(static_cast<double>(kWidth) / kHeight, std::max(0.5, 0.1 * height), farDistance) *
        camera.viewMatrix());
    view.viewportHeightPixels = kHeight;
    view.fieldOfViewY = camera.fieldOfViewY();
    return view;
}

/// The first point where the ray through pixel (x, y) meets the ellipsoid, if it does.
std::optional<glm::dvec3> pick(const Camera& camera, const Ellipsoid& ellipsoid, double x, double y)
{
    const double tanY = std::tan(0.5 * camera.fieldOfViewY());
    const double tanX = tanY * kWidth / kHeight;
    const glm::dvec3 right = camera.right();
    const glm::dvec3 up = glm::cross(right, camera.direction()); // the camera's up need not be square to it
    const glm::dvec3 direction = glm::normalize(camera.direction() + right * ((2.0 * x / kWidth - 1.0) * tanX) +
                                                up * ((2.0 * y / kHeight - 1.0) * tanY));
    const auto hit = intersectRayEllipsoid(Ray{camera.eye(), direction}, ellipsoid);
    if (!hit || hit->nearDistance <= 0.0) {
        return std::nullopt;
    }
    return camera.eye() + direction * hit->nearDistance;
}

/// How many drawn tiles hold p (0: a hole; 2: an overlap): the tile holding p at each level,
/// looked up among the drawn ones.
std::set<TileKey> drawnKeys(const TileSelection& selection)
{
    std::set<TileKey> drawn;
    for (const QuadtreeTile* tile : selection.drawn) {
        drawn.insert(tile->key);
    }
    return drawn;
}

int drawnTilesHolding(const std::set<TileKey>& drawn, const TilingScheme& scheme, const Ellipsoid& ellipsoid,
                      const glm::dvec3& p)
{
    const Geodetic2D g = ellipsoid.toGeodetic2D(p);
    int count = 0;
    for (std::uint32_t level = 0; level <= kMaximumTileLevel; ++level) {
        count += drawn.contains(*scheme.tileAt(g, level)) ? 1 : 0;
    }
    return count;
}

/// Visible points to check for cover: pixels at random and along the viewport's border, and
/// points just inside the limb (the horizon) where horizon culling works at its edge.
std::vector<glm::dvec3> visiblePoints(std::mt19937_64& random, const Camera& camera, const Ellipsoid& ellipsoid,
                                      const TileView& view)
{
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<glm::dvec3> points;
    for (int k = 0; k < 48; ++k) {
        double x = unit(random) * kWidth;
        double y = unit(random) * kHeight;
        if (k % 2) {
            (k % 4 == 1 ? x : y) = (unit(random) < 0.5 ? 0.01 : 0.99) * (k % 4 == 1 ? kWidth : kHeight);
        }
        if (const auto p = pick(camera, ellipsoid, x, y)) {
            points.push_back(*p);
        }
    }
    const EllipsoidalOccluder occluder(ellipsoid, camera.eye());
    const glm::dvec3 eye = camera.eye();
    const glm::dvec3 axis = glm::normalize(eye);
    const glm::dvec3 side = glm::normalize(glm::cross(axis, anyPerpendicular(axis)));
    for (int k = 0; k < 48; ++k) {
        // A point on the sphere of the equatorial radius where the line from the eye is tangent,
        // moved a little towards the eye and dropped onto the ellipsoid.
        const double r = ellipsoid.radii().x;
        const double d = glm::length(eye);
        if (d <= r * 1.0001) {
            break;
        }
        const double angle = kTwoPi * unit(random);
        const glm::dvec3 around = std::cos(angle) * side + std::sin(angle) * glm::cross(axis, side);
        const double cosine = r / d * (1.0 + 1e-4 * unit(random));
        const glm::dvec3 p = ellipsoid.scaleToGeodeticSurface(r * (cosine * axis + std::sqrt(1.0 - cosine * cosine) * around));
        if (occluder.isPointVisible(p) && view.frustum.contains(p)) {
            // Keep only points the segment from the eye reaches without passing through the globe.
            const glm::dvec3 toPoint = p - eye;
            const auto hit = intersectRayEllipsoid(Ray{eye, glm::normalize(toPoint)}, ellipsoid);
            if (hit && hit->nearDistance >= glm::length(toPoint) * (1.0 - 1e-9)) {
                points.push_back(p);
            }
        }
    }
    return points;
}

} // namespace

TEST_CASE("Tile selection over 10,000 random views covers every visible point exactly once, at the error asked",
          "[scene][tiles]")
{
    const Ellipsoid wgs84 = Ellipsoid::wgs84();
    TileQuadtree quadtree(wgs84, TilingScheme::geographic(), 64, [](QuadtreeTile& tile) {
        tile.renderable = true;
        tile.wantsLoad = false;
    });
    TileSelectionOptions options;
    options.maximumLevel = 22;
    std::mt19937_64 random(20261201);
    TileSelection selection;
    std::size_t checkedPoints = 0;
    std::size_t horizonCulled = 0;
    std::size_t drawnTotal = 0;
    for (int viewIndex = 0; viewIndex < 10000; ++viewIndex) {
        const Camera camera = randomCamera(random, wgs84);
        const TileView view = viewOf(camera, wgs84);
        quadtree.select(view, options, static_cast<std::uint64_t>(viewIndex) + 1, selection);
        horizonCulled += selection.culledByHorizon;
        INFO("view " << viewIndex << " eye " << camera.eye().x << " " << camera.eye().y << " " << camera.eye().z);
        REQUIRE(selection.standIns == 0);
        REQUIRE(selection.loads.empty());
        REQUIRE(selection.selected == selection.drawn.size());
        drawnTotal += selection.drawn.size();
        for (std::size_t i = 0; i < selection.drawn.size(); ++i) {
            const bool finest = selection.drawn[i]->key.level == options.maximumLevel;
            REQUIRE((selection.drawnScreenSpaceErrors[i] <= options.maximumScreenSpaceError || finest));
        }
        const std::set<TileKey> drawn = drawnKeys(selection);
        for (const glm::dvec3& p : visiblePoints(random, camera, wgs84, view)) {
            ++checkedPoints;
            REQUIRE(drawnTilesHolding(drawn, quadtree.scheme(), wgs84, p) == 1);
        }
    }
    CHECK(checkedPoints > 300000);
    CHECK(horizonCulled > 10000);
    WARN("tiles drawn per view: " << static_cast<double>(drawnTotal) / 10000.0);
}

TEST_CASE("While tiles load, parents stand in for children not yet there: no hole in any frame of a descent",
          "[scene][tiles]")
{
    const Ellipsoid wgs84 = Ellipsoid::wgs84();
    // Tiles become drawable three frames after they are first asked for; the roots are there.
    std::map<TileKey, std::uint64_t> askedAt;
    TileQuadtree quadtree(wgs84, TilingScheme::geographic(), 64, [](QuadtreeTile& tile) {
        tile.renderable = tile.key.level == 0;
        tile.wantsLoad = !tile.renderable;
    });
    TileSelectionOptions options;
    options.maximumLevel = 20;
    options.loadingDescendantLimit = 20;
    std::mt19937_64 random(5);
    TileSelection selection;
    const Geodetic3D alps = Geodetic3D::fromDegrees(7.5, 46.0, 0.0);
    std::size_t maximumLoads = 0;
    bool converged = false;
    for (std::uint64_t frame = 1; frame <= 400; ++frame) {
        // From 20,000 km down to 2 km over the Alps in 200 frames, then hold still.
        const double t = std::min(1.0, static_cast<double>(frame) / 200.0);
        const double height = std::exp(std::log(2.0e7) * (1.0 - t) + std::log(2000.0) * t);
        const glm::dvec3 eye = wgs84.toCartesian(Geodetic3D(alps.longitude, alps.latitude, height));
        const ViewOrientation orientation = headingPitchRollToView(wgs84, eye, 0.3, toRadians(-40.0), 0.0);
        const Camera camera(eye, eye + orientation.direction * 1000.0, orientation.up, toRadians(60.0));
        const TileView view = viewOf(camera, wgs84);
        quadtree.select(view, options, frame, selection);
        INFO("frame " << frame);
        const std::set<TileKey> drawn = drawnKeys(selection);
        for (const glm::dvec3& p : visiblePoints(random, camera, wgs84, view)) {
            REQUIRE(drawnTilesHolding(drawn, quadtree.scheme(), wgs84, p) == 1);
        }
        maximumLoads = std::max(maximumLoads, selection.loads.size());
        converged = frame > 200 && selection.standIns == 0 && selection.loads.empty();
        // The loader: what was asked for three frames ago can be drawn now.
        for (const TileLoadCandidate& load : selection.loads) {
            askedAt.emplace(load.tile->key, frame);
        }
        std::vector<QuadtreeTile*> stack;
        for (auto& root : quadtree.roots()) {
            stack.push_back(root.get());
        }
        while (!stack.empty()) {
            QuadtreeTile* tile = stack.back();
            stack.pop_back();
            const auto asked = askedAt.find(tile->key);
            if (asked != askedAt.end() && frame >= asked->second + 3) {
                tile->renderable = true;
                tile->wantsLoad = false;
            }
            if (tile->hasChildren()) {
                for (auto& child : tile->children) {
                    stack.push_back(child.get());
                }
            }
        }
    }
    CHECK(converged);
    // No drawn tile asks for more than the limit at once (the two roots, each a stand-in at first).
    CHECK(maximumLoads <= 2 * options.loadingDescendantLimit);
    CHECK(maximumLoads >= options.loadingDescendantLimit);
}

namespace {

using Point = std::tuple<double, double, double>;

/// A mesh's open edges (no triangle of the same list runs them backwards) and the tile side each
/// lies on (0 north, 1 east, 2 south, 3 west), as positions. Edges of no length (along a pole) are
/// left out.
std::map<std::pair<Point, Point>, int> openEdges(const TileMesh& mesh, const std::vector<std::uint32_t>& indices)
{
    std::set<std::pair<std::uint32_t, std::uint32_t>> directed;
    for (std::size_t t = 0; t < indices.size(); t += 3) {
        for (int e = 0; e < 3; ++e) {
            directed.insert({indices[t + e], indices[t + (e + 1) % 3]});
        }
    }
    std::map<std::pair<Point, Point>, int> open;
    for (const auto& [a, b] : directed) {
        if (directed.contains({b, a})) {
            continue;
        }
        const glm::dvec3 pa = mesh.position(a);
        const glm::dvec3 pb = mesh.position(b);
        if (pa == pb) {
            continue;
        }
        const float* va = &mesh.vertices[a * TileMesh::kFloatsPerVertex];
        const float* vb = &mesh.vertices[b * TileMesh::kFloatsPerVertex];
        const int side = va[7] == 1.0f && vb[7] == 1.0f   ? 0
                         : va[6] == 1.0f && vb[6] == 1.0f ? 1
                         : va[7] == 0.0f && vb[7] == 0.0f ? 2
                                                          : 3;
        open[{{pa.x, pa.y, pa.z}, {pb.x, pb.y, pb.z}}] = side;
    }
    return open;
}

} // namespace

TEST_CASE("Drawn tiles stitched to their coarser neighbours share every edge of the surface", "[scene][tiles]")
{
    const Ellipsoid wgs84 = Ellipsoid::wgs84();
    const TilingScheme scheme = TilingScheme::geographic();
    TileQuadtree quadtree(wgs84, scheme, 64, [](QuadtreeTile& tile) {
        tile.renderable = true;
        tile.wantsLoad = false;
    });
    TileSelectionOptions options;
    options.maximumLevel = 22;
    std::mt19937_64 random(77);
    TileSelection selection;
    std::size_t sharedEdges = 0;
    for (int viewIndex = 0; viewIndex < 60; ++viewIndex) {
        const Camera camera = randomCamera(random, wgs84);
        quadtree.select(viewOf(camera, wgs84), options, static_cast<std::uint64_t>(viewIndex) + 1, selection);
        DrawnTileSet drawn;
        for (const QuadtreeTile* tile : selection.drawn) {
            drawn.insert(tile->key);
        }
        std::map<std::pair<Point, Point>, int> allOpen;
        std::vector<std::pair<TileKey, std::map<std::pair<Point, Point>, int>>> perTile;
        for (const QuadtreeTile* tile : selection.drawn) {
            const TileMesh mesh = TileMesh::build(wgs84, scheme, tile->key, 3, {}, 0.0);
            auto open = openEdges(mesh, TileMesh::indices(3, edgeCoarsening(scheme, tile->key, drawn), false));
            allOpen.insert(open.begin(), open.end());
            perTile.emplace_back(tile->key, std::move(open));
        }
        // An edge with a neighbour drawn at the same level or coarser must meet that neighbour's
        // edge exactly, the other way round.
        for (const auto& [key, open] : perTile) {
            const std::uint32_t columns = scheme.tilesX(key.level);
            const std::array<std::optional<TileKey>, 4> across{
                key.y + 1 < scheme.tilesY(key.level) ? std::optional(TileKey{key.level, key.x, key.y + 1}) : std::nullopt,
                TileKey{key.level, (key.x + 1) % columns, key.y},
                key.y > 0 ? std::optional(TileKey{key.level, key.x, key.y - 1}) : std::nullopt,
                TileKey{key.level, (key.x + columns - 1) % columns, key.y}};
            for (const auto& [segment, side] : open) {
                const auto& neighbour = across[static_cast<std::size_t>(side)];
                bool coarserOrSame = false;
                for (std::uint32_t level = 0; neighbour && level <= key.level; ++level) {
                    coarserOrSame = coarserOrSame || drawn.contains(neighbour->ancestor(level));
                }
                if (coarserOrSame) {
                    ++sharedEdges;
                    INFO("view " << viewIndex << " tile " << key.level << "/" << key.x << "/" << key.y << " side " << side);
                    REQUIRE(allOpen.contains({segment.second, segment.first}));
                }
            }
        }
    }
    CHECK(sharedEdges > 10000);
}
