#pragma once

#include <orbis/core/Image.h>
#include <orbis/core/Mesh.h>
#include <orbis/core/SamplerDescription.h>

#include <glm/vec4.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace orbis::world {

/// How a glTF material's alpha is used (glTF 2.0, material.alphaMode).
enum class AlphaMode : std::uint8_t {
    Opaque, ///< alpha ignored: drawn opaque whatever the factor and texture say
    Mask,   ///< fragments with alpha below alphaCutoff are discarded, the rest are opaque
    Blend,  ///< blended over what is behind, in the translucent pass
};

/// The parts of a glTF material that Orbis draws: pbrMetallicRoughness's base colour.
struct GltfMaterial {
    std::string name;
    glm::vec4 baseColorFactor{1.0f}; ///< linear RGBA, multiplies the texture
    /// Index into GltfModel::textures; empty: the factor alone.
    std::optional<std::size_t> baseColorTexture;
    AlphaMode alphaMode = AlphaMode::Opaque;
    float alphaCutoff = 0.5f;        ///< Mask only
    bool doubleSided = false;        ///< false: back faces are culled
};

/// A base-colour image as the file holds it (PNG or JPEG bytes), decoded only when a texture is
/// made from it, so that a model that is never drawn never pays for decoding.
struct GltfImage {
    std::string name;                  ///< "image 2" or "image 2 (\"paint.png\")", for messages
    std::vector<std::uint8_t> encoded; ///< PNG or JPEG; emptied once uploaded
    int width = 0;                     ///< read from the header when the file is loaded
    int height = 0;
};

/// A glTF texture: an image and how it is sampled.
struct GltfTexture {
    std::size_t image = 0; ///< index into GltfModel::images
    SamplerDescription sampler; ///< the glTF sampler's filters and wrapping; glTF's defaults otherwise
    bool mipmaps = true;        ///< the minification filter reads mipmaps
};

/// Every triangle of the default scene drawn with one material.
struct GltfBatch {
    /// Positions in the model's own glTF frame (metres, +y up, +z front), node transforms applied;
    /// unit normals for every vertex (flat ones computed where the file has none); texture
    /// coordinates (glTF's: v grows downwards in the image) only when the material has a texture.
    Mesh mesh;
    std::size_t material = 0; ///< index into GltfModel::materials
};

/// A glTF 2.0 model (.gltf with its buffers and images, or .glb) read into what Orbis draws: the
/// triangles of every mesh of the default scene (every node's transform applied, one batch per
/// material), base-colour materials, and the images those use, still encoded.
///
/// ```
/// GltfModel model = GltfModel::read("data/models/aircraft.glb");
/// auto primitive = std::make_shared<ModelPrimitive>(std::move(model), Ellipsoid::wgs84(), placement);
/// ```
///
/// Read: meshes with TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN primitives; POSITION, NORMAL and
/// TEXCOORD_n as floats or (KHR_mesh_quantization) normalised or plain integers; u8, u16 and u32
/// indices or none; node matrices and translation-rotation-scale; base colour factor and texture
/// with its sampler; alphaMode and doubleSided. Ignored: other material properties, cameras,
/// lights, skins and morph targets (the bind pose is drawn), animations, optional extensions.
struct GltfModel {
    std::filesystem::path source;
    std::vector<GltfBatch> batches;
    std::vector<GltfMaterial> materials;
    std::vector<GltfTexture> textures;
    std::vector<GltfImage> images;

    /// Reads a .gltf or .glb file (told apart by its first bytes, whatever its extension). Throws
    /// orbis::Error naming the file and the mesh, primitive, accessor, node or image at fault, and
    /// what was wrong: a missing or unreadable file, bad JSON, a missing buffer, a buffer view or
    /// accessor outside its buffer, an index outside the vertices, points or lines, a required
    /// extension Orbis lacks (Draco, Basis textures, ...), an image that is neither PNG nor JPEG,
    /// a node cycle, non-finite numbers, or a default scene with no triangles.
    static GltfModel read(const std::filesystem::path& file);

    /// Triangles over all batches.
    std::size_t triangleCount() const noexcept;

    /// images[index] decoded to 4 channels, rows top to bottom. Throws orbis::Error naming the file
    /// and the image when it cannot be decoded (or was released after an upload).
    Image decodeImage(std::size_t index) const;
};

} // namespace orbis::world
