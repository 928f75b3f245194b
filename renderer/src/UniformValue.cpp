#include "orbis/renderer/UniformValue.h"

namespace orbis {

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

void UniformValues::set(std::string_view name, const UniformValue& value)
{
    for (Entry& entry : _entries) {
        if (entry.name == name) {
            entry.value = value;
            return;
        }
    }
    _entries.push_back({std::string(name), value});
}

const UniformValue* UniformValues::find(std::string_view name) const noexcept
{
    for (const Entry& entry : _entries) {
        if (entry.name == name) {
            return &entry.value;
        }
    }
    return nullptr;
}

bool UniformValues::erase(std::string_view name)
{
    for (auto it = _entries.begin(); it != _entries.end(); ++it) {
        if (it->name == name) {
            _entries.erase(it);
            return true;
        }
    }
    return false;
}

} // namespace orbis
