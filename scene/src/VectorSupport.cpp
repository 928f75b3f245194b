#include "VectorSupport.h"

#include "orbis/scene/Effect.h"

#include <orbis/core/EllipsoidalOccluder.h>
#include <orbis/core/EmulatedDouble.h>
#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>

#include <glm/common.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

namespace orbis::scene::detail {

namespace {

/// a (a / b)^2: the arc an angle at the centre can span, over the smallest radius of curvature.
double curvatureScale(const Ellipsoid& ellipsoid) noexcept
{
    const double a = ellipsoid.maximumRadius();
    const double b = ellipsoid.minimumRadius();
    return a * (a / b) * (a / b);
}

constexpr double kSagMargin = 1.01;

} // namespace

double centralAngle(const glm::dvec3& a, const glm::dvec3& b) noexcept
{
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

double chordSagBound(const Ellipsoid& ellipsoid, double angle) noexcept
{
    return kSagMargin * curvatureScale(ellipsoid) * (1.0 - std::cos(0.5 * std::min(angle, kPi)));
}

double triangleSagBound(const Ellipsoid& ellipsoid, double angle) noexcept
{
    const double s = std::sin(0.5 * std::min(angle, kPi));
    return kSagMargin * curvatureScale(ellipsoid) * (1.0 - std::sqrt(std::max(0.0, 1.0 - 4.0 / 3.0 * s * s)));
}

std::vector<std::vector<std::uint32_t>> groupByRegion(const Ellipsoid& ellipsoid, std::span<const BoundingSphere> items)
{
    if (items.empty()) {
        return {};
    }
    BoundingSphere all = items[0];
    for (const BoundingSphere& item : items.subspan(1)) {
        all = BoundingSphere::merge(all, item);
    }
    const double large = 0.25 * ellipsoid.minimumRadius();
    if (all.radius < large) {
        std::vector<std::uint32_t> one(items.size());
        for (std::uint32_t i = 0; i < one.size(); ++i) {
            one[i] = i;
        }
        return {std::move(one)};
    }
    // 24 cells of small items, then 6 of large ones.
    std::array<std::vector<std::uint32_t>, 30> cells;
    for (std::uint32_t i = 0; i < items.size(); ++i) {
        const glm::dvec3 d = items[i].centre * ellipsoid.oneOverRadii();
        const glm::dvec3 m = glm::abs(d);
        const int axis = m.x >= m.y && m.x >= m.z ? 0 : (m.y >= m.z ? 1 : 2);
        const int face = 2 * axis + (d[axis] < 0.0 ? 1 : 0);
        if (items[i].radius >= large) {
            cells[24 + face].push_back(i);
            continue;
        }
        const double u = d[(axis + 1) % 3];
        const double v = d[(axis + 2) % 3];
        cells[4 * face + (u >= 0.0 ? 1 : 0) + (v >= 0.0 ? 2 : 0)].push_back(i);
    }
    std::vector<std::vector<std::uint32_t>> groups;
    for (std::vector<std::uint32_t>& cell : cells) {
        if (!cell.empty()) {
            groups.push_back(std::move(cell));
        }
    }
    return groups;
}

GroupBounds boundsOf(const Ellipsoid& ellipsoid, std::span<const glm::dvec3> positions)
{
    GroupBounds bounds;
    bounds.sphere = BoundingSphere::fromPoints(positions);
    const double length = glm::length(bounds.sphere.centre);
    if (length > 0.0) {
        // The occluder's camera does not matter for the point (see EllipsoidalOccluder).
        const EllipsoidalOccluder occluder(ellipsoid, glm::dvec3(0.0));
        bounds.occlusionPoint = occluder.horizonOcclusionPoint(bounds.sphere.centre / length, positions);
    }
    return bounds;
}

void boundDepth(SceneCommand& command, const Ellipsoid& ellipsoid, const glm::dvec3& eye, double eyeHeight,
                double maxHeight) noexcept
{
    if (!(eyeHeight > 0.0)) {
        return;
    }
    const double b = ellipsoid.minimumRadius();
    const double top = ellipsoid.maximumRadius() + std::max(maxHeight, 0.0);
    const double eyeDistance = glm::length(eye);
    command.nearestDistance = std::max(0.0, eyeHeight - maxHeight);
    command.farthestDistance =
        std::sqrt(std::max(0.0, eyeDistance * eyeDistance - b * b)) + std::sqrt(top * top - b * b);
}

void appendPosition(std::vector<float>& out, const glm::dvec3& position, bool relativeToEye, const glm::dvec3& centre)
{
    if (relativeToEye) {
        const EmulatedDVec3 encoded = EmulatedDVec3::fromDVec3(position);
        out.insert(out.end(), {encoded.high.x, encoded.high.y, encoded.high.z, encoded.low.x, encoded.low.y,
                               encoded.low.z});
    } else {
        const glm::vec3 offset(position - centre);
        out.insert(out.end(), {offset.x, offset.y, offset.z});
    }
}

std::array<std::uint8_t, 4> packColor(const glm::vec4& color) noexcept
{
    std::array<std::uint8_t, 4> bytes{};
    for (int i = 0; i < 4; ++i) {
        const float c = std::isfinite(color[i]) ? std::clamp(color[i], 0.0f, 1.0f) : 0.0f;
        bytes[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(std::lround(c * 255.0f));
    }
    return bytes;
}

glm::vec4 depthOffsetUniform(const Ellipsoid& ellipsoid, bool enabled, double steps, double fractionOfDistance,
                             double meters) noexcept
{
    const auto radius = static_cast<float>(ellipsoid.maximumRadius());
    if (!enabled) {
        return {0.0f, 0.0f, 0.0f, radius};
    }
    return {static_cast<float>(steps), static_cast<float>(fractionOfDistance), static_cast<float>(meters), radius};
}

renderer::RenderState vectorRenderState(Pass pass, bool cullBackFaces, bool blend) noexcept
{
    renderer::RenderState state;
    state.facetCulling.enabled = cullBackFaces;
    if (blend || pass == Pass::Translucent) {
        state.blending = renderer::Blending::alphaBlending();
        state.blending.sourceAlphaFactor = renderer::SourceBlendingFactor::One;
    }
    state.depthMask = pass != Pass::Translucent;
    return state;
}

renderer::ShaderProgramDescription vectorProgramDescription(VectorShape shape, bool relativeToEye, bool draped,
                                                            DepthStrategy strategy)
{
    renderer::ShaderProgramDescription description;
    description.vertex = renderer::ShaderSource::embedded("scene/vector/vector.vert.glsl");
    if (shape == VectorShape::Polylines) {
        description.name = "polylines";
        description.geometry = renderer::ShaderSource::embedded("scene/vector/polyline.geom.glsl");
        description.fragment = renderer::ShaderSource::embedded("scene/vector/polyline.frag.glsl");
        description.defines.push_back({"POLYLINE"});
    } else {
        description.name = "polygons";
        if (strategy == DepthStrategy::LogarithmicVertex) {
            description.geometry = renderer::ShaderSource::embedded("scene/vector/polygon.geom.glsl");
        }
        description.fragment = renderer::ShaderSource::embedded("scene/vector/polygon.frag.glsl");
        if (draped) {
            description.name = "draped polygons";
            description.defines.push_back({"DRAPED"});
        }
    }
    if (description.geometry) {
        description.defines.push_back({"DEPTH_IN_GEOMETRY_SHADER"});
    }
    if (!relativeToEye) {
        description.defines.push_back({"RELATIVE_TO_CENTER"});
    }
    return description;
}

VectorBatch::VectorBatch(const Ellipsoid& ellipsoid, VectorShape shape, bool relativeToEye, bool draped)
    : _ellipsoid(ellipsoid)
    , _shape(shape)
    , _relativeToEye(relativeToEye)
    , _programs([shape, relativeToEye, draped](DepthStrategy strategy, Pass) {
        return vectorProgramDescription(shape, relativeToEye, draped, strategy);
    })
{
}

void VectorBatch::build(FrameState& frameState, std::span<const VectorItem> items, std::size_t bytesPerVertex,
                        const AttributeWriter& writeAttributes)
{
    // Groups by region, each with its culling volume (and centre, for RTC).
    std::vector<std::size_t> drawable;
    std::vector<BoundingSphere> spheres;
    std::size_t vertexCount = 0;
    for (std::size_t i = 0; i < items.size(); ++i) {
        if (!items[i].positions.empty()) {
            drawable.push_back(i);
            spheres.push_back(items[i].sphere);
            vertexCount += items[i].positions.size();
        }
    }
    _groups.clear();
    for (const std::vector<std::uint32_t>& members : groupByRegion(_ellipsoid, spheres)) {
        Group group;
        std::vector<glm::dvec3> positions;
        for (const std::uint32_t member : members) {
            const VectorItem& item = items[drawable[member]];
            group.items.push_back(drawable[member]);
            group.maxHeight = std::max(group.maxHeight, item.maxHeight);
            positions.insert(positions.end(), item.positions.begin(), item.positions.end());
        }
        group.bounds = boundsOf(_ellipsoid, positions);
        _groups.push_back(std::move(group));
    }

    // Vertices group by group.
    _bytesPerVertex = bytesPerVertex;
    _firstVertex.assign(items.size(), kNotDrawn);
    _vertexCount.assign(items.size(), 0);
    std::vector<float> positionData;
    positionData.reserve(vertexCount * (_relativeToEye ? 6 : 3));
    std::vector<std::byte> attributeData;
    attributeData.reserve(vertexCount * bytesPerVertex);
    std::size_t vertex = 0;
    for (const Group& group : _groups) {
        for (const std::size_t index : group.items) {
            const VectorItem& item = items[index];
            _firstVertex[index] = vertex;
            _vertexCount[index] = item.positions.size();
            vertex += item.positions.size();
            for (const glm::dvec3& position : item.positions) {
                appendPosition(positionData, position, _relativeToEye, group.bounds.sphere.centre);
            }
            writeAttributes(index, attributeData);
        }
    }
    assert(attributeData.size() == vertexCount * bytesPerVertex);
    renderer::Device& device = frameState.device;
    _positions = device.createVertexBuffer(std::as_bytes(std::span(positionData)));
    _attributes = device.createVertexBuffer(std::span<const std::byte>(attributeData), renderer::BufferUsage::DynamicDraw);
    _vertexArray = frameState.context.createVertexArray();
    if (_relativeToEye) {
        _vertexArray.setAttribute(renderer::VertexAttributeLocation::PositionHigh, _positions,
                                  {renderer::ComponentType::Float, 3, false, false, 24, 0});
        _vertexArray.setAttribute(renderer::VertexAttributeLocation::PositionLow, _positions,
                                  {renderer::ComponentType::Float, 3, false, false, 24, 12});
    } else {
        _vertexArray.setAttribute(renderer::VertexAttributeLocation::Position, _positions, {renderer::ComponentType::Float, 3});
    }
    _ranges.clear();
    _indices = renderer::IndexBuffer();
}

void VectorBatch::rewriteAttributes(std::vector<std::size_t>& items, const AttributeWriter& writeAttributes)
{
    std::sort(items.begin(), items.end());
    items.erase(std::unique(items.begin(), items.end()), items.end());
    std::vector<std::byte> bytes;
    for (const std::size_t index : items) {
        if (index >= _firstVertex.size() || _firstVertex[index] == kNotDrawn) {
            continue;
        }
        bytes.clear();
        writeAttributes(index, bytes);
        assert(bytes.size() == _vertexCount[index] * _bytesPerVertex);
        _attributes.copyFromSystemMemory(bytes, _firstVertex[index] * _bytesPerVertex);
    }
    items.clear();
}

void VectorBatch::buildIndices(renderer::Device& device, const std::function<bool(std::size_t item)>& opaque,
                               const IndexWriter& writeIndices, bool rangePerItem)
{
    std::vector<std::uint32_t> indices;
    _ranges.clear();
    for (std::size_t g = 0; g < _groups.size(); ++g) {
        for (const Pass pass : {Pass::Opaque, Pass::Translucent}) {
            std::size_t first = indices.size();
            for (const std::size_t index : _groups[g].items) {
                if ((pass == Pass::Opaque) == opaque(index)) {
                    writeIndices(index, static_cast<std::uint32_t>(_firstVertex[index]), indices);
                    if (rangePerItem && indices.size() > first) {
                        _ranges.push_back({g, pass, first, indices.size() - first, index});
                        first = indices.size();
                    }
                }
            }
            if (indices.size() > first) {
                _ranges.push_back({g, pass, first, indices.size() - first});
            }
        }
    }
    _vertexArray.setIndexBuffer(nullptr);
    _indices = renderer::IndexBuffer();
    if (!indices.empty()) {
        _indices = device.createIndexBuffer(std::span<const std::uint32_t>(indices));
        _vertexArray.setIndexBuffer(&_indices);
    }
}

void VectorBatch::appendCommands(FrameState& frameState, const glm::vec4& depthOffset, CommandList& commands,
                                 const ItemCommand& finishItem)
{
    const bool lines = _shape == VectorShape::Polylines;
    const glm::dvec3 eye = frameState.camera.eye();
    const double eyeHeight = _ellipsoid.toGeodetic3D(eye).height;
    for (const Range& range : _ranges) {
        const Group& group = _groups[range.group];
        SceneCommand command;
        command.draw.debugName = lines ? "polylines" : "polygons";
        command.tags = static_cast<std::uint32_t>(lines ? Effect::Polylines : Effect::Polygons);
        command.draw.vertexArray = &_vertexArray;
        command.draw.primitiveType = lines ? PrimitiveType::LineStripAdjacency : PrimitiveType::Triangles;
        command.draw.first = range.first;
        command.draw.count = range.count;
        command.draw.shaderProgram = &_programs.get(frameState, range.pass);
        command.draw.uniforms.set("u_depthOffset", depthOffset);
        // Fills cull their back faces; lines blend in both passes (anti-aliased edges).
        command.draw.renderState = vectorRenderState(range.pass, !lines, lines);
        if (lines) {
            command.draw.renderState.primitiveRestart = {true, kRestartIndex};
        }
        if (!_relativeToEye) {
            command.draw.modelMatrix = glm::translate(glm::dmat4(1.0), group.bounds.sphere.centre);
        }
        command.pass = range.pass;
        command.boundingSphere = group.bounds.sphere;
        command.horizonOcclusionPoint = group.bounds.occlusionPoint;
        boundDepth(command, _ellipsoid, eye, eyeHeight, group.maxHeight);
        if (range.item != kNotDrawn && finishItem && !finishItem(range.item, command)) {
            continue;
        }
        commands.push_back(std::move(command));
    }
}

} // namespace orbis::scene::detail
