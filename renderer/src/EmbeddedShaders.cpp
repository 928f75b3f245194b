#include "orbis/renderer/EmbeddedShaders.h"

#include <map>
#include <mutex>

namespace orbis::renderer {

namespace {

/// Constructed on first use: tables register during static initialisation, in any order.
struct Registry {
    std::mutex mutex;
    std::map<std::string_view, const EmbeddedShaderFile*, std::less<>> files;
};

Registry& registry() noexcept
{
    static Registry instance;
    return instance;
}

} // namespace

bool registerEmbeddedShaders(std::span<const EmbeddedShaderFile> files) noexcept
{
    Registry& r = registry();
    const std::lock_guard lock(r.mutex);
    for (const EmbeddedShaderFile& file : files) {
        r.files.try_emplace(file.path, &file);
    }
    return true;
}

const EmbeddedShaderFile* findEmbeddedShader(std::string_view path) noexcept
{
    Registry& r = registry();
    const std::lock_guard lock(r.mutex);
    const auto found = r.files.find(path);
    return found == r.files.end() ? nullptr : found->second;
}

std::optional<std::string_view> embeddedShader(std::string_view path) noexcept
{
    const EmbeddedShaderFile* file = findEmbeddedShader(path);
    return file ? std::optional<std::string_view>(file->text) : std::nullopt;
}

std::vector<std::string_view> embeddedShaderPaths()
{
    Registry& r = registry();
    const std::lock_guard lock(r.mutex);
    std::vector<std::string_view> paths;
    paths.reserve(r.files.size());
    for (const auto& [path, file] : r.files) {
        paths.push_back(path);
    }
    return paths;
}

} // namespace orbis::renderer
