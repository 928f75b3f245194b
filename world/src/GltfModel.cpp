#include "orbis/world/GltfModel.h"

#include "JsonText.h"
#include "TinyGltf.h"

#include "orbis/world/FileAccess.h"

#include <orbis/core/Error.h>

// Declarations only: the implementation is compiled into libstb (Debian's libstb-dev).
#include <stb/stb_image.h>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <span>

namespace orbis::world {

namespace {

namespace fs = std::filesystem;

// glTF's numeric codes (glTF 2.0 specification, section 5).
constexpr int kByte = 5120;
constexpr int kUnsignedByte = 5121;
constexpr int kShort = 5122;
constexpr int kUnsignedShort = 5123;
constexpr int kUnsignedInt = 5125;
constexpr int kFloat = 5126;

constexpr int kTriangles = 4;
constexpr int kTriangleStrip = 5;
constexpr int kTriangleFan = 6;

constexpr int kNearest = 9728;
constexpr int kLinear = 9729;
constexpr int kNearestMipmapNearest = 9984;
constexpr int kLinearMipmapNearest = 9985;
constexpr int kNearestMipmapLinear = 9986;
constexpr int kLinearMipmapLinear = 9987;
constexpr int kClampToEdge = 33071;
constexpr int kMirroredRepeat = 33648;
constexpr int kRepeat = 10497;

/// The most vertices a model may unfold into (node instances and flat-shaded triangles counted):
/// 32 Mi vertices, about 1.5 GB as read. A small file must not be able to ask for more.
constexpr std::size_t kMaxVertices = std::size_t{1} << 25;

/// Extensions a file may require and still be drawn right.
constexpr std::array<std::string_view, 1> kSupportedRequiredExtensions = {"KHR_mesh_quantization"};

const char* modeName(int mode)
{
    switch (mode) {
    case 0: return "POINTS";
    case 1: return "LINES";
    case 2: return "LINE_LOOP";
    case 3: return "LINE_STRIP";
    case 4: return "TRIANGLES";
    case 5: return "TRIANGLE_STRIP";
    case 6: return "TRIANGLE_FAN";
    default: return "an unknown mode";
    }
}

const char* componentTypeName(int type)
{
    switch (type) {
    case kByte: return "BYTE";
    case kUnsignedByte: return "UNSIGNED_BYTE";
    case kShort: return "SHORT";
    case kUnsignedShort: return "UNSIGNED_SHORT";
    case kUnsignedInt: return "UNSIGNED_INT";
    case kFloat: return "FLOAT";
    default: return "an unknown component type";
    }
}

int componentSize(int type)
{
    switch (type) {
    case kByte:
    case kUnsignedByte: return 1;
    case kShort:
    case kUnsignedShort: return 2;
    case kUnsignedInt:
    case kFloat: return 4;
    default: return 0;
    }
}

const char* typeName(int components)
{
    switch (components) {
    case 1: return "SCALAR";
    case 2: return "VEC2";
    case 3: return "VEC3";
    case 4: return "VEC4";
    default: return "another type";
    }
}

/// tinygltf's type code for SCALAR and VECn.
int typeCode(int components)
{
    return components == 1 ? TINYGLTF_TYPE_SCALAR : components;
}

std::string quoted(const std::string& name)
{
    return name.empty() ? std::string() : " (\"" + name + "\")";
}

/// tinygltf's messages: one per line, with a trailing newline. Joined with "; ".
std::string joinLines(const std::string& text)
{
    std::string joined;
    std::size_t start = 0;
    while (start < text.size()) {
        std::size_t end = text.find('\n', start);
        if (end == std::string::npos) {
            end = text.size();
        }
        if (end > start) {
            if (!joined.empty()) {
                joined += "; ";
            }
            joined.append(text, start, end - start);
        }
        start = end + 1;
    }
    return joined;
}

bool allFinite(std::span<const double> values)
{
    for (const double value : values) {
        if (!std::isfinite(value)) {
            return false;
        }
    }
    return true;
}

// ---------------------------------------------------------------------------------------------
// Images stay encoded: tinygltf hands each one's bytes to this callback, which keeps a copy.

struct EncodedImages {
    const tinygltf::Model* model = nullptr; ///< the model being loaded: its buffers come first
    std::map<int, std::vector<std::uint8_t>> bytes;
};

bool keepEncodedImage(tinygltf::Image* image, const int index, std::string* error, std::string*, int, int,
                      const unsigned char* bytes, int size, void* userData)
{
    EncodedImages& images = *static_cast<EncodedImages*>(userData);
    if (image->bufferView >= 0) {
        // tinygltf checked that the view and its buffer exist, but not that the view lies inside the
        // buffer: check that before the bytes are read.
        const tinygltf::BufferView& view = images.model->bufferViews[static_cast<std::size_t>(image->bufferView)];
        const std::size_t bufferSize = images.model->buffers[static_cast<std::size_t>(view.buffer)].data.size();
        if (view.byteOffset > bufferSize || view.byteLength > bufferSize - view.byteOffset ||
            view.byteLength > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
            if (error) {
                *error += "image " + std::to_string(index) + ": buffer view " + std::to_string(image->bufferView) +
                          " (bytes " + std::to_string(view.byteOffset) + " to " +
                          std::to_string(view.byteOffset + view.byteLength) + ") lies outside buffer " +
                          std::to_string(view.buffer) + " (" + std::to_string(bufferSize) + " bytes)\n";
            }
            return false;
        }
    }
    if (bytes == nullptr || size <= 0) {
        if (error) {
            *error += "image " + std::to_string(index) + " is empty\n";
        }
        return false;
    }
    images.bytes[index].assign(bytes, bytes + size);
    return true;
}

// ---------------------------------------------------------------------------------------------

/// Reads the default scene of a loaded tinygltf model into a GltfModel, checking every index,
/// range and number it uses, and naming what is wrong.
class Reader {
public:
    Reader(const tinygltf::Model& model, EncodedImages& images, GltfModel& out)
        : _model(model)
        , _images(images)
        , _out(out)
    {
    }

