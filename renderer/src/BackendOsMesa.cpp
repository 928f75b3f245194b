// Mesa's off-screen library: a software context (llvmpipe) with no display at all. Each context is
// made current on a 1 x 1 buffer it owns; all drawing goes to framebuffer objects.

#include <GL/osmesa.h>

#include "Backend.h"

#include "orbis/core/Error.h"

#include <array>

namespace orbis::renderer::detail {
namespace {

GlProc osMesaProc(const char* name)
{
    return reinterpret_cast<GlProc>(OSMesaGetProcAddress(name));
}

class OsMesaContext final : public BackendContext {
public:
    explicit OsMesaContext(OSMesaContext context) noexcept : _context(context) {}
    ~OsMesaContext() override
    {
        if (OSMesaGetCurrentContext() == _context) {
            OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
        }
        OSMesaDestroyContext(_context);
    }
    void makeCurrent() override
    {
        if (!OSMesaMakeCurrent(_context, _buffer.data(), GL_UNSIGNED_BYTE, 1, 1)) {
            throw Error("OSMesa: OSMesaMakeCurrent failed");
        }
    }
    void releaseCurrent() noexcept override { OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0); }
    OSMesaContext handle() const noexcept { return _context; }

private:
    OSMesaContext _context;
    std::array<unsigned char, 4> _buffer{};
};

class OsMesaBackend final : public Backend {
public:
    explicit OsMesaBackend(const BackendRequest& request) : _request(request) {}

    std::unique_ptr<BackendContext> createContext(BackendContext* shareWith) override
    {
        const int attributes[] = {
            OSMESA_FORMAT, OSMESA_RGBA,
            OSMESA_DEPTH_BITS, 0,
            OSMESA_STENCIL_BITS, 0,
            OSMESA_ACCUM_BITS, 0,
            OSMESA_PROFILE, OSMESA_CORE_PROFILE,
            OSMESA_CONTEXT_MAJOR_VERSION, _request.majorVersion,
            OSMESA_CONTEXT_MINOR_VERSION, _request.minorVersion,
            0,
        };
        OSMesaContext share = shareWith ? static_cast<OsMesaContext*>(shareWith)->handle() : nullptr;
        OSMesaContext context = OSMesaCreateContextAttribs(attributes, share);
        if (!context) {
            throw Error("OSMesa: OSMesaCreateContextAttribs cannot create an OpenGL " +
                        std::to_string(_request.majorVersion) + "." + std::to_string(_request.minorVersion) +
                        " core context");
        }
        return std::make_unique<OsMesaContext>(context);
    }
    GetProcAddressFunction getProcAddress() const noexcept override { return &osMesaProc; }
    std::string description() const override { return "OSMesa (Mesa off-screen, software)"; }

private:
    BackendRequest _request;
};

} // namespace

std::unique_ptr<Backend> createOsMesaBackend(const BackendRequest& request)
{
    return std::make_unique<OsMesaBackend>(request);
}

} // namespace orbis::renderer::detail
