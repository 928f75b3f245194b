#include "orbis/world/ImageFile.h"

#include "orbis/world/FileAccess.h"
#include "orbis/world/ImageCodec.h"

#include <orbis/core/Error.h>

namespace orbis::world {

Image readImage(const std::filesystem::path& path, int desiredChannels)
{
    return decodeImage(readFileBytes(path, "image"), path.string(), desiredChannels);
}

void writePng(const Image& image, const std::filesystem::path& path, int compressionLevel)
{
    if (image.width <= 0 || image.height <= 0) {
        throw Error(path.string() + ": cannot write an empty image (" + std::to_string(image.width) + "x" +
                    std::to_string(image.height) + ")");
    }
    writeFileAtomically(path, encodePng(image, compressionLevel));
}

} // namespace orbis::world
