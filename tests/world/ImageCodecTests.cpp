#include "WorldTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/world/FileAccess.h>
#include <orbis/world/ImageCodec.h>

#include <catch2/catch.hpp>

#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#include <stb_image.h>

#include <atomic>
#include <random>
#include <thread>

using namespace orbis;
using namespace orbis::world;
using orbis::test::handmadePng;
using orbis::test::maximumDifference;
using orbis::test::meanDifference;
using orbis::test::testPattern;
using Catch::Matchers::Contains;

namespace {

const std::filesystem::path kNaturalEarthTile = ORBIS_SOURCE_DIR "/data/imagery/NaturalEarthII/1/2/1.jpg";

/// Decoding must give an orbis::Error naming the source; returns its message.
std::string decodeError(const std::vector<std::uint8_t>& bytes, const std::string& name = "tile 3/1/2")
{
    try {
        decodeImage(bytes, name);
    } catch (const Error& error) {
        return error.what();
    }
    FAIL("decoding " << name << " succeeded");
    return {};
}

/// The position of a JPEG's start-of-frame segment (baseline or progressive), which holds its size.
std::size_t startOfFrame(const std::vector<std::uint8_t>& jpeg)
{
    for (std::size_t i = 2; i + 9 < jpeg.size(); ++i) {
        if (jpeg[i] == 0xFF && (jpeg[i + 1] == 0xC0 || jpeg[i + 1] == 0xC2)) {
            return i;
        }
    }
    FAIL("no SOF segment");
    return 0;
}

} // namespace

TEST_CASE("The image format is told from the first bytes, not the name", "[world][codec]")
{
    const Image image = testPattern(32, 16, 3);
    REQUIRE(detectImageFormat(encodeJpeg(image, 90)) == ImageFormat::Jpeg);
    REQUIRE(detectImageFormat(encodePng(image, 6)) == ImageFormat::Png);
    REQUIRE(detectImageFormat(encodeWebp(image, 80)) == ImageFormat::Webp);
    const std::vector<std::uint8_t> html = {'<', 'h', 't', 'm', 'l', '>'};
    REQUIRE(detectImageFormat(html) == ImageFormat::Unknown);
    REQUIRE(detectImageFormat({}) == ImageFormat::Unknown);
    REQUIRE(imageFormatFromName("JPEG") == ImageFormat::Jpeg);
    REQUIRE(imageFormatFromName("image/png") == ImageFormat::Png);
    REQUIRE(imageFormatFromName("webp") == ImageFormat::Webp);
    REQUIRE(imageFormatFromName("pbf") == ImageFormat::Unknown);
    REQUIRE(imageFormatExtension(ImageFormat::Jpeg) == "jpg");
}

TEST_CASE("PNG and lossless WebP round-trip every channel count exactly", "[world][codec]")
{
    for (int channels = 1; channels <= 4; ++channels) {
        INFO("channels " << channels);
        const Image image = testPattern(67, 33, channels);
        for (int level : {0, 1, 9}) {
            const Image back = decodeImage(encodePng(image, level), "round trip", channels);
            REQUIRE(maximumDifference(image, back) == 0);
        }
        if (channels >= 3) {
            const Image back = decodeImage(encodeWebp(image, 100, true), "round trip", channels);
            REQUIRE(maximumDifference(image, back) == 0);
        }
    }
}

TEST_CASE("A PNG keeps its own channels when asked for 0, and converts to the channels asked for", "[world][codec]")
{
    const Image rgba = testPattern(20, 10, 4);
    const std::vector<std::uint8_t> png = encodePng(rgba, 6);
    REQUIRE(decodeImage(png, "rgba", 0).channels == 4);
    const Image grey = decodeImage(png, "rgba", 1);
    REQUIRE(grey.channels == 1);
    const std::uint8_t* p = rgba.pixel(7, 3);
    // Rec. 601 luminance, rounded.
    REQUIRE(int(grey.pixel(7, 3)[0]) == (77 * p[0] + 150 * p[1] + 29 * p[2] + 128) / 256);
    const Image greyAlpha = decodeImage(png, "rgba", 2);
    REQUIRE(int(greyAlpha.pixel(7, 3)[1]) == p[3]);
    const Image rgb = decodeImage(png, "rgba", 3);
    REQUIRE(std::equal(p, p + 3, rgb.pixel(7, 3)));

    const Image greyImage = testPattern(20, 10, 1);
    const Image spread = decodeImage(encodePng(greyImage, 6), "grey", 4);
    REQUIRE(int(spread.pixel(5, 5)[0]) == greyImage.pixel(5, 5)[0]);
    REQUIRE(int(spread.pixel(5, 5)[2]) == greyImage.pixel(5, 5)[0]);
    REQUIRE(int(spread.pixel(5, 5)[3]) == 255);
}

