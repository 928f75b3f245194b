// libFuzzer target for the CSV points reader: any input either gives finite positions, one text
// per position for every kept column, or is refused with an orbis::Error naming the file. Any
// other exception, a crash, a hang or a sanitizer report is a bug.
// Built and run by scripts/fuzz.sh (clang, -fsanitize=fuzzer,address,undefined).
#include <orbis/core/Error.h>
#include <orbis/world/CsvPoints.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

namespace {

void require(bool condition)
{
    if (!condition) {
        std::abort();
    }
}

void parseOnce(const std::string& text, bool skipInvalidRows)
{
    constexpr std::string_view kOrigin = "fuzz.csv";
    orbis::world::CsvPointsOptions options;
    options.skipInvalidRows = skipInvalidRows;
    try {
        const orbis::world::CsvPoints points = orbis::world::parseCsvPoints(text, kOrigin, options);
        for (const orbis::Geodetic3D& position : points.positions) {
            require(std::isfinite(position.longitude) && std::isfinite(position.latitude) &&
                    std::isfinite(position.height));
        }
        require(points.properties.size() == points.propertyNames.size());
        for (const std::vector<std::string>& column : points.properties) {
            require(column.size() == points.size());
        }
        for (const std::string& warning : points.warnings) {
            require(warning.find(kOrigin) != std::string::npos); // "skipped fuzz.csv:5: ..."
        }
    } catch (const orbis::Error& error) {
        require(std::string_view(error.what()).starts_with(kOrigin));
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const std::string text(reinterpret_cast<const char*>(data), size);
    parseOnce(text, false);
    parseOnce(text, true);
    return 0;
}
