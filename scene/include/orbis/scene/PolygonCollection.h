#pragma once

#include "orbis/scene/PolylineCollection.h"

#include <orbis/core/EarClipping.h>
#include <orbis/core/Mesh.h>
#include <orbis/world/Feature.h>

#include <functional>
#include <string>
#include <string_view>

namespace orbis::scene {

struct PolygonCollectionOptions {
    /// Largest angle at the centre subtended by a triangle's edge (triangulatePolygon's
    /// subdivision), clamped to at least 1e-6.
    double granularityRadians = toRadians(1.0);
    VertexEncoding encoding = VertexEncoding::RelativeToEye;
    /// The z-fighting technique of shaders/scene/vector/vector.vert.glsl. Off only to show what it
    /// prevents.
    bool depthOffset = true;
    /// Draped over the ground the scene draws (docs/terrain.md, "Draped polygons"): each polygon is
    /// a closed shadow volume over its triangles on the ellipsoid, which each frame reaches from
    /// below to above the ground drawn under it (FrameState::groundHeights; the top raised further
    /// by what the volume's own flat triangles sag), and colours the pixels of that ground inside
    /// it by a z-fail stencil count: two draws a polygon, in Pass::Draped, so the frame needs a
    /// stencil buffer. A polygon with no ground drawn under it is not drawn; depthOffset does not
    /// apply.
    bool draped = false;
    /// When set (and not draped), the fills stand on the ground: each drawn vertex lifted by the
    /// ground's height under it (metres above the ellipsoid) and by its polygon's height above
    /// the ground there (a GeoJSON polygon's positions' heights, linear over the triangles of its
    /// ear clipping; 0 for the other add), then as on the ellipsoid. Polygons are subdivided to
    /// the granularity (give the terrain's sample spacing), but no finer than 1/512 of their width.
    std::function<double(const Geodetic2D&)> groundHeight;
};

/// Filled polygons on the ellipsoid, book chapter 8: each polygon (an outer ring and holes) is ear
/// clipped on the ellipsoid and subdivided to the granularity (core triangulatePolygon: any polygon
/// smaller than a hemisphere, across the antimeridian or around a pole), and all of them share one
/// mesh with a colour per polygon. Polygons with alpha below 1 are drawn in the translucent pass.
///
/// Each polygon is lifted along the surface normal by how far its flat triangles would otherwise
/// dip below the ellipsoid (about a (a / b)^2 g^2 / 6 for granularity g: 324 m at 1 degree), so
/// the globe never shows through; drawn after the globe without fighting it (see
/// shaders/scene/vector/vector.vert.glsl). Triangulation happens in add(), so bad polygons throw
/// there; nothing is allocated on the GPU before the first update(); setColor() later rewrites only
/// that polygon's vertices. Drawn in groups by region like PolylineCollection; draped polygons
/// (PolygonCollectionOptions::draped) instead each by itself, lying on the terrain.
///
/// ```
/// auto fills = std::make_shared<PolygonCollection>(Ellipsoid::wgs84());
/// if (const Polygon* polygon = std::get_if<Polygon>(&feature.geometry->value)) {
///     fills->add(*polygon, {1, 0.5f, 0, 0.6f}, "Chad"); // translucent orange
/// }
/// scene.add(fills);
/// ```
class PolygonCollection final : public Primitive {
public:
    explicit PolygonCollection(const Ellipsoid& ellipsoid, const PolygonCollectionOptions& options = {});
    ~PolygonCollection() override;
    PolygonCollection(const PolygonCollection&) = delete;
    PolygonCollection& operator=(const PolygonCollection&) = delete;

    const Ellipsoid& ellipsoid() const noexcept { return _ellipsoid; }
    const PolygonCollectionOptions& options() const noexcept { return _options; }