TEST_CASE("JPEG and lossy WebP round-trip within their losses", "[world][codec]")
{
    const Image image = testPattern(128, 64, 3);
    const Image jpeg = decodeImage(encodeJpeg(image, 95), "jpeg", 3);
    // Quality 95 with 4:2:0 chroma: a few levels on average, more at the sharp block edges.
    REQUIRE(meanDifference(image, jpeg) < 3.0);
    const Image webp = decodeImage(encodeWebp(image, 95), "webp", 3);
    REQUIRE(meanDifference(image, webp) < 3.0);

    const Image grey = testPattern(64, 64, 1);
    const std::vector<std::uint8_t> greyJpeg = encodeJpeg(grey, 95);
    REQUIRE(decodeImage(greyJpeg, "grey jpeg", 0).channels == 1);
    REQUIRE(meanDifference(grey, decodeImage(greyJpeg, "grey jpeg", 1)) < 2.0);
    // RGBA asked of a JPEG: opaque.
    REQUIRE(int(decodeImage(greyJpeg, "grey jpeg", 4).pixel(3, 3)[3]) == 255);
}

TEST_CASE("TurboJPEG and libspng decode real tiles as stb_image does", "[world][codec]")
{
    const std::vector<std::uint8_t> jpeg = readFileBytes(kNaturalEarthTile, "tile");
    const Image ours = decodeImage(jpeg, kNaturalEarthTile.string(), 3);
    int width = 0;
    int height = 0;
    int channels = 0;
    stbi_uc* reference = stbi_load_from_memory(jpeg.data(), int(jpeg.size()), &width, &height, &channels, 3);
    REQUIRE(reference);
    Image stb(width, height, 3);
    std::copy_n(reference, stb.pixels.size(), stb.pixels.begin());
    stbi_image_free(reference);
    REQUIRE(ours.width == 256);
    REQUIRE(ours.height == 256);
    // Two correct decoders differ by their IDCT and chroma upsampling: by a level or two.
    REQUIRE(meanDifference(ours, stb) < 1.5);

    const std::vector<std::uint8_t> png = encodePng(ours, 6);
    stbi_uc* pngReference = stbi_load_from_memory(png.data(), int(png.size()), &width, &height, &channels, 3);
    REQUIRE(pngReference);
    REQUIRE(std::equal(ours.pixels.begin(), ours.pixels.end(), pngReference));
    stbi_image_free(pngReference);
}

TEST_CASE("16-bit grey PNGs decode to native-endian samples", "[world][codec]")
{
    // Scanlines written by hand, big-endian as PNG stores them: 0x0102 then 0xFFFE, 0x8000 then 0x0000.
    const std::vector<std::uint8_t> scanlines = {0, 0x01, 0x02, 0xFF, 0xFE, 0, 0x80, 0x00, 0x00, 0x00};
    const GreyImage16 image = decodePng16(handmadePng(2, 2, 16, 0, scanlines), "heights");
    REQUIRE(image.width == 2);
    REQUIRE(image.height == 2);
    REQUIRE(image.at(0, 0) == 0x0102);
    REQUIRE(image.at(1, 0) == 0xFFFE);
    REQUIRE(image.at(0, 1) == 0x8000);
    REQUIRE(image.at(1, 1) == 0);

    // Our encoder writes what stb_image (native-endian 16-bit) reads back.
    GreyImage16 heights{37, 21, {}};
    for (int i = 0; i < 37 * 21; ++i) {
        heights.samples.push_back(static_cast<std::uint16_t>(i * 977 + 32768));
    }
    const std::vector<std::uint8_t> png = encodePng16(heights, 6);
    int width = 0;
    int height = 0;
    int channels = 0;
    stbi_us* reference = stbi_load_16_from_memory(png.data(), int(png.size()), &width, &height, &channels, 1);
    REQUIRE(reference);
    REQUIRE(std::equal(heights.samples.begin(), heights.samples.end(), reference));
    stbi_image_free(reference);
    REQUIRE(decodePng16(png, "heights").samples == heights.samples);

    REQUIRE_THROWS_WITH(decodePng16(encodePng(testPattern(8, 8, 1), 6), "tile 2/3/1.png"),
                        Contains("tile 2/3/1.png") && Contains("expected a 16-bit greyscale PNG, found 8-bit"));
    REQUIRE_THROWS_WITH(decodePng16(encodeJpeg(testPattern(8, 8, 1), 90), "tile 2/3/1.png"),
                        Contains("tile 2/3/1.png: not a PNG"));
}

