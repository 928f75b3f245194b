#include "orbis/renderer/ShaderProgram.h"

#include "AutomaticUniforms.h"
#include "ContextState.h"
#include "ShaderProgramAccess.h"

#include "orbis/core/Error.h"
#include "orbis/renderer/Device.h"
#include "orbis/renderer/EmbeddedShaders.h"
#include "orbis/renderer/VertexArray.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>

namespace orbis::renderer {
namespace {

using detail::ShaderProgramAccess;

/// The built-in GLSL library, prepended (after #version and the defines) on request.
constexpr const char* kBuiltinLibrary[] = {"renderer/builtin/constants.glsl", "renderer/builtin/functions.glsl",
                                           "renderer/builtin/vertex_transform.glsl", "renderer/builtin/depth.glsl"};

const char* stageName(GLenum stage)
{
    switch (stage) {
    case GL_VERTEX_SHADER: return "vertex";
    case GL_GEOMETRY_SHADER: return "geometry";
    default: return "fragment";
    }
}

/// Comments out #version lines (the renderer writes its own) without changing line numbers.
std::string withoutVersion(const std::string& text)
{
    std::string result;
    result.reserve(text.size() + 8);
    std::istringstream lines(text);
    std::string line;
    while (std::getline(lines, line)) {
        const std::size_t start = line.find_first_not_of(" \t");
        if (start != std::string::npos && line.compare(start, 8, "#version") == 0) {
            result += "// " + line.substr(start + 1) + "\n";
        } else {
            result += line + "\n";
        }
    }
    return result;
}

/// Lines of the strings before the stage's own file start at kLineBlock x their index (after
/// "#line"), so that a driver's line number alone says which file it is in: Mesa reports source
/// string 0 for most errors whatever #line said.
constexpr long kLineBlock = 100000;

/// Rewrites the driver's "<string>:<line>(<column>): message" lines (Mesa; NVIDIA's
/// "<string>(<line>) : message" and "ERROR: <string>:<line>: message" too) as
/// "<file>:<line>:<column>: message". `names[k]` is the file of line block k; lines below
/// kLineBlock are the stage's own file, `ownName`.
std::string mapLog(const std::string& log, const std::vector<std::string>& names, const std::string& ownName)
{
    static const std::regex mesa(R"(^\s*(\d+):(\d+)\((\d+)\):\s*(.*)$)");
    static const std::regex nvidia(R"(^\s*(\d+)\((\d+)\)\s*:\s*(.*)$)");
    static const std::regex generic(R"(^\s*(ERROR|WARNING):\s*(\d+):(\d+):\s*(.*)$)");
    auto location = [&](const std::string& lineText) {
        const long line = std::stol(lineText);
        const long block = line / kLineBlock;
        if (block == 0) {
            return ownName + ":" + std::to_string(line);
        }
        const std::string& name = block < static_cast<long>(names.size()) ? names[block] : ownName;
        return name + ":" + std::to_string(line % kLineBlock);
    };
    std::string mapped;
    std::istringstream lines(log);
    std::string line;
    while (std::getline(lines, line)) {
        if (!line.empty() && line.back() == '\r') {
            line.pop_back();
        }
        if (line.find_first_not_of(" \t") == std::string::npos) {
            continue;
        }
        std::smatch m;
        if (std::regex_match(line, m, mesa)) {
            mapped += location(m[2]) + ":" + m[3].str() + ": " + m[4].str() + "\n";
        } else if (std::regex_match(line, m, nvidia)) {
            mapped += location(m[2]) + ": " + m[3].str() + "\n";
        } else if (std::regex_match(line, m, generic)) {
            std::string kind = m[1].str() == "ERROR" ? "error" : "warning";
            mapped += location(m[3]) + ": " + kind + ": " + m[4].str() + "\n";
        } else {
            mapped += line + "\n";
        }
    }
    return mapped;
}

std::string shaderLog(const detail::GlApi& gl, GLuint shader)
{
    GLint length = 0;
    gl.glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    gl.glGetShaderInfoLog(shader, length, nullptr, log.data());
    log.resize(std::strlen(log.c_str()));
    return log;
}

std::string programLog(const detail::GlApi& gl, GLuint program)
{
    GLint length = 0;
    gl.glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    gl.glGetProgramInfoLog(program, length, nullptr, log.data());
    log.resize(std::strlen(log.c_str()));
    return log;
}

struct CompiledShader {
    const detail::GlApi& gl;
    GLuint name = 0;
    ~CompiledShader()
    {
        if (name) {
            gl.glDeleteShader.unchecked(name);
        }
    }
};

GLuint compile(const detail::GlApi& gl, GLenum stage, const ShaderSource& source,
               const ShaderProgramDescription& description, const std::string& programName)
{
    // Source string 0: version and defines; then the library files; then the stage's file. Each
    // starts with "#line <first> <n>": the stage's file at line 1, the others at kLineBlock x n + 1,
    // so that the driver's messages say which file and line (see mapLog).
    std::vector<std::string> names;
    std::vector<std::string> texts;
    auto lineDirective = [&](std::size_t index) {
        return "#line " + std::to_string(static_cast<long>(index) * kLineBlock + 1) + " " + std::to_string(index) + "\n";
    };
    // The defines get block 9: block 0 is the stage's file.
    constexpr std::size_t kDefinesBlock = 9;
    names.push_back("<" + programName + " defines>");
    std::string preamble = "#version 330 core\n";
    for (const std::string& extension : description.extensions) {
        preamble += "#extension " + extension + " : require\n";
    }
    preamble += "#line " + std::to_string(kDefinesBlock * kLineBlock + 1) + " 0\n";
    preamble += stage == GL_VERTEX_SHADER     ? "#define OG_VERTEX_SHADER 1\n"
                : stage == GL_GEOMETRY_SHADER ? "#define OG_GEOMETRY_SHADER 1\n"
                                              : "#define OG_FRAGMENT_SHADER 1\n";
    for (const ShaderDefine& define : description.defines) {
        preamble += "#define " + define.name + " " + define.value + "\n";
    }
    texts.push_back(std::move(preamble));
    if (description.builtinLibrary) {
        for (const char* path : kBuiltinLibrary) {
            const EmbeddedShaderFile* file = findEmbeddedShader(path);
            if (!file) {
                throw Error(std::string("shaders/") + path + ": the built-in GLSL library was not embedded");
            }
            names.push_back(file->source);
            texts.push_back(lineDirective(names.size() - 1) + file->text + "\n");
        }
    }
    names.push_back(source.name);
    texts.push_back("#line 1 " + std::to_string(names.size() - 1) + "\n" + withoutVersion(source.text));
    names.resize(kDefinesBlock + 1, source.name);
    names[kDefinesBlock] = "<" + programName + " defines>";

    std::vector<const GLchar*> pointers;
    std::vector<GLint> lengths;
    for (const std::string& text : texts) {
        pointers.push_back(text.c_str());
        lengths.push_back(static_cast<GLint>(text.size()));
    }
    const GLuint shader = gl.glCreateShader(stage);
    gl.glShaderSource(shader, static_cast<GLsizei>(pointers.size()), pointers.data(), lengths.data());
    gl.glCompileShader(shader);
    GLint ok = GL_FALSE;
    gl.glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        const std::string log = shaderLog(gl, shader);
        gl.glDeleteShader(shader);
        throw Error("shader program '" + programName + "': the " + stageName(stage) + " shader " + source.name +
                    " does not compile:\n" + mapLog(log, names, source.name));
    }
    return shader;
}

UniformType fromGl(GLenum type) noexcept
{
    switch (type) {
    case GL_BOOL: return UniformType::Bool;
    case GL_INT: return UniformType::Int;
    case GL_INT_VEC2: return UniformType::IntVec2;
    case GL_INT_VEC3: return UniformType::IntVec3;
    case GL_INT_VEC4: return UniformType::IntVec4;
    case GL_FLOAT: return UniformType::Float;
    case GL_FLOAT_VEC2: return UniformType::FloatVec2;
    case GL_FLOAT_VEC3: return UniformType::FloatVec3;
    case GL_FLOAT_VEC4: return UniformType::FloatVec4;
    case GL_FLOAT_MAT2: return UniformType::FloatMat2;
    case GL_FLOAT_MAT3: return UniformType::FloatMat3;
    case GL_FLOAT_MAT4: return UniformType::FloatMat4;
    case GL_SAMPLER_2D: return UniformType::Sampler2D;
    case GL_SAMPLER_2D_SHADOW: return UniformType::Sampler2DShadow;
    default: return UniformType::Unsupported;
    }
}

bool isSampler(UniformType type) noexcept
{
    return type == UniformType::Sampler2D || type == UniformType::Sampler2DShadow;
}

/// Bytes of one value of a settable type, as glUniform*v reads it.
std::size_t elementSize(UniformType type) noexcept
{
    switch (type) {
    case UniformType::Bool:
    case UniformType::Int:
    case UniformType::Float:
    case UniformType::Sampler2D:
    case UniformType::Sampler2DShadow: return 4;
    case UniformType::IntVec2:
    case UniformType::FloatVec2: return 8;
    case UniformType::IntVec3:
    case UniformType::FloatVec3: return 12;
    case UniformType::IntVec4:
    case UniformType::FloatVec4:
    case UniformType::FloatMat2: return 16;
    case UniformType::FloatMat3: return 36;
    case UniformType::FloatMat4: return 64;
    case UniformType::Unsupported: return 0;
    }
    return 0;
}

/// og_texture0, og_texture1, ...: the unit in the name; -1 for other names.
int ogTextureUnit(std::string_view name) noexcept
{
    constexpr std::string_view prefix = "og_texture";
    if (name.substr(0, prefix.size()) != prefix || name.size() == prefix.size() || name.size() > prefix.size() + 2) {
        return -1;
    }
    int unit = 0;
    for (char c : name.substr(prefix.size())) {
        if (c < '0' || c > '9') {
            return -1;
        }
        unit = unit * 10 + (c - '0');
    }
    return unit;
}

std::string activeUniformList(const std::vector<ShaderUniform>& uniforms)
{
    std::string list;
    for (const ShaderUniform& u : uniforms) {
        list += (list.empty() ? "" : ", ") + u.name;
    }
    return list.empty() ? "none" : list;
}

} // namespace

