#pragma once

#include "orbis/core/Mesh.h"
#include "orbis/renderer/IndexBuffer.h"
#include "orbis/renderer/VertexBuffer.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace orbis::renderer {

namespace detail {
class ContextState;
struct VertexArrayAccess;
struct RawGlBaselineAccess;
} // namespace detail
class Context;

/// The type of one vertex attribute component in a buffer.
enum class ComponentType : std::uint8_t { Byte, UnsignedByte, Short, UnsignedShort, Int, UnsignedInt, Float };

/// Where an attribute's values lie in a vertex buffer.
struct VertexAttributeFormat {
    ComponentType type = ComponentType::Float;
    int components = 3;             ///< 1 to 4
    bool normalized = false;        ///< integers mapped to 0..1 or -1..1 (floating-point inputs only)
    bool integer = false;           ///< integer inputs (ivec, uint) in the shader: no conversion
    std::size_t strideInBytes = 0;  ///< 0: tightly packed
    std::size_t offsetInBytes = 0;
};

/// Attribute names every Orbis shader and mesh agree on, bound to fixed locations before linking
/// so that one vertex array serves every program that follows the names. Other names get a
/// location from the linker.
namespace VertexAttributeLocation {
inline constexpr int Position = 0;          ///< "position": float(position - centre)
inline constexpr int Normal = 1;            ///< "normal"
inline constexpr int TextureCoordinate = 2; ///< "textureCoordinate"
inline constexpr int PositionHigh = 3;      ///< "positionHigh": float(position)
inline constexpr int PositionLow = 4;       ///< "positionLow": float(position - double(positionHigh))
inline constexpr int Color = 5;             ///< "color"
} // namespace VertexAttributeLocation

/// The fixed location of a standard attribute name; -1 for other names.
int standardAttributeLocation(std::string_view name) noexcept;
/// The standard name at a fixed location; empty for others.
std::string_view standardAttributeName(int location) noexcept;

/// How Context::createVertexArray turns a Mesh into buffers.
struct VertexArrayOptions {
    BufferUsage usage = BufferUsage::StaticDraw;
    /// "position" is sent as float(position - center): pass the centre of a mesh far from the
    /// origin (relative to centre, RTC) and put the centre in the model matrix.
    glm::dvec3 center{0.0};
    /// Index width; empty: 16 bits when every index fits, 32 otherwise.
    std::optional<IndexType> indexType;
};

/// The vertex attributes and index buffer of a draw: one GL vertex array object, move-only. A
/// vertex array belongs to the Context that created it (GL does not share them between contexts)
/// and must be changed and drawn there.
///
/// ```
/// ShaderProgram program = device.createShaderProgram(description);
/// VertexArray va = context.createVertexArray(mesh, program); // attributes matched by name
/// ```
class VertexArray final {
public:
    static constexpr int kMaxAttributes = 16;

    VertexArray() noexcept = default;
    ~VertexArray();
    VertexArray(VertexArray&& other) noexcept;
    VertexArray& operator=(VertexArray&& other) noexcept;
    VertexArray(const VertexArray&) = delete;
    VertexArray& operator=(const VertexArray&) = delete;

    /// Reads attribute `location` from `buffer`. The buffer is not owned: keep it alive while the
    /// array uses it. Throws orbis::Error for a location outside 0..15 or a bad format.
    void setAttribute(int location, const VertexBuffer& buffer, const VertexAttributeFormat& format);
    /// The same for a standard name ("position", "normal", ...); throws for another name.
    void setAttribute(std::string_view standardName, const VertexBuffer& buffer, const VertexAttributeFormat& format);
    void removeAttribute(int location);
    /// Sets or (null) removes the index buffer. Not owned.
    void setIndexBuffer(const IndexBuffer* indexBuffer);

    bool valid() const noexcept { return _name != 0; }
    bool indexed() const noexcept { return _indexCount.has_value(); }
    IndexType indexType() const noexcept { return _indexType; }
    /// Indices in the index buffer; 0 when not indexed.
    std::size_t indexCount() const noexcept { return _indexCount.value_or(0); }
    /// Vertices every attribute can supply (the smallest over the attributes); 0 with none.
    std::size_t vertexCount() const noexcept;
    /// Bit i set when attribute location i is supplied.
    std::uint32_t attributeMask() const noexcept { return _mask; }
    /// The primitive type of the mesh it was made from (Triangles otherwise).
    PrimitiveType meshPrimitiveType() const noexcept { return _meshPrimitiveType; }

private:
    friend class Context;
    friend struct detail::VertexArrayAccess;
    friend struct detail::RawGlBaselineAccess; // the benchmark's raw-GL baseline, bench/RawGlBaseline.cpp
    VertexArray(detail::ContextState& owner, unsigned name) noexcept;
    detail::ContextState& bindForChange(const char* what);

    detail::ContextState* _owner = nullptr;
    unsigned _name = 0;
    std::uint64_t _serial = 0;
    std::uint32_t _mask = 0;
    std::array<std::size_t, kMaxAttributes> _vertexCounts{};
    std::optional<std::size_t> _indexCount;
    IndexType _indexType = IndexType::UnsignedInt;
    PrimitiveType _meshPrimitiveType = PrimitiveType::Triangles;
    // Buffers made from a Mesh belong to the array.
    std::vector<VertexBuffer> _ownedVertexBuffers;
    IndexBuffer _ownedIndexBuffer;
};

} // namespace orbis::renderer
