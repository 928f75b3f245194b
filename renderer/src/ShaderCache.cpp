#include "orbis/renderer/ShaderCache.h"

#include "orbis/renderer/Device.h"

namespace orbis::renderer {

std::shared_ptr<ShaderProgram> ShaderCache::get(const ShaderProgramDescription& description)
{
    std::string key = description.cacheKey();
    std::lock_guard lock(_mutex);
    if (auto found = _programs.find(key); found != _programs.end()) {
        ++_hits;
        return found->second;
    }
    auto program = std::make_shared<ShaderProgram>(_device.createShaderProgram(description));
    ++_compiles;
    _programs.emplace(std::move(key), program);
    return program;
}

std::size_t ShaderCache::size() const
{
    std::lock_guard lock(_mutex);
    return _programs.size();
}

std::uint64_t ShaderCache::compiles() const
{
    std::lock_guard lock(_mutex);
    return _compiles;
}

std::uint64_t ShaderCache::hits() const
{
    std::lock_guard lock(_mutex);
    return _hits;
}

void ShaderCache::clear()
{
    std::lock_guard lock(_mutex);
    _programs.clear();
    _compiles = 0;
    _hits = 0;
}

} // namespace orbis::renderer