ShaderSource ShaderSource::embedded(std::string_view path)
{
    const EmbeddedShaderFile* file = findEmbeddedShader(path);
    if (!file) {
        throw Error("shaders/" + std::string(path) +
                    ": no such embedded shader (a library or program embeds its shader folder at build time "
                    "with orbis_embed_shaders; read other files with ShaderSource::fromFile)");
    }
    return {file->source, file->text};
}

ShaderSource ShaderSource::fromFile(const std::filesystem::path& path)
{
    std::error_code ignored;
    if (std::filesystem::is_directory(path, ignored)) {
        throw Error(path.string() + ": cannot read a folder as a shader file");
    }
    if (std::filesystem::exists(path, ignored) && !std::filesystem::is_regular_file(path, ignored)) {
        throw Error(path.string() + ": cannot read the shader file: not a regular file"); // a pipe would block
    }
    std::ifstream file(path, std::ios::binary);
    if (!file) {
        const int error = errno;
        throw Error(path.string() + ": cannot open the shader file (" + std::strerror(error) + ")");
    }
    std::ostringstream text;
    text << file.rdbuf();
    if (file.bad()) {
        throw Error(path.string() + ": cannot read the shader file");
    }
    return {path.string(), text.str()};
}

ShaderSource ShaderSource::fromText(std::string name, std::string text)
{
    return {std::move(name), std::move(text)};
}

