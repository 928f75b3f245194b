#pragma once

#include "orbis/scene/FrameState.h"

#include <orbis/core/Tessellation.h>
#include <orbis/renderer/Sampler.h>
#include <orbis/renderer/Texture2D.h>
#include <orbis/renderer/VertexArray.h>
#include <orbis/world/GlobeMethod.h>

#include <glm/vec4.hpp>

#include <array>
#include <filesystem>
#include <memory>
#include <optional>

namespace orbis::renderer {
class ShaderProgram;
} // namespace orbis::renderer

namespace orbis::scene {

/// Named in scene files, hence the world layer's: scene::GlobeMethod is world::GlobeMethod.
using world::GlobeMethod;

/// Which core tessellator a Tessellated globe uses, and what its level means.
enum class GlobeTessellation {
    SubdivisionEllipsoid, ///< level = octahedron subdivisions (8 x 4^level triangles)
    CubeMap,              ///< level = cells along a cube face's edge (12 x level^2 triangles)
    GeographicGrid,       ///< level = stacks, with twice as many slices
};

struct GlobeOptions {
    GlobeMethod method = GlobeMethod::RayCast;
    /// An image file or a TMS folder (equirectangular, north up); empty: the plain colour.
    std::filesystem::path dayTexture;
    /// City lights shown on the night side; empty: none (and no night-lights shader variant).
    std::filesystem::path nightTexture;
    /// Lit by the scene's Sun (Scene::setSunDirection). Off by default, as in a scene file that
    /// places no Sun and as CesiumJS's globe: the colours as they are, no lighting computed (no
    /// "lighting" effect in the statistics).
    bool lighting = false;
    bool grid = false;                   ///< latitude-longitude lines, spaced by the viewer's distance
    glm::vec4 color{0.2f, 0.35f, 0.6f, 1.0f};
    glm::vec4 gridColor{1.0f, 1.0f, 1.0f, 0.7f};
    GlobeTessellation tessellation = GlobeTessellation::CubeMap; ///< Tessellated only
    int tessellationLevel = 64;
};

/// The Earth (or any ellipsoid) of book chapter 4: ray-cast or tessellated, textured, lit by the
/// Sun with night lights across the terminator, and an optional graticule. One draw command per
/// frame. Resources (program variant, geometry, textures) are created on the first update.
class Globe final : public Primitive {
public:
    explicit Globe(const Ellipsoid& ellipsoid, GlobeOptions options = {});
    ~Globe() override;

    const GlobeOptions& options() const noexcept { return _options; }

    std::optional<BoundingSphere> boundingSphere() const override;
    void update(FrameState& frameState, CommandList& commands) override;
    /// Both methods write every DepthStrategy's depth (the ray caster computes it per fragment).
    bool supportsLogarithmicDepth() const override { return true; }

    /// The mesh a Tessellated globe draws (with its deviation from the ellipsoid when measured).
    static TessellationResult tessellate(const Ellipsoid& ellipsoid, GlobeTessellation tessellation, int level,
                                         Deviation deviation = Deviation::Skip);

    /// The graticule spacing (radians) given the size of a pixel on the ground below the eye: the
    /// finest of 0.1, 0.25, 0.5, 1, 2, 5, 10, 15, 30 degrees whose lines stay at least 60 pixels apart.
    static double gridSpacing(double metersPerPixelOnGround, double radius) noexcept;

private:
    void createResources(FrameState& frameState);
    /// The program variant for the frame's depth strategy, compiled on first use.
    renderer::ShaderProgram& program(FrameState& frameState);

    Ellipsoid _ellipsoid;
    GlobeOptions _options;
    std::array<std::shared_ptr<renderer::ShaderProgram>, 6> _programs; ///< by DepthStrategy
    std::optional<renderer::VertexArray> _vertexArray;
    std::optional<renderer::Texture2D> _dayTexture;
    std::optional<renderer::Texture2D> _nightTexture;
    std::optional<renderer::Sampler> _sampler;
};

} // namespace orbis::scene
