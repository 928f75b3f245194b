#include "orbis/scene/PolylineCollection.h"

#include "VectorSupport.h"

#include <orbis/core/Geodesic.h>
#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cassert>
#include <cstring>

namespace orbis::scene {

namespace {

constexpr std::size_t kStyleBytes = 16; ///< colour, outline colour (4 bytes each), width, outline width (floats)
/// Where vector.vert.glsl reads "outlineColor" and "widths": fixed, so that the one vertex array
/// serves the program of every depth strategy.
constexpr int kOutlineColorLocation = 6;
constexpr int kWidthsLocation = 7;

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
                double height = (1.0 - t) * points[i].height + t * points[j].height;
                if (_options.groundHeight) {
                    const Geodetic3D g = _ellipsoid.toGeodetic3D(curve[k]);
                    height += _options.groundHeight(Geodetic2D(g.longitude, g.latitude));
                }
                drawn.push_back({curve[k], height});
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
    detail::VectorBatch& batch = *_batch;
    std::vector<detail::VectorItem> items;
    items.reserve(_lines.size());
    for (const Line& line : _lines) {
        items.push_back({line.positions, line.sphere, line.maxHeight});
    }
    batch.build(frameState, items, kStyleBytes,
                [&](std::size_t index, std::vector<std::byte>& out) { writeStyle(_lines[index], out); });
    renderer::VertexArray& vertexArray = batch.vertexArray();
    vertexArray.setAttribute(renderer::VertexAttributeLocation::Color, batch.attributes(),
                             {renderer::ComponentType::UnsignedByte, 4, true, false, kStyleBytes, 0});
    vertexArray.setAttribute(kOutlineColorLocation, batch.attributes(),
                             {renderer::ComponentType::UnsignedByte, 4, true, false, kStyleBytes, 4});
    vertexArray.setAttribute(kWidthsLocation, batch.attributes(), {renderer::ComponentType::Float, 2, false, false, kStyleBytes, 8});
    _geometryDirty = false;
    _styleDirty.clear();
    buildIndices(frameState.device);
}

void PolylineCollection::buildIndices(renderer::Device& device)
{
    // A strip with adjacency per line: the vertex before the first segment and the one after the
    // last; an open end repeats its own vertex (no joint), a loop wraps around.
    _batch->buildIndices(
        device, [&](std::size_t index) { return _lines[index].style.opaque(); },
        [&](std::size_t index, std::uint32_t f, std::vector<std::uint32_t>& indices) {
            const Line& line = _lines[index];
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
            indices.push_back(detail::VectorBatch::kRestartIndex);
        });
    _indicesDirty = false;
}

void PolylineCollection::update(FrameState& frameState, CommandList& commands)
{
    if (_segmentCount == 0) {
        return;
    }
    if (!_batch) {
        _batch = std::make_unique<detail::VectorBatch>(_ellipsoid, detail::VectorShape::Polylines,
                                                       _options.encoding == VertexEncoding::RelativeToEye);
    }
    if (_geometryDirty) {
        build(frameState);
    } else {
        _batch->rewriteAttributes(
            _styleDirty, [&](std::size_t index, std::vector<std::byte>& out) { writeStyle(_lines[index], out); });
        if (_indicesDirty) {
            buildIndices(frameState.device);
        }
    }

    const glm::vec4 depthOffset = detail::depthOffsetUniform(
        _ellipsoid, _options.depthOffset, kLineDepthSteps, kLineDepthFraction,
        detail::triangleSagBound(_ellipsoid, _options.granularityRadians));
    _batch->appendCommands(frameState, depthOffset, commands);
}

} // namespace orbis::scene