    void read()
    {
        const std::string& version = _model.asset.version;
        if (version.empty() || version[0] != '2') {
            fail("asset version \"" + version + "\": only glTF 2.0 is read");
        }
        for (const std::string& extension : _model.extensionsRequired) {
            if (std::find(kSupportedRequiredExtensions.begin(), kSupportedRequiredExtensions.end(), extension) ==
                kSupportedRequiredExtensions.end()) {
                fail("requires the extension " + extension + ", which Orbis does not support");
            }
        }
        readScene();
        if (_out.triangleCount() == 0) {
            fail("the default scene has no triangles to draw");
        }
    }

private:
    [[noreturn]] void fail(const std::string& what) const { throw Error(what); }

    // -- nodes ------------------------------------------------------------------------------------

    void readScene()
    {
        const std::size_t nodeCount = _model.nodes.size();
        std::vector<int> roots;
        if (!_model.scenes.empty()) {
            const int sceneIndex = _model.defaultScene >= 0 ? _model.defaultScene : 0;
            if (static_cast<std::size_t>(sceneIndex) >= _model.scenes.size()) {
                fail("the default scene " + std::to_string(sceneIndex) + " does not exist (" +
                     std::to_string(_model.scenes.size()) + " scenes)");
            }
            roots = _model.scenes[static_cast<std::size_t>(sceneIndex)].nodes;
        } else {
            // No scene: every node that is no other node's child.
            std::vector<bool> isChild(nodeCount, false);
            for (const tinygltf::Node& node : _model.nodes) {
                for (const int child : node.children) {
                    if (child >= 0 && static_cast<std::size_t>(child) < nodeCount) {
                        isChild[static_cast<std::size_t>(child)] = true;
                    }
                }
            }
            for (std::size_t i = 0; i < nodeCount; ++i) {
                if (!isChild[i]) {
                    roots.push_back(static_cast<int>(i));
                }
            }
        }

        // Depth first without recursion (a long chain of nodes must not exhaust the stack). Nodes
        // form a forest: one reached twice is in a cycle or has two parents, and is refused.
        std::vector<bool> reached(nodeCount, false);
        struct Pending {
            int node;
            glm::dmat4 parent;
        };
        std::vector<Pending> stack;
        for (auto root = roots.rbegin(); root != roots.rend(); ++root) {
            stack.push_back({*root, glm::dmat4(1.0)});
        }
        while (!stack.empty()) {
            const Pending pending = stack.back();
            stack.pop_back();
            if (pending.node < 0 || static_cast<std::size_t>(pending.node) >= nodeCount) {
                fail("node " + std::to_string(pending.node) + " does not exist (" + std::to_string(nodeCount) +
                     " nodes)");
            }
            const auto index = static_cast<std::size_t>(pending.node);
            if (reached[index]) {
                fail("node " + std::to_string(pending.node) +
                     " is reached twice: nodes must form trees (one parent each, no cycles)");
            }
            reached[index] = true;
            const tinygltf::Node& node = _model.nodes[index];
            const glm::dmat4 world = pending.parent * localMatrix(node, pending.node);
            if (node.mesh >= 0) {
                readMesh(node.mesh, world, pending.node);
            } else if (node.mesh < -1) {
                fail("node " + std::to_string(pending.node) + ": mesh " + std::to_string(node.mesh) + " does not exist");
            }
            for (auto child = node.children.rbegin(); child != node.children.rend(); ++child) {
                stack.push_back({*child, world});
            }
        }
    }

