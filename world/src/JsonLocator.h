#pragma once

// Source positions for JSON that nlohmann::json has already accepted. nlohmann 3.11 keeps no
// locations in its values, so the scene-file parser finds a key or value again in the text, by
// its JSON pointer, only when it has an error to report (and once per parse, for duplicate keys).
// The scanner is iterative (any nesting depth) and stops without reading past the end on any
// input, valid or not.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace orbis::world::detail {

/// 1-based line and column (in UTF-8 characters) of a byte offset; an offset past the end is
/// the end. A leading byte-order mark is not counted.
struct TextPosition {
    std::size_t line = 1;
    std::size_t column = 1;
};
TextPosition textPositionOf(std::string_view text, std::size_t offset) noexcept;

/// token appended to an RFC 6901 pointer, "~" and "/" escaped.
std::string appendToPointer(std::string_view pointer, std::string_view token);

/// The reference tokens of an RFC 6901 pointer, unescaped ("" has none).
std::vector<std::string> splitPointer(std::string_view pointer);

/// Byte offset of the value at pointer (of its key's opening quote when atKey), in JSON text;
/// empty when not found or the text is not valid JSON there.
std::optional<std::size_t> locateInJson(std::string_view text, std::string_view pointer, bool atKey);

/// A key given twice in one object (the parser keeps the last silently).
struct DuplicateKey {
    std::string pointer;     ///< of the second occurrence
    std::size_t offset;      ///< of the second occurrence's key
    std::size_t firstOffset; ///< of the first occurrence's key
};
/// The first duplicate key in document order; empty when none (or the text is not valid JSON).
std::optional<DuplicateKey> findDuplicateKey(std::string_view text);

} // namespace orbis::world::detail
