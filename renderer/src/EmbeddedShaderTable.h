#pragma once

// The table the build writes into generated/EmbeddedShaders.cpp (renderer/cmake/EmbedShaders.cmake).

#include <cstddef>

namespace orbis::renderer::detail {

struct EmbeddedShaderFile {
    const char* path; ///< relative to shaders/
    const char* text;
};

/// kEmbeddedShaderFileCount entries, sorted by path, then a null entry.
extern const EmbeddedShaderFile kEmbeddedShaderFiles[];
extern const std::size_t kEmbeddedShaderFileCount;

} // namespace orbis::renderer::detail
