#pragma once

// Where label fonts come from: a path given, or fontconfig's answer, never a fixed system path.

#include <filesystem>
#include <optional>
#include <string_view>

namespace orbis::scene {

/// The family labels are drawn in unless told otherwise (fontconfig falls back to the system's
/// closest sans-serif TrueType font when it is not installed).
inline constexpr std::string_view kDefaultFontFamily = "DejaVu Sans";

/// The TrueType (or OpenType) file fontconfig matches best for a pattern ("DejaVu Sans",
/// "Noto Sans:bold"); empty when fontconfig has no such font, or no fonts at all.
std::optional<std::filesystem::path> findFont(std::string_view pattern);

/// The font labels use when no path is given: the file ORBIS_FONT names when set, else
/// findFont(kDefaultFontFamily). Throws orbis::Error when ORBIS_FONT names no file, or when
/// fontconfig finds no TrueType font, saying how to give one.
std::filesystem::path defaultFontPath();

} // namespace orbis::scene