    glm::dmat4 localMatrix(const tinygltf::Node& node, int index) const
    {
        const std::string where = "node " + std::to_string(index) + quoted(node.name);
        if (!node.matrix.empty()) {
            if (node.matrix.size() != 16 || !allFinite(node.matrix)) {
                fail(where + ": matrix must be 16 finite numbers");
            }
            glm::dmat4 matrix(1.0);
            for (int column = 0; column < 4; ++column) {
                for (int row = 0; row < 4; ++row) {
                    matrix[column][row] = node.matrix[static_cast<std::size_t>(column * 4 + row)];
                }
            }
            return matrix;
        }
        glm::dmat4 matrix(1.0);
        if (!node.translation.empty()) {
            if (node.translation.size() != 3 || !allFinite(node.translation)) {
                fail(where + ": translation must be 3 finite numbers");
            }
            matrix[3] = glm::dvec4(node.translation[0], node.translation[1], node.translation[2], 1.0);
        }
        if (!node.rotation.empty()) {
            if (node.rotation.size() != 4 || !allFinite(node.rotation)) {
                fail(where + ": rotation must be a quaternion of 4 finite numbers (x, y, z, w)");
            }
            glm::dquat rotation(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
            const double length = glm::length(rotation);
            if (length < 1e-12) {
                fail(where + ": rotation is a zero quaternion");
            }
            matrix = matrix * glm::dmat4(glm::mat3_cast(rotation / length));
        }
        if (!node.scale.empty()) {
            if (node.scale.size() != 3 || !allFinite(node.scale)) {
                fail(where + ": scale must be 3 finite numbers");
            }
            matrix[0] *= node.scale[0];
            matrix[1] *= node.scale[1];
            matrix[2] *= node.scale[2];
        }
        return matrix;
    }

    // -- meshes -----------------------------------------------------------------------------------

    void readMesh(int meshIndex, const glm::dmat4& world, int nodeIndex)
    {
        if (static_cast<std::size_t>(meshIndex) >= _model.meshes.size()) {
            fail("node " + std::to_string(nodeIndex) + ": mesh " + std::to_string(meshIndex) + " does not exist (" +
                 std::to_string(_model.meshes.size()) + " meshes)");
        }
        const tinygltf::Mesh& mesh = _model.meshes[static_cast<std::size_t>(meshIndex)];
        for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
            const std::string where =
                "mesh " + std::to_string(meshIndex) + quoted(mesh.name) + " primitive " + std::to_string(p);
            readPrimitive(mesh.primitives[p], world, where);
        }
    }

    void readPrimitive(const tinygltf::Primitive& primitive, const glm::dmat4& world, const std::string& where)
    {
        if (primitive.mode != kTriangles && primitive.mode != kTriangleStrip && primitive.mode != kTriangleFan) {
            fail(where + ": mode " + std::to_string(primitive.mode) + " (" + modeName(primitive.mode) +
                 ") is not drawn; only TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN are");
        }
        const std::size_t materialIndex = material(primitive.material, where);
        const GltfMaterial& material = _out.materials[materialIndex];

        const auto positionAttribute = primitive.attributes.find("POSITION");
        if (positionAttribute == primitive.attributes.end()) {
            fail(where + ": no POSITION attribute");
        }
        const std::vector<float> positions = readAccessor(positionAttribute->second, 3, where + ": POSITION");
        const std::size_t vertexCount = positions.size() / 3;

        std::vector<float> normals;
        if (const auto normal = primitive.attributes.find("NORMAL"); normal != primitive.attributes.end()) {
            normals = readAccessor(normal->second, 3, where + ": NORMAL");
            requireCount(normals.size() / 3, vertexCount, where + ": NORMAL");
        }
        std::vector<float> textureCoordinates;
        if (material.baseColorTexture) {
            const std::string name = "TEXCOORD_" + std::to_string(_textureCoordinateSet[materialIndex]);
            if (const auto attribute = primitive.attributes.find(name); attribute != primitive.attributes.end()) {
                textureCoordinates = readAccessor(attribute->second, 2, where + ": " + name);
                requireCount(textureCoordinates.size() / 2, vertexCount, where + ": " + name);
            } else {
                textureCoordinates.assign(vertexCount * 2, 0.0f); // the texture's first texel
            }
        }

        std::vector<std::uint32_t> indices;
        if (primitive.indices >= 0) {
            indices = readIndices(primitive.indices, vertexCount, where);
        } else {
            indices.resize(vertexCount);
            for (std::size_t i = 0; i < vertexCount; ++i) {
                indices[i] = static_cast<std::uint32_t>(i);
            }
        }
        std::vector<std::uint32_t> triangles = toTriangles(indices, primitive.mode, where);

        // Node transform: positions by the matrix, normals by its inverse transpose; a mirroring
        // transform turns the winding, so the front faces stay counter-clockwise (glTF 3.7.4).
        const glm::dmat3 linear(world);
        const double determinant = glm::determinant(linear);
        if (!std::isfinite(determinant) || std::abs(determinant) < 1e-300) {
            fail(where + ": its node transform is singular or not finite");
        }
        const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(linear));
        if (determinant < 0.0) {
            for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
                std::swap(triangles[t + 1], triangles[t + 2]);
            }
        }

        const std::size_t added = normals.empty() ? triangles.size() : vertexCount;
        if (added > kMaxVertices - _vertices) {
            fail(where + ": the model unfolds into more than " + std::to_string(kMaxVertices) +
                 " vertices (counting every node that uses a mesh), too many to draw");
        }
        _vertices += added;

