#include "orbis/scene/PolylineCollection.h"

#include "orbis/scene/Effect.h"

#include "VectorSupport.h"

#include <orbis/core/Geodesic.h>
#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>

#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cassert>
#include <cstring>

namespace orbis {

namespace {

constexpr std::uint32_t kRestartIndex = 0xFFFFFFFFu;
constexpr std::size_t kStyleBytes = 16; ///< colour, outline colour (4 bytes each), width, outline width (floats)

/// Depth-buffer steps and least fraction of the distance lines move towards the eye: four times
/// the polygons' (PolygonCollection), so borders win over fills as well as over the globe.
constexpr double kLineDepthSteps = 16.0;
constexpr double kLineDepthFraction = 2e-5;

struct SurfacePoint {
    glm::dvec3 surface;
    double height;
};

} // namespace

struct PolylineCollection::Line {
    std::vector<glm::dvec3> positions; ///< drawn: subdivided and lifted
    double lift = 0.0;
    double maxHeight = 0.0; ///< of the drawn positions above the ellipsoid: lift and heights given
    bool loop = false;
    PolylineStyle style;
    BoundingSphere sphere;
    std::size_t firstVertex = 0; ///< in the vertex buffers, once built
};

struct PolylineCollection::Gpu {
    struct Group {
        detail::GroupBounds bounds;
        double maxHeight = 0.0;
        std::vector<std::size_t> lines;
    };
    struct Range {
        std::size_t group = 0;
        Pass pass = Pass::Opaque;
        std::size_t first = 0;
        std::size_t count = 0;
    };
    std::shared_ptr<ShaderProgram> program;
    VertexBuffer positions;
    VertexBuffer styles;
    IndexBuffer indices;
    VertexArray vertexArray;
    std::vector<Group> groups;
    std::vector<Range> ranges;
};

PolylineCollection::PolylineCollection(const Ellipsoid& ellipsoid, const PolylineCollectionOptions& options)
    : _ellipsoid(ellipsoid)
    , _options(options)
{
    _options.granularityRadians = std::max(_options.granularityRadians, 1e-6);
    if (_options.curve == CurveType::Geodesic) {
        assert(ellipsoid.isSpheroid());
        _geodesic = std::make_unique<const Geodesic>(ellipsoid);
    }
}

PolylineCollection::~PolylineCollection() = default;

std::size_t PolylineCollection::size() const noexcept
{
    return _lines.size();
}

std::size_t PolylineCollection::add(std::span<const Geodetic3D> positions, const PolylineStyle& style, bool loop)
{
    std::vector<glm::dvec3> cartesian;
    cartesian.reserve(positions.size());
    for (const Geodetic3D& position : positions) {
        cartesian.push_back(_ellipsoid.toCartesian(position));
    }
    return add(cartesian, style, loop);
}

std::size_t PolylineCollection::add(std::span<const glm::dvec3> positions, const PolylineStyle& style, bool loop)
{
    // The positions on the surface with their heights, duplicates dropped.
    std::vector<SurfacePoint> points;
    points.reserve(positions.size());
    std::vector<Geodetic2D> geodetic;
    for (const glm::dvec3& position : positions) {
        if (!isFinite(position)) {
            continue;
        }
        const Geodetic3D g = _ellipsoid.toGeodetic3D(position);
        const SurfacePoint point{_ellipsoid.toCartesian(Geodetic2D(g.longitude, g.latitude)), g.height};
        if (!points.empty() && glm::distance(points.back().surface, point.surface) < 1e-6 &&
            std::abs(points.back().height - point.height) < 1e-6) {
            continue;
        }
        points.push_back(point);
        geodetic.emplace_back(g.longitude, g.latitude);
    }
    if (loop && points.size() > 1 && glm::distance(points.back().surface, points.front().surface) < 1e-6 &&
        std::abs(points.back().height - points.front().height) < 1e-6) {
        points.pop_back();
        geodetic.pop_back();
    }
    loop = loop && points.size() >= 3;

    Line line;
    line.loop = loop;
    line.style = style;
    if (points.size() >= 2) {
        // The curve between each pair, heights interpolated along it.
        std::vector<SurfacePoint> drawn;
        const std::size_t segments = loop ? points.size() : points.size() - 1;
        for (std::size_t i = 0; i < segments; ++i) {
            const std::size_t j = (i + 1) % points.size();
            const std::vector<glm::dvec3> curve =
                _geodesic ? _geodesic->computeGeodesic(geodetic[i], geodetic[j], _options.granularityRadians)
                          : _ellipsoid.computeCurve(points[i].surface, points[j].surface, _options.granularityRadians);
            const std::size_t last = curve.size() - 1;
            // Each curve's last point is the next one's first; a loop's last is the line's first.
            const std::size_t end = (i + 1 == segments) && !loop ? curve.size() : last;
            for (std::size_t k = 0; k < end; ++k) {
                const double t = static_cast<double>(k) / static_cast<double>(last);
                drawn.push_back({curve[k], (1.0 - t) * points[i].height + t * points[j].height});
            }
        }
        double widest = 0.0;
        const std::size_t count = drawn.size();
        for (std::size_t k = 0; k + 1 < count + (loop ? 1 : 0); ++k) {
            widest = std::max(widest, detail::centralAngle(drawn[k].surface, drawn[(k + 1) % count].surface));
        }
        line.lift = detail::chordSagBound(_ellipsoid, widest);
        line.maxHeight = line.lift;
        for (const SurfacePoint& point : drawn) {
            line.maxHeight = std::max(line.maxHeight, point.height + line.lift);
        }
        line.positions.reserve(count);
        for (const SurfacePoint& point : drawn) {
            line.positions.push_back(point.surface +
                                     (point.height + line.lift) * _ellipsoid.geodeticSurfaceNormal(point.surface));
        }
        line.sphere = BoundingSphere::fromPoints(line.positions);
        _boundingSphere = _boundingSphere ? BoundingSphere::merge(*_boundingSphere, line.sphere) : line.sphere;
        _vertexCount += count;
        _segmentCount += loop ? count : count - 1;
    }
    _lines.push_back(std::move(line));
    _geometryDirty = true;
    return _lines.size() - 1;
}

const PolylineStyle& PolylineCollection::style(std::size_t index) const
{
    assert(index < _lines.size());
    return _lines[index].style;
}

void PolylineCollection::setStyle(std::size_t index, const PolylineStyle& style)
{
    assert(index < _lines.size());
    Line& line = _lines[index];
    if (line.style.opaque() != style.opaque()) {
        _indicesDirty = true;
    }
    line.style = style;
    _styleDirty.push_back(index);
}

std::span<const glm::dvec3> PolylineCollection::positions(std::size_t index) const
{
    assert(index < _lines.size());
    return _lines[index].positions;
}

bool PolylineCollection::isLoop(std::size_t index) const
{
    assert(index < _lines.size());
    return _lines[index].loop;
}

double PolylineCollection::liftMeters(std::size_t index) const
{
    assert(index < _lines.size());
    return _lines[index].lift;
}

void PolylineCollection::writeStyle(const Line& line, std::vector<std::byte>& out) const
{
    const PolylineStyle& style = line.style;
    const auto color = detail::packColor(style.color);
    const auto outline = detail::packColor(style.outlineColor);
    const float widths[2] = {style.show ? std::max(style.widthPixels, 0.0f) : 0.0f,
                             style.show ? std::max(style.outlineWidthPixels, 0.0f) : 0.0f};
    std::byte vertex[kStyleBytes];
    std::memcpy(vertex, color.data(), 4);
    std::memcpy(vertex + 4, outline.data(), 4);
    std::memcpy(vertex + 8, widths, 8);
    for (std::size_t i = 0; i < line.positions.size(); ++i) {
        out.insert(out.end(), vertex, vertex + kStyleBytes);
    }
}

void PolylineCollection::build(FrameState& frameState)
{
    Gpu& gpu = *_gpu;
    const bool relativeToEye = _options.encoding == VertexEncoding::RelativeToEye;

    // Groups by region, each with its culling volume (and centre, for RTC).
    std::vector<std::size_t> drawable;
    std::vector<BoundingSphere> spheres;
    for (std::size_t i = 0; i < _lines.size(); ++i) {
        if (_lines[i].positions.size() >= 2) {
            drawable.push_back(i);
            spheres.push_back(_lines[i].sphere);
        }
    }
    gpu.groups.clear();
    for (const std::vector<std::uint32_t>& members : detail::groupByRegion(_ellipsoid, spheres)) {
        Gpu::Group group;
        std::vector<glm::dvec3> positions;
        for (const std::uint32_t member : members) {
            const Line& line = _lines[drawable[member]];
            group.lines.push_back(drawable[member]);
            group.maxHeight = std::max(group.maxHeight, line.maxHeight);
            positions.insert(positions.end(), line.positions.begin(), line.positions.end());
        }
        group.bounds = detail::boundsOf(_ellipsoid, positions);
        gpu.groups.push_back(std::move(group));
    }

    // Vertices group by group.
    std::vector<float> positionData;
    positionData.reserve(_vertexCount * (relativeToEye ? 6 : 3));
    std::vector<std::byte> styleData;
    styleData.reserve(_vertexCount * kStyleBytes);
    std::size_t vertex = 0;
    for (const Gpu::Group& group : gpu.groups) {
        for (const std::size_t index : group.lines) {
            Line& line = _lines[index];
            line.firstVertex = vertex;
            vertex += line.positions.size();
            for (const glm::dvec3& position : line.positions) {
                detail::appendPosition(positionData, position, relativeToEye, group.bounds.sphere.centre);
            }
            writeStyle(line, styleData);
        }
    }
    Device& device = frameState.device;
    gpu.positions = device.createVertexBuffer(std::as_bytes(std::span(positionData)));
    gpu.styles = device.createVertexBuffer(std::span<const std::byte>(styleData), BufferUsage::DynamicDraw);
    gpu.vertexArray = frameState.context.createVertexArray();
    if (relativeToEye) {
        gpu.vertexArray.setAttribute(VertexAttributeLocation::PositionHigh, gpu.positions,
                                     {ComponentType::Float, 3, false, false, 24, 0});
        gpu.vertexArray.setAttribute(VertexAttributeLocation::PositionLow, gpu.positions,
                                     {ComponentType::Float, 3, false, false, 24, 12});
    } else {
        gpu.vertexArray.setAttribute(VertexAttributeLocation::Position, gpu.positions, {ComponentType::Float, 3});
    }
    gpu.vertexArray.setAttribute(VertexAttributeLocation::Color, gpu.styles,
                                 {ComponentType::UnsignedByte, 4, true, false, kStyleBytes, 0});
    if (const ShaderVertexAttribute* outline = gpu.program->findVertexAttribute("outlineColor")) {
        gpu.vertexArray.setAttribute(outline->location, gpu.styles,
                                     {ComponentType::UnsignedByte, 4, true, false, kStyleBytes, 4});
    }
    if (const ShaderVertexAttribute* widths = gpu.program->findVertexAttribute("widths")) {
        gpu.vertexArray.setAttribute(widths->location, gpu.styles,
                                     {ComponentType::Float, 2, false, false, kStyleBytes, 8});
    }
    _geometryDirty = false;
    _styleDirty.clear();
    buildIndices(device);
}

void PolylineCollection::buildIndices(Device& device)
{
    Gpu& gpu = *_gpu;
    std::vector<std::uint32_t> indices;
    indices.reserve(_vertexCount + 4 * _lines.size());
    gpu.ranges.clear();
    for (std::size_t g = 0; g < gpu.groups.size(); ++g) {
        for (const Pass pass : {Pass::Opaque, Pass::Translucent}) {
            const std::size_t first = indices.size();
            for (const std::size_t index : gpu.groups[g].lines) {
                const Line& line = _lines[index];
                if ((pass == Pass::Opaque) != line.style.opaque()) {
                    continue;
                }
                // A strip with adjacency: the vertex before the first segment and the one after the
                // last; an open end repeats its own vertex (no joint), a loop wraps around.
                const auto f = static_cast<std::uint32_t>(line.firstVertex);
                const auto n = static_cast<std::uint32_t>(line.positions.size());
                indices.push_back(line.loop ? f + n - 1 : f);
                for (std::uint32_t k = 0; k < n; ++k) {
                    indices.push_back(f + k);
                }
                if (line.loop) {
                    indices.push_back(f);
                    indices.push_back(f + 1);
                } else {
                    indices.push_back(f + n - 1);
                }
                indices.push_back(kRestartIndex);
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

void PolylineCollection::update(FrameState& frameState, CommandList& commands)
{
    if (_segmentCount == 0) {
        return;
    }
    if (!_gpu) {
        _gpu = std::make_unique<Gpu>();
        ShaderProgramDescription description;
        description.name = "polylines";
        description.vertex = ShaderSource::embedded("scene/vector/vector.vert.glsl");
        description.geometry = ShaderSource::embedded("scene/vector/polyline.geom.glsl");
        description.fragment = ShaderSource::embedded("scene/vector/polyline.frag.glsl");
        description.defines.push_back({"POLYLINE"});
        if (_options.encoding == VertexEncoding::RelativeToCenter) {
            description.defines.push_back({"RELATIVE_TO_CENTER"});
        }
        _gpu->program = frameState.device.shaderCache().get(description);
    }
    Gpu& gpu = *_gpu;
    if (_geometryDirty) {
        build(frameState);
    } else {
        std::sort(_styleDirty.begin(), _styleDirty.end());
        _styleDirty.erase(std::unique(_styleDirty.begin(), _styleDirty.end()), _styleDirty.end());
        std::vector<std::byte> bytes;
        for (const std::size_t index : _styleDirty) {
            const Line& line = _lines[index];
            if (line.positions.empty()) {
                continue;
            }
            bytes.clear();
            writeStyle(line, bytes);
            gpu.styles.copyFromSystemMemory(bytes, line.firstVertex * kStyleBytes);
        }
        _styleDirty.clear();
        if (_indicesDirty) {
            buildIndices(frameState.device);
        }
    }

    const glm::vec4 depthOffset = detail::depthOffsetUniform(
        _ellipsoid, _options.depthOffset, kLineDepthSteps, kLineDepthFraction,
        detail::triangleSagBound(_ellipsoid, _options.granularityRadians));
    const glm::dvec3 eye = frameState.camera.eye();
    const double eyeHeight = _ellipsoid.toGeodetic3D(eye).height;
    for (const Gpu::Range& range : gpu.ranges) {
        const Gpu::Group& group = gpu.groups[range.group];
        DrawCommand command;
        command.debugName = "polylines";
        command.tags = static_cast<std::uint32_t>(Effect::Polylines);
        command.vertexArray = &gpu.vertexArray;
        command.primitiveType = PrimitiveType::LineStripAdjacency;
        command.first = range.first;
        command.count = range.count;
        command.shaderProgram = gpu.program.get();
        command.uniforms.set("u_depthOffset", depthOffset);
        command.renderState = detail::vectorRenderState(range.pass, false, true);
        command.renderState.primitiveRestart = {true, kRestartIndex};
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
