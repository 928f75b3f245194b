#pragma once

#include "orbis/renderer/UniformValue.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace orbis::renderer {

class Device;
namespace detail {
class ContextState;
struct ShaderProgramAccess;
} // namespace detail

/// The text of one shader stage and the name its errors are reported under.
struct ShaderSource {
    std::string name; ///< for messages: the file ("shaders/scene/globe/globe.vert.glsl") or a name given
    std::string text; ///< GLSL; a `#version` line is ignored: the renderer puts `#version 330 core` first

    /// A file a library or program embedded at build time (orbis_embed_shaders, EmbeddedShaders.h),
    /// by its embedded path ("examples/triangle/triangle.vert.glsl"). Throws orbis::Error naming the
    /// path when no library or program of the process embedded one.
    static ShaderSource embedded(std::string_view path);
    /// A file read now, named by its path in messages. Throws orbis::Error naming the file when it
    /// cannot be opened or read.
    static ShaderSource fromFile(const std::filesystem::path& path);
    static ShaderSource fromText(std::string name, std::string text);
};

/// A preprocessor definition put before a program's sources: "#define name value".
struct ShaderDefine {
    std::string name;
    std::string value = "1";
    friend bool operator==(const ShaderDefine&, const ShaderDefine&) = default;
};

/// Everything a program is built from. Two descriptions with the same cacheKey() build the same
/// program.
struct ShaderProgramDescription {
    std::string name; ///< for messages; empty: the vertex shader's name
    ShaderSource vertex;
    std::optional<ShaderSource> geometry;
    ShaderSource fragment;
    std::vector<ShaderDefine> defines;
    /// GLSL extensions each stage requires (`#extension NAME : require` after `#version`), e.g.
    /// "GL_ARB_gpu_shader5" for `precise` (DeviceInfo::gpuShader5 says whether it is there).
    std::vector<std::string> extensions;
    /// Vertex (or geometry) shader outputs that Context::captureVertexOutputs reads back,
    /// interleaved in this order; built-ins such as "gl_Position" included. Float types only.
    std::vector<std::string> transformFeedbackVaryings;
    /// Prepend the built-in GLSL library (shaders/renderer/builtin: og_pi, og_... functions). Each
    /// stage also gets OG_VERTEX_SHADER, OG_GEOMETRY_SHADER or OG_FRAGMENT_SHADER defined.
    bool builtinLibrary = true;

    /// Sources, defines and options, joined; the shader cache's key.
    std::string cacheKey() const;
};

/// An active vertex attribute of a linked program.
struct ShaderVertexAttribute {
    std::string name;
    int location = -1;
    UniformType type = UniformType::Unsupported; ///< float, vec2..vec4, int, ivec2..ivec4, matN
};

/// An active uniform of a linked program.
struct ShaderUniform {
    std::string name;
    int location = -1;
    UniformType type = UniformType::Unsupported;
    int arraySize = 1;
    bool automatic = false; ///< an og_ uniform the Context sets at draw time
};

/// Vertex, optional geometry, and fragment shaders compiled and linked: one GL program object,
/// move-only, shared between the device's contexts. Built by Device::createShaderProgram (or the
/// Device's ShaderCache). Compile errors name the file and line ("shaders/x.frag.glsl:12:...").
///
/// Uniform values are kept here and sent to GL at draw time, only those that changed. Automatic
/// uniforms (og_modelViewProjectionMatrix, og_cameraEyeHigh, ... see docs/renderer.md) are filled by
/// the Context from the SceneState; sampler uniforms named og_textureN are set to unit N. Every
/// other active uniform must have been given a value before the first draw.
///
/// ```
/// ShaderProgramDescription description;
/// description.vertex = ShaderSource::embedded("examples/triangle/triangle.vert.glsl");
/// description.fragment = ShaderSource::embedded("examples/triangle/triangle.frag.glsl");
/// ShaderProgram program = device.createShaderProgram(description);
/// program.setUniform("u_color", glm::vec4(1, 0.5f, 0, 1));
/// ```
class ShaderProgram final {
public:
    ShaderProgram() noexcept = default;
    ~ShaderProgram();
    ShaderProgram(ShaderProgram&& other) noexcept;
    ShaderProgram& operator=(ShaderProgram&& other) noexcept;
    ShaderProgram(const ShaderProgram&) = delete;
    ShaderProgram& operator=(const ShaderProgram&) = delete;