std::string ShaderProgramDescription::cacheKey() const
{
    // Lengths before each part keep "ab"+"c" and "a"+"bc" apart.
    std::string key;
    auto add = [&](const std::string& part) {
        key += std::to_string(part.size());
        key += ':';
        key += part;
    };
    add(vertex.text);
    add(geometry ? geometry->text : std::string("\x01none"));
    add(fragment.text);
    for (const ShaderDefine& define : defines) {
        add(define.name);
        add(define.value);
    }
    key += builtinLibrary ? "|lib" : "|nolib";
    for (const std::string& extension : extensions) {
        add("#extension");
        add(extension);
    }
    for (const std::string& varying : transformFeedbackVaryings) {
        add("#capture");
        add(varying);
    }
    return key;
}

namespace {

/// Compiles the description's stages and links them into `handle`, with the standard attribute
/// locations and the transform-feedback outputs. Throws orbis::Error with the compiler's or the
/// linker's log, naming the files.
void linkProgram(const detail::GlApi& gl, GLuint handle, const ShaderProgramDescription& description,
                 const std::string& programName)
{
    if (description.vertex.text.empty() || description.fragment.text.empty()) {
        throw Error("shader program '" + programName + "': the " +
                    (description.vertex.text.empty() ? "vertex" : "fragment") + " shader " +
                    (description.vertex.text.empty() ? description.vertex.name : description.fragment.name) +
                    " is empty");
    }
    CompiledShader vertex{gl, compile(gl, GL_VERTEX_SHADER, description.vertex, description, programName)};
    CompiledShader geometry{gl, description.geometry
                                    ? compile(gl, GL_GEOMETRY_SHADER, *description.geometry, description, programName)
                                    : 0u};
    CompiledShader fragment{gl, compile(gl, GL_FRAGMENT_SHADER, description.fragment, description, programName)};
    gl.glAttachShader(handle, vertex.name);
    if (geometry.name) {
        gl.glAttachShader(handle, geometry.name);
    }
    gl.glAttachShader(handle, fragment.name);
    // The standard attribute names get fixed locations so that one vertex array fits every program.
    for (int location = 0; location < VertexArray::kMaxAttributes; ++location) {
        const std::string_view standard = standardAttributeName(location);
        if (!standard.empty()) {
            gl.glBindAttribLocation(handle, static_cast<GLuint>(location), std::string(standard).c_str());
        }
    }
    if (!description.transformFeedbackVaryings.empty()) {
        std::vector<const GLchar*> varyings;
        for (const std::string& varying : description.transformFeedbackVaryings) {
            varyings.push_back(varying.c_str());
        }
        gl.glTransformFeedbackVaryings(handle, static_cast<GLsizei>(varyings.size()), varyings.data(),
                                       GL_INTERLEAVED_ATTRIBS);
    }
    gl.glLinkProgram(handle);
    gl.glDetachShader(handle, vertex.name);
    if (geometry.name) {
        gl.glDetachShader(handle, geometry.name);
    }
    gl.glDetachShader(handle, fragment.name);
    GLint linked = GL_FALSE;
    gl.glGetProgramiv(handle, GL_LINK_STATUS, &linked);
    if (!linked) {
        std::string files = description.vertex.name;
        if (description.geometry) {
            files += ", " + description.geometry->name;
        }
        files += ", " + description.fragment.name;
        throw Error("shader program '" + programName + "' (" + files + ") does not link:\n" + programLog(gl, handle));
    }
}

/// What transform feedback captures, in floats per vertex.
int capturedComponents(const detail::GlApi& gl, GLuint handle, const ShaderProgramDescription& description,
                       const std::string& programName)
{
    int total = 0;
    for (std::size_t i = 0; i < description.transformFeedbackVaryings.size(); ++i) {
        GLchar varyingName[256];
        GLsizei length = 0;
        GLsizei size = 0;
        GLenum type = 0;
        gl.glGetTransformFeedbackVarying(handle, static_cast<GLuint>(i), sizeof varyingName, &length, &size, &type,
                                         varyingName);
        int components = 0;
        switch (type) {
        case GL_FLOAT: components = 1; break;
        case GL_FLOAT_VEC2: components = 2; break;
        case GL_FLOAT_VEC3: components = 3; break;
        case GL_FLOAT_VEC4: components = 4; break;
        default:
            throw Error("shader program '" + programName + "': captured output " +
                        description.transformFeedbackVaryings[i] + " is not a float, vec2, vec3 or vec4");
        }
        total += components * size;
    }
    return total;
}

/// The active vertex attributes (built-ins left out), by location.
std::vector<ShaderVertexAttribute> activeAttributes(const detail::GlApi& gl, GLuint handle)
{
    GLint count = 0;
    GLint maxLength = 0;
    gl.glGetProgramiv(handle, GL_ACTIVE_ATTRIBUTES, &count);
    gl.glGetProgramiv(handle, GL_ACTIVE_ATTRIBUTE_MAX_LENGTH, &maxLength);
    std::vector<GLchar> nameBuffer(static_cast<std::size_t>(std::max(maxLength, 1)) + 1);
    std::vector<ShaderVertexAttribute> attributes;
    for (GLint i = 0; i < count; ++i) {
        GLsizei length = 0;
        GLint size = 0;
        GLenum type = 0;
        gl.glGetActiveAttrib(handle, static_cast<GLuint>(i), static_cast<GLsizei>(nameBuffer.size()), &length, &size,
                             &type, nameBuffer.data());
        std::string name(nameBuffer.data(), static_cast<std::size_t>(length));
        if (name.rfind("gl_", 0) == 0) {
            continue;
        }
        attributes.push_back({name, gl.glGetAttribLocation(handle, name.c_str()), fromGl(type)});
    }
    std::sort(attributes.begin(), attributes.end(),
              [](const ShaderVertexAttribute& a, const ShaderVertexAttribute& b) { return a.location < b.location; });
    return attributes;
}

/// The active uniforms of the default block (blocks are not supported yet), arrays named without
/// their "[0]"; `automatic` not yet decided.
std::vector<ShaderUniform> activeUniforms(const detail::GlApi& gl, GLuint handle)
{
    GLint count = 0;
    GLint maxLength = 0;
    gl.glGetProgramiv(handle, GL_ACTIVE_UNIFORMS, &count);
    gl.glGetProgramiv(handle, GL_ACTIVE_UNIFORM_MAX_LENGTH, &maxLength);
    std::vector<GLchar> nameBuffer(static_cast<std::size_t>(std::max(maxLength, 1)) + 1, 0);
    std::vector<ShaderUniform> uniforms;
    for (GLint i = 0; i < count; ++i) {
        GLsizei length = 0;
        GLint size = 0;
        GLenum type = 0;
        gl.glGetActiveUniform(handle, static_cast<GLuint>(i), static_cast<GLsizei>(nameBuffer.size()), &length, &size,
                              &type, nameBuffer.data());
        std::string name(nameBuffer.data(), static_cast<std::size_t>(length));
        const GLint location = gl.glGetUniformLocation(handle, name.c_str());
        if (location < 0) {
            continue; // a uniform-block member
        }
        if (name.size() > 3 && name.compare(name.size() - 3, 3, "[0]") == 0) {
            name.resize(name.size() - 3);
        }
        uniforms.push_back({name, location, fromGl(type), size, false});
    }
    return uniforms;
}

/// The automatic uniform an og_ uniform (other than og_textureN) is; throws orbis::Error for a name
/// that is none, or the wrong type.
int automaticUniformOf(const ShaderUniform& uniform, const std::string& programName)
{
    const int id = detail::automaticUniformId(uniform.name);
    if (id < 0) {
        std::string known;
        for (const detail::AutomaticUniformInfo& info : detail::kAutomaticUniforms) {
            known += std::string(known.empty() ? "" : ", ") + info.name;
        }
        throw Error("shader program '" + programName + "': uniform " + uniform.name +
                    " uses the og_ prefix kept for automatic uniforms but is not one (they are " + known +
                    ", og_texture0.." + std::to_string(detail::kMaxTrackedTextureUnits - 2) + ")");
    }
    const UniformType expected = detail::kAutomaticUniforms[id].type;
    if (uniform.type != expected || uniform.arraySize != 1) {
        throw Error("shader program '" + programName + "': automatic uniform " + uniform.name + " must be " +
                    uniformTypeName(expected) + ", not " + uniformTypeName(uniform.type) +
                    (uniform.arraySize != 1 ? " array" : ""));
    }
    return id;
}

} // namespace