        GltfBatch& batch = batchFor(materialIndex);
        Mesh& mesh = batch.mesh;
        const bool textured = material.baseColorTexture.has_value();
        auto position = [&](std::size_t i) {
            return glm::dvec3(world * glm::dvec4(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2], 1.0));
        };
        auto textureCoordinate = [&](std::size_t i) {
            return glm::vec2(textureCoordinates[2 * i], textureCoordinates[2 * i + 1]);
        };
        const std::size_t base = mesh.positions.size();
        if (!normals.empty()) {
            if (base + vertexCount > std::numeric_limits<std::uint32_t>::max()) {
                fail(where + ": more than 2^32 vertices in one material");
            }
            for (std::size_t i = 0; i < vertexCount; ++i) {
                mesh.positions.push_back(position(i));
                glm::dvec3 normal = normalMatrix * glm::dvec3(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]);
                const double length = glm::length(normal);
                normal = length > 1e-30 && std::isfinite(length) ? normal / length : glm::dvec3(0.0, 1.0, 0.0);
                mesh.normals.push_back(glm::vec3(normal));
                if (textured) {
                    mesh.textureCoordinates.push_back(textureCoordinate(i));
                }
            }
            for (const std::uint32_t index : triangles) {
                mesh.indices.push_back(static_cast<std::uint32_t>(base + index));
            }
            return;
        }
        // No normals in the file: flat shading (glTF 3.7.2.1), three vertices per triangle.
        if (base + triangles.size() > std::numeric_limits<std::uint32_t>::max()) {
            fail(where + ": more than 2^32 vertices in one material");
        }
        for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
            const glm::dvec3 a = position(triangles[t]);
            const glm::dvec3 b = position(triangles[t + 1]);
            const glm::dvec3 c = position(triangles[t + 2]);
            glm::dvec3 normal = glm::cross(b - a, c - a);
            const double length = glm::length(normal);
            normal = length > 1e-30 && std::isfinite(length) ? normal / length : glm::dvec3(0.0, 1.0, 0.0);
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t index = triangles[t + static_cast<std::size_t>(k)];
                mesh.indices.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
                mesh.positions.push_back(k == 0 ? a : k == 1 ? b : c);
                mesh.normals.push_back(glm::vec3(normal));
                if (textured) {
                    mesh.textureCoordinates.push_back(textureCoordinate(index));
                }
            }
        }
    }

    void requireCount(std::size_t count, std::size_t vertexCount, const std::string& where) const
    {
        if (count != vertexCount) {
            fail(where + ": " + std::to_string(count) + " elements, but POSITION has " + std::to_string(vertexCount));
        }
    }

    std::vector<std::uint32_t> toTriangles(const std::vector<std::uint32_t>& indices, int mode,
                                           const std::string& where) const
    {
        if (mode == kTriangles) {
            if (indices.size() % 3 != 0) {
                fail(where + ": " + std::to_string(indices.size()) + " vertices do not make whole triangles");
            }
            return indices;
        }
        std::vector<std::uint32_t> triangles;
        for (std::size_t i = 0; i + 2 < indices.size(); ++i) {
            if (mode == kTriangleStrip) {
                // Every other triangle is turned back to keep the strip's winding (glTF 3.7.2.1).
                const std::size_t odd = i % 2;
                triangles.insert(triangles.end(), {indices[i], indices[i + 1 + odd], indices[i + 2 - odd]});
            } else {
                triangles.insert(triangles.end(), {indices[i + 1], indices[i + 2], indices[0]});
            }
        }
        return triangles;
    }

    GltfBatch& batchFor(std::size_t material)
    {
        for (GltfBatch& batch : _out.batches) {
            if (batch.material == material) {
                return batch;
            }
        }
        _out.batches.push_back({Mesh{}, material});
        return _out.batches.back();
    }

    // -- accessors --------------------------------------------------------------------------------

    /// The bytes an accessor reads, checked to lie inside its buffer view and the view inside its
    /// buffer; null data for an accessor without a view (all zeros, glTF 3.6.2.4).
    struct AccessorBytes {
        const std::uint8_t* data = nullptr;
        std::size_t count = 0;
        std::size_t stride = 0;
        int componentType = 0;
        bool normalized = false;
    };

    AccessorBytes accessorBytes(int accessorIndex, int components, std::span<const int> componentTypes,
                                const std::string& what) const
    {
        if (accessorIndex < 0 || static_cast<std::size_t>(accessorIndex) >= _model.accessors.size()) {
            fail(what + ": accessor " + std::to_string(accessorIndex) + " does not exist (" +
                 std::to_string(_model.accessors.size()) + " accessors)");
        }
        const tinygltf::Accessor& accessor = _model.accessors[static_cast<std::size_t>(accessorIndex)];
        const std::string where = what + ": accessor " + std::to_string(accessorIndex);
        if (accessor.type != typeCode(components)) {
            fail(where + ": expected type " + typeName(components) + ", got " +
                 typeName(accessor.type == TINYGLTF_TYPE_SCALAR ? 1 : accessor.type));
        }
        if (std::find(componentTypes.begin(), componentTypes.end(), accessor.componentType) == componentTypes.end()) {
            std::string allowed;
            for (const int type : componentTypes) {
                allowed += (allowed.empty() ? "" : ", ") + std::string(componentTypeName(type));
            }
            fail(where + ": component type " + std::to_string(accessor.componentType) + " (" +
                 componentTypeName(accessor.componentType) + ") is not one of " + allowed);
        }
        if (accessor.sparse.isSparse) {
            fail(where + ": sparse accessors are not read");
        }
        AccessorBytes bytes;
        bytes.count = accessor.count;
        bytes.componentType = accessor.componentType;
        bytes.normalized = accessor.normalized;
        const std::size_t elementSize = static_cast<std::size_t>(components * componentSize(accessor.componentType));
        bytes.stride = elementSize;
        if (accessor.bufferView < 0) {
            if (accessor.count > kMaxVertices) {
                fail(where + ": " + std::to_string(accessor.count) + " zero elements without a buffer view is too many");
            }
            return bytes;
        }
        if (static_cast<std::size_t>(accessor.bufferView) >= _model.bufferViews.size()) {
            fail(where + ": buffer view " + std::to_string(accessor.bufferView) + " does not exist (" +
                 std::to_string(_model.bufferViews.size()) + " buffer views)");
        }
        const tinygltf::BufferView& view = _model.bufferViews[static_cast<std::size_t>(accessor.bufferView)];
        const std::string viewName = "buffer view " + std::to_string(accessor.bufferView);
        if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= _model.buffers.size()) {
            fail(where + ": " + viewName + ": buffer " + std::to_string(view.buffer) + " does not exist (" +
                 std::to_string(_model.buffers.size()) + " buffers)");
        }
        const tinygltf::Buffer& buffer = _model.buffers[static_cast<std::size_t>(view.buffer)];
        if (buffer.data.empty()) {
            fail(where + ": " + viewName + ": buffer " + std::to_string(view.buffer) + quoted(buffer.uri) +
                 " has no data (missing from the file?)");
        }
        if (view.byteOffset > buffer.data.size() || view.byteLength > buffer.data.size() - view.byteOffset) {
            fail(where + ": " + viewName + " (bytes " + std::to_string(view.byteOffset) + " to " +
                 std::to_string(view.byteOffset + view.byteLength) + ") lies outside buffer " +
                 std::to_string(view.buffer) + " (" + std::to_string(buffer.data.size()) + " bytes)");
        }
        if (view.byteStride != 0) {
            if (view.byteStride < elementSize) {
                fail(where + ": " + viewName + ": byte stride " + std::to_string(view.byteStride) +
                     " is smaller than an element (" + std::to_string(elementSize) + " bytes)");
            }
            bytes.stride = view.byteStride;
        }
        if (accessor.count > 0) {
            // byteOffset + stride * (count - 1) + elementSize <= byteLength, without overflow.
            const std::size_t length = view.byteLength;
            const bool fits = accessor.byteOffset <= length && elementSize <= length - accessor.byteOffset &&
                              (accessor.count - 1) <= (length - accessor.byteOffset - elementSize) / bytes.stride;
            if (!fits) {
                fail(where + ": " + std::to_string(accessor.count) + " elements of " + std::to_string(elementSize) +
                     " bytes from byte " + std::to_string(accessor.byteOffset) + " (stride " +
                     std::to_string(bytes.stride) + ") run past the end of " + viewName + " (" +
                     std::to_string(length) + " bytes)");
            }
        }
        bytes.data = buffer.data.data() + view.byteOffset + accessor.byteOffset;
        return bytes;
    }

    /// An attribute as floats, components per element, normalised integers mapped as glTF says.
    std::vector<float> readAccessor(int accessorIndex, int components, const std::string& what) const
    {
        static constexpr std::array<int, 5> kTypes = {kFloat, kByte, kUnsignedByte, kShort, kUnsignedShort};
        const AccessorBytes bytes = accessorBytes(accessorIndex, components, kTypes, what);
        const auto n = static_cast<std::size_t>(components);
        std::vector<float> values(bytes.count * n, 0.0f);
        if (!bytes.data) {
            return values;
        }
        const int size = componentSize(bytes.componentType);
        for (std::size_t i = 0; i < bytes.count; ++i) {
            const std::uint8_t* element = bytes.data + i * bytes.stride;
            for (std::size_t c = 0; c < n; ++c) {
                const std::uint8_t* at = element + c * static_cast<std::size_t>(size);
                float value = 0.0f;
                switch (bytes.componentType) {
                case kFloat: std::memcpy(&value, at, 4); break;
                case kByte: {
                    std::int8_t v;
                    std::memcpy(&v, at, 1);
                    value = bytes.normalized ? std::max(static_cast<float>(v) / 127.0f, -1.0f) : static_cast<float>(v);
                    break;
                }
                case kUnsignedByte: value = bytes.normalized ? static_cast<float>(*at) / 255.0f : static_cast<float>(*at); break;
                case kShort: {
                    std::int16_t v;
                    std::memcpy(&v, at, 2);
                    value = bytes.normalized ? std::max(static_cast<float>(v) / 32767.0f, -1.0f) : static_cast<float>(v);
                    break;
                }
                default: {
                    std::uint16_t v;
                    std::memcpy(&v, at, 2);
                    value = bytes.normalized ? static_cast<float>(v) / 65535.0f : static_cast<float>(v);
                    break;
                }
                }
                if (!std::isfinite(value)) {
                    fail(what + ": accessor " + std::to_string(accessorIndex) + ": element " + std::to_string(i) +
                         " is not a finite number");
                }
                values[i * n + c] = value;
            }
        }
        return values;
    }

    std::vector<std::uint32_t> readIndices(int accessorIndex, std::size_t vertexCount, const std::string& where) const
    {
        static constexpr std::array<int, 3> kTypes = {kUnsignedByte, kUnsignedShort, kUnsignedInt};
        const AccessorBytes bytes = accessorBytes(accessorIndex, 1, kTypes, where + ": indices");
        std::vector<std::uint32_t> indices(bytes.count, 0);
        if (!bytes.data) {
            return indices;
        }
        for (std::size_t i = 0; i < bytes.count; ++i) {
            const std::uint8_t* at = bytes.data + i * bytes.stride;
            std::uint32_t index = 0;
            if (bytes.componentType == kUnsignedByte) {
                index = *at;
            } else if (bytes.componentType == kUnsignedShort) {
                std::uint16_t v;
                std::memcpy(&v, at, 2);
                index = v;
            } else {
                std::memcpy(&index, at, 4);
            }
            if (index >= vertexCount) {
                fail(where + ": indices: accessor " + std::to_string(accessorIndex) + ": index " + std::to_string(i) +
                     " is " + std::to_string(index) + ", but there are " + std::to_string(vertexCount) + " vertices");
            }
            indices[i] = index;
        }
        return indices;
    }

    // -- materials, textures, images --------------------------------------------------------------

    /// The GltfModel material for a glTF material index (-1: the default material), read once.
    std::size_t material(int index, const std::string& where)
    {
        if (const auto found = _materials.find(index); found != _materials.end()) {
            return found->second;
        }
        GltfMaterial out;
        int textureCoordinateSet = 0;
        if (index >= 0) {
            if (static_cast<std::size_t>(index) >= _model.materials.size()) {
                fail(where + ": material " + std::to_string(index) + " does not exist (" +
                     std::to_string(_model.materials.size()) + " materials)");
            }
            const tinygltf::Material& material = _model.materials[static_cast<std::size_t>(index)];
            const std::string at = where + ": material " + std::to_string(index) + quoted(material.name);
            out.name = material.name;
            const std::vector<double>& factor = material.pbrMetallicRoughness.baseColorFactor;
            if (factor.size() != 4 || !allFinite(factor)) {
                fail(at + ": baseColorFactor must be 4 finite numbers");
            }
            out.baseColorFactor = glm::vec4(glm::dvec4(factor[0], factor[1], factor[2], factor[3]));
            const tinygltf::TextureInfo& texture = material.pbrMetallicRoughness.baseColorTexture;
            if (texture.index >= 0) {
                out.baseColorTexture = this->texture(texture.index, at);
                if (texture.texCoord < 0) {
                    fail(at + ": baseColorTexture.texCoord " + std::to_string(texture.texCoord) + " is negative");
                }
                textureCoordinateSet = texture.texCoord;
            } else if (texture.index < -1) {
                fail(at + ": texture " + std::to_string(texture.index) + " does not exist");
            }
            if (material.alphaMode == "OPAQUE") {
                out.alphaMode = AlphaMode::Opaque;
            } else if (material.alphaMode == "MASK") {
                out.alphaMode = AlphaMode::Mask;
            } else if (material.alphaMode == "BLEND") {
                out.alphaMode = AlphaMode::Blend;
            } else {
                fail(at + ": alphaMode \"" + material.alphaMode + "\" is not OPAQUE, MASK or BLEND");
            }
            if (!std::isfinite(material.alphaCutoff)) {
                fail(at + ": alphaCutoff is not a finite number");
            }
            out.alphaCutoff = static_cast<float>(material.alphaCutoff);
            out.doubleSided = material.doubleSided;
        } else {
            out.name = "default";
        }
        _out.materials.push_back(std::move(out));
        _textureCoordinateSet.push_back(textureCoordinateSet);
        _materials[index] = _out.materials.size() - 1;
        return _out.materials.size() - 1;
    }

    std::size_t texture(int index, const std::string& where)
    {
        if (const auto found = _textures.find(index); found != _textures.end()) {
            return found->second;
        }
        if (static_cast<std::size_t>(index) >= _model.textures.size()) {
            fail(where + ": texture " + std::to_string(index) + " does not exist (" +
                 std::to_string(_model.textures.size()) + " textures)");
        }
        const tinygltf::Texture& texture = _model.textures[static_cast<std::size_t>(index)];
        const std::string at = where + ": texture " + std::to_string(index) + quoted(texture.name);
        if (texture.source < 0) {
            fail(at + ": no source image (an image only an extension names, such as KHR_texture_basisu or "
                      "EXT_texture_webp, is not read)");
        }
        GltfTexture out;
        out.image = image(texture.source, at);
        if (texture.sampler >= 0) {
            if (static_cast<std::size_t>(texture.sampler) >= _model.samplers.size()) {
                fail(at + ": sampler " + std::to_string(texture.sampler) + " does not exist (" +
                     std::to_string(_model.samplers.size()) + " samplers)");
            }
            const tinygltf::Sampler& sampler = _model.samplers[static_cast<std::size_t>(texture.sampler)];
            const std::string samplerName = at + ": sampler " + std::to_string(texture.sampler);
            out.sampler = samplerDescription(sampler, samplerName);
        } else {
            out.sampler = samplerDescription(tinygltf::Sampler{}, at);
        }
        _out.textures.push_back(out);
        _textures[index] = _out.textures.size() - 1;
        return _out.textures.size() - 1;
    }

    SamplerDescription samplerDescription(const tinygltf::Sampler& sampler, const std::string& where) const
    {
        SamplerDescription description;
        // Undefined filters: trilinear, what glTF viewers commonly choose.
        switch (sampler.minFilter) {
        case -1:
        case kLinearMipmapLinear: description.minificationFilter = TextureMinificationFilter::LinearMipmapLinear; break;
        case kNearest: description.minificationFilter = TextureMinificationFilter::Nearest; break;
        case kLinear: description.minificationFilter = TextureMinificationFilter::Linear; break;
        case kNearestMipmapNearest:
            description.minificationFilter = TextureMinificationFilter::NearestMipmapNearest;
            break;
        case kLinearMipmapNearest: description.minificationFilter = TextureMinificationFilter::LinearMipmapNearest; break;
        case kNearestMipmapLinear: description.minificationFilter = TextureMinificationFilter::NearestMipmapLinear; break;
        default: fail(where + ": minFilter " + std::to_string(sampler.minFilter) + " is not a glTF filter");
        }
        switch (sampler.magFilter) {
        case -1:
        case kLinear: description.magnificationFilter = TextureMagnificationFilter::Linear; break;
        case kNearest: description.magnificationFilter = TextureMagnificationFilter::Nearest; break;
        default: fail(where + ": magFilter " + std::to_string(sampler.magFilter) + " is not a glTF filter");
        }
        auto wrap = [&](int mode, const char* key) {
            switch (mode) {
            case kRepeat: return TextureWrap::Repeat;
            case kClampToEdge: return TextureWrap::Clamp;
            case kMirroredRepeat: return TextureWrap::MirroredRepeat;
            default: fail(where + ": " + key + " " + std::to_string(mode) + " is not a glTF wrap mode");
            }
        };
        description.wrapS = wrap(sampler.wrapS, "wrapS");
        description.wrapT = wrap(sampler.wrapT, "wrapT");
        return description;
    }

    std::size_t image(int index, const std::string& where)
    {
        if (const auto found = _imageIndices.find(index); found != _imageIndices.end()) {
            return found->second;
        }
        if (static_cast<std::size_t>(index) >= _model.images.size()) {
            fail(where + ": image " + std::to_string(index) + " does not exist (" + std::to_string(_model.images.size()) +
                 " images)");
        }
        const tinygltf::Image& image = _model.images[static_cast<std::size_t>(index)];
        GltfImage out;
        out.name = "image " + std::to_string(index) + quoted(image.uri.empty() || image.uri.starts_with("data:")
                                                                  ? image.name
                                                                  : image.uri);
        const auto bytes = _images.bytes.find(index);
        if (bytes == _images.bytes.end()) {
            fail(where + ": " + out.name + ": cannot read the file");
        }
        out.encoded = std::move(bytes->second);
        int channels = 0;
        if (out.encoded.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()) ||
            !stbi_info_from_memory(out.encoded.data(), static_cast<int>(out.encoded.size()), &out.width, &out.height,
                                   &channels) ||
            out.width <= 0 || out.height <= 0) {
            fail(where + ": " + out.name + ": not a PNG or JPEG image that can be decoded");
        }
        _out.images.push_back(std::move(out));
        _imageIndices[index] = _out.images.size() - 1;
        return _out.images.size() - 1;
    }

    const tinygltf::Model& _model;
    EncodedImages& _images;
    GltfModel& _out;
    std::map<int, std::size_t> _materials;   ///< glTF index to GltfModel index
    std::vector<int> _textureCoordinateSet;  ///< per GltfModel material: n of TEXCOORD_n
    std::map<int, std::size_t> _textures;
    std::map<int, std::size_t> _imageIndices;
    std::size_t _vertices = 0; ///< unfolded so far
};

