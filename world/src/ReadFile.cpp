#include "ReadFile.h"

#include "orbis/core/Error.h"

#include <cerrno>
#include <cstring>
#include <fstream>

namespace orbis::world {

std::string readTextFile(const std::filesystem::path& path, const char* kind)
{
    std::ifstream file(path, std::ios::binary | std::ios::ate);
    if (!file) {
        throw Error(path.string() + ": cannot open " + kind + " file: " + std::strerror(errno));
    }
    const std::streamoff size = file.tellg();
    if (size < 0) {
        throw Error(path.string() + ": cannot read " + kind + " file");
    }
    std::string text(static_cast<std::size_t>(size), '\0');
    file.seekg(0);
    if (!file.read(text.data(), size)) {
        throw Error(path.string() + ": cannot read " + kind + " file");
    }
    return text;
}

} // namespace orbis::world