ShaderProgram Device::createShaderProgram(const ShaderProgramDescription& description)
{
    detail::ContextState& state = detail::requireCurrent(this, "Device::createShaderProgram");
    const detail::GlApi& gl = state.gl;
    const std::string programName = description.name.empty() ? description.vertex.name : description.name;

    ShaderProgram program;
    program._device = this;
    program._handle = gl.glCreateProgram(); // deleted by the program's destructor if a step below throws
    program._serial = detail::nextObjectSerial();
    program._name = programName;
    const GLuint handle = program._handle;
    linkProgram(gl, handle, description, programName);
    program._capturedComponents = capturedComponents(gl, handle, description, programName);
    program._attributes = activeAttributes(gl, handle);
    for (const ShaderVertexAttribute& attribute : program._attributes) {
        if (attribute.location >= 0 && attribute.location < 32) {
            program._attributeMask |= 1u << attribute.location;
        }
    }

    // A slot per uniform: automatic ones set by the Context at draw time, the others by the user.
    for (ShaderUniform& uniform : activeUniforms(gl, handle)) {
        ShaderProgram::Slot slot;
        slot.location = uniform.location;
        slot.type = uniform.type;
        const int textureUnit = ogTextureUnit(uniform.name);
        if (uniform.name.rfind("og_", 0) == 0) {
            uniform.automatic = true;
            if (textureUnit >= 0 && isSampler(uniform.type)) {
                // og_textureN reads texture unit N: set once, here.
                const GLint unit = textureUnit;
                std::memcpy(slot.value, &unit, sizeof unit);
                slot.hasValue = true;
                slot.dirty = true;
            } else {
                slot.automatic = automaticUniformOf(uniform, programName);
                program._automaticSlots.emplace_back(slot.automatic, static_cast<int>(program._uniforms.size()));
            }
        } else if (uniform.type == UniformType::Unsupported || (uniform.arraySize != 1 && isSampler(uniform.type))) {
            slot.hasValue = true; // not settable (other types, sampler arrays): GL's zero stays
        } else {
            slot.settable = true;
            slot.count = uniform.arraySize;
            if (uniform.arraySize != 1) {
                slot.arrayValue.assign(static_cast<std::size_t>(uniform.arraySize) * elementSize(uniform.type), 0);
            }
            ++program._unsetCount;
        }
        if (isSampler(uniform.type)) {
            program._samplerSlots.push_back(static_cast<int>(program._uniforms.size()));
        }
        if (slot.dirty) {
            program._dirtySlots.push_back(static_cast<int>(program._uniforms.size()));
        }
        program._uniforms.push_back(std::move(uniform));
        program._slots.push_back(slot);
    }
    if (gl.glObjectLabel) {
        gl.glObjectLabel(GL_PROGRAM, handle, static_cast<GLsizei>(programName.size()), programName.c_str());
    }
    return program;
}

