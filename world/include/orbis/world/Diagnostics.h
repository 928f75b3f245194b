#pragma once

// How the world layer's readers (scene files, camera paths, GeoJSON, CSV, glTF, images, TMS
// folders) say what is wrong with their input: one format for every fault, a list that collects
// them (`orbis validate` reports every fault of a file in one run), and the text helpers their
// messages share, so that every format's errors read alike.

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace orbis::world {

/// One fault of an input file. text() is "file:line:column: where: what", the line and column left
/// out when unknown and `where` when the fault is about the whole file:
///   scenes/bad.json:3:12: /width: expected a positive integer, got "wide"
///   cities.csv:12: column 2 "lat": expected a number (latitude), got "north"
struct Diagnostic {
    std::string file;        ///< the file as the caller named it, or the name given for text in memory
    std::size_t line = 0;    ///< 1-based; 0 when unknown
    std::size_t column = 0;  ///< 1-based, in characters; 0 when unknown
    std::string where;       ///< within the file: a JSON pointer, "feature 3 (name \"Fiji\"): geometry", "column 2 \"lat\""
    std::string what;        ///< what is wrong

    std::string text() const;
    friend bool operator==(const Diagnostic&, const Diagnostic&) = default;
};

/// Faults gathered while reading on past them, in the order found.
class DiagnosticList {
public:
    void add(Diagnostic diagnostic) { _entries.push_back(std::move(diagnostic)); }
    /// Every entry of another list, after this list's.
    void append(const DiagnosticList& other);
    const std::vector<Diagnostic>& entries() const noexcept { return _entries; }
    bool empty() const noexcept { return _entries.empty(); }
    std::size_t size() const noexcept { return _entries.size(); }
    /// Each entry's text, one a line.
    std::string text() const;

private:
    std::vector<Diagnostic> _entries;
};

/// `value` for a message: as is when short, else its first `maximumCharacters` characters and
/// "... (N bytes)", so that a hostile name or URL cannot make a message megabytes long. Never cuts a
/// UTF-8 sequence in two.
std::string cutForMessage(std::string_view value, std::size_t maximumCharacters = 300);

/// `value` as a JSON string literal (quotes, escapes; invalid UTF-8 replaced), its first
/// `maximumBytes` bytes followed by "..." inside the quotes when longer: "colour", "xxxx...".
std::string quote(std::string_view value, std::size_t maximumBytes = 60);

/// Quoted words joined by ", ": "auto", "single".
std::string quoteList(std::span<const std::string_view> words);

/// Whole numbers below 1e15 in full ("1000000", not "1e+06"), others as short as they round-trip.
std::string formatNumber(double value);

/// The number the whole of `text` spells (spaces around it and a leading '+' allowed); empty for
/// anything else, a partial number ("12abc") included, and for numbers that overflow a double.
std::optional<double> parseNumber(std::string_view text) noexcept;

/// The candidate closest to `word` (case ignored) when it is within two edits (a swap of two
/// neighbours counting as one) and fewer edits than either word has letters, so "x" suggests nothing.
std::optional<std::string_view> closestWord(std::string_view word, std::span<const std::string_view> candidates);

/// " (did you mean "color"?)" when a candidate is close to `word`, else "; expected "a"" or
/// "; expected one of "a", "b"".
std::string suggestion(std::string_view word, std::span<const std::string_view> candidates);

} // namespace orbis::world
