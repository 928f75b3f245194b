#include "orbis/scene/PolygonCollection.h"

#include "VectorSupport.h"

#include "orbis/scene/Effect.h"

#include <orbis/core/EllipsoidPolygon.h>
#include <orbis/core/TriangleMeshSubdivision.h>
#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_set>

namespace orbis::scene {

namespace {

/// Depth-buffer steps and least fraction of the distance fills move towards the eye: a quarter of
/// the lines' (PolylineCollection), so borders drawn over fills win.
constexpr double kFillDepthSteps = 4.0;
constexpr double kFillDepthFraction = 1e-5;

bool isOpaque(const glm::vec4& color) noexcept { return color.a >= 1.0f; }

/// Metres a draped volume reaches beyond the ground's heights, for their rounding (floats).
constexpr double kDrapeMarginMeters = 1.0;

/// The closed volume over a polygon's triangles on the surface: their vertices twice, the first
/// copy its bottom's and the second its top's (the vertex shader moves each along its normal to the
/// frame's heights), the triangles at the top, reversed at the bottom, and a wall under each edge
/// of the outline (an edge of one triangle only: the subdivision shares its inner edges), every
/// face counter-clockwise seen from outside, as the stencil count needs.
Mesh shadowVolume(const Mesh& surface)
{
    const std::size_t n = surface.positions.size();
    Mesh volume;
    volume.positions.reserve(2 * n);
    volume.positions.insert(volume.positions.end(), surface.positions.begin(), surface.positions.end());
    volume.positions.insert(volume.positions.end(), surface.positions.begin(), surface.positions.end());
    const auto up = [n](std::uint32_t i) { return static_cast<std::uint32_t>(i + n); };
    const auto edgeKey = [](std::uint32_t from, std::uint32_t to) { return (std::uint64_t{from} << 32) | to; };
    const std::vector<std::uint32_t>& t = surface.indices;
    std::unordered_set<std::uint64_t> edges;
    for (std::size_t i = 0; i < t.size(); i += 3) {
        for (int k = 0; k < 3; ++k) {
            edges.insert(edgeKey(t[i + k], t[i + (k + 1) % 3]));
        }
    }
    std::vector<std::uint32_t>& out = volume.indices;
    for (std::size_t i = 0; i < t.size(); i += 3) {
        out.insert(out.end(), {up(t[i]), up(t[i + 1]), up(t[i + 2]), t[i], t[i + 2], t[i + 1]});
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[i + k];
            const std::uint32_t b = t[i + (k + 1) % 3];
            if (!edges.contains(edgeKey(b, a))) {
                // The inside lies left of a -> b seen from above, so this quad faces out.
                out.insert(out.end(), {a, b, up(b), a, up(b), up(a)});
            }
        }
    }
    return volume;
}

/// The geodetic extent of a polygon's triangles on the surface (edges at most widestEdge radians
/// at the centre): the latitudes of their corners, widened for what an edge bulges poleward between
/// its ends (under widestEdge^2 / 8; widened by twice that), and the shortest run of longitudes
/// holding every edge (a flat triangle clear of the axis spans no longitude beyond its corners');
/// every longitude, to the pole, where a triangle holds a pole.
GeodeticExtent footprintOf(const Ellipsoid& ellipsoid, const Mesh& surface, double widestEdge)
{
    GeodeticExtent extent{-kPi, kHalfPi, kPi, -kHalfPi};
    std::vector<double> longitudes;
    longitudes.reserve(surface.positions.size());
    for (const glm::dvec3& position : surface.positions) {
        const Geodetic2D g = ellipsoid.toGeodetic2D(position);
        extent.south = std::min(extent.south, g.latitude);
        extent.north = std::max(extent.north, g.latitude);
        longitudes.push_back(position.x == 0.0 && position.y == 0.0 ? std::numeric_limits<double>::quiet_NaN() : g.longitude);
    }
    const double bulge = 0.25 * widestEdge * widestEdge + 1e-9;
    extent.south = std::max(extent.south - bulge, -kHalfPi);
    extent.north = std::min(extent.north + bulge, kHalfPi);
    // Each edge's run of longitudes, eastwards from its start; edges at a pole run along one meridian.
    std::vector<std::pair<double, double>> runs;
    const std::vector<std::uint32_t>& t = surface.indices;
    bool pole = false;
    for (std::size_t i = 0; i + 2 < t.size(); i += 3) {
        const glm::dvec3& a = surface.positions[t[i]];
        const glm::dvec3& b = surface.positions[t[i + 1]];
        const glm::dvec3& c = surface.positions[t[i + 2]];
        for (const double z : {1.0, -1.0}) {
            const glm::dvec3 axis(0.0, 0.0, z);
            if (glm::dot(glm::cross(a, b), axis) >= 0.0 && glm::dot(glm::cross(b, c), axis) >= 0.0 &&
                glm::dot(glm::cross(c, a), axis) >= 0.0) {
                (z > 0.0 ? extent.north : extent.south) = z * kHalfPi;
                pole = true;
            }
        }
        for (int k = 0; k < 3; ++k) {
            const double from = longitudes[t[i + static_cast<std::size_t>(k)]];
            const double to = longitudes[t[i + static_cast<std::size_t>((k + 1) % 3)]];
            const double across = std::remainder(to - from, kTwoPi);
            if (std::isfinite(across)) {
                runs.emplace_back(across >= 0.0 ? from : to, std::abs(across));
            }
        }
    }
    if (pole || runs.empty()) {
        return extent;
    }
    // The widest gap between the runs, on the circle, is what the extent leaves out.
    std::sort(runs.begin(), runs.end());
    double reach = runs.front().first + runs.front().second; // east end of the runs so far
    double gapWidth = 0.0;
    double gapStart = 0.0;
    for (std::size_t i = 1; i < runs.size(); ++i) {
        if (runs[i].first > reach && runs[i].first - reach > gapWidth) {
            gapWidth = runs[i].first - reach;
            gapStart = reach;
        }
        reach = std::max(reach, runs[i].first + runs[i].second);
    }
    const double around = runs.front().first + kTwoPi - reach;
    if (around > gapWidth) {
        gapWidth = around;
        gapStart = reach;
    }
    if (gapWidth > 0.0) {
        extent.west = std::remainder(gapStart + gapWidth, kTwoPi);
        extent.east = std::remainder(gapStart, kTwoPi);
    }
    return extent;
}

/// A draped polygon's volume drawn twice for the z-fail stencil count (docs/terrain.md): the first
/// draw adds one in the stencil for each back face behind the depth drawn so far and takes one
/// for each front face, which leaves non-zero exactly the pixels whose ground lies inside the
/// volume; the second colours those pixels and zeroes their stencil for the next volume. Depth
/// clamping keeps the faces beyond the frustum's near and far planes, so that the count is right
/// in every frustum of a multi-frustum frame: one before the near plane lies in front of all this
/// frustum drew; one beyond the far plane, clamped to the depth the frustum's clear left, behind
/// what it drew but not behind the clear (LessOrEqual), where a farther frustum drew the ground.
void appendDrapedDraws(SceneCommand volume, CommandList& commands)
{
    volume.pass = Pass::Draped;
    volume.tags = Effect::Polygons | Effect::DrapedPolygons;
    renderer::RenderState& state = volume.draw.renderState;
    state = renderer::RenderState{};
    state.facetCulling.enabled = false;
    state.depthClamp = true;
    state.depthMask = false;
    state.stencilTest.enabled = true;

    SceneCommand count = volume;
    count.draw.debugName = "draped polygon count";
    renderer::RenderState& counting = count.draw.renderState;
    counting.colorMask = {false, false, false, false};
    counting.depthTest.function = renderer::CompareFunction::LessOrEqual;
    counting.stencilTest.frontFace.depthFailStencilPassOperation = renderer::StencilOperation::DecrementWrap;
    counting.stencilTest.backFace.depthFailStencilPassOperation = renderer::StencilOperation::IncrementWrap;
    commands.push_back(std::move(count));

    volume.draw.debugName = "draped polygon";
    state.depthTest.enabled = false;
    for (renderer::StencilTestFace* face : {&state.stencilTest.frontFace, &state.stencilTest.backFace}) {
        face->function = renderer::CompareFunction::NotEqual;
        face->referenceValue = 0;
        face->depthPassStencilPassOperation = renderer::StencilOperation::Zero;
    }
    state.blending = detail::vectorRenderState(Pass::Translucent, false, true).blending;
    commands.push_back(std::move(volume));
}

} // namespace

