#pragma once

#include "orbis/scene/FrameState.h"

#include <orbis/core/Geodetic.h>
#include <orbis/core/HeadingPitchRoll.h>
#include <orbis/renderer/Sampler.h>
#include <orbis/renderer/Texture2D.h>
#include <orbis/renderer/VertexArray.h>
#include <orbis/world/GltfModel.h>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

namespace orbis::renderer {
class ShaderProgram;
} // namespace orbis::renderer

namespace orbis::scene {

/// Where a model stands on the ellipsoid and which way it faces.
struct ModelPlacement {
    Geodetic3D position;          ///< radians, metres: where the model's origin goes
    HeadingPitchRoll orientation; ///< radians: heading clockwise from north, pitch nose up, roll right wing down
    double scale = 1.0;           ///< > 0, multiplies the model's metres

    friend bool operator==(const ModelPlacement&, const ModelPlacement&) = default;
};

/// How a model is drawn, beyond what its file and placement say.
struct ModelOptions {
    /// Lit by the Sun (og_sunDirectionEye): base colour x (0.3 + 0.7 x the cosine to the Sun).
    /// false, the default (as for globes, and as in a scene file that places no Sun): the base
    /// colours as they are, and no lighting computed (no "lighting" effect).
    bool lighting = false;
};

/// glTF's axes to the local east-north-up axes a model starts from before heading, pitch and roll
/// turn it: glTF +y (up) to up, +z (the asset's front) to north, +x (the asset's left) to west.
/// A rotation (determinant +1): x_enu = -x, y_enu = z, z_enu = y.
glm::dmat3 gltfToEastNorthUp() noexcept;

/// Model (glTF) coordinates to Earth-fixed ones: the east-north-up frame at the position (up the
/// geodetic normal), turned by heading, pitch and roll (as headingPitchRollToView turns a view:
/// the front is the view direction, up the view's up), times scale, times gltfToEastNorthUp().
glm::dmat4 modelToFixedFrame(const Ellipsoid& ellipsoid, const ModelPlacement& placement) noexcept;

/// A glTF 2.0 model placed on the globe (book section 5.2 for the precision): one draw command
/// per material (tagged Effect::Models, and Effect::Lighting when lit), lit by the Sun like
/// MeshPrimitive unless the options say not, drawn relative to the model's origin. The GPU
/// gets float positions in the model's own frame; the model matrix (placement, in double) carries
/// the Earth-scale translation, and the model-view-projection product is formed on the CPU in
/// double. Base colours (factor times texture, sRGB textures decoded to linear) are lit in linear
/// space and written sRGB-encoded. Materials with alphaMode BLEND draw in the translucent pass.
///
/// Loading: geometry is read when the primitive is made (the bounding sphere and the errors need
/// it); images are read but stay encoded. Nothing reaches the GPU, and no image is decoded, before
/// the first update(), so a model that is always culled costs no GPU memory; after the upload the
/// CPU copies of the geometry and the images are released.
///
/// ```
/// ModelPlacement placement{Geodetic3D::fromDegrees(2.35, 48.86, 500.0), {toRadians(90.0), 0.0, 0.0}, 1.0};
/// scene.add(ModelPrimitive::fromFile("data/models/aircraft.glb", scene.ellipsoid(), placement));
/// ```
class ModelPrimitive final : public Primitive {
public:
    /// The model must have at least one triangle (GltfModel::read ensures it; asserted).
    ModelPrimitive(world::GltfModel model, const Ellipsoid& ellipsoid, const ModelPlacement& placement,
                   const ModelOptions& options = {});
    ~ModelPrimitive() override;

    /// Reads a .gltf or .glb file (GltfModel::read, whose orbis::Error it passes on).
    static std::shared_ptr<ModelPrimitive> fromFile(const std::filesystem::path& file, const Ellipsoid& ellipsoid,
                                                    const ModelPlacement& placement, const ModelOptions& options = {});

    const ModelPlacement& placement() const noexcept { return _placement; }
    const ModelOptions& options() const noexcept { return _options; }
    /// Moves or turns the model; no GPU work (the bounding spheres follow).
    void setPlacement(const ModelPlacement& placement) noexcept;
    /// modelToFixedFrame of the placement.
    const glm::dmat4& modelMatrix() const noexcept { return _modelMatrix; }

    /// Holds every vertex: the sphere around the model's vertices (node transforms applied) in its
    /// own frame, carried by the model matrix (a rotation, a uniform scale and a translation).
    std::optional<BoundingSphere> boundingSphere() const override { return _boundingSphere; }
    /// The horizon occlusion point of the model's bounding box corners, ellipsoid-scaled; empty
    /// when there is none (a model reaching round a quarter of the Earth).
    const std::optional<glm::dvec3>& horizonOcclusionPoint() const noexcept { return _occlusionPoint; }

    void update(FrameState& frameState, CommandList& commands) override;
    /// Its materials write every DepthStrategy's depth.
    bool supportsLogarithmicDepth() const override { return true; }

    /// True once the first update() has made the buffers, textures and programs.
    bool resourcesCreated() const noexcept { return _resourcesCreated; }
    /// Draw commands per frame: one per material used.
    std::size_t batchCount() const noexcept;
    std::size_t triangleCount() const noexcept { return _triangleCount; }

private:
    struct Batch;
    void createResources(FrameState& frameState);

    Ellipsoid _ellipsoid;
    ModelPlacement _placement;
    ModelOptions _options;
    glm::dmat4 _modelMatrix{1.0};
    world::GltfModel _model; ///< geometry and encoded images released once uploaded; materials kept
    std::vector<Batch> _batches;
    BoundingSphere _localSphere; ///< model frame
    glm::dvec3 _localMinimum{0.0};
    glm::dvec3 _localMaximum{0.0};
    BoundingSphere _boundingSphere;
    std::optional<glm::dvec3> _occlusionPoint;
    std::size_t _triangleCount = 0;
    bool _resourcesCreated = false;
    std::vector<renderer::Texture2D> _textures; ///< per GltfModel image
    std::vector<renderer::Sampler> _samplers;   ///< per GltfModel texture
};

} // namespace orbis::scene
