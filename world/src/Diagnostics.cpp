#include "orbis/world/Diagnostics.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>

namespace orbis::world {

namespace {

std::string lowercase(std::string_view s)
{
    std::string out(s);
    std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return out;
}

/// The length of the longest prefix of `value` of at most `maximumBytes` that ends on a character.
std::size_t utf8Prefix(std::string_view value, std::size_t maximumBytes)
{
    if (value.size() <= maximumBytes) {
        return value.size();
    }
    std::size_t end = maximumBytes;
    while (end > 0 && (static_cast<unsigned char>(value[end]) & 0xC0) == 0x80) {
        --end;
    }
    return end;
}

/// Optimal string alignment distance: edits, with swapping two neighbours counted as one.
std::size_t editDistance(std::string_view a, std::string_view b)
{
    std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
    for (std::size_t i = 0; i <= a.size(); ++i) {
        d[i][0] = i;
    }
    for (std::size_t j = 0; j <= b.size(); ++j) {
        d[0][j] = j;
    }
    for (std::size_t i = 1; i <= a.size(); ++i) {
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
            }
        }
    }
    return d[a.size()][b.size()];
}

} // namespace

std::string Diagnostic::text() const
{
    std::string message = file;
    if (line > 0) {
        message += ':' + std::to_string(line);
        if (column > 0) {
            message += ':' + std::to_string(column);
        }
    }
    message += ": ";
    if (!where.empty()) {
        // A JSON pointer holds the file's keys, which may be megabytes long.
        message.append(cutForMessage(where)).append(": ");
    }
    return message + what;
}

void DiagnosticList::append(const DiagnosticList& other)
{
    _entries.insert(_entries.end(), other._entries.begin(), other._entries.end());
}

std::string DiagnosticList::text() const
{
    std::string text;
    for (const Diagnostic& entry : _entries) {
        text += entry.text() + '\n';
    }
    return text;
}

std::string cutForMessage(std::string_view value, std::size_t maximumCharacters)
{
    if (value.size() <= maximumCharacters) {
        return std::string(value);
    }
    return std::string(value.substr(0, utf8Prefix(value, maximumCharacters))) + "... (" + std::to_string(value.size()) +
           " bytes)";
}

std::string quote(std::string_view value, std::size_t maximumBytes)
{
    const std::size_t kept = utf8Prefix(value, maximumBytes);
    std::string quoted = nlohmann::json(std::string(value.substr(0, kept)))
                             .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    if (kept < value.size()) {
        quoted.insert(quoted.size() - 1, "...");
    }
    return quoted;
}

std::string quoteList(std::span<const std::string_view> words)
{
    std::string list;
    for (std::size_t i = 0; i < words.size(); ++i) {
        list += (i == 0 ? "" : ", ") + quote(words[i]);
    }
    return list;
}

std::string formatNumber(double value)
{
    std::array<char, 64> buffer{};
    const bool whole = std::abs(value) < 1e15 && std::trunc(value) == value;
    const auto result = whole ? std::to_chars(buffer.data(), buffer.data() + buffer.size(), value,
                                              std::chars_format::fixed, 0)
                              : std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
    return std::string(buffer.data(), result.ptr);
}

std::optional<double> parseNumber(std::string_view text) noexcept
{
    while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) {
        text.remove_prefix(1);
    }
    while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) {
        text.remove_suffix(1);
    }
    if (!text.empty() && text.front() == '+') {
        text.remove_prefix(1);
    }
    double value = 0.0;
    const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || result.ec != std::errc() || result.ptr != text.data() + text.size() || !std::isfinite(value)) {
        return std::nullopt;
    }
    return value;
}

std::optional<std::string_view> closestWord(std::string_view word, std::span<const std::string_view> candidates)
{
    // Longer words than any key are not misspellings of one; skip the quadratic table for them.
    constexpr std::size_t kMaxCompared = 64;
    if (word.size() > kMaxCompared) {
        return std::nullopt;
    }
    const std::string lowerWord = lowercase(word);
    std::optional<std::string_view> best;
    std::size_t bestDistance = 3;
    for (const std::string_view candidate : candidates) {
        // The distance is at least the difference in length.
        if (candidate.size() > word.size() + 2 || word.size() > candidate.size() + 2) {
            continue;
        }
        const std::size_t distance = editDistance(lowerWord, lowercase(candidate));
        if (distance < bestDistance && distance < std::min(word.size(), candidate.size())) {
            best = candidate;
            bestDistance = distance;
        }
    }
    return best;
}

std::string suggestion(std::string_view word, std::span<const std::string_view> candidates)
{
    if (const auto closest = closestWord(word, candidates)) {
        return " (did you mean " + quote(*closest) + "?)";
    }
    return "; expected " + std::string(candidates.size() == 1 ? "" : "one of ") + quoteList(candidates);
}

} // namespace orbis::world
