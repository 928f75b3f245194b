#include "JsonText.h"

#include <algorithm>
#include <cctype>

namespace orbis::world::detail {

namespace {

std::string lowercase(std::string_view s)
{
    std::string out(s);
    std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return out;
}

/// nlohmann's reason without its "[json.exception.parse_error.101] parse error at line 1,
/// column 2: " prefix (our own location replaces it).
std::string syntaxReason(const std::string& what)
{
    const std::size_t parseError = what.find("parse error");
    const std::size_t colon = parseError == std::string::npos ? std::string::npos : what.find(": ", parseError);
    return colon == std::string::npos ? what : what.substr(colon + 2);
}

/// A hint for the mistakes JSON does not forgive, looking at the text around the error.
std::string syntaxHint(std::string_view text, std::size_t offset)
{
    if (offset >= text.size()) {
        return {};
    }
    std::size_t start = offset;
    const auto isWordCharacter = [](char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '-' || c == '+'; };
    while (start > 0 && isWordCharacter(text[start - 1])) {
        --start;
    }
    std::size_t end = offset;
    while (end < text.size() && isWordCharacter(text[end])) {
        ++end;
    }
    std::string word = lowercase(text.substr(start, end - start));
    while (!word.empty() && (word.front() == '-' || word.front() == '+')) {
        word.erase(0, 1);
    }
    if (word.starts_with("nan") || word.starts_with("inf")) {
        return " (JSON has no NaN or Infinity; write a finite number)";
    }
    if (text[offset] == '/' || text[offset] == '#') {
        return " (JSON has no comments)";
    }
    if (text[offset] == '\'') {
        return " (JSON strings take double quotes)";
    }
    std::size_t previous = offset;
    while (previous > 0 && std::isspace(static_cast<unsigned char>(text[previous - 1]))) {
        --previous;
    }
    if ((text[offset] == '}' || text[offset] == ']') && previous > 0 && text[previous - 1] == ',') {
        return " (a comma before a closing bracket?)";
    }
    return {};
}

/// Byte offset of the first bracket nested deeper than `limit`, or npos.
std::size_t tooDeep(std::string_view text, std::size_t limit)
{
    std::size_t depth = 0;
    bool inString = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (c == '\\') {
                ++i;
            } else if (c == '"') {
                inString = false;
            }
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            if (++depth > limit) {
                return i;
            }
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return std::string_view::npos;
}

Diagnostic at(const std::string& origin, std::string_view text, std::size_t offset, std::string what)
{
    const TextPosition position = textPositionOf(text, offset);
    return {origin, position.line, position.column, "", std::move(what)};
}

} // namespace

std::optional<Diagnostic> jsonSyntaxFault(std::string_view text, const std::string& origin, std::size_t maxDepth,
                                          const nlohmann::json::exception* error)
{
    if (text.find_first_not_of(" \t\r\n") == std::string_view::npos) {
        return Diagnostic{origin, 0, 0, "", "the file is empty; expected a JSON object"};
    }
    // The parser would stop at a NUL byte and take what came before for the whole file.
    if (const std::size_t offset = text.find('\0'); offset != std::string_view::npos) {
        return at(origin, text, offset, "invalid JSON: a NUL byte (JSON text has none; is this a binary file?)");
    }
    if (const std::size_t offset = tooDeep(text, maxDepth); offset != std::string_view::npos) {
        return at(origin, text, offset, "invalid JSON: nested deeper than " + std::to_string(maxDepth) + " levels");
    }
    if (const auto* parse = dynamic_cast<const nlohmann::json::parse_error*>(error)) {
        // nlohmann counts the bytes read, so the offending byte is the one before.
        const std::size_t offset = parse->byte > 0 ? std::min<std::size_t>(parse->byte - 1, text.size()) : text.size();
        return at(origin, text, offset, "invalid JSON: " + syntaxReason(parse->what()) + syntaxHint(text, offset));
    }
    if (error) {
        // Numbers beyond double's range ("number overflow parsing '1e999'") come without a
        // position; the number's first occurrence in the text stands in for it.
        const std::string what = error->what();
        const std::size_t open = what.find('\'');
        const std::size_t close = open == std::string::npos ? std::string::npos : what.find('\'', open + 1);
        const std::string number = close == std::string::npos ? std::string() : what.substr(open + 1, close - open - 1);
        const std::size_t offset = number.empty() ? std::string_view::npos : text.find(number);
        if (offset == std::string_view::npos) {
            return Diagnostic{origin, 0, 0, "", "invalid JSON: a number too large for a double"};
        }
        return at(origin, text, offset, "invalid JSON: " + number + " is too large for a double");
    }
    return std::nullopt;
}

TextPosition positionOf(std::string_view text, std::string_view pointer, bool atKey)
{
    if (const auto offset = locateInJson(text, pointer, atKey)) {
        return textPositionOf(text, *offset);
    }
    return {0, 0};
}

} // namespace orbis::world::detail
