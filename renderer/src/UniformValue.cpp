#include "orbis/renderer/UniformValue.h"

#include <cstring>
#include <type_traits>

namespace orbis::renderer {

const char* uniformTypeName(UniformType type) noexcept
{
    switch (type) {
    case UniformType::Bool: return "bool";
    case UniformType::Int: return "int";
    case UniformType::IntVec2: return "ivec2";
    case UniformType::IntVec3: return "ivec3";
    case UniformType::IntVec4: return "ivec4";
    case UniformType::Float: return "float";
    case UniformType::FloatVec2: return "vec2";
    case UniformType::FloatVec3: return "vec3";
    case UniformType::FloatVec4: return "vec4";
    case UniformType::FloatMat2: return "mat2";
    case UniformType::FloatMat3: return "mat3";
    case UniformType::FloatMat4: return "mat4";
    case UniformType::Sampler2D: return "sampler2D";
    case UniformType::Sampler2DShadow: return "sampler2DShadow";
    case UniformType::Unsupported: return "an unsupported type";
    }
    return "an unsupported type";
}

UniformType uniformTypeOf(const UniformValue& value) noexcept
{
    constexpr UniformType byIndex[] = {
        UniformType::Bool,      UniformType::Int,       UniformType::IntVec2,   UniformType::IntVec3,
        UniformType::IntVec4,   UniformType::Float,     UniformType::FloatVec2, UniformType::FloatVec3,
        UniformType::FloatVec4, UniformType::FloatMat2, UniformType::FloatMat3, UniformType::FloatMat4,
    };
    static_assert(std::size(byIndex) == std::variant_size_v<UniformValue>);
    return byIndex[value.index()];
}

namespace {

/// The bytes GL takes for a value (bool as a 32-bit int); returns their count.
std::size_t toBytes(const UniformValue& value, unsigned char* out) noexcept
{
    return std::visit(
        [&](const auto& v) -> std::size_t {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, bool>) {
                const std::int32_t i = v ? 1 : 0;
                std::memcpy(out, &i, sizeof i);
                return sizeof i;
            } else {
                std::memcpy(out, &v, sizeof(T));
                return sizeof(T);
            }
        },
        value);
}

template <typename T>
T fromBytes(const unsigned char* bytes) noexcept
{
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
}

} // namespace

void UniformValues::set(std::string_view name, const UniformValue& value)
{
    alignas(16) unsigned char bytes[64];
    const std::size_t size = toBytes(value, bytes);
    std::size_t index = 0;
    while (index < _names.size() && _names[index] != name) {
        ++index;
    }
    if (index == _names.size()) {
        _names.emplace_back(name);
        if (_count >= kInlineEntries) {
            _moreEntries.emplace_back();
        }
        entry(_count) = Entry{};
        ++_count;
    }
    Entry& entry = this->entry(index);
    const bool reuseLarge = entry.size > kInline && entry.size == size;
    entry.type = uniformTypeOf(value);
    entry.size = static_cast<std::uint8_t>(size);
    if (size <= kInline) {
        std::memcpy(entry.inlineBytes, bytes, size);
    } else {
        if (!reuseLarge) {
            entry.offset = static_cast<std::uint32_t>(_large.size());
            _large.resize(_large.size() + size);
        }
        std::memcpy(_large.data() + entry.offset, bytes, size);
    }
}

UniformValue UniformValues::value(std::size_t i) const
{
    const Entry& e = entry(i);
    const unsigned char* b = bytes(e);
    switch (e.type) {
    case UniformType::Bool: return fromBytes<std::int32_t>(b) != 0;
    case UniformType::Int: return fromBytes<int>(b);
    case UniformType::IntVec2: return fromBytes<glm::ivec2>(b);
    case UniformType::IntVec3: return fromBytes<glm::ivec3>(b);
    case UniformType::IntVec4: return fromBytes<glm::ivec4>(b);
    case UniformType::Float: return fromBytes<float>(b);
    case UniformType::FloatVec2: return fromBytes<glm::vec2>(b);
    case UniformType::FloatVec3: return fromBytes<glm::vec3>(b);
    case UniformType::FloatVec4: return fromBytes<glm::vec4>(b);
    case UniformType::FloatMat2: return fromBytes<glm::mat2>(b);
    case UniformType::FloatMat3: return fromBytes<glm::mat3>(b);
    case UniformType::FloatMat4: return fromBytes<glm::mat4>(b);
    default: return fromBytes<float>(b);
    }
}

std::optional<UniformValue> UniformValues::find(std::string_view name) const
{
    for (std::size_t i = 0; i < _names.size(); ++i) {
        if (_names[i] == name) {
            return value(i);
        }
    }
    return std::nullopt;
}

bool UniformValues::erase(std::string_view name)
{
    for (std::size_t i = 0; i < _names.size(); ++i) {
        if (_names[i] == name) {
            // The bytes of a large value stay in _large, unused, until clear().
            _names.erase(_names.begin() + static_cast<std::ptrdiff_t>(i));
            for (std::size_t k = i; k + 1 < _count; ++k) {
                entry(k) = entry(k + 1);
            }
            --_count;
            if (_count >= kInlineEntries) {
                _moreEntries.pop_back();
            }
            return true;
        }
    }
    return false;
}

void UniformValues::clear() noexcept
{
    _count = 0;
    _moreEntries.clear();
    _names.clear();
    _large.clear();
}

} // namespace orbis::renderer
