#pragma once

#include "orbis/scene/FrameState.h"

#include <orbis/core/CurveType.h>
#include <orbis/core/Ellipsoid.h>
#include <orbis/core/Math.h>

#include <glm/vec4.hpp>

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace orbis {
class Geodesic;
} // namespace orbis

namespace orbis::scene {

namespace detail {
class VectorBatch;
} // namespace detail

/// How a vector collection's positions reach the GPU (docs/precision.md).
enum class VertexEncoding {
    /// positionHigh and positionLow, subtracted from the eye's on the GPU (book section 5.4):
    /// millimetres anywhere, 24 bytes a vertex.
    RelativeToEye,
    /// Float offsets from the centre of each culling group, which the model matrix carries (book
    /// section 5.2): 12 bytes a vertex, precise to about 1e-7 of the group's size (a fraction of a
    /// metre for a continent, millimetres for a city).
    RelativeToCenter,
};

/// How one polyline looks. Widths are in pixels, whatever the distance.
struct PolylineStyle {
    glm::vec4 color{1.0f};
    float widthPixels = 2.0f;
    glm::vec4 outlineColor{0.0f, 0.0f, 0.0f, 1.0f};
    float outlineWidthPixels = 0.0f; ///< on each side of the line; 0: no outline
    bool show = true;

    /// True when the line and (where it has one) its outline are opaque.
    bool opaque() const noexcept { return color.a >= 1.0f && (outlineWidthPixels <= 0.0f || outlineColor.a >= 1.0f); }
};

struct PolylineCollectionOptions {
    /// Largest angle at the centre between consecutive drawn vertices: the path between two
    /// positions is cut into pieces no longer than this (clamped to at least 1e-6).
    double granularityRadians = toRadians(1.0);
    CurveType curve = CurveType::PlaneSection;
    VertexEncoding encoding = VertexEncoding::RelativeToEye;
    /// The z-fighting technique of shaders/scene/vector/vector.vert.glsl. Off only to show what it
    /// prevents.
    bool depthOffset = true;
    /// Where set, the ground's height (metres) at a point of the surface: every drawn vertex of
    /// the curve is lifted by it, so that heights given are above the terrain (a height
    /// reference relative to the ground; heights of 0 clamp the line to it).
    std::function<double(const Geodetic2D&)> groundHeight;
};

/// Polylines on (or above) the ellipsoid, book chapter 7: many lines in one vertex buffer, each
/// with its own colour, width in pixels and optional outline, widened by a geometry shader with
/// mitred joins and anti-aliased edges.
///
/// Each line follows the ellipsoid between its positions (CurveType) at the granularity, and is
/// lifted along the surface normal by how far its straight segments would otherwise dip (at most
/// about a (a / b)^2 (1 - cos(g / 2)) for granularity g: 243 m at 1 degree, 2.4 m at 0.1), so no
/// segment cuts under the surface. Consecutive positions are joined the short way round: a segment
/// from 179 E to 179 W spans 2 degrees across the antimeridian. Positions keep their heights above
/// the ellipsoid. Drawn after the globe without fighting it (see the depth offset in
/// shaders/scene/vector/vector.vert.glsl), and in front of polygons of the same or finer
/// granularity, so add them after those.
///
/// Lines are drawn in groups by region (one command per group and pass, each with its bounding
/// sphere and horizon occlusion point, so the scene culls the far side of the globe): one draw for
/// a small collection, at most 60 for one that covers the world. Lines with any transparency are
/// drawn in the translucent pass. Nothing is allocated on the GPU before the first update();
/// setStyle() later rewrites only that line's vertices; add() after the first update rebuilds the
/// buffers at the next one.
///
/// ```
/// auto lines = std::make_shared<PolylineCollection>(Ellipsoid::wgs84());
/// const Geodetic3D route[] = {Geodetic3D::fromDegrees(179, -16), Geodetic3D::fromDegrees(-179, -17)};
/// lines->add(route, {.color = {1, 1, 0, 1}, .widthPixels = 3});
/// scene.add(lines);
/// ```
class PolylineCollection final : public Primitive {
public:
    /// A Geodesic curve needs an ellipsoid of revolution (asserted).
    explicit PolylineCollection(const Ellipsoid& ellipsoid, const PolylineCollectionOptions& options = {});
    ~PolylineCollection() override;
    PolylineCollection(const PolylineCollection&) = delete;
    PolylineCollection& operator=(const PolylineCollection&) = delete;

    const Ellipsoid& ellipsoid() const noexcept { return _ellipsoid; }
    const PolylineCollectionOptions& options() const noexcept { return _options; }

    /// Adds a line through world positions (metres) and returns its index. Consecutive duplicates
    /// are dropped; `loop` closes the line back to its first position (a last position equal to the
    /// first is dropped). A line left with fewer than two positions draws nothing but keeps its
    /// index. Non-finite positions are dropped.
    std::size_t add(std::span<const glm::dvec3> positions, const PolylineStyle& style = {}, bool loop = false);
    /// The same for geodetic positions (radians, metres).
    std::size_t add(std::span<const Geodetic3D> positions, const PolylineStyle& style = {}, bool loop = false);

    std::size_t size() const noexcept;
    bool empty() const noexcept { return size() == 0; }

    /// The style of line `index` (< size(), asserted).
    const PolylineStyle& style(std::size_t index) const;
    /// Changes a line's style; the next update rewrites only that line's vertices (and regroups the
    /// commands when the line becomes translucent or opaque).
    void setStyle(std::size_t index, const PolylineStyle& style);

    /// The positions drawn for line `index`: the curve between its positions at the granularity,
    /// lifted above the surface, world metres; a loop does not repeat its first position.
    std::span<const glm::dvec3> positions(std::size_t index) const;
    /// True when line `index` closes back to its first position (asked for, with three positions or more).
    bool isLoop(std::size_t index) const;
    /// How far line `index` is lifted along the surface normal above the heights given (metres).
    double liftMeters(std::size_t index) const;

    std::size_t vertexCount() const noexcept { return _vertexCount; }
    std::size_t segmentCount() const noexcept { return _segmentCount; }

    /// The sphere around every drawn position; none for an empty collection.
    std::optional<BoundingSphere> boundingSphere() const override { return _boundingSphere; }
    void update(FrameState& frameState, CommandList& commands) override;
    /// Its lines write every DepthStrategy's depth, with their depth offset scaled to it.
    bool supportsLogarithmicDepth() const override { return true; }

private:
    struct Line;
    void build(FrameState& frameState);
    void buildIndices(renderer::Device& device);
    void writeStyle(const Line& line, std::vector<std::byte>& out) const;

    Ellipsoid _ellipsoid;
    PolylineCollectionOptions _options;
    std::vector<Line> _lines;
    std::size_t _vertexCount = 0;
    std::size_t _segmentCount = 0;
    std::optional<BoundingSphere> _boundingSphere;
    std::unique_ptr<const Geodesic> _geodesic; ///< CurveType::Geodesic only
    std::unique_ptr<detail::VectorBatch> _batch;
    bool _geometryDirty = true;
    bool _indicesDirty = true;
    std::vector<std::size_t> _styleDirty; ///< lines whose style changed since the last upload
};

} // namespace orbis::scene
