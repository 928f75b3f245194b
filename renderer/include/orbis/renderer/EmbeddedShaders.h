#pragma once

#include <optional>
#include <string_view>
#include <vector>

namespace orbis::renderer {

/// The text of a file embedded from shaders/ at build time, by its path under shaders/
/// ("renderer/builtin/constants.glsl"); empty when no such file was embedded.
std::optional<std::string_view> embeddedShader(std::string_view path) noexcept;

/// The paths of every embedded file, sorted.
std::vector<std::string_view> embeddedShaderPaths();

} // namespace orbis::renderer
