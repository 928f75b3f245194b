#include "orbis/scene/ModelPrimitive.h"

#include "orbis/scene/Effect.h"

#include "DepthPrograms.h"

#include <orbis/core/EllipsoidalOccluder.h>
#include <orbis/core/Transforms.h>
#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>

#include <glm/geometric.hpp>

#include <array>
#include <cassert>
#include <cmath>

namespace orbis::scene {

namespace {

/// An RGB image with an opaque alpha channel added; a 4-channel one as it is.
Image withAlpha(Image image)
{
    if (image.channels == 4) {
        return image;
    }
    Image rgba(image.width, image.height, 4);
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const std::uint8_t* from = image.pixel(x, y);
            std::uint8_t* to = rgba.pixel(x, y);
            for (int c = 0; c < 4; ++c) {
                to[c] = c < image.channels ? from[c] : 255;
            }
            if (image.channels == 1 || image.channels == 2) {
                to[1] = to[2] = from[0]; // grey
                to[3] = image.channels == 2 ? from[1] : 255;
            }
        }
    }
    return rgba;
}

} // namespace

struct ModelPrimitive::Batch {
    Mesh mesh; ///< released once uploaded
    std::size_t material = 0;
    BoundingSphere localSphere;
    BoundingSphere sphere; ///< world
    Pass pass = Pass::Opaque;
    std::optional<detail::DepthPrograms> programs; ///< made with the other resources
    std::optional<renderer::VertexArray> vertexArray;
};

glm::dmat3 gltfToEastNorthUp() noexcept
{
    // Columns: where glTF's +x, +y and +z go in east-north-up coordinates.
    return {glm::dvec3(-1.0, 0.0, 0.0), glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(0.0, 1.0, 0.0)};
}

glm::dmat4 modelToFixedFrame(const Ellipsoid& ellipsoid, const ModelPlacement& placement) noexcept
{
    const glm::dvec3 origin = ellipsoid.toCartesian(placement.position);
    const HeadingPitchRoll& orientation = placement.orientation;
    // The front, up and right of the turned model, Earth-fixed: the same turn a view takes.
    const ViewOrientation view =
        headingPitchRollToView(ellipsoid, origin, orientation.heading, orientation.pitch, orientation.roll);
    const glm::dvec3 right = glm::cross(view.direction, view.up);
    // East-north-up axes turned: local +x (east at heading 0) is the right, +y the front, +z up.
    const glm::dmat3 turned(right, view.direction, view.up);
    glm::dmat4 matrix(turned * (placement.scale * gltfToEastNorthUp()));
    matrix[3] = glm::dvec4(origin, 1.0);
    return matrix;
}

ModelPrimitive::ModelPrimitive(world::GltfModel model, const Ellipsoid& ellipsoid, const ModelPlacement& placement,
                               const ModelOptions& options)
    : _ellipsoid(ellipsoid)
    , _options(options)
    , _model(std::move(model))
{
    std::vector<glm::dvec3> all;
    for (world::GltfBatch& batch : _model.batches) {
        Batch out;
        out.material = batch.material;
        out.localSphere = BoundingSphere::fromPoints(batch.mesh.positions);
        out.pass = _model.materials[batch.material].alphaMode == world::AlphaMode::Blend ? Pass::Translucent : Pass::Opaque;
        _triangleCount += batch.mesh.triangleCount();
        all.insert(all.end(), batch.mesh.positions.begin(), batch.mesh.positions.end());
        out.mesh = std::move(batch.mesh);
        _batches.push_back(std::move(out));
    }
    _model.batches.clear();
    assert(_triangleCount > 0);
    _localSphere = BoundingSphere::fromPoints(all);
    if (!all.empty()) {
        _localMinimum = _localMaximum = all.front();
        for (const glm::dvec3& p : all) {
            _localMinimum = glm::min(_localMinimum, p);
            _localMaximum = glm::max(_localMaximum, p);
        }
    }
    setPlacement(placement);
}

ModelPrimitive::~ModelPrimitive() = default;

std::shared_ptr<ModelPrimitive> ModelPrimitive::fromFile(const std::filesystem::path& file, const Ellipsoid& ellipsoid,
                                                         const ModelPlacement& placement, const ModelOptions& options)
{
    return std::make_shared<ModelPrimitive>(world::GltfModel::read(file), ellipsoid, placement, options);
}

std::size_t ModelPrimitive::batchCount() const noexcept
{
    return _batches.size();
}

void ModelPrimitive::setPlacement(const ModelPlacement& placement) noexcept
{
    assert(placement.scale > 0.0 && std::isfinite(placement.scale));
    _placement = placement;
    _modelMatrix = modelToFixedFrame(_ellipsoid, placement);
    // The model matrix is a similarity (rotation, uniform scale, translation): a sphere stays a
    // sphere, its radius scaled. A millimetre more covers the rounding of the Earth-scale centre.
    auto toWorld = [&](const BoundingSphere& local) {
        return BoundingSphere{glm::dvec3(_modelMatrix * glm::dvec4(local.centre, 1.0)),
                              local.radius * placement.scale + 1e-3};
    };
    _boundingSphere = toWorld(_localSphere);
    for (Batch& batch : _batches) {
        batch.sphere = toWorld(batch.localSphere);
    }
    std::array<glm::dvec3, 8> corners;
    for (std::size_t i = 0; i < corners.size(); ++i) {
        const glm::dvec3 local(i & 1 ? _localMaximum.x : _localMinimum.x, i & 2 ? _localMaximum.y : _localMinimum.y,
                               i & 4 ? _localMaximum.z : _localMinimum.z);
        corners[i] = glm::dvec3(_modelMatrix * glm::dvec4(local, 1.0));
    }
    _occlusionPoint =
        EllipsoidalOccluder(_ellipsoid, glm::dvec3(0.0)).horizonOcclusionPoint(_boundingSphere.centre, corners);
}