TEST_CASE("Truncated images give an error naming the source, in every format", "[world][codec][hostile]")
{
    const Image image = testPattern(96, 64, 3);
    for (const auto& [format, bytes] : {std::pair{"JPEG", encodeJpeg(image, 90)}, std::pair{"PNG", encodePng(image, 6)},
                                        std::pair{"WebP", encodeWebp(image, 90)}}) {
        INFO(format);
        for (const double fraction : {0.2, 0.5, 0.9}) {
            std::vector<std::uint8_t> cut(bytes.begin(), bytes.begin() + std::ptrdiff_t(double(bytes.size()) * fraction));
            const std::string message = decodeError(cut, "http://127.0.0.1/3/1/2.jpg");
            REQUIRE_THAT(message, Contains("http://127.0.0.1/3/1/2.jpg: "));
        }
    }
    // Cut before its end marker, a JPEG still decodes to a picture with a grey bottom: refused.
    const std::vector<std::uint8_t> jpeg = encodeJpeg(image, 90);
    REQUIRE_THAT(decodeError({jpeg.begin(), jpeg.end() - 100}), Contains("tile 3/1/2: corrupt JPEG"));
}

TEST_CASE("Bytes that are no image are named and shown", "[world][codec][hostile]")
{
    const std::vector<std::uint8_t> html = {'<', '!', 'D', 'O', 'C', 'T', 'Y', 'P', 'E', ' ', 'h'};
    REQUIRE_THAT(decodeError(html, "tiles/3/1/2.png"),
                 Contains("tiles/3/1/2.png: not a JPEG, PNG or WebP image (it starts with 3c 21 44 4f 43 54 59 50 ...)"));
    REQUIRE_THAT(decodeError({}, "empty.png"), Contains("empty.png: not a JPEG, PNG or WebP image (it is empty)"));
    REQUIRE_THAT(decodeError({0xFF, 0xD8, 0xFF}, "three.jpg"), Contains("three.jpg: ") && Contains("JPEG"));
    REQUIRE_THROWS_WITH(decodeImage(encodePng(testPattern(4, 4, 3), 6), "five", 5), Contains("five: cannot decode into 5 channels"));
}

TEST_CASE("A header claiming huge dimensions is refused before anything is allocated", "[world][codec][hostile]")
{
    // A PNG whose IHDR (checksum correct) claims 100,000 x 100,000 pixels over a few bytes of data.
    const std::vector<std::uint8_t> png = handmadePng(100000, 100000, 8, 2, std::vector<std::uint8_t>(301, 0));
    REQUIRE_THAT(decodeError(png, "liar.png"), Contains("liar.png: PNG header claims 100000x100000 pixels, more than the 67108864 allowed"));
    REQUIRE_THROWS_WITH(decodePng16(handmadePng(70000, 70000, 16, 0, {0}), "liar16.png"),
                        Contains("liar16.png: PNG header claims 70000x70000 pixels"));
    // A PNG claiming zero width.
    REQUIRE_THAT(decodeError(handmadePng(0, 10, 8, 2, {0}), "zero.png"), Contains("zero.png: corrupt PNG header"));

    // A JPEG whose frame header is patched to 60,000 x 60,000.
    std::vector<std::uint8_t> jpeg = encodeJpeg(testPattern(16, 16, 3), 90);
    const std::size_t sof = startOfFrame(jpeg);
    jpeg[sof + 5] = 0xEA;
    jpeg[sof + 6] = 0x60;
    jpeg[sof + 7] = 0xEA;
    jpeg[sof + 8] = 0x60;
    REQUIRE_THAT(decodeError(jpeg, "liar.jpg"), Contains("liar.jpg: JPEG header claims 60000x60000 pixels"));

    // A lossless WebP whose header says 16384 x 16384 (14 bits of width - 1, then of height - 1).
    std::vector<std::uint8_t> webp = encodeWebp(testPattern(16, 16, 3), 100, true);
    REQUIRE(std::string(webp.begin() + 12, webp.begin() + 16) == "VP8L");
    webp[21] = 0xFF;
    webp[22] = 0xFF;
    webp[23] = 0xFF;
    webp[24] = static_cast<std::uint8_t>((webp[24] & 0xF0) | 0x0F);
    REQUIRE_THAT(decodeError(webp, "liar.webp"), Contains("liar.webp: WebP header claims 16384x16384 pixels"));

    // A caller may allow less.
    REQUIRE_THROWS_WITH(decodeImage(encodePng(testPattern(300, 300, 3), 1), "big tile", 4, 256 * 256),
                        Contains("big tile: PNG header claims 300x300 pixels, more than the 65536 allowed"));
}

