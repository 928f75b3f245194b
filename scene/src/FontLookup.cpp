#include "orbis/scene/FontLookup.h"

#include <orbis/core/Error.h>

#include <fontconfig/fontconfig.h>

#include <cstdlib>
#include <memory>
#include <string>

namespace orbis::scene {

namespace {

template <typename T, void (*destroy)(T*)>
struct Deleter {
    void operator()(T* object) const noexcept { destroy(object); }
};
using Pattern = std::unique_ptr<FcPattern, Deleter<FcPattern, FcPatternDestroy>>;
using Config = std::unique_ptr<FcConfig, Deleter<FcConfig, FcConfigDestroy>>;

} // namespace

std::optional<std::filesystem::path> findFont(std::string_view pattern)
{
    // A configuration of our own (not FcInit's global one), so that threads and repeated calls do
    // not share fontconfig's state.
    const Config config(FcInitLoadConfigAndFonts());
    if (!config) {
        return std::nullopt;
    }
    const Pattern wanted(FcNameParse(reinterpret_cast<const FcChar8*>(std::string(pattern).c_str())));
    if (!wanted) {
        return std::nullopt;
    }
    // Only outline formats the renderer's Font reads (stb_truetype).
    FcPatternAddString(wanted.get(), FC_FONTFORMAT, reinterpret_cast<const FcChar8*>("TrueType"));
    FcConfigSubstitute(config.get(), wanted.get(), FcMatchPattern);
    FcDefaultSubstitute(wanted.get());
    FcResult result = FcResultNoMatch;
    const Pattern match(FcFontMatch(config.get(), wanted.get(), &result));
    FcChar8* file = nullptr;
    FcChar8* format = nullptr;
    if (!match || FcPatternGetString(match.get(), FC_FILE, 0, &file) != FcResultMatch ||
        FcPatternGetString(match.get(), FC_FONTFORMAT, 0, &format) != FcResultMatch ||
        std::string_view(reinterpret_cast<const char*>(format)) != "TrueType") {
        return std::nullopt;
    }
    std::filesystem::path path(reinterpret_cast<const char*>(file));
    std::error_code ignored;
    if (!std::filesystem::is_regular_file(path, ignored)) {
        return std::nullopt;
    }
    return path;
}

std::filesystem::path defaultFontPath()
{
    if (const char* given = std::getenv("ORBIS_FONT"); given && *given) {
        std::error_code ignored;
        if (!std::filesystem::is_regular_file(given, ignored)) {
            throw Error(std::string("ORBIS_FONT=") + given + ": no such font file");
        }
        return given;
    }
    if (std::optional<std::filesystem::path> found = findFont(kDefaultFontFamily)) {
        return *found;
    }
    throw Error("labels: no font found: fontconfig knows no TrueType font (install one, such as Debian's "
                "fonts-dejavu-core), or name a .ttf file with ORBIS_FONT or LabelCollectionOptions::fontPath");
}

} // namespace orbis::scene
