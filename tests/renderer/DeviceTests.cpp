#include "RendererTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>

#include <catch2/catch.hpp>

#include <cstdio>
#include <cstdlib>

using namespace orbis;
using namespace orbis::renderer;
using Catch::Matchers::Contains;

namespace {

/// The "major.minor" at the start of GL_VERSION, as a number like 45.
int versionNumber(const std::string& version)
{
    int major = 0;
    int minor = 0;
    std::sscanf(version.c_str(), "%d.%d", &major, &minor);
    return major * 10 + minor;
}

/// Sets an environment variable for the scope of a test and restores it afterwards.
struct ScopedEnvironment {
    ScopedEnvironment(const char* name_, const char* value) : name(name_)
    {
        if (const char* old = std::getenv(name)) {
            previous = old;
            hadPrevious = true;
        }
        setenv(name, value, 1);
    }
    ~ScopedEnvironment()
    {
        if (hadPrevious) {
            setenv(name, previous.c_str(), 1);
        } else {
            unsetenv(name);
        }
    }
    const char* name;
    std::string previous;
    bool hadPrevious = false;
};

} // namespace

TEST_CASE("Device gives an OpenGL 3.3 core context headless with each backend", "[renderer][device]")
{
    const GlBackend backend = GENERATE(GlBackend::Egl, GlBackend::OsMesa);
    DeviceOptions options;
    options.backend = backend;
    Device device(options);
    const DeviceInfo& info = device.info();
    INFO(info.backendDescription << " | " << info.renderer << " | " << info.version);
    CHECK(info.backend == backend);
    CHECK(versionNumber(info.version) >= 33);
    CHECK(info.maxTextureSize >= 1024);       // GL 3.3 guarantees 1024
    CHECK(info.maxTextureUnits >= 15);        // 16 guaranteed, one kept for uploads
    CHECK(info.maxColorAttachments >= 8);
    CHECK(device.context().isCurrent());
}

TEST_CASE("ORBIS_GL_BACKEND chooses the backend of an automatic device", "[renderer][device]")
{
    {
        ScopedEnvironment environment("ORBIS_GL_BACKEND", "osmesa");
        Device device;
        CHECK(device.info().backend == GlBackend::OsMesa);
    }
    {
        ScopedEnvironment environment("ORBIS_GL_BACKEND", "egl");
        Device device;
        CHECK(device.info().backend == GlBackend::Egl);
    }
    ScopedEnvironment environment("ORBIS_GL_BACKEND", "vulkan");
    REQUIRE_THROWS_WITH(Device(), Contains("ORBIS_GL_BACKEND=vulkan") && Contains("egl, osmesa"));
}

TEST_CASE("A version no backend can give is a clear error that says what each backend answered", "[renderer][device][headless]")
{
    DeviceOptions options;
    options.glMajorVersion = 9;
    options.glMinorVersion = 0;
    REQUIRE_THROWS_WITH(Device(options), Contains("no OpenGL 9.0 core context") && Contains("EGL:") &&
                                             Contains("OSMesa") && Contains("surfaceless"));
}

TEST_CASE("Two devices in one process keep their own contexts", "[renderer][device]")
{
    DeviceOptions egl;
    egl.backend = GlBackend::Egl;
    DeviceOptions osMesa;
    osMesa.backend = GlBackend::OsMesa;
    Device first(egl);
    Device second(osMesa);
    CHECK(second.context().isCurrent());
    CHECK_FALSE(first.context().isCurrent());
    // A resource of the first device needs the first device's context.
    REQUIRE_THROWS_WITH(first.createTexture2D({4, 4, TextureFormat::RGBA8}), Contains("another Device"));
    first.context().makeCurrent();
    CHECK(first.createTexture2D({4, 4, TextureFormat::RGBA8}).valid());
}