struct PolygonCollection::Item {
    Mesh mesh; ///< drawn: lifted positions (or a draped polygon's volume), no normals
    double lift = 0.0;
    double maxHeight = 0.0; ///< of the drawn positions above the ellipsoid (draped: of its surface)
    glm::vec4 color{1.0f};
    BoundingSphere sphere;
    // Draped only:
    GeodeticExtent footprint;
    double sag = 0.0; ///< how far its flat triangles dip below their corners
    std::optional<HeightInterval> drapedHeights; ///< the last frame's
};

PolygonCollection::PolygonCollection(const Ellipsoid& ellipsoid, const PolygonCollectionOptions& options)
    : _ellipsoid(ellipsoid)
    , _options(options)
{
    _options.granularityRadians = std::max(_options.granularityRadians, 1e-6);
}

PolygonCollection::~PolygonCollection() = default;

std::size_t PolygonCollection::size() const noexcept
{
    return _polygons.size();
}

std::size_t PolygonCollection::add(const world::Polygon& polygon, const glm::vec4& color, std::string_view name,
                                   std::vector<LeftOutHole>* leftOutHoles)
{
    std::vector<std::vector<glm::dvec3>> rings;
    std::vector<std::vector<double>> heights;
    rings.reserve(polygon.rings.size());
    for (const world::LinearRing& ring : polygon.rings) {
        std::vector<glm::dvec3>& cartesian = rings.emplace_back();
        std::vector<double>& ringHeights = heights.emplace_back();
        cartesian.reserve(ring.size());
        for (const Geodetic3D& position : ring) {
            cartesian.push_back(_ellipsoid.toCartesian(Geodetic2D{position.longitude, position.latitude}));
            ringHeights.push_back(position.height);
        }
    }
    return add(rings, heights, color, name, leftOutHoles);
}

