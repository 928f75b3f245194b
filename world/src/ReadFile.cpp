#include "ReadFile.h"

#include "orbis/world/FileAccess.h"

#include "orbis/core/Error.h"

#include <cstring>

namespace orbis::world {

std::string readTextFile(const std::filesystem::path& path, const char* kind)
{
    // Through readFileBytes, so that a folder or a named pipe is refused before anything blocks.
    const std::optional<std::vector<std::uint8_t>> bytes =
        readFileBytesIfExists(path, std::string(kind) + " file");
    if (!bytes) {
        throw Error(cutForMessage(path.string()) + ": cannot open " + kind + " file: " + std::strerror(ENOENT));
    }
    return {bytes->begin(), bytes->end()};
}

} // namespace orbis::world
