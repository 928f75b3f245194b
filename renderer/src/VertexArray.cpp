#include "orbis/renderer/VertexArray.h"

#include "ContextState.h"
#include "GlEnums.h"
#include "SplitDouble.h"

#include "orbis/core/Error.h"
#include "orbis/renderer/Context.h"
#include "orbis/renderer/Device.h"

#include <algorithm>
#include <limits>
#include <utility>

namespace orbis::renderer {
namespace {

constexpr std::string_view kStandardNames[] = {"position", "normal", "textureCoordinate", "positionHigh",
                                               "positionLow", "color"};

} // namespace

int standardAttributeLocation(std::string_view name) noexcept
{
    for (std::size_t i = 0; i < std::size(kStandardNames); ++i) {
        if (kStandardNames[i] == name) {
            return static_cast<int>(i);
        }
    }
    return -1;
}

std::string_view standardAttributeName(int location) noexcept
{
    return location >= 0 && location < static_cast<int>(std::size(kStandardNames)) ? kStandardNames[location]
                                                                                     : std::string_view();
}

VertexArray::VertexArray(detail::ContextState& owner, unsigned name) noexcept
    : _owner(&owner), _name(name), _serial(detail::nextObjectSerial())
{
}

VertexArray::~VertexArray()
{
    if (_name && detail::currentState() == _owner) {
        _owner->gl.glDeleteVertexArrays.unchecked(1, &_name);
    }
}

VertexArray::VertexArray(VertexArray&& other) noexcept
    : _owner(other._owner)
    , _name(std::exchange(other._name, 0u))
    , _serial(std::exchange(other._serial, 0u))
    , _mask(std::exchange(other._mask, 0u))
    , _vertexCounts(other._vertexCounts)
    , _indexCount(std::exchange(other._indexCount, std::nullopt))
    , _indexType(other._indexType)
    , _meshPrimitiveType(other._meshPrimitiveType)
    , _ownedVertexBuffers(std::move(other._ownedVertexBuffers))
    , _ownedIndexBuffer(std::move(other._ownedIndexBuffer))
{
}

VertexArray& VertexArray::operator=(VertexArray&& other) noexcept
{
    if (this != &other) {
        VertexArray moved(std::move(other));
        std::swap(_owner, moved._owner);
        std::swap(_name, moved._name);
        std::swap(_serial, moved._serial);
        std::swap(_mask, moved._mask);
        std::swap(_vertexCounts, moved._vertexCounts);
        std::swap(_indexCount, moved._indexCount);
        std::swap(_indexType, moved._indexType);
        std::swap(_meshPrimitiveType, moved._meshPrimitiveType);
        std::swap(_ownedVertexBuffers, moved._ownedVertexBuffers);
        std::swap(_ownedIndexBuffer, moved._ownedIndexBuffer);
    }
    return *this;
}

detail::ContextState& VertexArray::bindForChange(const char* what)
{
    if (!_name) {
        throw Error(std::string(what) + ": empty vertex array");
    }
    detail::ContextState* state = detail::currentState();
    if (state != _owner) {
        throw Error(std::string(what) +
                    ": the context that created the vertex array is not current on this thread (vertex arrays are "
                    "not shared between contexts)");
    }
    state->bindVertexArray(_serial, _name);
    return *state;
}

void VertexArray::setAttribute(int location, const VertexBuffer& buffer, const VertexAttributeFormat& format)
{
    constexpr const char* what = "VertexArray::setAttribute";
    if (location < 0 || location >= kMaxAttributes) {
        throw Error(std::string(what) + ": location " + std::to_string(location) + " is outside 0.." +
                    std::to_string(kMaxAttributes - 1));
    }
    if (format.components < 1 || format.components > 4) {
        throw Error(std::string(what) + ": " + std::to_string(format.components) + " components (1 to 4 allowed)");
    }
    if (!buffer.valid()) {
        throw Error(std::string(what) + ": empty vertex buffer");
    }
    if (format.integer && format.type == ComponentType::Float) {
        throw Error(std::string(what) + ": integer attributes need an integer component type");
    }
    detail::ContextState& state = bindForChange(what);
    if (buffer._device != &state.device) {
        throw Error(std::string(what) + ": the vertex buffer belongs to another Device");
    }
    const detail::GlApi& gl = state.gl;
    const GLuint index = static_cast<GLuint>(location);
    const auto stride = static_cast<GLsizei>(format.strideInBytes);
    const void* offset = reinterpret_cast<const void*>(static_cast<std::uintptr_t>(format.offsetInBytes));
    gl.glBindBuffer(GL_ARRAY_BUFFER, buffer._name);
    if (format.integer) {
        gl.glVertexAttribIPointer(index, format.components, detail::toGl(format.type), stride, offset);
    } else {
        gl.glVertexAttribPointer(index, format.components, detail::toGl(format.type), format.normalized, stride,
                                 offset);
    }
    gl.glEnableVertexAttribArray(index);
    const std::size_t elementSize = static_cast<std::size_t>(format.components) * detail::componentSize(format.type);
    const std::size_t step = format.strideInBytes ? format.strideInBytes : elementSize;
    const std::size_t size = buffer.sizeInBytes();
    _vertexCounts[location] =
        size >= format.offsetInBytes + elementSize ? (size - format.offsetInBytes - elementSize) / step + 1 : 0;
    _mask |= 1u << location;
}

void VertexArray::setAttribute(std::string_view standardName, const VertexBuffer& buffer,
                               const VertexAttributeFormat& format)
{
    const int location = standardAttributeLocation(standardName);
    if (location < 0) {
        throw Error("VertexArray::setAttribute: '" + std::string(standardName) +
                    "' is not a standard attribute name (position, normal, textureCoordinate, positionHigh, "
                    "positionLow, color); give a location instead");
    }
    setAttribute(location, buffer, format);
}

void VertexArray::removeAttribute(int location)
{
    if (location < 0 || location >= kMaxAttributes || !(_mask & (1u << location))) {
        return;
    }
    detail::ContextState& state = bindForChange("VertexArray::removeAttribute");
    state.gl.glDisableVertexAttribArray(static_cast<GLuint>(location));
    _mask &= ~(1u << location);
    _vertexCounts[location] = 0;
}

void VertexArray::setIndexBuffer(const IndexBuffer* indexBuffer)
{
    constexpr const char* what = "VertexArray::setIndexBuffer";
    if (indexBuffer && !indexBuffer->valid()) {
        throw Error(std::string(what) + ": empty index buffer");
    }
    detail::ContextState& state = bindForChange(what);
    if (indexBuffer && indexBuffer->_device != &state.device) {
        throw Error(std::string(what) + ": the index buffer belongs to another Device");
    }
    state.gl.glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indexBuffer ? indexBuffer->_name : 0u);
    if (indexBuffer) {
        _indexCount = indexBuffer->count();
        _indexType = indexBuffer->type();
    } else {
        _indexCount.reset();
    }
}