std::size_t PolygonCollection::add(std::span<const std::vector<glm::dvec3>> rings, const glm::vec4& color,
                                   std::string_view name, std::vector<LeftOutHole>* leftOutHoles)
{
    return add(rings, {}, color, name, leftOutHoles);
}

std::size_t PolygonCollection::add(std::span<const std::vector<glm::dvec3>> rings,
                                   std::span<const std::vector<double>> heights, const glm::vec4& color,
                                   std::string_view name, std::vector<LeftOutHole>* leftOutHoles)
{
    if (!_options.groundHeight || draped()) {
        return addMesh(triangulatePolygon(_ellipsoid, rings, _options.granularityRadians, name, leftOutHoles), color, {});
    }
    // Its heights above the ground, linear over the triangles of the ear clipping, which are made
    // of the positions given (as the triangulation puts them on the surface); a vertex the
    // triangulation makes (where a polygon too large for one plane is cut) takes their mean.
    std::map<std::array<double, 3>, double> heightAt;
    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t r = 0; r < heights.size(); ++r) {
        for (std::size_t i = 0; i < heights[r].size(); ++i) {
            const glm::dvec3 surface = _ellipsoid.scaleToGeodeticSurface(rings[r][i]);
            heightAt[{surface.x, surface.y, surface.z}] = heights[r][i];
            sum += heights[r][i];
            ++count;
        }
    }
    const Mesh clipped = triangulatePolygon(_ellipsoid, rings, kPi, name, leftOutHoles);
    std::vector<double> vertexHeights;
    vertexHeights.reserve(clipped.positions.size());
    for (const glm::dvec3& position : clipped.positions) {
        const auto found = heightAt.find({position.x, position.y, position.z});
        vertexHeights.push_back(found != heightAt.end() ? found->second
                                                        : sum / static_cast<double>(std::max<std::size_t>(count, 1)));
    }
    Mesh mesh = subdivideOnEllipsoid(_ellipsoid, clipped.positions, clipped.indices, groundGranularity(clipped), &vertexHeights);
    return addMesh(std::move(mesh), color, vertexHeights);
}

double PolygonCollection::groundGranularity(const Mesh& clipped) const
{
    // No finer than 1/512 of the polygon's width: a drawn vertex per terrain sample could be
    // millions for a large polygon.
    if (clipped.positions.empty()) {
        return _options.granularityRadians;
    }
    const double width = 2.0 * BoundingSphere::fromPoints(clipped.positions).radius / _ellipsoid.minimumRadius();
    return std::max(_options.granularityRadians, width / 512.0);
}

