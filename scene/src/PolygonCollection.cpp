#include "orbis/scene/PolygonCollection.h"

#include "VectorSupport.h"

#include "orbis/scene/Effect.h"

#include <orbis/core/EllipsoidPolygon.h>
#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>

#include <algorithm>
#include <cassert>
#include <unordered_set>

namespace orbis::scene {

namespace {

/// Depth-buffer steps and least fraction of the distance fills move towards the eye: a quarter of
/// the lines' (PolylineCollection), so borders drawn over fills win.
constexpr double kFillDepthSteps = 4.0;
constexpr double kFillDepthFraction = 1e-5;

bool isOpaque(const glm::vec4& color) noexcept { return color.a >= 1.0f; }

/// The closed volume over a polygon's triangles on the surface, from `bottom` to `top` metres
/// above it along the geodetic normals: the triangles at the top, reversed at the bottom, and a
/// wall under each edge of the outline (an edge of one triangle only: the subdivision shares its
/// inner edges), every face counter-clockwise seen from outside, as the stencil count needs.
Mesh shadowVolume(const Ellipsoid& ellipsoid, const Mesh& surface, double bottom, double top)
{
    const std::size_t n = surface.positions.size();
    Mesh volume;
    volume.positions.reserve(2 * n);
    for (const double height : {bottom, top}) {
        for (const glm::dvec3& position : surface.positions) {
            volume.positions.push_back(position + height * ellipsoid.geodeticSurfaceNormal(position));
        }
    }
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
    double maxHeight = 0.0; ///< of the drawn positions above the ellipsoid
    glm::vec4 color{1.0f};
    BoundingSphere sphere;
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
    rings.reserve(polygon.rings.size());
    for (const world::LinearRing& ring : polygon.rings) {
        std::vector<glm::dvec3>& cartesian = rings.emplace_back();
        cartesian.reserve(ring.size());
        for (const Geodetic3D& position : ring) {
            cartesian.push_back(_ellipsoid.toCartesian(Geodetic2D{position.longitude, position.latitude}));
        }
    }
    return add(rings, color, name, leftOutHoles);
}

std::size_t PolygonCollection::add(std::span<const std::vector<glm::dvec3>> rings, const glm::vec4& color,
                                   std::string_view name, std::vector<LeftOutHole>* leftOutHoles)
{
    Item item;
    item.color = color;
    item.mesh = triangulatePolygon(_ellipsoid, rings, _options.granularityRadians, name, leftOutHoles);
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
            const HeightInterval ground = _options.groundHeights(item.mesh);
            item.maxHeight = ground.highest + sag;
            item.mesh = shadowVolume(_ellipsoid, item.mesh, ground.lowest, item.maxHeight);
        } else {
            item.lift = sag;
            item.maxHeight = sag;
            for (glm::dvec3& position : item.mesh.positions) {
                position += item.lift * _ellipsoid.geodeticSurfaceNormal(position);
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
    batch.build(frameState, items, 4, [&](std::size_t index, std::vector<std::byte>& out) { writeColor(index, out); });
    batch.vertexArray().setAttribute(renderer::VertexAttributeLocation::Color, batch.attributes(),
                                     {renderer::ComponentType::UnsignedByte, 4, true});
    _geometryDirty = false;
    _colorDirty.clear();
    buildIndices(frameState.device);
}

void PolygonCollection::writeColor(std::size_t index, std::vector<std::byte>& out) const
{
    const Item& item = _polygons[index];
    const auto color = detail::packColor(item.color);
    const auto bytes = std::as_bytes(std::span(color));
    for (std::size_t i = 0; i < item.mesh.positions.size(); ++i) {
        out.insert(out.end(), bytes.begin(), bytes.end());
    }
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
                                                       _options.encoding == VertexEncoding::RelativeToEye);
    }
    if (_geometryDirty) {
        build(frameState);
    } else {
        _batch->rewriteAttributes(_colorDirty,
                                  [&](std::size_t index, std::vector<std::byte>& out) { writeColor(index, out); });
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
    _batch->appendCommands(frameState, depthOffset, volumes);
    for (SceneCommand& volume : volumes) {
        appendDrapedDraws(std::move(volume), commands);
    }
}

} // namespace orbis::scene