/// No glTF file needs more; tinygltf's parser recurses per level (a deeper file would exhaust the
/// stack), so the depth is checked before it sees the text.
constexpr std::size_t kMaxJsonDepth = 128;

/// The JSON of a glTF file: the whole text, or a .glb's first chunk (a 12-byte header, then chunks
/// of length, type and data, the first the JSON); empty when a .glb is too short for its chunk
/// (tinygltf then says what is wrong).
std::string_view jsonOf(std::span<const std::uint8_t> bytes, bool binary)
{
    const std::string_view all(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    if (!binary) {
        return all;
    }
    if (bytes.size() < 20) {
        return {};
    }
    std::uint32_t length = 0;
    std::memcpy(&length, bytes.data() + 12, 4); // little-endian, as the specification and x86 are
    if (length > bytes.size() - 20) {
        return {};
    }
    // The chunk is padded with spaces; some writers pad with NUL bytes: padding, not content.
    std::string_view json = all.substr(20, length);
    while (!json.empty() && json.back() == '\0') {
        json.remove_suffix(1);
    }
    return json;
}

// tinygltf reads buffers and images through these, so that every file it opens is checked as
// Orbis checks its own: a regular file (a folder or named pipe is refused before a byte is read),
// at most kMaximumFileBytes, and no shell-style expansion of the name.
bool gltfFileExists(const std::string& path, void*)
{
    std::error_code error;
    return fs::exists(path, error);
}

std::string gltfExpandPath(const std::string& path, void*)
{
    return path;
}

bool gltfReadFile(std::vector<unsigned char>* out, std::string* error, const std::string& path, void*)
{
    try {
        *out = readFileBytes(path, "glTF buffer or image");
        return true;
    } catch (const Error& failure) {
        if (error) {
            *error += std::string(failure.what()) + "\n";
        }
        return false;
    }
}

bool gltfWriteFile(std::string* error, const std::string&, const std::vector<unsigned char>&, void*)
{
    if (error) {
        *error += "Orbis writes no glTF files\n";
    }
    return false;
}

} // namespace