std::size_t PolygonCollection::addMesh(Mesh mesh, const glm::vec4& color, std::span<const double> heightsAboveGround)
{
    Item item;
    item.color = color;
    item.mesh = std::move(mesh);
    item.mesh.normals.clear();
    item.mesh.normals.shrink_to_fit();
    if (!item.mesh.indices.empty()) {
        // Lift by the deepest dip a triangle with the polygon's widest edge can have.
        double widest = 0.0;
        const std::vector<glm::dvec3>& p = item.mesh.positions;
        const std::vector<std::uint32_t>& t = item.mesh.indices;
        for (std::size_t i = 0; i + 2 < t.size(); i += 3) {
            widest = std::max({widest, detail::centralAngle(p[t[i]], p[t[i + 1]]),
                               detail::centralAngle(p[t[i + 1]], p[t[i + 2]]),
                               detail::centralAngle(p[t[i + 2]], p[t[i]])});
        }
        const double sag = detail::triangleSagBound(_ellipsoid, widest);
        if (draped()) {
            item.sag = sag;
            item.footprint = footprintOf(_ellipsoid, item.mesh, widest);
            item.mesh = shadowVolume(item.mesh);
        } else {
            item.lift = sag;
            item.maxHeight = sag;
            for (std::size_t v = 0; v < item.mesh.positions.size(); ++v) {
                glm::dvec3& position = item.mesh.positions[v];
                double height = item.lift;
                if (_options.groundHeight) {
                    height += _options.groundHeight(_ellipsoid.toGeodetic2D(position)) +
                              (heightsAboveGround.empty() ? 0.0 : heightsAboveGround[v]);
                    item.maxHeight = std::max(item.maxHeight, height);
                }
                position += height * _ellipsoid.geodeticSurfaceNormal(position);
            }
        }
        item.sphere = BoundingSphere::fromPoints(item.mesh.positions);
        _boundingSphere = _boundingSphere ? BoundingSphere::merge(*_boundingSphere, item.sphere) : item.sphere;
        _vertexCount += item.mesh.positions.size();
        _triangleCount += item.mesh.triangleCount();
    } else {
        item.mesh.positions.clear();
    }
    _polygons.push_back(std::move(item));
    _geometryDirty = true;
    return _polygons.size() - 1;
}

const glm::vec4& PolygonCollection::color(std::size_t index) const
{
    assert(index < _polygons.size());
    return _polygons[index].color;
}

void PolygonCollection::setColor(std::size_t index, const glm::vec4& color)
{
    assert(index < _polygons.size());
    Item& item = _polygons[index];
    if (!draped() && isOpaque(item.color) != isOpaque(color)) {
        _indicesDirty = true;
    }
    item.color = color;
    _colorDirty.push_back(index);
}

const Mesh& PolygonCollection::mesh(std::size_t index) const
{
    assert(index < _polygons.size());
    return _polygons[index].mesh;
}

std::optional<HeightInterval> PolygonCollection::drapedHeights(std::size_t index) const
{
    assert(index < _polygons.size());
    return _polygons[index].drapedHeights;
}

const GeodeticExtent& PolygonCollection::footprint(std::size_t index) const
{
    assert(index < _polygons.size());
    return _polygons[index].footprint;
}

double PolygonCollection::liftMeters(std::size_t index) const
{
    assert(index < _polygons.size());
    return _polygons[index].lift;
}

void PolygonCollection::build(FrameState& frameState)
{
    detail::VectorBatch& batch = *_batch;
    std::vector<detail::VectorItem> items;
    items.reserve(_polygons.size());
    for (const Item& item : _polygons) {
        items.push_back({item.mesh.positions, item.sphere, item.maxHeight});
    }
    // A colour per vertex, and for a draped volume its normal and side (kDrapeLocation).
    const std::size_t bytesPerVertex = draped() ? 4 + 4 * sizeof(float) : 4;
    batch.build(frameState, items, bytesPerVertex,
                [&](std::size_t index, std::vector<std::byte>& out) { writeAttributes(index, out); });
    batch.vertexArray().setAttribute(renderer::VertexAttributeLocation::Color, batch.attributes(),
                                     {renderer::ComponentType::UnsignedByte, 4, true, false, bytesPerVertex, 0});
    if (draped()) {
        batch.vertexArray().setAttribute(detail::kDrapeLocation, batch.attributes(),
                                         {renderer::ComponentType::Float, 4, false, false, bytesPerVertex, 4});
    }
    _geometryDirty = false;
    _colorDirty.clear();
    buildIndices(frameState.device);
}