    /// Adds a polygon: rings[0] the outer boundary, the others holes, world positions (moved to the
    /// surface), edges along plane sections through the centre, either winding. Returns its index.
    /// A polygon with no area keeps its index and draws nothing. Throws orbis::Error naming `name`
    /// for what triangulatePolygon rejects (self-crossing rings, a ring cutting the ellipsoid in
    /// halves, non-finite positions). With leftOutHoles given, faulty holes are left out and listed
    /// there instead (triangulatePolygon's leftOutHoles).
    std::size_t add(std::span<const std::vector<glm::dvec3>> rings, const glm::vec4& color,
                    std::string_view name = "polygon", std::vector<LeftOutHole>* leftOutHoles = nullptr);
    /// The same for a GeoJSON polygon (radians; heights ignored, but for PolygonCollectionOptions::
    /// groundHeight).
    std::size_t add(const world::Polygon& polygon, const glm::vec4& color, std::string_view name = "polygon",
                    std::vector<LeftOutHole>* leftOutHoles = nullptr);

    std::size_t size() const noexcept;
    bool empty() const noexcept { return size() == 0; }

    /// The colour of polygon `index` (< size(), asserted).
    const glm::vec4& color(std::size_t index) const;
    /// Changes a polygon's colour; the next update rewrites only its vertices (and regroups the
    /// commands when it becomes translucent or opaque).
    void setColor(std::size_t index, const glm::vec4& color);

    /// The triangles drawn for polygon `index`: world positions lifted above the surface, indices
    /// counter-clockwise seen from outside. Draped: its closed volume with its surface triangles'
    /// vertices on the ellipsoid twice, first as its bottom's and then as its top's (the vertex
    /// shader moves them to drapedHeights).
    const Mesh& mesh(std::size_t index) const;
    /// The heights of a draped polygon's bottom and top in the last frame, from the ground drawn
    /// under it; empty when it was not drawn, and for polygons that are not draped.
    std::optional<HeightInterval> drapedHeights(std::size_t index) const;
    /// The extent a draped polygon asks the ground's heights over (its triangles on the surface).
    const GeodeticExtent& footprint(std::size_t index) const;
    /// How far polygon `index` is lifted along the surface normal (metres), above the ground and
    /// its height there with PolygonCollectionOptions::groundHeight; 0 when draped.
    double liftMeters(std::size_t index) const;
    bool draped() const noexcept { return _options.draped; }

    std::size_t vertexCount() const noexcept { return _vertexCount; }
    std::size_t triangleCount() const noexcept { return _triangleCount; }

    /// The sphere around every drawn position; none while no polygon has triangles, and when
    /// draped (its heights come with each frame's ground: each polygon is culled by itself).
    std::optional<BoundingSphere> boundingSphere() const override { return draped() ? std::nullopt : _boundingSphere; }
    void update(FrameState& frameState, CommandList& commands) override;
    /// Its fills write every DepthStrategy's depth, with their depth offset scaled to it (draped
    /// ones test against it).
    bool supportsLogarithmicDepth() const override { return true; }

private:
    struct Item;
    /// The rings' heights (one per position, ring by ring; none: 0) count with groundHeight only.
    std::size_t add(std::span<const std::vector<glm::dvec3>> rings, std::span<const std::vector<double>> heights,
                    const glm::vec4& color, std::string_view name, std::vector<LeftOutHole>* leftOutHoles);
    std::size_t addMesh(Mesh mesh, const glm::vec4& color, std::span<const double> heightsAboveGround);
    double groundGranularity(const Mesh& clipped) const;
    void build(FrameState& frameState);
    void buildIndices(renderer::Device& device);
    void writeAttributes(std::size_t index, std::vector<std::byte>& out) const;
    bool finishDrapedCommand(const FrameState& frameState, double eyeHeight, std::size_t index, SceneCommand& command);

    Ellipsoid _ellipsoid;
    PolygonCollectionOptions _options;
    std::vector<Item> _polygons;
    std::size_t _vertexCount = 0;
    std::size_t _triangleCount = 0;
    std::optional<BoundingSphere> _boundingSphere;
    std::unique_ptr<detail::VectorBatch> _batch;
    bool _geometryDirty = true;
    bool _indicesDirty = true;
    std::vector<std::size_t> _colorDirty;
};

} // namespace orbis::scene
