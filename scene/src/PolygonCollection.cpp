#include "orbis/scene/PolygonCollection.h"

#include "VectorSupport.h"

#include <orbis/core/EllipsoidPolygon.h>
#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>

#include <algorithm>
#include <cassert>

namespace orbis::scene {

namespace {

/// Depth-buffer steps and least fraction of the distance fills move towards the eye: a quarter of
/// the lines' (PolylineCollection), so borders drawn over fills win.
constexpr double kFillDepthSteps = 4.0;
constexpr double kFillDepthFraction = 1e-5;

bool isOpaque(const glm::vec4& color) noexcept { return color.a >= 1.0f; }

} // namespace

struct PolygonCollection::Item {
    Mesh mesh; ///< drawn: lifted positions, no normals
    double lift = 0.0;
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

std::size_t PolygonCollection::add(const world::Polygon& polygon, const glm::vec4& color, std::string_view name)
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
    return add(rings, color, name);
}

std::size_t PolygonCollection::add(std::span<const std::vector<glm::dvec3>> rings, const glm::vec4& color,
                                   std::string_view name)
{
    Item item;
    item.color = color;
    item.mesh = triangulatePolygon(_ellipsoid, rings, _options.granularityRadians, name);
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
        item.lift = detail::triangleSagBound(_ellipsoid, widest);
        for (glm::dvec3& position : item.mesh.positions) {
            position += item.lift * _ellipsoid.geodeticSurfaceNormal(position);
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
    if (isOpaque(item.color) != isOpaque(color)) {
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
        items.push_back({item.mesh.positions, item.sphere, item.lift}); // polygons lie on the ellipsoid
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
    _batch->buildIndices(
        device, [&](std::size_t index) { return isOpaque(_polygons[index].color); },
        [&](std::size_t index, std::uint32_t firstVertex, std::vector<std::uint32_t>& indices) {
            for (const std::uint32_t i : _polygons[index].mesh.indices) {
                indices.push_back(firstVertex + i);
            }
        });
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

    const glm::vec4 depthOffset =
        detail::depthOffsetUniform(_ellipsoid, _options.depthOffset, kFillDepthSteps, kFillDepthFraction, 0.0);
    _batch->appendCommands(frameState, depthOffset, commands);
}

} // namespace orbis::scene
