#include <orbis/world/CsvPoints.h>

#include <orbis/core/Error.h>
#include <orbis/core/Math.h>

#include "GeodeticChecks.h"
#include "TempFiles.h"

#include <catch2/catch.hpp>

#include <algorithm>

using namespace orbis;
using namespace orbis::world;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;

namespace {

const std::filesystem::path kCities = std::filesystem::path(ORBIS_SOURCE_DIR) / "data/geonames/cities.csv";

std::size_t indexOf(const std::vector<std::string>& column, std::string_view value)
{
    return static_cast<std::size_t>(std::find(column.begin(), column.end(), value) - column.begin());
}

} // namespace

TEST_CASE("loadCsvPoints reads all 171075 GeoNames cities with the default columns", "[world][csv]")
{
    const CsvPoints cities = loadCsvPoints(kCities);
    REQUIRE(cities.size() == 171075);
    CHECK(cities.warnings.empty());
    CHECK(cities.propertyNames == std::vector<std::string>{"name", "country"});
    const auto* names = cities.column("name");
    const auto* countries = cities.column("country");
    REQUIRE(names);
    REQUIRE(countries);
    REQUIRE(names->size() == cities.size());
    CHECK(cities.column("lat") == nullptr);

    // The first row: "Vila",42.53176,1.56654,AD
    CHECK((*names)[0] == "Vila");
    CHECK((*countries)[0] == "AD");
    test::checkPosition(cities.positions[0], 1.56654, 42.53176);

    // A quoted name with a comma, and UTF-8 kept byte for byte.
    const std::size_t gjader = indexOf(*names, "Gjad\xC3\xABr, Dajc");
    REQUIRE(gjader < cities.size());
    CHECK((*countries)[gjader] == "AL");
    test::checkPosition(cities.positions[gjader], 19.59139, 41.88);
}

TEST_CASE("parseCsvPoints follows RFC 4180 quoting, line ends and a byte-order mark", "[world][csv]")
{
    const std::string text = "\xEF\xBB\xBFname,lat,lon,note\r\n"
                             "\"Saint-Jean, Quebec\",46.3,-72.2,plain\r\n"
                             "\r\n"
                             "\"He said \"\"hi\"\"\",1,2,\"two\nlines\"\n"
                             "S\xC3\xA3o Paulo, -23.55 ,-46.63,\"\"\n"
                             "\"\",0,0,last without a line end";
    const CsvPoints points = parseCsvPoints(text, "quoted.csv");
    REQUIRE(points.size() == 4);
    CHECK(points.propertyNames == std::vector<std::string>{"name", "note"});
    const auto& names = *points.column("name");
    const auto& notes = *points.column("note");
    CHECK(names[0] == "Saint-Jean, Quebec");
    CHECK(names[1] == "He said \"hi\"");
    CHECK(notes[1] == "two\nlines");
    CHECK(names[2] == "S\xC3\xA3o Paulo");
    CHECK(notes[2].empty());
    CHECK(names[3].empty());
    CHECK(notes[3] == "last without a line end");
    test::checkPosition(points.positions[0], -72.2, 46.3);
    test::checkPosition(points.positions[2], -46.63, -23.55);
}

TEST_CASE("parseCsvPoints takes named longitude, latitude and height columns and chosen properties", "[world][csv]")
{
    const std::string text = "id;x;y;z;label;unused\n"
                             "a;10.5;-20.25;1200;first;-\n"
                             "b;-180;90;-5.5;second;-\n";
    CsvPointsOptions options;
    // Assigned from std::string: GCC 12 warns falsely (-Wrestrict, bug 105329) on assigning a literal.
    options.longitudeColumn = std::string("x");
    options.latitudeColumn = std::string("y");
    options.heightColumn = std::string("z");
    options.propertyColumns = std::vector<std::string>{"label", "id"};
    options.delimiter = ';';
    const CsvPoints points = parseCsvPoints(text, "points.csv", options);
    REQUIRE(points.size() == 2);
    test::checkPosition(points.positions[0], 10.5, -20.25, 1200.0);
    test::checkPosition(points.positions[1], -180, 90, -5.5);
    CHECK(points.propertyNames == std::vector<std::string>{"label", "id"});
    CHECK(points.properties[0] == std::vector<std::string>{"first", "second"});
    CHECK(points.properties[1] == std::vector<std::string>{"a", "b"});

    options.propertyColumns = std::vector<std::string>{};
    CHECK(parseCsvPoints(text, "points.csv", options).propertyNames.empty());
}

