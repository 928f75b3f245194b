#pragma once

#include <orbis/core/Geodetic.h>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace orbis::world {

/// Which columns loadCsvPoints reads; the defaults fit data/geonames/cities.csv (name,lat,lon,country).
/// The column names scene files accept for coordinates, compared without regard to case.
inline constexpr std::array<std::string_view, 4> kLongitudeColumnNames = {"lon", "lng", "long", "longitude"};
inline constexpr std::array<std::string_view, 2> kLatitudeColumnNames = {"lat", "latitude"};

struct CsvPointsOptions {
    /// Degrees in [-180, 180]; empty: the first column named one of kLongitudeColumnNames.
    std::string longitudeColumn = "lon";
    /// Degrees in [-90, 90]; empty: the first column named one of kLatitudeColumnNames.
    std::string latitudeColumn = "lat";
    std::string heightColumn;            ///< metres; empty: the file has none and heights are 0
    /// Columns kept as properties, in this order. Empty optional: every column except longitude,
    /// latitude and height, in file order.
    std::optional<std::vector<std::string>> propertyColumns;
    char delimiter = ',';
    /// false: the first bad row throws. true: bad rows are left out and described in
    /// CsvPoints::warnings; a bad header still throws.
    bool skipInvalidRows = false;
};

/// Points from a CSV file, stored by column: positions[i] goes with properties[c][i].
struct CsvPoints {
    std::vector<Geodetic3D> positions;               ///< radians and metres
    std::vector<std::string> propertyNames;          ///< the kept columns
    std::vector<std::vector<std::string>> properties; ///< properties[c][i]: column propertyNames[c] of point i
    std::vector<std::string> warnings;               ///< one line per skipped row, naming the file and line

    std::size_t size() const noexcept { return positions.size(); }
    /// The values of a kept column, one per point; nullptr when no kept column has that name.
    const std::vector<std::string>* column(std::string_view name) const noexcept;
};

/// Reads points from a CSV file with a header row (RFC 4180: fields may be double-quoted, a
/// quoted field may hold the delimiter, line breaks and doubled quotes, and blanks around its
/// quotes are dropped; CRLF or LF line ends; a UTF-8 byte-order mark is dropped; empty lines are
/// skipped). Text is kept as bytes (UTF-8 stays UTF-8). Numbers may have surrounding spaces and must be finite. Throws orbis::Error naming the
/// file, the line and the column as every reader does (Diagnostics.h), e.g.
///   cities.csv:12: column 2 "lat": expected a finite number (latitude), got "north"
CsvPoints loadCsvPoints(const std::filesystem::path& path, const CsvPointsOptions& options = {});

/// The columns of a CSV file's header row (read as loadCsvPoints reads it, blanks trimmed), reading
/// no further than the first line. Throws orbis::Error naming the file when it cannot be read, has
/// no header row, or a first line longer than 64 KiB.
std::vector<std::string> readCsvHeader(const std::filesystem::path& path, char delimiter = ',');

/// Parses CSV text already in memory; `sourceName` stands for the file in messages.
CsvPoints parseCsvPoints(std::string text, std::string_view sourceName, const CsvPointsOptions& options = {});

} // namespace orbis::world
