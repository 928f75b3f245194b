#pragma once

// What the JSON readers (scene files, camera paths, GeoJSON) share: parsing with bounded nesting and
// syntax errors put in words at their line and column, and values described for "expected X, got Y".
// Private to orbis::world.

#include "JsonLocator.h"

#include "orbis/world/Diagnostics.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

namespace orbis::world::detail {

/// What a value is, for "expected X, got Y": null, true, "text" (quoted, cut), 12, 1.5, 1.0 (a
/// whole number written with a fraction), "an array of 2 elements", "an object".
template <class Json>
std::string describeJson(const Json& value)
{
    switch (value.type()) {
    case Json::value_t::null: return "null";
    case Json::value_t::boolean: return value.template get<bool>() ? "true" : "false";
    case Json::value_t::string: return quote(value.template get_ref<const std::string&>());
    case Json::value_t::number_integer: return std::to_string(value.template get<std::int64_t>());
    case Json::value_t::number_unsigned: return std::to_string(value.template get<std::uint64_t>());
    case Json::value_t::number_float: {
        const double number = value.template get<double>();
        if (!std::isfinite(number)) {
            return "a number too large for a double";
        }
        const std::string text = formatNumber(number);
        return text.find_first_of(".e") == std::string::npos ? text + ".0" : text;
    }
    case Json::value_t::array:
        return value.empty() ? "an empty array"
                             : "an array of " + std::to_string(value.size()) + (value.size() == 1 ? " element" : " elements");
    case Json::value_t::object: return value.empty() ? "an empty object" : "an object";
    default: return "an unsupported value";
    }
}

/// The fault of text that is not JSON (or holds a NUL byte, or nests deeper than maxDepth), at its
/// line and column; empty when `text` parses. `what` is "invalid JSON: ..." with a hint for the common mistakes.
std::optional<Diagnostic> jsonSyntaxFault(std::string_view text, const std::string& origin, std::size_t maxDepth,
                                          const nlohmann::json::exception* error);

/// Parses JSON text nested at most maxDepth levels: the document, or the fault that stops it.
template <class Json>
std::variant<Json, Diagnostic> parseJson(std::string_view text, const std::string& origin, std::size_t maxDepth)
{
    // Checked before parsing: reading, copying and freeing a document recurse once per level.
    if (auto fault = jsonSyntaxFault(text, origin, maxDepth, nullptr)) {
        return *fault;
    }
    try {
        return Json::parse(text.begin(), text.end());
    } catch (const typename Json::exception& error) {
        return *jsonSyntaxFault(text, origin, maxDepth, &error);
    }
}

/// The line and column of the value (or key) at a JSON pointer, for a Diagnostic; 0, 0 when the
/// pointer is not found in the text.
TextPosition positionOf(std::string_view text, std::string_view pointer, bool atKey);

} // namespace orbis::world::detail