TEST_CASE("A corrupt PNG chunk is caught by its checksum", "[world][codec][hostile]")
{
    std::vector<std::uint8_t> png = encodePng(testPattern(64, 64, 3), 6);
    png[png.size() / 2] ^= 0x55; // inside the IDAT data
    REQUIRE_THAT(decodeError(png, "flipped.png"), Contains("flipped.png: corrupt PNG"));
}

TEST_CASE("Damaged images of every format decode or throw orbis::Error, never crash", "[world][codec][hostile]")
{
    const Image image = testPattern(48, 40, 4);
    const std::vector<std::vector<std::uint8_t>> originals = {
        encodeJpeg(image, 80), encodePng(image, 6), encodeWebp(image, 80), encodeWebp(image, 80, true),
        handmadePng(3, 2, 16, 0, std::vector<std::uint8_t>(14, 7))};
    const Image goodBefore = decodeImage(originals[0], "good", 0);
    const unsigned seed = Catch::rngSeed();
    INFO("seed " << seed);
    std::mt19937 random(seed);
    int refused = 0;
    int decoded = 0;
    for (const auto& original : originals) {
        for (int trial = 0; trial < 150; ++trial) {
            std::vector<std::uint8_t> damaged = original;
            const int flips = 1 + trial % 8;
            for (int i = 0; i < flips; ++i) {
                damaged[random() % damaged.size()] = static_cast<std::uint8_t>(random());
            }
            if (trial % 3 == 0) {
                damaged.resize(random() % damaged.size());
            }
            try {
                const Image result = decodeImage(damaged, "damaged", 0);
                REQUIRE(result.pixels.size() == std::size_t(result.width) * result.height * result.channels);
                ++decoded;
            } catch (const Error& error) {
                REQUIRE_THAT(error.what(), Contains("damaged: "));
                ++refused;
            }
            try {
                decodePng16(damaged, "damaged");
            } catch (const Error&) {
            }
        }
    }
    REQUIRE(refused > 0);
    INFO(decoded << " damaged images still decoded");
    // The decoders' state after all those errors does not leak into the next image.
    REQUIRE(decodeImage(originals[0], "good", 0).pixels == goodBefore.pixels);
}

TEST_CASE("Images decode on many threads at once with the same results", "[world][codec][threads]")
{
    const std::vector<std::uint8_t> jpeg = readFileBytes(kNaturalEarthTile, "tile");
    const std::vector<std::uint8_t> png = encodePng(testPattern(100, 80, 4), 3);
    const Image jpegOnce = decodeImage(jpeg, "jpeg", 3);
    const Image pngOnce = decodeImage(png, "png", 4);
    std::atomic<int> mismatches{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < 6; ++t) {
        threads.emplace_back([&] {
            for (int i = 0; i < 20; ++i) {
                if (decodeImage(jpeg, "jpeg", 3).pixels != jpegOnce.pixels ||
                    decodeImage(png, "png", 4).pixels != pngOnce.pixels ||
                    decodeImage(encodeJpeg(jpegOnce, 90), "encoded", 3).width != 256) {
                    ++mismatches;
                }
            }
        });
    }
    for (std::thread& thread : threads) {
        thread.join();
    }
    REQUIRE(mismatches == 0);
}