TEST_CASE("CSV errors name the file, the line and the column, as every reader's do", "[world][csv]")
{
    const test::TempDirectory directory;
    const auto missingColumn = directory.write("missing.csv", "name,latitude,lon\nx,1,2\n");
    CHECK_THAT(test::errorMessage([&] { loadCsvPoints(missingColumn); }),
               Equals(missingColumn.string() +
                      ":1: no latitude column \"lat\" in the header (columns: \"name\", \"latitude\", \"lon\")"));

    const auto unterminated = directory.write("quote.csv", "name,lat,lon\n\"ok\",1,2\n\"Saint-Jean, Quebec,3,4\nx,5,6\n");
    CHECK_THAT(test::errorMessage([&] { loadCsvPoints(unterminated); }),
               Equals(unterminated.string() + ":3: column 1: unterminated quoted field (the closing quote is "
                                              "missing before the end of the file)"));

    const auto nonNumeric = directory.write("lat.csv", "name,lat,lon\na,1,2\nb,north,3\n");
    CHECK_THAT(test::errorMessage([&] { loadCsvPoints(nonNumeric); }),
               Equals(nonNumeric.string() + ":3: column 2 \"lat\": expected a finite number (latitude), got \"north\""));

    struct Case {
        std::string row;
        std::string expected;
    };
    const Case cases[] = {
        {"a,1", "f.csv:2: expected 3 fields as in the header, got 2"},
        {"a,1,2,3", "f.csv:2: expected 3 fields as in the header, got 4"},
        {"a,95,2", "f.csv:2: column 2 \"lat\": latitude 95 out of range [-90, 90]"},
        {"a,1,-180.5", "f.csv:2: column 3 \"lon\": longitude -180.5 out of range [-180, 180]"},
        {"a,nan,2", "f.csv:2: column 2 \"lat\": expected a finite number (latitude), got \"nan\""},
        {"a,1,inf", "f.csv:2: column 3 \"lon\": expected a finite number (longitude), got \"inf\""},
        {"a,1e999,2", "f.csv:2: column 2 \"lat\": expected a finite number (latitude), got \"1e999\""},
        {"a,,2", "f.csv:2: column 2 \"lat\": expected a finite number (latitude), got \"\""},
        {"a,1.5x,2", "f.csv:2: column 2 \"lat\": expected a finite number (latitude), got \"1.5x\""},
        {"\"a\"b,1,2", "f.csv:2: column 1: unexpected character after a closing quote"},
    };
    for (const Case& c : cases) {
        INFO(c.row);
        CHECK_THAT(test::errorMessage([&] { parseCsvPoints("name,lat,lon\n" + c.row + "\n", "f.csv"); }),
                   Contains(c.expected));
    }

    CHECK_THAT(test::errorMessage([] { parseCsvPoints("", "empty.csv"); }),
               Equals("empty.csv: the file is empty; expected a header row"));
    CHECK_THAT(test::errorMessage([] { loadCsvPoints("/nonexistent/cities.csv"); }),
               Contains("/nonexistent/cities.csv: CSV file: no such file"));
}

TEST_CASE("skipInvalidRows keeps the valid rows and reports each bad one with its line", "[world][csv]")
{
    const std::string text = "name,lat,lon\n"
                             "a,1,2\n"
                             "b,x,2\n"
                             "\"c\"d,1,2\n"
                             "\"e\",\"multi\nline\",3\n"
                             "f,3,4\n"
                             "g,5,\"unterminated\n"
                             "h,6,7\n";
    CHECK_THROWS_AS(parseCsvPoints(text, "f.csv"), Error);
    CsvPointsOptions options;
    options.skipInvalidRows = true;
    const CsvPoints points = parseCsvPoints(text, "f.csv", options);
    REQUIRE(points.size() == 2);
    CHECK(*points.column("name") == std::vector<std::string>{"a", "f"});
    REQUIRE(points.warnings.size() == 4);
    CHECK_THAT(points.warnings[0], Contains("f.csv:3: column 2 \"lat\""));
    CHECK_THAT(points.warnings[1], Contains("f.csv:4: column 1: unexpected character after a closing quote"));
    CHECK_THAT(points.warnings[2], Contains("f.csv:5: column 2 \"lat\": expected a finite number (latitude), got "
                                            "\"multi\\nline\"")); // quoted as JSON writes it: one line
    CHECK_THAT(points.warnings[3], Contains("f.csv:8: column 3: unterminated quoted field"));
}
