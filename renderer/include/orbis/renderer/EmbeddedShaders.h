#pragma once

// Shader files compiled into libraries and programs (cmake/OrbisEmbedShaders.cmake): each
// registers its table once, before main; lookups search every table of the process.

#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace orbis::renderer {

/// One embedded file, as orbis_embed_shaders writes it.
struct EmbeddedShaderFile {
    const char* path;   ///< the lookup key: the embedding's prefix and the path in its folder
    const char* source; ///< the file it came from, relative to its project's source folder, for messages
    const char* text;
};

/// Adds a table of embedded files (called by the code orbis_embed_shaders generates; the files
/// must outlive the process). A path registered before keeps its first file. Returns true.
bool registerEmbeddedShaders(std::span<const EmbeddedShaderFile> files) noexcept;

/// The embedded file at a path ("renderer/builtin/constants.glsl", "scene/globe/globe.vert.glsl");
/// null when no library or program of the process embedded one.
const EmbeddedShaderFile* findEmbeddedShader(std::string_view path) noexcept;

/// The text of the embedded file at a path; empty when there is none.
std::optional<std::string_view> embeddedShader(std::string_view path) noexcept;

/// The paths of every embedded file, sorted.
std::vector<std::string_view> embeddedShaderPaths();

} // namespace orbis::renderer
