#include "orbis/world/CsvPoints.h"

#include "orbis/core/Error.h"

#include "ReadFile.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <span>

namespace orbis::world {

const std::vector<std::string>* CsvPoints::column(std::string_view name) const noexcept
{
    for (std::size_t c = 0; c < propertyNames.size(); ++c) {
        if (propertyNames[c] == name) {
            return &properties[c];
        }
    }
    return nullptr;
}

namespace {

/// A bad row: the message after "file: line N".
struct BadRow {
    std::string message;
};

/// The file ends inside a quoted field.
struct Unterminated {
    std::size_t line;
    std::size_t column;
};

/// Splits the text into records in place: quoted fields are unescaped inside the buffer, so every
/// field is a view into it and nothing is allocated per field.
class CsvReader {
public:
    CsvReader(std::string& text, char delimiter) : _text(text), _delimiter(delimiter)
    {
        if (_text.compare(0, 3, "\xEF\xBB\xBF") == 0) {
            _position = 3;
        }
    }

    /// Reads the next non-empty record into `fields`; false at the end of the text.
    bool next(std::vector<std::string_view>& fields)
    {
        fields.clear();
        // Skip empty lines.
        while (_position < _text.size() && (_text[_position] == '\n' || _text[_position] == '\r')) {
            if (_text[_position] == '\n') {
                ++_line;
            }
            ++_position;
        }
        if (_position >= _text.size()) {
            return false;
        }
        _recordLine = _line;
        _inRecord = true;
        for (;;) {
            fields.push_back(_position < _text.size() && _text[_position] == '"' ? quoted(fields.size()) : unquoted());
            if (_position >= _text.size()) {
                _inRecord = false;
                return true;
            }
            const char c = _text[_position];
            if (c == _delimiter) {
                ++_position;
                continue;
            }
            // End of the record: \n, \r\n or a lone \r.
            ++_position;
            if (c == '\r' && _position < _text.size() && _text[_position] == '\n') {
                ++_position;
            }
            ++_line;
            _inRecord = false;
            return true;
        }
    }

    std::size_t recordLine() const noexcept { return _recordLine; }

    /// After a malformed record: continues after the next line end, or stays put when the record
    /// already ended.
    void skipRestOfLine()
    {
        if (!_inRecord) {
            return;
        }
        while (_position < _text.size() && _text[_position] != '\n') {
            ++_position;
        }
        _inRecord = false;
    }

private:
    std::string_view unquoted()
    {
        const std::size_t begin = _position;
        const char* data = _text.data();
        std::size_t end = begin;
        const std::size_t size = _text.size();
        while (end < size && data[end] != _delimiter && data[end] != '\n' && data[end] != '\r') {
            ++end;
        }
        _position = end;
        return {data + begin, end - begin};
    }

    std::string_view quoted(std::size_t fieldIndex)
    {
        char* data = _text.data();
        const std::size_t size = _text.size();
        const std::size_t openLine = _line;
        const std::size_t begin = _position + 1;
        std::size_t read = begin;
        std::size_t write = begin;
        for (;;) {
            const void* found = std::memchr(data + read, '"', size - read);
            if (!found) {
                throw Unterminated{openLine, fieldIndex + 1};
            }
            const std::size_t quote = static_cast<std::size_t>(static_cast<const char*>(found) - data);
            _line += static_cast<std::size_t>(std::count(data + read, data + quote, '\n'));
            if (write != read) {
                std::memmove(data + write, data + read, quote - read);
            }
            write += quote - read;
            if (quote + 1 < size && data[quote + 1] == '"') {
                data[write++] = '"';
                read = quote + 2;
                continue;
            }
            read = quote + 1;
            break;
        }
        _position = read;
        if (read < size && data[read] != _delimiter && data[read] != '\n' && data[read] != '\r') {
            throw BadRow{", column " + std::to_string(fieldIndex + 1) +
                         ": unexpected character after a closing quote (a quote inside a quoted field must be "
                         "doubled)"};
        }
        return {data + begin, write - begin};
    }

    std::string& _text;
    char _delimiter;
    std::size_t _position = 0;
    std::size_t _line = 1;
    std::size_t _recordLine = 1;
    bool _inRecord = false;
};

std::string_view trim(std::string_view s)
{
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) {
        s.remove_prefix(1);
    }
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) {
        s.remove_suffix(1);
    }
    return s;
}

std::string quote(std::string_view s)
{
    if (s.size() > 40) {
        return "\"" + std::string(s.substr(0, 40)) + "...\"";
    }
    return "\"" + std::string(s) + "\"";
}

std::string formatNumber(double value)
{
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    return std::string(buffer, result.ptr);
}

struct ColumnRef {
    std::size_t index; ///< from 0
    std::string_view name;

    std::string describe() const { return ", column " + std::to_string(index + 1) + " " + quote(name); }
};

double readNumber(std::string_view field, const ColumnRef& column, const char* what)
{
    std::string_view s = trim(field);
    if (!s.empty() && s.front() == '+') {
        s.remove_prefix(1);
    }
    double value = 0.0;
    const auto result = std::from_chars(s.data(), s.data() + s.size(), value);
    if (s.empty() || result.ec == std::errc::invalid_argument || result.ptr != s.data() + s.size()) {
        throw BadRow{column.describe() + ": expected a number (" + what + "), got " + quote(field)};
    }
    if (result.ec == std::errc::result_out_of_range || !std::isfinite(value)) {
        throw BadRow{column.describe() + ": " + what + " " + quote(field) + " is not a finite number"};
    }
    return value;
}

} // namespace