ShaderProgram::~ShaderProgram()
{
    if (_handle) {
        if (detail::ContextState* state = detail::currentStateOf(_device)) {
            state->gl.glDeleteProgram.unchecked(_handle);
        }
    }
}

ShaderProgram::ShaderProgram(ShaderProgram&& other) noexcept
    : _device(other._device)
    , _handle(std::exchange(other._handle, 0))
    , _serial(std::exchange(other._serial, 0))
    , _name(std::move(other._name))
    , _attributes(std::move(other._attributes))
    , _uniforms(std::move(other._uniforms))
    , _slots(std::move(other._slots))
    , _dirtySlots(std::move(other._dirtySlots))
    , _automaticSlots(std::move(other._automaticSlots))
    , _samplerSlots(std::move(other._samplerSlots))
    , _unsetCount(std::exchange(other._unsetCount, 0))
    , _attributeMask(std::exchange(other._attributeMask, 0u))
    , _capturedComponents(std::exchange(other._capturedComponents, 0))
{
}

ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept
{
    if (this != &other) {
        ShaderProgram moved(std::move(other));
        std::swap(_device, moved._device);
        std::swap(_handle, moved._handle);
        std::swap(_serial, moved._serial);
        std::swap(_name, moved._name);
        std::swap(_attributes, moved._attributes);
        std::swap(_uniforms, moved._uniforms);
        std::swap(_slots, moved._slots);
        std::swap(_dirtySlots, moved._dirtySlots);
        std::swap(_automaticSlots, moved._automaticSlots);
        std::swap(_samplerSlots, moved._samplerSlots);
        std::swap(_unsetCount, moved._unsetCount);
        std::swap(_attributeMask, moved._attributeMask);
        std::swap(_capturedComponents, moved._capturedComponents);
    }
    return *this;
}

