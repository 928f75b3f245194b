#pragma once

#include <glm/mat2x2.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace orbis::renderer {

namespace detail {
struct UniformValuesAccess;
}

/// The GLSL type of an active uniform, as reflected from a linked program.
enum class UniformType : std::uint8_t {
    Bool, Int, IntVec2, IntVec3, IntVec4, Float, FloatVec2, FloatVec3, FloatVec4,
    FloatMat2, FloatMat3, FloatMat4, Sampler2D, Sampler2DShadow,
    Unsupported ///< a type the setters do not handle (unsigned, bvec, arrays of samplers, ...)
};

/// "vec4", "sampler2D", ... for messages.
const char* uniformTypeName(UniformType type) noexcept;

/// A value for one uniform. Samplers take an int (the texture unit); bool uniforms take a bool
/// or an int.
using UniformValue = std::variant<bool, int, glm::ivec2, glm::ivec3, glm::ivec4, float, glm::vec2, glm::vec3,
                                  glm::vec4, glm::mat2, glm::mat3, glm::mat4>;

/// The uniform type a value of this alternative sets.
UniformType uniformTypeOf(const UniformValue& value) noexcept;

/// A small map from uniform name to value, owned by a DrawCommand; insertion order is kept.
/// Values are stored as GL takes them (ints for bool, column-major floats); the first four inside
/// the map itself, so that drawing a command reads its uniforms from the command's own memory
/// rather than chasing a pointer per command. The names are kept apart, read only the first time a
/// command meets a program.
class UniformValues {
public:
    /// Adds the uniform or replaces its value.
    void set(std::string_view name, const UniformValue& value);
    /// The value; empty when the map has none for name.
    std::optional<UniformValue> find(std::string_view name) const;
    /// Removes the uniform; false when it was absent.
    bool erase(std::string_view name);
    void clear() noexcept;

    std::size_t size() const noexcept { return _count; }
    bool empty() const noexcept { return _count == 0; }
    /// The name and value of the i-th uniform, in insertion order.
    const std::string& name(std::size_t i) const { return _names[i]; }
    UniformValue value(std::size_t i) const;

private:
    friend class Context;
    friend struct detail::UniformValuesAccess;

    struct Entry {
        // Where the last program that drew this entry keeps the uniform: a lookup cache the
        // Context fills, not part of the value.
        mutable std::uint64_t cachedProgramSerial = 0;
        mutable int cachedSlot = -1;
        UniformType type = UniformType::Float;
        std::uint8_t size = 0;     ///< bytes of the value
        std::uint32_t offset = 0;  ///< into _large when size > kInline
        alignas(4) unsigned char inlineBytes[16] = {};
    };
    static constexpr std::size_t kInline = 16;

    static constexpr std::size_t kInlineEntries = 4;

    const unsigned char* bytes(const Entry& entry) const noexcept
    {
        return entry.size > kInline ? _large.data() + entry.offset : entry.inlineBytes;
    }
    const Entry& entry(std::size_t i) const noexcept
    {
        return i < kInlineEntries ? _inlineEntries[i] : _moreEntries[i - kInlineEntries];
    }
    Entry& entry(std::size_t i) noexcept
    {
        return i < kInlineEntries ? _inlineEntries[i] : _moreEntries[i - kInlineEntries];
    }

    std::uint32_t _count = 0;
    Entry _inlineEntries[kInlineEntries];
    std::vector<Entry> _moreEntries;    ///< entries beyond the first four
    std::vector<std::string> _names;    ///< one per entry
    std::vector<unsigned char> _large;  ///< values larger than kInline (mat3, mat4)
};

} // namespace orbis::renderer
