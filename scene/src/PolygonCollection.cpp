#include "orbis/scene/PolygonCollection.h"

#include "orbis/scene/Effect.h"

#include "VectorSupport.h"

#include <orbis/core/EllipsoidPolygon.h>
#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>

#include <glm/ext/matrix_transform.hpp>

#include <algorithm>
#include <cassert>
#include <cstring>

namespace orbis {

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
    std::size_t firstVertex = 0;
};

struct PolygonCollection::Gpu {
    struct Group {
        detail::GroupBounds bounds;
        double maxHeight = 0.0; ///< the largest lift: polygons lie on the ellipsoid
        std::vector<std::size_t> polygons;
    };
    struct Range {
        std::size_t group = 0;
        Pass pass = Pass::Opaque;
        std::size_t first = 0;
        std::size_t count = 0;
    };
    std::shared_ptr<ShaderProgram> program;
    VertexBuffer positions;
    VertexBuffer colors;
    IndexBuffer indices;
    VertexArray vertexArray;
    std::vector<Group> groups;
    std::vector<Range> ranges;
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

std::size_t PolygonCollection::add(const Polygon& polygon, const glm::vec4& color, std::string_view name)
{
    std::vector<std::vector<glm::dvec3>> rings;
    rings.reserve(polygon.rings.size());
    for (const LinearRing& ring : polygon.rings) {
        std::vector<glm::dvec3>& cartesian = rings.emplace_back();
        cartesian.reserve(ring.size());
        for (const Geodetic3D& position : ring) {
            cartesian.push_back(_ellipsoid.toCartesian(Geodetic2D(position.longitude, position.latitude)));
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
    Gpu& gpu = *_gpu;
    const bool relativeToEye = _options.encoding == VertexEncoding::RelativeToEye;

    std::vector<std::size_t> drawable;
    std::vector<BoundingSphere> spheres;
    for (std::size_t i = 0; i < _polygons.size(); ++i) {
        if (!_polygons[i].mesh.indices.empty()) {
            drawable.push_back(i);
            spheres.push_back(_polygons[i].sphere);
        }
    }
    gpu.groups.clear();
    for (const std::vector<std::uint32_t>& members : detail::groupByRegion(_ellipsoid, spheres)) {
        Gpu::Group group;
        std::vector<glm::dvec3> positions;
        for (const std::uint32_t member : members) {
            const Mesh& mesh = _polygons[drawable[member]].mesh;
            group.polygons.push_back(drawable[member]);
            group.maxHeight = std::max(group.maxHeight, _polygons[drawable[member]].lift);
            positions.insert(positions.end(), mesh.positions.begin(), mesh.positions.end());
        }
        group.bounds = detail::boundsOf(_ellipsoid, positions);
        gpu.groups.push_back(std::move(group));
    }

    std::vector<float> positionData;
    positionData.reserve(_vertexCount * (relativeToEye ? 6 : 3));
    std::vector<std::array<std::uint8_t, 4>> colorData;
    colorData.reserve(_vertexCount);
    std::size_t vertex = 0;
    for (const Gpu::Group& group : gpu.groups) {
        for (const std::size_t index : group.polygons) {
            Item& item = _polygons[index];
            item.firstVertex = vertex;
            vertex += item.mesh.positions.size();
            for (const glm::dvec3& position : item.mesh.positions) {
                detail::appendPosition(positionData, position, relativeToEye, group.bounds.sphere.centre);
            }
            colorData.insert(colorData.end(), item.mesh.positions.size(), detail::packColor(item.color));
        }
    }
    Device& device = frameState.device;
    gpu.positions = device.createVertexBuffer(std::as_bytes(std::span(positionData)));
    gpu.colors = device.createVertexBuffer(std::as_bytes(std::span(colorData)), BufferUsage::DynamicDraw);
    gpu.vertexArray = frameState.context.createVertexArray();
    if (relativeToEye) {
        gpu.vertexArray.setAttribute(VertexAttributeLocation::PositionHigh, gpu.positions,
                                     {ComponentType::Float, 3, false, false, 24, 0});
        gpu.vertexArray.setAttribute(VertexAttributeLocation::PositionLow, gpu.positions,
                                     {ComponentType::Float, 3, false, false, 24, 12});
    } else {
        gpu.vertexArray.setAttribute(VertexAttributeLocation::Position, gpu.positions, {ComponentType::Float, 3});
    }
    gpu.vertexArray.setAttribute(VertexAttributeLocation::Color, gpu.colors, {ComponentType::UnsignedByte, 4, true});
    _geometryDirty = false;
    _colorDirty.clear();
    buildIndices(device);
}

void PolygonCollection::buildIndices(Device& device)
{
    Gpu& gpu = *_gpu;
    std::vector<std::uint32_t> indices;
    indices.reserve(3 * _triangleCount);
    gpu.ranges.clear();
    for (std::size_t g = 0; g < gpu.groups.size(); ++g) {
        for (const Pass pass : {Pass::Opaque, Pass::Translucent}) {
            const std::size_t first = indices.size();
            for (const std::size_t index : gpu.groups[g].polygons) {
                const Item& item = _polygons[index];
                if ((pass == Pass::Opaque) != isOpaque(item.color)) {
                    continue;
                }
                const auto offset = static_cast<std::uint32_t>(item.firstVertex);
                for (const std::uint32_t i : item.mesh.indices) {
                    indices.push_back(offset + i);
                }
            }
            if (indices.size() > first) {
                gpu.ranges.push_back({g, pass, first, indices.size() - first});
            }
        }
    }
    gpu.vertexArray.setIndexBuffer(nullptr);
    gpu.indices = IndexBuffer();
    if (!indices.empty()) {
        gpu.indices = device.createIndexBuffer(std::span<const std::uint32_t>(indices));
        gpu.vertexArray.setIndexBuffer(&gpu.indices);
    }
    _indicesDirty = false;
}

void PolygonCollection::update(FrameState& frameState, CommandList& commands)
{
    if (_triangleCount == 0) {
        return;
    }
    if (!_gpu) {
        _gpu = std::make_unique<Gpu>();
        ShaderProgramDescription description;
        description.name = "polygons";
        description.vertex = ShaderSource::embedded("scene/vector/vector.vert.glsl");
        description.fragment = ShaderSource::embedded("scene/vector/polygon.frag.glsl");
        if (_options.encoding == VertexEncoding::RelativeToCenter) {
            description.defines.push_back({"RELATIVE_TO_CENTER"});
        }
        _gpu->program = frameState.device.shaderCache().get(description);
    }
    Gpu& gpu = *_gpu;
    if (_geometryDirty) {
        build(frameState);
    } else {
        std::sort(_colorDirty.begin(), _colorDirty.end());
        _colorDirty.erase(std::unique(_colorDirty.begin(), _colorDirty.end()), _colorDirty.end());
        for (const std::size_t index : _colorDirty) {
            const Item& item = _polygons[index];
            if (item.mesh.positions.empty()) {
                continue;
            }
            const std::vector<std::array<std::uint8_t, 4>> bytes(item.mesh.positions.size(),
                                                                  detail::packColor(item.color));
            gpu.colors.copyFromSystemMemory(std::as_bytes(std::span(bytes)), item.firstVertex * 4);
        }
        _colorDirty.clear();
        if (_indicesDirty) {
            buildIndices(frameState.device);
        }
    }

    const glm::vec4 depthOffset =
        detail::depthOffsetUniform(_ellipsoid, _options.depthOffset, kFillDepthSteps, kFillDepthFraction, 0.0);
    const glm::dvec3 eye = frameState.camera.eye();
    const double eyeHeight = _ellipsoid.toGeodetic3D(eye).height;
    for (const Gpu::Range& range : gpu.ranges) {
        const Gpu::Group& group = gpu.groups[range.group];
        DrawCommand command;
        command.debugName = "polygons";
        command.tags = static_cast<std::uint32_t>(Effect::Polygons);
        command.vertexArray = &gpu.vertexArray;
        command.first = range.first;
        command.count = range.count;
        command.shaderProgram = gpu.program.get();
        command.uniforms.set("u_depthOffset", depthOffset);
        command.renderState = detail::vectorRenderState(range.pass, true, false);
        if (_options.encoding == VertexEncoding::RelativeToCenter) {
            command.modelMatrix = glm::translate(glm::dmat4(1.0), group.bounds.sphere.centre);
        }
        command.pass = range.pass;
        command.boundingSphere = group.bounds.sphere;
        command.horizonOcclusionPoint = group.bounds.occlusionPoint;
        detail::boundDepth(command, _ellipsoid, eye, eyeHeight, group.maxHeight);
        commands.push_back(std::move(command));
    }
}

} // namespace orbis