const ShaderVertexAttribute* ShaderProgram::findVertexAttribute(std::string_view name) const noexcept
{
    for (const ShaderVertexAttribute& attribute : _attributes) {
        if (attribute.name == name) {
            return &attribute;
        }
    }
    return nullptr;
}

bool ShaderProgram::hasUniform(std::string_view name) const noexcept
{
    return ShaderProgramAccess::findSlot(*this, name) >= 0;
}

int ShaderProgram::uniformIndex(std::string_view name) const
{
    const int slot = ShaderProgramAccess::findSlot(*this, name);
    if (slot < 0) {
        throw Error("shader program '" + _name + "' has no active uniform " + std::string(name) +
                    " (active: " + activeUniformList(_uniforms) +
                    "; a uniform the shaders declare but never use is removed by the GLSL compiler)");
    }
    return slot;
}

bool ShaderProgram::setUniform(std::string_view name, const UniformValue& value)
{
    return setUniform(uniformIndex(name), value);
}

bool ShaderProgram::setUniformArrayBytes(std::string_view name, UniformType type, const void* values,
                                         std::size_t elementSize, std::size_t count)
{
    const int index = ShaderProgramAccess::findSlot(*this, name);
    const std::string where = "shader program '" + _name + "': uniform " + std::string(name);
    if (index < 0) {
        throw Error(where + " is not an active uniform");
    }
    const Slot& slot = _slots[static_cast<std::size_t>(index)];
    if (slot.count == 1 || !slot.settable) {
        throw Error(where + (slot.count == 1 ? " is not an array: set it with setUniform"
                                             : " is an array that cannot be set (samplers are set by unit)"));
    }
    if (type != slot.type && !(type == UniformType::Int && slot.type == UniformType::Bool)) {
        throw Error(where + " is an array of " + uniformTypeName(slot.type) + ", not of " + uniformTypeName(type));
    }
    if (count == 0) {
        throw Error(where + ": no values given");
    }
    const std::size_t bytes = std::min(count, static_cast<std::size_t>(slot.count)) * elementSize;
    return ShaderProgramAccess::assignRaw(*this, index, values, bytes);
}

