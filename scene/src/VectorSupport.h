#pragma once

// What PolylineCollection and PolygonCollection share: how far straight chords and flat triangles
// between surface points sag below the ellipsoid, the culling groups a collection is drawn in,
// vertex encoding, the depth offset both shaders apply, and the GPU side (VectorBatch). Private.

#include "orbis/scene/FrameState.h"

#include "DepthPrograms.h"

#include <orbis/core/BoundingSphere.h>
#include <orbis/core/Ellipsoid.h>
#include <orbis/renderer/IndexBuffer.h>
#include <orbis/renderer/VertexArray.h>
#include <orbis/renderer/VertexBuffer.h>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

namespace orbis::scene::detail {

/// Angle at the centre between two positions (radians, 0..pi); 0 when either is the centre.
double centralAngle(const glm::dvec3& a, const glm::dvec3& b) noexcept;

/// An upper bound (metres) on how far the straight chord between two surface points `angle`
/// apart at the centre dips below the ellipsoid. On a sphere of radius R the chord's midpoint lies
/// R (1 - cos(angle / 2)) below; on an ellipsoid the curve the chord cuts is most curved where the
/// radius of curvature is smallest, b^2 / a (the meridian at the equator of an oblate one), while
/// the angle maps to an arc of at most a * angle: the sag is at most a (a / b)^2 (1 - cos(angle / 2)).
/// One percent more covers the higher-order terms (the tests sample chords to check it).
double chordSagBound(const Ellipsoid& ellipsoid, double angle) noexcept;

/// The same for a flat triangle whose edges subtend at most `angle`: its deepest point is the foot
/// of the centre's perpendicular, the circumcentre, at most chord / sqrt(3) from the corners for an
/// acute triangle (an obtuse one dips deepest on its longest edge, less), so on a sphere the depth is
/// at most R (1 - sqrt(1 - (4/3) sin^2(angle / 2))); scaled for the ellipsoid as chordSagBound.
double triangleSagBound(const Ellipsoid& ellipsoid, double angle) noexcept;

/// Items (lines, polygons) put into groups by where they lie, so that each group is drawn by
/// one command the scene can cull by its own bounding sphere and horizon occlusion point. A
/// collection smaller than a quarter of the globe's radius is one group; otherwise items fall into
/// 24 cells (a cube around the ellipsoid, each face cut in four) by their centre's direction, and
/// items larger than that (Russia, Antarctica) into six more groups, so that they do not spoil the
/// small items' horizon culling. Groups are returned non-empty, in a fixed order.
std::vector<std::vector<std::uint32_t>> groupByRegion(const Ellipsoid& ellipsoid, std::span<const BoundingSphere> items);

/// A group's culling volume: the sphere about its positions and, when one exists, their horizon
/// occlusion point towards the sphere's centre.
struct GroupBounds {
    BoundingSphere sphere;
    std::optional<glm::dvec3> occlusionPoint;
};
GroupBounds boundsOf(const Ellipsoid& ellipsoid, std::span<const glm::dvec3> positions);

/// Sets a command's nearestDistance and farthestDistance for geometry no higher than maxHeight
/// above the ellipsoid, seen from `eye` (nothing when the eye is not above the ellipsoid): nothing
/// is nearer than the eye's height less maxHeight, and nothing visible is farther than the tangent
/// from the eye to the inscribed sphere (radius b: a sight line through it meets the ellipsoid)
/// continued to the sphere of radius a + maxHeight. Far tighter than a group's sphere, which a
/// low eye is often inside, so low views need fewer frustums.
void boundDepth(SceneCommand& command, const Ellipsoid& ellipsoid, const glm::dvec3& eye, double eyeHeight,
                double maxHeight) noexcept;

/// Appends a position as the vertex shader reads it: positionHigh, positionLow (relative to the
/// eye on the GPU) or a float offset from `centre` (relative to centre).
void appendPosition(std::vector<float>& out, const glm::dvec3& position, bool relativeToEye, const glm::dvec3& centre);

/// A colour as four normalised bytes, red first (what the "color" attributes read).
std::array<std::uint8_t, 4> packColor(const glm::vec4& color) noexcept;

/// u_depthOffset for the vector shaders: x, depth-buffer steps; y, the least offset as a fraction
/// of the distance; z, metres more; w, the ellipsoid's largest radius (for a cap). Zero offsets
/// when not enabled. See shaders/scene/vector/vector.vert.glsl for the technique.
glm::vec4 depthOffsetUniform(const Ellipsoid& ellipsoid, bool enabled, double steps, double fractionOfDistance,
                             double meters) noexcept;

/// The render state of a vector command: depth tested; blended over what is there when asked
/// (always for translucent commands): alpha "over" in both colour and alpha, so an opaque background
/// stays opaque; translucent commands do not write depth.
renderer::RenderState vectorRenderState(Pass pass, bool cullBackFaces, bool blend) noexcept;

/// One item of a vector collection (a line, a polygon) as VectorBatch lays it out.
struct VectorItem {
    std::span<const glm::dvec3> positions; ///< drawn, world metres; empty: the item draws nothing
    BoundingSphere sphere;
    double maxHeight = 0.0; ///< of its drawn positions above the ellipsoid
};

/// What a VectorBatch draws: wide lines (a geometry shader widens line strips with adjacency, with
/// primitive restart between lines) or filled triangles.
enum class VectorShape : std::uint8_t { Polylines, Polygons };

/// The program a VectorBatch draws with under a depth strategy (before its depth defines):
/// shaders/scene/vector with the shape's stages and the encoding's define, and for draped
/// polygons' volumes DRAPED (their vertices moved to the frame's heights). Depth is applied in a
/// geometry shader where there is one (DEPTH_IN_GEOMETRY_SHADER): the polylines' always, and for
/// polygons a pass-through one under LogarithmicVertex, which keeps each triangle's interpolated
/// logarithm from falling behind its true depth (og_depthPrimitiveVertex).
renderer::ShaderProgramDescription vectorProgramDescription(VectorShape shape, bool relativeToEye, bool draped,
                                                            DepthStrategy strategy);

/// Where a draped polygon's vertices find their geodetic normal and side of the volume (0 bottom,
/// 1 top): shaders/scene/vector/vector.vert.glsl's "drape".
inline constexpr int kDrapeLocation = 6;

/// The GPU side PolylineCollection and PolygonCollection share: their items in groups by region
/// (groupByRegion), the items' positions in one vertex buffer laid out group by group (relative to
/// the eye, or to their group's centre), the collection's per-vertex attributes in a second
/// buffer, one index buffer with a range per group and pass, and one command per range, culled by
/// its group's sphere and horizon occlusion point and bounded in depth by its height (boundDepth).
class VectorBatch {
public:
    /// Appends an item's per-vertex attributes, bytesPerVertex for each of its positions.
    using AttributeWriter = std::function<void(std::size_t item, std::vector<std::byte>& out)>;
    /// Appends an item's indices, its vertices numbered from firstVertex.
    using IndexWriter = std::function<void(std::size_t item, std::uint32_t firstVertex, std::vector<std::uint32_t>& out)>;
    /// Finishes the command of an item drawn by itself (buildIndices' rangePerItem): its bounds
    /// and uniforms; false leaves it out of the frame.
    using ItemCommand = std::function<bool(std::size_t item, SceneCommand& command)>;

