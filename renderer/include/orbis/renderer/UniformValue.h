#pragma once

#include <glm/mat2x2.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace orbis {

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
class UniformValues {
public:
    struct Entry {
        std::string name;
        UniformValue value;
        // Where the last program that drew this entry keeps the uniform (a lookup cache the
        // Context fills; not part of the value).
        mutable std::uint64_t cachedProgramSerial = 0;
        mutable int cachedSlot = -1;
    };

    /// Adds the uniform or replaces its value.
    void set(std::string_view name, const UniformValue& value);
    /// The value, or null when the map has none for name.
    const UniformValue* find(std::string_view name) const noexcept;
    /// Removes the uniform; false when it was absent.
    bool erase(std::string_view name);
    void clear() noexcept { _entries.clear(); }

    std::size_t size() const noexcept { return _entries.size(); }
    bool empty() const noexcept { return _entries.empty(); }
    std::vector<Entry>::const_iterator begin() const noexcept { return _entries.begin(); }
    std::vector<Entry>::const_iterator end() const noexcept { return _entries.end(); }

private:
    std::vector<Entry> _entries;
};

} // namespace orbis
