#pragma once

// What the Context needs from a ShaderProgram's internals. Private.

#include "GlApi.h"

#include "orbis/renderer/ShaderProgram.h"

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace orbis::renderer::detail {

/// Who an error message is about, put into words only when an error is thrown (draws are hot).
struct ErrorSource {
    const char* kind;      ///< "DrawCommand", "Context::clear", "shader program"
    std::string_view name; ///< a debug name; may be empty
    std::string text() const
    {
        if (name.empty()) {
            return std::string(kind) + (std::string_view(kind) == "DrawCommand" ? " (unnamed)" : "");
        }
        return std::string(kind) + " '" + std::string(name) + "'";
    }
};

struct ShaderProgramAccess {
    static GLuint handle(const ShaderProgram& p) noexcept { return p._handle; }
    static std::uint64_t serial(const ShaderProgram& p) noexcept { return p._serial; }
    static const Device* device(const ShaderProgram& p) noexcept { return p._device; }
    /// The slot of an active uniform; -1 when there is none.
    static int findSlot(const ShaderProgram& p, std::string_view name) noexcept;
    /// Sets a slot from a value; throws orbis::Error naming `where` for a type mismatch or an
    /// automatic uniform. Returns true when the value changed.
    static bool assign(ShaderProgram& p, int slot, const UniformValue& value, const ErrorSource& where);
    /// Sets a slot from the bytes of a value of type `given` (as UniformValues keeps them); the same
    /// checks as assign.
    static bool assignBytes(ShaderProgram& p, int slot, UniformType given, const void* bytes, std::size_t size,
                            const ErrorSource& where);
    /// Sets a slot from raw bytes of its type; true when they changed.
    static bool assignRaw(ShaderProgram& p, int slot, const void* data, std::size_t size) noexcept;
    static const std::vector<std::pair<int, int>>& automaticSlots(const ShaderProgram& p) noexcept
    {
        return p._automaticSlots;
    }
    static int samplerUnitOfSlot(const ShaderProgram& p, int slot) noexcept;
    static const std::vector<int>& samplerSlots(const ShaderProgram& p) noexcept { return p._samplerSlots; }
    static const std::string& uniformName(const ShaderProgram& p, int slot) noexcept { return p._uniforms[slot].name; }
    /// Throws orbis::Error naming `where` and every uniform that has never been given a value.
    static void checkAllSet(const ShaderProgram& p, const std::string& where);
    static int unsetCount(const ShaderProgram& p) noexcept { return p._unsetCount; }
    /// Marks every value as not yet in GL (after GL calls made outside the renderer).
    static void markAllDirty(ShaderProgram& p);
    /// Sends the changed values to GL; the program must be bound. Returns how many were sent.
    static std::uint64_t flush(ShaderProgram& p, const GlApi& gl);
};

} // namespace orbis::renderer::detail
