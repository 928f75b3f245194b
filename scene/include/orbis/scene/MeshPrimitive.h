#pragma once

#include "orbis/scene/FrameState.h"

#include <orbis/core/Mesh.h>
#include <orbis/renderer/VertexArray.h>

#include <glm/vec4.hpp>

#include <memory>
#include <optional>

namespace orbis {

class ShaderProgram;

/// A core Mesh with world positions, drawn relative to its bounding sphere's centre in one
/// colour: opaque, or translucent (blended, drawn after the opaque commands of each frustum).
/// Lit by the Sun when the mesh has normals. Markers, satellites, test objects.
class MeshPrimitive final : public Primitive {
public:
    /// The mesh must have triangles and at least one position (asserted).
    MeshPrimitive(Mesh mesh, const glm::vec4& color, Pass pass = Pass::Opaque);
    ~MeshPrimitive() override;

    std::optional<BoundingSphere> boundingSphere() const override { return _boundingSphere; }
    void update(FrameState& frameState, CommandList& commands) override;

    void setColor(const glm::vec4& color) noexcept { _color = color; }
    /// The horizon occlusion point (ellipsoid-scaled) of the mesh, so the scene culls it when it is
    /// wholly below the horizon; none (the default): never horizon-culled.
    void setHorizonOcclusionPoint(const std::optional<glm::dvec3>& point) noexcept { _occlusionPoint = point; }

private:
    Mesh _mesh; ///< positions relative to the centre; released once uploaded
    BoundingSphere _boundingSphere;
    glm::vec4 _color;
    Pass _pass;
    bool _lit;
    std::optional<glm::dvec3> _occlusionPoint;
    std::shared_ptr<ShaderProgram> _program;
    std::optional<VertexArray> _vertexArray;
};

} // namespace orbis