CsvPoints parseCsvPoints(std::string text, std::string_view sourceName, const CsvPointsOptions& options)
{
    const std::string source(sourceName);
    CsvReader reader(text, options.delimiter);
    std::vector<std::string_view> fields;
    CsvPoints result;

    auto unterminated = [&](const Unterminated& u) {
        return source + ": line " + std::to_string(u.line) + ", column " + std::to_string(u.column) +
               ": unterminated quoted field (the closing quote is missing before the end of the file)";
    };

    // The header.
    std::vector<std::string> header;
    try {
        if (!reader.next(fields)) {
            throw Error(source + ": empty CSV file (expected a header row)");
        }
    } catch (const Unterminated& u) {
        throw Error(unterminated(u));
    } catch (const BadRow& bad) {
        throw Error(source + ": line " + std::to_string(reader.recordLine()) + bad.message);
    }
    for (std::string_view field : fields) {
        header.emplace_back(trim(field));
    }
    auto listColumns = [&] {
        std::string list;
        for (const std::string& name : header) {
            list += (list.empty() ? "" : ", ") + name;
        }
        return list;
    };
    auto find = [&](const std::string& name, const char* role) -> std::size_t {
        const auto it = std::find(header.begin(), header.end(), name);
        if (it == header.end()) {
            throw Error(source + ": line " + std::to_string(reader.recordLine()) + ": no " + role + " column " +
                        quote(name) + " in the header (columns: " + listColumns() + ")");
        }
        return static_cast<std::size_t>(it - header.begin());
    };
    // An empty name: the first column whose lower-case name is one of the accepted ones.
    auto findNamed = [&](const std::string& name, std::span<const std::string_view> accepted, const char* role) {
        if (!name.empty()) {
            return find(name, role);
        }
        for (std::size_t c = 0; c < header.size(); ++c) {
            std::string lower = header[c];
            std::transform(lower.begin(), lower.end(), lower.begin(),
                           [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
            if (std::find(accepted.begin(), accepted.end(), lower) != accepted.end()) {
                return c;
            }
        }
        return find(std::string(accepted.front()), role);
    };
    const std::size_t longitudeIndex = findNamed(options.longitudeColumn, kLongitudeColumnNames, "longitude");
    const std::size_t latitudeIndex = findNamed(options.latitudeColumn, kLatitudeColumnNames, "latitude");
    constexpr std::size_t kNone = static_cast<std::size_t>(-1);
    const std::size_t heightIndex = options.heightColumn.empty() ? kNone : find(options.heightColumn, "height");
    std::vector<std::size_t> propertyIndices;
    if (options.propertyColumns) {
        for (const std::string& name : *options.propertyColumns) {
            propertyIndices.push_back(find(name, "property"));
        }
    } else {
        for (std::size_t c = 0; c < header.size(); ++c) {
            if (c != longitudeIndex && c != latitudeIndex && c != heightIndex) {
                propertyIndices.push_back(c);
            }
        }
    }
    for (std::size_t c : propertyIndices) {
        result.propertyNames.push_back(header[c]);
    }
    result.properties.resize(propertyIndices.size());

    // The rows: the count of line ends bounds their number, so the columns never reallocate.
    const auto estimate = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
    result.positions.reserve(estimate);
    for (auto& column : result.properties) {
        column.reserve(estimate);
    }
    const ColumnRef longitudeColumn{longitudeIndex, header[longitudeIndex]};
    const ColumnRef latitudeColumn{latitudeIndex, header[latitudeIndex]};
    for (;;) {
        try {
            if (!reader.next(fields)) {
                break;
            }
            if (fields.size() != header.size()) {
                throw BadRow{": expected " + std::to_string(header.size()) + " fields as in the header, got " +
                             std::to_string(fields.size())};
            }
            const double longitude = readNumber(fields[longitudeIndex], longitudeColumn, "longitude");
            const double latitude = readNumber(fields[latitudeIndex], latitudeColumn, "latitude");
            const double height =
                heightIndex == kNone ? 0.0 : readNumber(fields[heightIndex], {heightIndex, header[heightIndex]}, "height");
            if (longitude < -180.0 || longitude > 180.0) {
                throw BadRow{longitudeColumn.describe() + ": longitude " + formatNumber(longitude) +
                             " out of range [-180, 180]"};
            }
            if (latitude < -90.0 || latitude > 90.0) {
                throw BadRow{latitudeColumn.describe() + ": latitude " + formatNumber(latitude) +
                             " out of range [-90, 90]"};
            }
            result.positions.push_back(Geodetic3D::fromDegrees(longitude, latitude, height));
            for (std::size_t k = 0; k < propertyIndices.size(); ++k) {
                result.properties[k].emplace_back(fields[propertyIndices[k]]);
            }
        } catch (const BadRow& bad) {
            const std::string message = source + ": line " + std::to_string(reader.recordLine()) + bad.message;
            if (!options.skipInvalidRows) {
                throw Error(message);
            }
            result.warnings.push_back("skipped " + message);
            reader.skipRestOfLine();
        } catch (const Unterminated& u) {
            if (!options.skipInvalidRows) {
                throw Error(unterminated(u));
            }
            result.warnings.push_back("skipped the rest of the file: " + unterminated(u));
            break;
        }
    }
    return result;
}

CsvPoints loadCsvPoints(const std::filesystem::path& path, const CsvPointsOptions& options)
{
    return parseCsvPoints(readTextFile(path, "CSV"), path.string(), options);
}

} // namespace orbis::world