std::size_t VertexArray::vertexCount() const noexcept
{
    if (_mask == 0) {
        return 0;
    }
    std::size_t count = std::numeric_limits<std::size_t>::max();
    for (int i = 0; i < kMaxAttributes; ++i) {
        if (_mask & (1u << i)) {
            count = std::min(count, _vertexCounts[i]);
        }
    }
    return count;
}

// Context's vertex-array factories live here, next to the type they build.

namespace {

enum class MeshAttribute { Position, PositionHigh, PositionLow, Normal, TextureCoordinate };

std::vector<float> meshAttributeData(const Mesh& mesh, MeshAttribute attribute, const glm::dvec3& center)
{
    std::vector<float> data;
    switch (attribute) {
    case MeshAttribute::Position:
        data.reserve(mesh.positions.size() * 3);
        for (const glm::dvec3& p : mesh.positions) {
            const glm::dvec3 r = p - center;
            data.insert(data.end(), {static_cast<float>(r.x), static_cast<float>(r.y), static_cast<float>(r.z)});
        }
        break;
    case MeshAttribute::PositionHigh:
    case MeshAttribute::PositionLow:
        data.reserve(mesh.positions.size() * 3);
        for (const glm::dvec3& p : mesh.positions) {
            for (int i = 0; i < 3; ++i) {
                float high = 0.0f;
                float low = 0.0f;
                detail::splitDouble(p[i], high, low);
                data.push_back(attribute == MeshAttribute::PositionHigh ? high : low);
            }
        }
        break;
    case MeshAttribute::Normal:
        for (const glm::vec3& n : mesh.normals) {
            data.insert(data.end(), {n.x, n.y, n.z});
        }
        break;
    case MeshAttribute::TextureCoordinate:
        for (const glm::vec2& t : mesh.textureCoordinates) {
            data.insert(data.end(), {t.x, t.y});
        }
        break;
    }
    return data;
}

int components(MeshAttribute attribute) noexcept
{
    return attribute == MeshAttribute::TextureCoordinate ? 2 : 3;
}

void checkMesh(const Mesh& mesh, const char* what)
{
    const std::size_t n = mesh.positions.size();
    if (!mesh.normals.empty() && mesh.normals.size() != n) {
        throw Error(std::string(what) + ": the mesh has " + std::to_string(mesh.normals.size()) + " normals for " +
                    std::to_string(n) + " positions");
    }
    if (!mesh.textureCoordinates.empty() && mesh.textureCoordinates.size() != n) {
        throw Error(std::string(what) + ": the mesh has " + std::to_string(mesh.textureCoordinates.size()) +
                    " texture coordinates for " + std::to_string(n) + " positions");
    }
    for (std::size_t i = 0; i < mesh.indices.size(); ++i) {
        if (mesh.indices[i] >= n) {
            throw Error(std::string(what) + ": index " + std::to_string(i) + " is " + std::to_string(mesh.indices[i]) +
                        " but the mesh has " + std::to_string(n) + " positions");
        }
    }
}

} // namespace

