#include "GlApi.h"

#include "orbis/core/Error.h"

#include <cstdio>

namespace orbis::renderer::detail {

thread_local std::uint64_t tlsGlCallCount = 0;

GlApi::GlApi(GetProcAddressFunction getProcAddress, const std::string& backendName, bool checks)
    : _checks(checks)
{
#define ORBIS_GL_LOAD_REQUIRED(type, name)                                                                   \
    name._pointer = reinterpret_cast<type>(getProcAddress(#name));                                         \
    name._name = #name;                                                                                      \
    name._api = this;                                                                                        \
    name._checks = &_checks;                                                                                 \
    if (!name._pointer) {                                                                                    \
        throw Error(backendName + ": the OpenGL function " #name                                            \
                                  " is missing; the driver does not provide OpenGL 3.3 core");              \
    }
#define ORBIS_GL_LOAD_OPTIONAL(type, name)                                                                   \
    name._pointer = reinterpret_cast<type>(getProcAddress(#name));                                         \
    name._name = #name;                                                                                      \
    name._api = this;                                                                                        \
    name._checks = &_checks;
    ORBIS_GL_REQUIRED_FUNCTIONS(ORBIS_GL_LOAD_REQUIRED)
    ORBIS_GL_OPTIONAL_FUNCTIONS(ORBIS_GL_LOAD_OPTIONAL)
#undef ORBIS_GL_LOAD_REQUIRED
#undef ORBIS_GL_LOAD_OPTIONAL
}

void GlApi::checkError(const char* function) const
{
    const GLenum first = glGetError.pointer()();
    if (first == GL_NO_ERROR) {
        return;
    }
    // Drain the other flags so that the next check reports its own call.
    for (int i = 0; i < 16 && glGetError.pointer()() != GL_NO_ERROR; ++i) {
    }
    throw Error(std::string("OpenGL error ") + glErrorName(first) + " after " + function);
}

std::string glErrorName(GLenum error)
{
    switch (error) {
    case GL_NO_ERROR: return "GL_NO_ERROR";
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    default: {
        char text[32];
        std::snprintf(text, sizeof text, "0x%04X", error);
        return text;
    }
    }
}

} // namespace orbis::renderer::detail