void PolygonCollection::writeAttributes(std::size_t index, std::vector<std::byte>& out) const
{
    const Item& item = _polygons[index];
    const auto color = detail::packColor(item.color);
    const auto bytes = std::as_bytes(std::span(color));
    const std::size_t count = item.mesh.positions.size();
    for (std::size_t i = 0; i < count; ++i) {
        out.insert(out.end(), bytes.begin(), bytes.end());
        if (draped()) {
            const glm::vec3 normal(_ellipsoid.geodeticSurfaceNormal(item.mesh.positions[i]));
            const std::array<float, 4> drape{normal.x, normal.y, normal.z, i < count / 2 ? 0.0f : 1.0f};
            const auto drapeBytes = std::as_bytes(std::span(drape));
            out.insert(out.end(), drapeBytes.begin(), drapeBytes.end());
        }
    }
}

bool PolygonCollection::finishDrapedCommand(const FrameState& frameState, double eyeHeight, std::size_t index,
                                            SceneCommand& command)
{
    Item& item = _polygons[index];
    item.drapedHeights = frameState.groundHeights(item.footprint);
    if (!item.drapedHeights) {
        return false; // no ground drawn under it: nothing to colour
    }
    HeightInterval& heights = *item.drapedHeights;
    heights.lowest -= kDrapeMarginMeters;
    heights.highest += item.sag + kDrapeMarginMeters;
    command.draw.uniforms.set("u_drapeHeights", glm::vec2(static_cast<float>(heights.lowest), static_cast<float>(heights.highest)));
    command.boundingSphere = {item.sphere.centre,
                              item.sphere.radius + std::max(std::abs(heights.lowest), std::abs(heights.highest))};
    command.horizonOcclusionPoint.reset(); // the ground it needs is drawn, so not all below the horizon
    const glm::dvec3 eye = frameState.camera.eye();
    detail::boundDepth(command, _ellipsoid, eye, eyeHeight, heights.highest);
    return true;
}

void PolygonCollection::buildIndices(renderer::Device& device)
{
    // Draped volumes are one range each, all blended in their own pass (appendDrapedDraws).
    _batch->buildIndices(
        device, [&](std::size_t index) { return draped() || isOpaque(_polygons[index].color); },
        [&](std::size_t index, std::uint32_t firstVertex, std::vector<std::uint32_t>& indices) {
            for (const std::uint32_t i : _polygons[index].mesh.indices) {
                indices.push_back(firstVertex + i);
            }
        },
        draped());
    _indicesDirty = false;
}

void PolygonCollection::update(FrameState& frameState, CommandList& commands)
{
    if (_triangleCount == 0) {
        return;
    }
    if (!_batch) {
        _batch = std::make_unique<detail::VectorBatch>(_ellipsoid, detail::VectorShape::Polygons,
                                                       _options.encoding == VertexEncoding::RelativeToEye, draped());
    }
    if (_geometryDirty) {
        build(frameState);
    } else {
        _batch->rewriteAttributes(_colorDirty,
                                  [&](std::size_t index, std::vector<std::byte>& out) { writeAttributes(index, out); });
        if (_indicesDirty) {
            buildIndices(frameState.device);
        }
    }

    const glm::vec4 depthOffset = detail::depthOffsetUniform(_ellipsoid, _options.depthOffset && !draped(),
                                                             kFillDepthSteps, kFillDepthFraction, 0.0);
    if (!draped()) {
        _batch->appendCommands(frameState, depthOffset, commands);
        return;
    }
    CommandList volumes;
    for (Item& item : _polygons) {
        item.drapedHeights.reset();
    }
    const double eyeHeight = _ellipsoid.toGeodetic3D(frameState.camera.eye()).height;
    _batch->appendCommands(frameState, depthOffset, volumes, [&](std::size_t index, SceneCommand& command) {
        return finishDrapedCommand(frameState, eyeHeight, index, command);
    });
    for (SceneCommand& volume : volumes) {
        appendDrapedDraws(std::move(volume), commands);
    }
}

} // namespace orbis::scene