    const std::string& name() const noexcept { return _name; }
    bool valid() const noexcept { return _handle != 0; }

    const std::vector<ShaderVertexAttribute>& vertexAttributes() const noexcept { return _attributes; }
    const std::vector<ShaderUniform>& uniforms() const noexcept { return _uniforms; }
    /// Null when the program has no active attribute of that name.
    const ShaderVertexAttribute* findVertexAttribute(std::string_view name) const noexcept;
    /// False also for uniforms declared but unused: the GLSL compiler removes those.
    bool hasUniform(std::string_view name) const noexcept;
    /// Bit i set when the program reads attribute location i.
    std::uint32_t attributeMask() const noexcept { return _attributeMask; }
    /// Floats per vertex that Context::captureVertexOutputs returns: 0 for a program built without
    /// transformFeedbackVaryings.
    int capturedComponents() const noexcept { return _capturedComponents; }

    /// The index of an active uniform for the fast setter; throws orbis::Error naming the program,
    /// the uniform and the active ones when it is not active.
    int uniformIndex(std::string_view name) const;
    /// Sets a uniform's value; nothing is sent to GL when it equals the current value. Throws
    /// orbis::Error when the uniform is not active, is automatic, or has another type. Returns true
    /// when the value changed.
    bool setUniform(std::string_view name, const UniformValue& value);
    bool setUniform(int index, const UniformValue& value);

    /// Sets the first values.size() elements of a uniform array (float, int, their vectors and the
    /// matrices), keeping the others; nothing is sent to GL when they are unchanged. Values past the
    /// active size are dropped: drivers may report an array only as long as its last element used.
    /// Arrays are set here, on the program, not in DrawCommand::uniforms. Throws orbis::Error when
    /// the uniform is not an active array of that element type, or values is empty. Returns true
    /// when the values changed.
    template <class T>
    bool setUniformArray(std::string_view name, std::span<const T> values)
    {
        static_assert(!std::is_same_v<T, bool>, "bool arrays: pass ints");
        return setUniformArrayBytes(name, uniformTypeOf(UniformValue(T{})), values.data(), sizeof(T), values.size());
    }

private:
    friend class Device;
    friend struct detail::ShaderProgramAccess;

    bool setUniformArrayBytes(std::string_view name, UniformType type, const void* values, std::size_t elementSize,
                              std::size_t count);

    struct Slot {
        int location = -1;
        UniformType type = UniformType::Unsupported;
        int count = 1; ///< elements: more than one for an array, whose values live in arrayValue
        int automatic = -1; ///< an AutomaticUniform, or -1
        bool settable = false; ///< by the application: not automatic, a single value of a supported type
        bool hasValue = false;
        bool dirty = false;
        alignas(16) unsigned char value[64] = {};
        std::vector<unsigned char> arrayValue; ///< count elements, as glUniform*v takes them

        /// Where the value lives: inline for one element, arrayValue for an array.
        unsigned char* bytes() noexcept { return count == 1 ? value : arrayValue.data(); }
        const unsigned char* bytes() const noexcept { return count == 1 ? value : arrayValue.data(); }
    };

    Device* _device = nullptr;
    unsigned _handle = 0;
    std::uint64_t _serial = 0;
    std::string _name;
    std::vector<ShaderVertexAttribute> _attributes;
    std::vector<ShaderUniform> _uniforms;
    std::vector<Slot> _slots;           ///< parallel to _uniforms
    std::vector<int> _dirtySlots;       ///< slots whose value GL does not have yet
    std::vector<std::pair<int, int>> _automaticSlots; ///< (AutomaticUniform, slot)
    std::vector<int> _samplerSlots;     ///< slots of sampler uniforms
    int _unsetCount = 0;                ///< non-automatic slots without a value
    std::uint32_t _attributeMask = 0;
    int _capturedComponents = 0;
};

} // namespace orbis::renderer