bool ShaderProgram::setUniform(int index, const UniformValue& value)
{
    if (index < 0 || index >= static_cast<int>(_slots.size())) {
        throw Error("shader program '" + _name + "': uniform index " + std::to_string(index) + " out of range");
    }
    return ShaderProgramAccess::assign(*this, index, value, detail::ErrorSource{"shader program", _name});
}

namespace detail {

int ShaderProgramAccess::findSlot(const ShaderProgram& p, std::string_view name) noexcept
{
    for (std::size_t i = 0; i < p._uniforms.size(); ++i) {
        if (p._uniforms[i].name == name) {
            return static_cast<int>(i);
        }
    }
    return -1;
}

bool ShaderProgramAccess::assign(ShaderProgram& p, int slotIndex, const UniformValue& value, const ErrorSource& source)
{
    alignas(16) unsigned char bytes[64];
    std::size_t size = 0;
    std::visit(
        [&](const auto& v) {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, bool>) {
                const GLint i = v ? 1 : 0;
                std::memcpy(bytes, &i, sizeof i);
                size = sizeof i;
            } else {
                static_assert(sizeof(T) <= sizeof bytes);
                std::memcpy(bytes, &v, sizeof(T));
                size = sizeof(T);
            }
        },
        value);
    return assignBytes(p, slotIndex, uniformTypeOf(value), bytes, size, source);
}

bool ShaderProgramAccess::assignBytes(ShaderProgram& p, int slotIndex, UniformType given, const void* bytes,
                                      std::size_t size, const ErrorSource& source)
{
    const ShaderProgram::Slot& slot = p._slots[slotIndex];
    if (given != slot.type || !slot.settable || slot.count != 1) [[unlikely]] {
        const ShaderUniform& uniform = p._uniforms[slotIndex];
        if (uniform.automatic) {
            throw Error(source.text() + ": uniform " + uniform.name +
                        " is automatic (set by the Context from the SceneState)");
        }
        if (uniform.arraySize != 1) {
            throw Error(source.text() + ": uniform " + uniform.name + " is an array of " +
                        std::to_string(uniform.arraySize) + " " + uniformTypeName(uniform.type) +
                        "; set it with ShaderProgram::setUniformArray");
        }
        if (!slot.settable) {
            throw Error(source.text() + ": uniform " + uniform.name + " is of an unsupported type (" +
                        uniformTypeName(uniform.type) + ")");
        }
        const bool intForInt =
            given == UniformType::Int && (uniform.type == UniformType::Bool || isSampler(uniform.type));
        if (!intForInt) {
            throw Error(source.text() + ": uniform " + uniform.name + " is " + uniformTypeName(uniform.type) +
                        " but the value is " + uniformTypeName(given));
        }
    }
    return assignRaw(p, slotIndex, bytes, size);
}