    /// Index value that separates the lines of a Polylines batch.
    static constexpr std::uint32_t kRestartIndex = 0xFFFFFFFFu;

    /// With `draped`, Polygons batches draw shadow volumes (vectorProgramDescription's DRAPED).
    VectorBatch(const Ellipsoid& ellipsoid, VectorShape shape, bool relativeToEye, bool draped = false);

    /// Groups the items that have positions, uploads their positions and attributes (a new vertex
    /// array reads the positions; attach the attributes from attributes()), and forgets the
    /// indices: call buildIndices next.
    void build(FrameState& frameState, std::span<const VectorItem> items, std::size_t bytesPerVertex,
               const AttributeWriter& writeAttributes);
    /// Rewrites the attributes of the items listed (repeats allowed; items without positions are
    /// skipped) where they lie in the buffer, then empties the list.
    void rewriteAttributes(std::vector<std::size_t>& items, const AttributeWriter& writeAttributes);
    /// Rebuilds the index buffer: in each group the opaque items (`opaque`), then the others, each
    /// range drawn in its pass; with rangePerItem, each item a range of its own.
    void buildIndices(renderer::Device& device, const std::function<bool(std::size_t item)>& opaque,
                      const IndexWriter& writeIndices, bool rangePerItem = false);
    /// Appends one command per range, tagged with the shape's effect, drawn with the program for
    /// the frame's depth strategy and the range's pass, u_depthOffset set (depthOffsetUniform);
    /// a range of one item's (rangePerItem) goes through finishItem when given.
    void appendCommands(FrameState& frameState, const glm::vec4& depthOffset, CommandList& commands,
                        const ItemCommand& finishItem = {});

    renderer::VertexArray& vertexArray() noexcept { return _vertexArray; }
    const renderer::VertexBuffer& attributes() const noexcept { return _attributes; }

private:
    struct Group {
        GroupBounds bounds;
        double maxHeight = 0.0;
        std::vector<std::size_t> items;
    };
    static constexpr std::size_t kNotDrawn = static_cast<std::size_t>(-1);
    struct Range {
        std::size_t group = 0;
        Pass pass = Pass::Opaque;
        std::size_t first = 0;
        std::size_t count = 0;
        std::size_t item = kNotDrawn; ///< the one item it draws (rangePerItem)
    };

    Ellipsoid _ellipsoid;
    VectorShape _shape;
    bool _relativeToEye;
    DepthPrograms _programs;
    std::size_t _bytesPerVertex = 0;
    std::vector<Group> _groups;
    std::vector<Range> _ranges;
    std::vector<std::size_t> _firstVertex; ///< by item; kNotDrawn for items without positions
    std::vector<std::size_t> _vertexCount; ///< by item
    renderer::VertexBuffer _positions;
    renderer::VertexBuffer _attributes;
    renderer::IndexBuffer _indices;
    renderer::VertexArray _vertexArray;
};

} // namespace orbis::scene::detail
