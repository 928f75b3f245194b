#include "orbis/world/CsvPoints.h"

#include "orbis/core/Error.h"
#include "orbis/world/Diagnostics.h"
#include "orbis/world/FileAccess.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
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

/// A bad row: where in it (a column, or empty for the whole row) and what is wrong.
struct BadRow {
    std::string where;
    std::string what;
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
            fields.push_back(quotedAhead() ? quoted(fields.size()) : unquoted());
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
    /// Whether the field starting here is quoted, blanks before its quote allowed (`a, "b"`);
    /// moves to the quote when it is.
    bool quotedAhead()
    {
        std::size_t at = _position;
        while (at < _text.size() && (_text[at] == ' ' || _text[at] == '\t')) {
            ++at;
        }
        if (at < _text.size() && _text[at] == '"') {
            _position = at;
            return true;
        }
        return false;
    }

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
        // Blanks after the closing quote are allowed too.
        while (read < size && (data[read] == ' ' || data[read] == '\t') && data[read] != _delimiter) {
            ++read;
        }
        _position = read;
        if (read < size && data[read] != _delimiter && data[read] != '\n' && data[read] != '\r') {
            throw BadRow{"column " + std::to_string(fieldIndex + 1),
                         "unexpected character after a closing quote (a quote inside a quoted field must be doubled)"};
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

struct ColumnRef {
    std::size_t index; ///< from 0
    std::string_view name;

    std::string describe() const { return "column " + std::to_string(index + 1) + " " + quote(name); }
};

double readNumber(std::string_view field, const ColumnRef& column, const char* what)
{
    const std::optional<double> value = parseNumber(field);
    if (!value) {
        throw BadRow{column.describe(), std::string("expected a finite number (") + what + "), got " + quote(field)};
    }
    return *value;
}

/// A fault at a line of the file, as every reader states one.
std::string faultAt(const std::string& source, std::size_t line, std::string where, std::string what)
{
    return Diagnostic{source, line, 0, std::move(where), std::move(what)}.text();
}

constexpr std::size_t kNoColumn = static_cast<std::size_t>(-1);

/// The header's columns and which of them the options read.
struct CsvLayout {
    std::vector<std::string> header;
    std::size_t longitude = kNoColumn;
    std::size_t latitude = kNoColumn;
    std::size_t height = kNoColumn;
    std::vector<std::size_t> properties;
};

std::string unterminatedFault(const std::string& source, const Unterminated& u)
{
    return faultAt(source, u.line, "column " + std::to_string(u.column),
                   "unterminated quoted field (the closing quote is missing before the end of the file)");
}

/// Reads the header row and finds the columns the options name. Throws orbis::Error naming the
/// file for an empty file, a malformed header or a column it lacks.
CsvLayout readLayout(CsvReader& reader, const std::string& source, const CsvPointsOptions& options)
{
    std::vector<std::string_view> fields;
    try {
        if (!reader.next(fields)) {
            throw Error(faultAt(source, 0, "", "the file is empty; expected a header row"));
        }
    } catch (const Unterminated& u) {
        throw Error(unterminatedFault(source, u));
    } catch (const BadRow& bad) {
        throw Error(faultAt(source, reader.recordLine(), bad.where, bad.what));
    }
    CsvLayout layout;
    for (std::string_view field : fields) {
        layout.header.emplace_back(trim(field));
    }
    const std::vector<std::string>& header = layout.header;
    auto find = [&](const std::string& name, const char* role) -> std::size_t {
        const auto it = std::find(header.begin(), header.end(), name);
        if (it == header.end()) {
            std::string columns;
            for (const std::string& column : header) {
                columns += (columns.empty() ? "" : ", ") + quote(column);
            }
            throw Error(faultAt(source, reader.recordLine(), "",
                                std::string("no ") + role + " column " + quote(name) + " in the header (columns: " +
                                    columns + ")"));
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
    layout.longitude = findNamed(options.longitudeColumn, kLongitudeColumnNames, "longitude");
    layout.latitude = findNamed(options.latitudeColumn, kLatitudeColumnNames, "latitude");
    layout.height = options.heightColumn.empty() ? kNoColumn : find(options.heightColumn, "height");
    if (options.propertyColumns) {
        for (const std::string& name : *options.propertyColumns) {
            layout.properties.push_back(find(name, "property"));
        }
    } else {
        for (std::size_t c = 0; c < header.size(); ++c) {
            if (c != layout.longitude && c != layout.latitude && c != layout.height) {
                layout.properties.push_back(c);
            }
        }
    }
    return layout;
}

/// Reads one row's position into `result`, and its kept fields; throws BadRow.
void readRow(const std::vector<std::string_view>& fields, const CsvLayout& layout, CsvPoints& result)
{
    const std::vector<std::string>& header = layout.header;
    if (fields.size() != header.size()) {
        throw BadRow{"", "expected " + std::to_string(header.size()) + " fields as in the header, got " +
                             std::to_string(fields.size())};
    }
    const ColumnRef longitudeColumn{layout.longitude, header[layout.longitude]};
    const ColumnRef latitudeColumn{layout.latitude, header[layout.latitude]};
    const double longitude = readNumber(fields[layout.longitude], longitudeColumn, "longitude");
    const double latitude = readNumber(fields[layout.latitude], latitudeColumn, "latitude");
    const double height = layout.height == kNoColumn
                              ? 0.0
                              : readNumber(fields[layout.height], {layout.height, header[layout.height]}, "height");
    if (longitude < -180.0 || longitude > 180.0) {
        throw BadRow{longitudeColumn.describe(), "longitude " + formatNumber(longitude) + " out of range [-180, 180]"};
    }
    if (latitude < -90.0 || latitude > 90.0) {
        throw BadRow{latitudeColumn.describe(), "latitude " + formatNumber(latitude) + " out of range [-90, 90]"};
    }
    result.positions.push_back(Geodetic3D::fromDegrees(longitude, latitude, height));
    for (std::size_t k = 0; k < layout.properties.size(); ++k) {
        result.properties[k].emplace_back(fields[layout.properties[k]]);
    }
}

} // namespace

CsvPoints parseCsvPoints(std::string text, std::string_view sourceName, const CsvPointsOptions& options)
{
    const std::string source(sourceName);
    CsvReader reader(text, options.delimiter);
    const CsvLayout layout = readLayout(reader, source, options);
    CsvPoints result;
    for (std::size_t c : layout.properties) {
        result.propertyNames.push_back(layout.header[c]);
    }
    result.properties.resize(layout.properties.size());

    // The rows: the count of line ends bounds their number, so the columns never reallocate.
    const auto estimate = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
    result.positions.reserve(estimate);
    for (auto& column : result.properties) {
        column.reserve(estimate);
    }
    std::vector<std::string_view> fields;
    for (;;) {
        try {
            if (!reader.next(fields)) {
                break;
            }
            readRow(fields, layout, result);
        } catch (const BadRow& bad) {
            const std::string message = faultAt(source, reader.recordLine(), bad.where, bad.what);
            if (!options.skipInvalidRows) {
                throw Error(message);
            }
            result.warnings.push_back("skipped " + message);
            reader.skipRestOfLine();
        } catch (const Unterminated& u) {
            if (!options.skipInvalidRows) {
                throw Error(unterminatedFault(source, u));
            }
            result.warnings.push_back("skipped the rest of the file: " + unterminatedFault(source, u));
            break;
        }
    }
    return result;
}

CsvPoints loadCsvPoints(const std::filesystem::path& path, const CsvPointsOptions& options)
{
    const std::vector<std::uint8_t> bytes = readFileBytes(path, "CSV file");
    return parseCsvPoints(std::string(bytes.begin(), bytes.end()), path.string(), options);
}

std::vector<std::string> readCsvHeader(const std::filesystem::path& path, char delimiter)
{
    // Only the first line is needed: a longer one is not a header.
    constexpr std::size_t kMaxHeaderBytes = 64 * 1024;
    const std::string source = path.string();
    std::ifstream file(path, std::ios::binary);
    std::error_code error;
    if (std::filesystem::is_directory(path, error) || !file) {
        throw Error(faultAt(source, 0, "", "cannot be opened as a CSV file"));
    }
    std::string text(kMaxHeaderBytes + 1, '\0');
    file.read(text.data(), static_cast<std::streamsize>(text.size()));
    text.resize(static_cast<std::size_t>(file.gcount()));
    if (text.size() > kMaxHeaderBytes && text.find('\n') == std::string::npos) {
        throw Error(faultAt(source, 1, "", "has a first line longer than 64 KiB; expected a header row"));
    }
    text.erase(std::min(text.find('\n'), text.size())); // the rest may end inside a record
    CsvReader reader(text, delimiter);
    std::vector<std::string_view> fields;
    try {
        if (!reader.next(fields) || (fields.size() == 1 && trim(fields[0]).empty())) {
            throw Error(faultAt(source, 0, "", "has no header row"));
        }
    } catch (const Unterminated& u) {
        throw Error(unterminatedFault(source, u));
    } catch (const BadRow& bad) {
        throw Error(faultAt(source, 1, bad.where, bad.what));
    }
    std::vector<std::string> columns;
    for (std::string_view field : fields) {
        columns.emplace_back(trim(field));
    }
    return columns;
}

} // namespace orbis::world
