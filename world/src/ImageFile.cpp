#include "orbis/world/ImageFile.h"

#include "orbis/core/Error.h"

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <algorithm>
#include <cassert>
#include <memory>
#include <system_error>

namespace orbis::world {

Image readImage(const std::filesystem::path& path, int desiredChannels)
{
    int width = 0;
    int height = 0;
    int fileChannels = 0;
    std::unique_ptr<stbi_uc, void (*)(void*)> data(
        stbi_load(path.c_str(), &width, &height, &fileChannels, desiredChannels), stbi_image_free);
    if (!data) {
        throw Error(path.string() + ": cannot read image: " + stbi_failure_reason());
    }
    Image image(width, height, desiredChannels);
    std::copy_n(data.get(), image.pixels.size(), image.pixels.begin());
    return image;
}

void writePng(const Image& image, const std::filesystem::path& path)
{
    if (image.width <= 0 || image.height <= 0) {
        throw Error(path.string() + ": cannot write an empty image (" + std::to_string(image.width) + "x" +
                    std::to_string(image.height) + ")");
    }
    std::filesystem::path temporary = path;
    temporary += ".partial";
    const int ok = stbi_write_png(temporary.c_str(), image.width, image.height, image.channels, image.pixels.data(),
                                  image.width * image.channels);
    if (!ok) {
        std::error_code ignored;
        std::filesystem::remove(temporary, ignored);
        throw Error(path.string() + ": cannot write PNG");
    }
    std::error_code error;
    std::filesystem::rename(temporary, path, error);
    if (error) {
        std::filesystem::remove(temporary, error);
        throw Error(path.string() + ": cannot write PNG: " + error.message());
    }
}

} // namespace orbis::world