namespace {

/// memcmp(a, b, size) == 0 for the sizes uniforms have, with constant sizes the compiler inlines.
bool sameBytes(const void* a, const void* b, std::size_t size) noexcept
{
    switch (size) {
    case 4: return std::memcmp(a, b, 4) == 0;
    case 8: return std::memcmp(a, b, 8) == 0;
    case 12: return std::memcmp(a, b, 12) == 0;
    case 16: return std::memcmp(a, b, 16) == 0;
    case 36: return std::memcmp(a, b, 36) == 0;
    case 64: return std::memcmp(a, b, 64) == 0;
    default: return std::memcmp(a, b, size) == 0;
    }
}

} // namespace

bool ShaderProgramAccess::assignRaw(ShaderProgram& p, int slotIndex, const void* data, std::size_t size) noexcept
{
    ShaderProgram::Slot& slot = p._slots[slotIndex];
    if (slot.hasValue && sameBytes(slot.bytes(), data, size)) {
        return false;
    }
    std::memcpy(slot.bytes(), data, size);
    if (!slot.hasValue) {
        slot.hasValue = true;
        if (slot.automatic < 0) {
            --p._unsetCount;
        }
    }
    if (!slot.dirty) {
        slot.dirty = true;
        p._dirtySlots.push_back(slotIndex);
    }
    return true;
}

int ShaderProgramAccess::samplerUnitOfSlot(const ShaderProgram& p, int slot) noexcept
{
    const ShaderProgram::Slot& s = p._slots[slot];
    if (!s.hasValue) {
        return -1;
    }
    GLint unit = 0;
    std::memcpy(&unit, s.value, sizeof unit);
    return unit;
}

void ShaderProgramAccess::checkAllSet(const ShaderProgram& p, const std::string& where)
{
    if (p._unsetCount == 0) {
        return;
    }
    std::string names;
    for (std::size_t i = 0; i < p._slots.size(); ++i) {
        if (!p._slots[i].hasValue) {
            names += (names.empty() ? "" : ", ") + p._uniforms[i].name + " (" + uniformTypeName(p._uniforms[i].type) +
                     ")";
        }
    }
    throw Error(where + ": shader program '" + p._name + "' has uniforms that were never given a value: " + names +
                " (set them in DrawCommand::uniforms or with ShaderProgram::setUniform)");
}

void ShaderProgramAccess::markAllDirty(ShaderProgram& p)
{
    for (std::size_t i = 0; i < p._slots.size(); ++i) {
        ShaderProgram::Slot& slot = p._slots[i];
        if (slot.hasValue && !slot.dirty && (slot.settable || slot.automatic >= 0)) {
            slot.dirty = true;
            p._dirtySlots.push_back(static_cast<int>(i));
        }
    }
}

std::uint64_t ShaderProgramAccess::flush(ShaderProgram& p, const GlApi& gl)
{
    const std::uint64_t sent = p._dirtySlots.size();
    for (const int index : p._dirtySlots) {
        ShaderProgram::Slot& slot = p._slots[index];
        slot.dirty = false;
        const GLint location = slot.location;
        const GLsizei n = slot.count;
        const auto* f = reinterpret_cast<const GLfloat*>(slot.bytes());
        const auto* i = reinterpret_cast<const GLint*>(slot.bytes());
        switch (slot.type) {
        case UniformType::Bool:
        case UniformType::Int:
        case UniformType::Sampler2D:
        case UniformType::Sampler2DShadow: gl.glUniform1iv(location, n, i); break;
        case UniformType::IntVec2: gl.glUniform2iv(location, n, i); break;
        case UniformType::IntVec3: gl.glUniform3iv(location, n, i); break;
        case UniformType::IntVec4: gl.glUniform4iv(location, n, i); break;
        case UniformType::Float: gl.glUniform1fv(location, n, f); break;
        case UniformType::FloatVec2: gl.glUniform2fv(location, n, f); break;
        case UniformType::FloatVec3: gl.glUniform3fv(location, n, f); break;
        case UniformType::FloatVec4: gl.glUniform4fv(location, n, f); break;
        case UniformType::FloatMat2: gl.glUniformMatrix2fv(location, n, GL_FALSE, f); break;
        case UniformType::FloatMat3: gl.glUniformMatrix3fv(location, n, GL_FALSE, f); break;
        case UniformType::FloatMat4: gl.glUniformMatrix4fv(location, n, GL_FALSE, f); break;
        case UniformType::Unsupported: break;
        }
    }
    p._dirtySlots.clear();
    return sent;
}

} // namespace detail
} // namespace orbis::renderer