VertexArray Context::createVertexArray()
{
    detail::ContextState& state = *_state;
    if (!state.isCurrent()) {
        throw Error("Context::createVertexArray: the context is not current on this thread");
    }
    GLuint name = 0;
    state.gl.glGenVertexArrays(1, &name);
    return VertexArray(state, name);
}

namespace {

struct AttributeUpload {
    MeshAttribute attribute;
    int location;
};

} // namespace

namespace detail {
struct VertexArrayAccess {
    static VertexArray build(Context& context, const Mesh& mesh, const std::vector<AttributeUpload>& uploads,
                             const VertexArrayOptions& options);
};

VertexArray VertexArrayAccess::build(Context& context, const Mesh& mesh, const std::vector<AttributeUpload>& uploads,
                             const VertexArrayOptions& options)
{
    VertexArray array = context.createVertexArray();
    Device& device = context.device();
    for (const AttributeUpload& upload : uploads) {
        const std::vector<float> data = meshAttributeData(mesh, upload.attribute, options.center);
        VertexBuffer buffer = device.createVertexBuffer(std::as_bytes(std::span(data)), options.usage);
        VertexAttributeFormat format;
        format.components = components(upload.attribute);
        array.setAttribute(upload.location, buffer, format);
        array._ownedVertexBuffers.push_back(std::move(buffer));
    }
    if (!mesh.indices.empty()) {
        const bool fits16 = mesh.positions.size() <= 65536;
        IndexType type = options.indexType.value_or(fits16 ? IndexType::UnsignedShort : IndexType::UnsignedInt);
        if (type == IndexType::UnsignedShort && !fits16) {
            throw Error("Context::createVertexArray: 16-bit indices asked for a mesh of " +
                        std::to_string(mesh.positions.size()) + " positions (at most 65536)");
        }
        if (type == IndexType::UnsignedShort) {
            std::vector<std::uint16_t> narrow(mesh.indices.begin(), mesh.indices.end());
            array._ownedIndexBuffer = device.createIndexBuffer(std::span<const std::uint16_t>(narrow), options.usage);
        } else {
            array._ownedIndexBuffer =
                device.createIndexBuffer(std::span<const std::uint32_t>(mesh.indices), options.usage);
        }
        array.setIndexBuffer(&array._ownedIndexBuffer);
    }
    array._meshPrimitiveType = mesh.primitiveType;
    return array;
}
} // namespace detail

VertexArray Context::createVertexArray(const Mesh& mesh, const VertexArrayOptions& options)
{
    checkMesh(mesh, "Context::createVertexArray");
    std::vector<AttributeUpload> uploads;
    if (!mesh.positions.empty()) {
        uploads.push_back({MeshAttribute::Position, VertexAttributeLocation::Position});
    }
    if (!mesh.normals.empty()) {
        uploads.push_back({MeshAttribute::Normal, VertexAttributeLocation::Normal});
    }
    if (!mesh.textureCoordinates.empty()) {
        uploads.push_back({MeshAttribute::TextureCoordinate, VertexAttributeLocation::TextureCoordinate});
    }
    return detail::VertexArrayAccess::build(*this, mesh, uploads, options);
}

VertexArray Context::createVertexArray(const Mesh& mesh, const ShaderProgram& program, const VertexArrayOptions& options)
{
    constexpr const char* what = "Context::createVertexArray";
    checkMesh(mesh, what);
    std::vector<AttributeUpload> uploads;
    for (const ShaderVertexAttribute& attribute : program.vertexAttributes()) {
        const std::string& name = attribute.name;
        MeshAttribute source;
        bool present = !mesh.positions.empty();
        if (name == "position") {
            source = MeshAttribute::Position;
        } else if (name == "positionHigh") {
            source = MeshAttribute::PositionHigh;
        } else if (name == "positionLow") {
            source = MeshAttribute::PositionLow;
        } else if (name == "normal") {
            source = MeshAttribute::Normal;
            present = !mesh.normals.empty();
        } else if (name == "textureCoordinate") {
            source = MeshAttribute::TextureCoordinate;
            present = !mesh.textureCoordinates.empty();
        } else {
            throw Error(std::string(what) + ": shader program '" + program.name() + "' reads vertex attribute '" + name +
                        "', which no Mesh has (a mesh supplies position, positionHigh, positionLow, normal and "
                        "textureCoordinate)");
        }
        if (!present) {
            throw Error(std::string(what) + ": shader program '" + program.name() + "' reads vertex attribute '" + name +
                        "' but the mesh has no " + (source == MeshAttribute::Normal ? "normals" : source == MeshAttribute::TextureCoordinate ? "texture coordinates" : "positions"));
        }
        uploads.push_back({source, attribute.location});
    }
    return detail::VertexArrayAccess::build(*this, mesh, uploads, options);
}

} // namespace orbis::renderer
