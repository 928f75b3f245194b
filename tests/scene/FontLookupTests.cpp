#include "TempFiles.h"

#include <orbis/core/Error.h>
#include <orbis/renderer/Font.h>
#include <orbis/scene/FontLookup.h>

#include <catch2/catch.hpp>

#include <cstdlib>
#include <optional>
#include <string>

using namespace orbis;
using namespace orbis::scene;
using Catch::Matchers::Contains;

namespace {

/// Sets an environment variable for one scope, putting back what was there.
class ScopedEnvironment {
public:
    ScopedEnvironment(const char* name, const std::string& value) : _name(name)
    {
        if (const char* old = std::getenv(name)) {
            _old = old;
        }
        ::setenv(name, value.c_str(), 1);
    }
    ~ScopedEnvironment()
    {
        if (_old) {
            ::setenv(_name, _old->c_str(), 1);
        } else {
            ::unsetenv(_name);
        }
    }
    ScopedEnvironment(const ScopedEnvironment&) = delete;
    ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

private:
    const char* _name;
    std::optional<std::string> _old;
};

} // namespace

TEST_CASE("fontconfig finds DejaVu Sans as a TrueType file the renderer reads", "[scene][font]")
{
    const std::optional<std::filesystem::path> found = findFont("DejaVu Sans");
    REQUIRE(found);
    CHECK(found->filename().string().starts_with("DejaVuSans"));
    CHECK(found->extension() == ".ttf");
    const renderer::Font font(*found);
    CHECK(font.glyphIndex(U'A') != 0);
}

TEST_CASE("ORBIS_FONT names the default font, and a missing one is an error naming it", "[scene][font]")
{
    const std::filesystem::path dejaVu = findFont("DejaVu Sans").value();
    {
        const ScopedEnvironment font("ORBIS_FONT", dejaVu.string());
        CHECK(defaultFontPath() == dejaVu);
    }
    const ScopedEnvironment font("ORBIS_FONT", "/no/such/font.ttf");
    REQUIRE_THROWS_WITH(defaultFontPath(), Contains("ORBIS_FONT=/no/such/font.ttf: no such font file"));
}

TEST_CASE("Without any font, the default font is a clear error saying how to give one", "[scene][font]")
{
    // A fontconfig configuration that lists no font folder at all.
    const test::TempDirectory folder;
    const std::filesystem::path config = folder.write("fonts.conf", "<?xml version=\"1.0\"?>\n<fontconfig>\n"
                                                                    "<cachedir>" + folder.path().string() +
                                                                    "</cachedir>\n</fontconfig>\n");
    const ScopedEnvironment file("FONTCONFIG_FILE", config.string());
    const ScopedEnvironment noOverride("ORBIS_FONT", "");
    CHECK_FALSE(findFont("DejaVu Sans"));
    const std::string message = test::errorMessage([] { defaultFontPath(); });
    CHECK_THAT(message, Contains("no font found"));
    CHECK_THAT(message, Contains("ORBIS_FONT"));
    CHECK_THAT(message, Contains("fonts-dejavu-core"));
}
