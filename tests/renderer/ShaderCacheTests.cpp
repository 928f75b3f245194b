#include "RendererTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>

#include <catch2/catch.hpp>

using namespace orbis;
using namespace orbis::renderer;

TEST_CASE("The shader cache compiles each variant once, on first use", "[renderer][shadercache]")
{
    DeviceOptions options;
    Device device(options); // a fresh cache
    ShaderCache& cache = device.shaderCache();
    CHECK(cache.size() == 0);
    CHECK(cache.compiles() == 0);

    const ShaderProgramDescription plain = test::solidColorDescription();
    const auto first = cache.get(plain);
    const auto second = cache.get(plain);
    CHECK(first == second);
    CHECK(cache.compiles() == 1);
    CHECK(cache.hits() == 1);

    ShaderProgramDescription variant = plain;
    variant.defines = {{"NIGHT_LIGHTS", "1"}};
    const auto third = cache.get(variant);
    CHECK(third != first);
    CHECK(cache.compiles() == 2);
    CHECK(cache.get(variant) == third);
    CHECK(cache.size() == 2);

    // The same sources without the library are another variant; the name is not part of the key.
    ShaderProgramDescription noLibrary = plain;
    noLibrary.builtinLibrary = false;
    CHECK(cache.get(noLibrary) != first);
    ShaderProgramDescription renamed = plain;
    renamed.name = "another name";
    CHECK(cache.get(renamed) == first);

    // A failure throws and leaves nothing behind.
    ShaderProgramDescription broken = plain;
    broken.fragment.text = "void main() { nonsense; }";
    CHECK_THROWS_AS(cache.get(broken), Error);
    CHECK(cache.size() == 3);
    CHECK(cache.compiles() == 3);
}

TEST_CASE("Cache keys keep apart sources that join to the same text", "[renderer][shadercache]")
{
    ShaderProgramDescription a = test::solidColorDescription();
    ShaderProgramDescription b = a;
    a.defines = {{"AB", "C"}};
    b.defines = {{"A", "BC"}};
    CHECK(a.cacheKey() != b.cacheKey());
    CHECK(a.cacheKey() == ShaderProgramDescription(a).cacheKey());
}
