#pragma once

#include "orbis/scene/FrameState.h"
#include "orbis/scene/VertexTransform.h"

#include <orbis/core/Mesh.h>

#include <glm/vec4.hpp>

#include <array>
#include <memory>
#include <optional>

namespace orbis::renderer {
class ShaderProgram;
struct DeviceInfo;
} // namespace orbis::renderer

namespace orbis::scene {

/// A core Mesh with world positions in one colour: opaque, or translucent (blended, drawn after
/// the opaque commands of each frustum). Lit by the Sun when the mesh has normals. Its vertices
/// reach the GPU by the chosen VertexTransform (book chapter 5; relative to its bounding sphere's
/// centre by default) and it writes every DepthStrategy's depth. Markers, satellites, test objects.
class MeshPrimitive final : public Primitive {
public:
    /// The mesh must have triangles (or points, for measurements) and at least one position
    /// (asserted).
    MeshPrimitive(Mesh mesh, const glm::vec4& color, Pass pass = Pass::Opaque,
                  VertexTransform transform = VertexTransform::RelativeToCenter);
    ~MeshPrimitive() override;

    std::optional<BoundingSphere> boundingSphere() const override { return _boundingSphere; }
    void update(FrameState& frameState, CommandList& commands) override;
    bool supportsLogarithmicDepth() const override { return true; }

    void setColor(const glm::vec4& color) noexcept { _color = color; }
    /// The horizon occlusion point (ellipsoid-scaled) of the mesh, so the scene culls it when it is
    /// wholly below the horizon; none (the default): never horizon-culled.
    void setHorizonOcclusionPoint(const std::optional<glm::dvec3>& point) noexcept { _occlusionPoint = point; }

    VertexTransform vertexTransform() const noexcept { return _transform; }
    /// The concrete transform the last update() drew with (Automatic's choice that frame).
    VertexTransform lastVertexTransform() const noexcept { return _lastTransform; }
    /// Floats the CPU rewrote relative to the eye so far (RelativeToEyeCpu's per-frame cost).
    std::uint64_t floatsRewritten() const noexcept { return _arrays->floatsRewritten(); }

    /// The program a MeshPrimitive draws with under a concrete transform and a resolved depth
    /// strategy: shaders/scene/mesh with the built-in library's defines.
    static renderer::ShaderProgramDescription programDescription(VertexTransform transform, DepthStrategy depth, Pass pass,
                                                       bool lit, const renderer::DeviceInfo& device);

private:
    BoundingSphere _boundingSphere;
    glm::vec4 _color;
    Pass _pass;
    bool _lit;
    PrimitiveType _primitiveType;
    VertexTransform _transform;
    VertexTransform _lastTransform;
    std::optional<glm::dvec3> _occlusionPoint;
    std::unique_ptr<VertexTransformArrays> _arrays;
    /// By concrete transform, then by depth strategy: each variant compiled on first use.
    std::array<std::array<std::shared_ptr<renderer::ShaderProgram>, 6>, 5> _programs;
};

} // namespace orbis::scene
