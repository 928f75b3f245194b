#include "orbis/renderer/EmbeddedShaders.h"

#include "EmbeddedShaderTable.h"

namespace orbis::renderer {

std::optional<std::string_view> embeddedShader(std::string_view path) noexcept
{
    for (std::size_t i = 0; i < detail::kEmbeddedShaderFileCount; ++i) {
        if (path == detail::kEmbeddedShaderFiles[i].path) {
            return std::string_view(detail::kEmbeddedShaderFiles[i].text);
        }
    }
    return std::nullopt;
}

std::vector<std::string_view> embeddedShaderPaths()
{
    std::vector<std::string_view> paths;
    paths.reserve(detail::kEmbeddedShaderFileCount);
    for (std::size_t i = 0; i < detail::kEmbeddedShaderFileCount; ++i) {
        paths.emplace_back(detail::kEmbeddedShaderFiles[i].path);
    }
    return paths;
}

} // namespace orbis::renderer