void ModelPrimitive::createResources(FrameState& frameState)
{
    // Everything is made before anything is released, so that an error (an image that does not
    // decode, a texture too large for the device) leaves the primitive as it was, to try again.
    renderer::Device& device = frameState.device;
    std::vector<renderer::Texture2D> textures;
    for (std::size_t i = 0; i < _model.images.size(); ++i) {
        // The images are base colour textures, sRGB-encoded (glTF 3.9.2): the GPU decodes them to
        // linear before filtering. Mipmaps whatever the samplers say: a third more texels, and any
        // filter can read them.
        const Image rgba = withAlpha(_model.decodeImage(i));
        renderer::Texture2D texture =
            device.createTexture2D({rgba.width, rgba.height, renderer::TextureFormat::SRGB8Alpha8, true});
        texture.copyFromImage(rgba);
        texture.generateMipmaps();
        textures.push_back(std::move(texture));
    }
    std::vector<renderer::Sampler> samplers;
    for (const world::GltfTexture& texture : _model.textures) {
        samplers.push_back(device.createSampler(texture.sampler));
    }
    std::vector<detail::DepthPrograms> programs;
    std::vector<renderer::VertexArray> vertexArrays;
    for (const Batch& batch : _batches) {
        const world::GltfMaterial& material = _model.materials[batch.material];
        renderer::ShaderProgramDescription description;
        description.name = "model";
        description.vertex = renderer::ShaderSource::embedded("scene/model/model.vert.glsl");
        description.fragment = renderer::ShaderSource::embedded("scene/model/model.frag.glsl");
        if (_options.lighting) {
            description.defines.push_back({"LIGHTING"});
        }
        if (material.baseColorTexture) {
            description.defines.push_back({"BASE_COLOR_TEXTURE"});
        }
        if (material.alphaMode == world::AlphaMode::Mask) {
            description.defines.push_back({"ALPHA_MASK"});
        } else if (material.alphaMode == world::AlphaMode::Blend) {
            description.defines.push_back({"ALPHA_BLEND"});
        }
        programs.emplace_back([description](DepthStrategy, Pass) { return description; });
        // Standard attribute names only: the array fits the program of every depth strategy.
        vertexArrays.push_back(
            frameState.context.createVertexArray(batch.mesh, programs.back().get(frameState, batch.pass)));
    }
    for (std::size_t i = 0; i < _batches.size(); ++i) {
        _batches[i].programs = std::move(programs[i]);
        _batches[i].vertexArray = std::move(vertexArrays[i]);
    }
    // On the GPU now: the CPU copies go.
    _textures = std::move(textures);
    _samplers = std::move(samplers);
    for (world::GltfImage& image : _model.images) {
        image.encoded = {};
    }
    for (Batch& batch : _batches) {
        batch.mesh = Mesh();
    }
    _resourcesCreated = true;
}

void ModelPrimitive::update(FrameState& frameState, CommandList& commands)
{
    if (!_resourcesCreated) {
        createResources(frameState);
    }
    for (Batch& batch : _batches) {
        const world::GltfMaterial& material = _model.materials[batch.material];
        SceneCommand command;
        command.draw.debugName = "model";
        command.tags = _options.lighting ? Effect::Models | Effect::Lighting : static_cast<std::uint32_t>(Effect::Models);
        command.draw.vertexArray = &*batch.vertexArray;
        command.draw.shaderProgram = &batch.programs->get(frameState, batch.pass);
        command.draw.modelMatrix = _modelMatrix;
        command.draw.uniforms.set("u_baseColorFactor", material.baseColorFactor);
        if (material.alphaMode == world::AlphaMode::Mask) {
            command.draw.uniforms.set("u_alphaCutoff", material.alphaCutoff);
        }
        if (material.baseColorTexture) {
            const world::GltfTexture& texture = _model.textures[*material.baseColorTexture];
            command.draw.textures.push_back({0, &_textures[texture.image], &_samplers[*material.baseColorTexture]});
        }
        command.draw.renderState.facetCulling.enabled = !material.doubleSided;
        command.pass = batch.pass;
        command.boundingSphere = batch.sphere;
        command.horizonOcclusionPoint = _occlusionPoint;
        if (batch.pass == Pass::Translucent) {
            command.draw.renderState.blending = renderer::Blending::alphaBlending();
            // "Over" for alpha too, so an opaque background stays opaque.
            command.draw.renderState.blending.sourceAlphaFactor = renderer::SourceBlendingFactor::One;
            command.draw.renderState.depthMask = false;
        }
        commands.push_back(std::move(command));
    }
}

} // namespace orbis::scene
