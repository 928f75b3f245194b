// libFuzzer target for the tile decoders (TurboJPEG, libspng, libwebp behind decodeImage, and
// decodePng16): any input either decodes into an image of the size it says, within the pixel
// limit, or throws orbis::Error naming the tile. Any other exception, a crash, a sanitizer report
// or a broken invariant is a bug. Built and run by scripts/fuzz.sh --target tiles.
#include <orbis/core/Error.h>
#include <orbis/world/ImageCodec.h>

#include <cstdint>
#include <cstdlib>
#include <span>
#include <string_view>

namespace {

void require(bool condition)
{
    if (!condition) {
        std::abort();
    }
}

void requireNamed(const orbis::Error& error)
{
    require(std::string_view(error.what()).starts_with("fuzz tile: "));
}

// A smaller limit than the default, so the fuzzer spends its time in the decoders, not in memset.
constexpr std::uint64_t kPixels = std::uint64_t{1} << 22;

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const std::span<const std::uint8_t> bytes(data, size);
    for (const int channels : {0, 1, 3, 4}) {
        try {
            const orbis::Image image = orbis::world::decodeImage(bytes, "fuzz tile", channels, kPixels);
            require(image.width > 0 && image.height > 0);
            require(std::uint64_t(image.width) * std::uint64_t(image.height) <= kPixels);
            require(channels == 0 ? image.channels >= 1 && image.channels <= 4 : image.channels == channels);
            require(image.pixels.size() == std::size_t(image.width) * std::size_t(image.height) * std::size_t(image.channels));
        } catch (const orbis::Error& error) {
            requireNamed(error);
        }
    }
    try {
        const orbis::world::GreyImage16 heights = orbis::world::decodePng16(bytes, "fuzz tile", kPixels);
        require(heights.samples.size() == std::size_t(heights.width) * std::size_t(heights.height));
    } catch (const orbis::Error& error) {
        requireNamed(error);
    }
    return 0;
}