GltfModel GltfModel::read(const fs::path& file)
{
    const std::string name = file.string();
    std::error_code error;
    if (!fs::exists(file, error)) {
        throw Error(name + ": no such file");
    }
    const std::vector<std::uint8_t> bytes = readFileBytes(file, "glTF model");
    const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
    const std::string_view json = jsonOf(bytes, binary);
    // Only the nesting here (and an empty file); tinygltf says what else is wrong with the JSON,
    // and what is wrong with a .glb too short for its JSON chunk.
    const bool glbWithoutJson = binary && json.empty();
    if (const std::optional<Diagnostic> fault =
            glbWithoutJson ? std::nullopt : detail::jsonSyntaxFault(json, name, kMaxJsonDepth, nullptr)) {
        throw Error(fault->text());
    }
    if (bytes.size() > std::numeric_limits<unsigned int>::max()) {
        throw Error(name + ": larger than 4 GiB");
    }

    tinygltf::Model model;
    EncodedImages images;
    images.model = &model;
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(keepEncodedImage, &images);
    loader.SetFsCallbacks({gltfFileExists, gltfExpandPath, gltfReadFile, gltfWriteFile, nullptr});
    std::string errors;
    std::string warnings;
    bool loaded = false;
    const std::string folder = file.parent_path().string();
    try {
        loaded = binary ? loader.LoadBinaryFromMemory(&model, &errors, &warnings, bytes.data(),
                                                      static_cast<unsigned int>(bytes.size()), folder)
                        : loader.LoadASCIIFromString(&model, &errors, &warnings, json.data(),
                                                     static_cast<unsigned int>(json.size()), folder);
    } catch (const std::exception& exception) {
        throw Error(name + ": " + exception.what());
    }
    if (!loaded) {
        const std::string reason = joinLines(errors.empty() ? warnings : errors);
        throw Error(name + ": " + (reason.empty() ? std::string("not a glTF file") : cutForMessage(reason)));
    }

    GltfModel out;
    out.source = file;
    try {
        Reader(model, images, out).read();
    } catch (const Error& failure) {
        throw Error(name + ": " + failure.what());
    } catch (const std::bad_alloc&) {
        throw Error(name + ": not enough memory to read the model");
    }
    return out;
}

Image GltfModel::decodeImage(std::size_t index) const
{
    const GltfImage& image = images.at(index);
    const std::string where = source.string() + ": " + image.name;
    if (image.encoded.empty() || image.encoded.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
        throw Error(where + ": no encoded image to decode");
    }
    int width = 0;
    int height = 0;
    int channels = 0;
    const std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
        stbi_load_from_memory(image.encoded.data(), static_cast<int>(image.encoded.size()), &width, &height, &channels, 4),
        stbi_image_free);
    if (!pixels || width <= 0 || height <= 0) {
        throw Error(where + ": cannot decode the image");
    }
    Image decoded(width, height, 4);
    std::memcpy(decoded.pixels.data(), pixels.get(), decoded.pixels.size());
    return decoded;
}

std::size_t GltfModel::triangleCount() const noexcept
{
    std::size_t count = 0;
    for (const GltfBatch& batch : batches) {
        count += batch.mesh.triangleCount();
    }
    return count;
}

} // namespace orbis::world
