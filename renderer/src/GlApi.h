#pragma once

// The OpenGL entry points the renderer uses, loaded at run time through the backend's
// getProcAddress (eglGetProcAddress, OSMesaGetProcAddress, glfwGetProcAddress). Private to
// renderer/src: no public header includes this file, so the rest of Orbis never sees GL.

#include "GlProc.h"

#include <GL/glcorearb.h>

#include <cstdint>
#include <string>
#include <type_traits>

namespace orbis::renderer::detail {

// clang-format off
/// OpenGL 3.3 core functions: a driver without one of them cannot run the renderer.
#define ORBIS_GL_REQUIRED_FUNCTIONS(X)                                                             \
    X(PFNGLGETERRORPROC, glGetError)                                                               \
    X(PFNGLGETSTRINGPROC, glGetString)                                                             \
    X(PFNGLGETSTRINGIPROC, glGetStringi)                                                           \
    X(PFNGLGETINTEGERVPROC, glGetIntegerv)                                                         \
    X(PFNGLGETFLOATVPROC, glGetFloatv)                                                             \
    X(PFNGLENABLEPROC, glEnable)                                                                   \
    X(PFNGLDISABLEPROC, glDisable)                                                                 \
    X(PFNGLFINISHPROC, glFinish)                                                                   \
    X(PFNGLFLUSHPROC, glFlush)                                                                     \
    X(PFNGLVIEWPORTPROC, glViewport)                                                               \
    X(PFNGLSCISSORPROC, glScissor)                                                                 \
    X(PFNGLCLEARCOLORPROC, glClearColor)                                                           \
    X(PFNGLCLEARDEPTHPROC, glClearDepth)                                                           \
    X(PFNGLCLEARSTENCILPROC, glClearStencil)                                                       \
    X(PFNGLCLEARPROC, glClear)                                                                     \
    X(PFNGLCOLORMASKPROC, glColorMask)                                                             \
    X(PFNGLDEPTHMASKPROC, glDepthMask)                                                             \
    X(PFNGLSTENCILMASKSEPARATEPROC, glStencilMaskSeparate)                                         \
    X(PFNGLCULLFACEPROC, glCullFace)                                                               \
    X(PFNGLFRONTFACEPROC, glFrontFace)                                                             \
    X(PFNGLPOLYGONMODEPROC, glPolygonMode)                                                         \
    X(PFNGLPOLYGONOFFSETPROC, glPolygonOffset)                                                     \
    X(PFNGLDEPTHFUNCPROC, glDepthFunc)                                                             \
    X(PFNGLDEPTHRANGEPROC, glDepthRange)                                                           \
    X(PFNGLSTENCILFUNCSEPARATEPROC, glStencilFuncSeparate)                                         \
    X(PFNGLSTENCILOPSEPARATEPROC, glStencilOpSeparate)                                             \
    X(PFNGLBLENDFUNCSEPARATEPROC, glBlendFuncSeparate)                                             \
    X(PFNGLBLENDEQUATIONSEPARATEPROC, glBlendEquationSeparate)                                     \
    X(PFNGLBLENDCOLORPROC, glBlendColor)                                                           \
    X(PFNGLPRIMITIVERESTARTINDEXPROC, glPrimitiveRestartIndex)                                     \
    X(PFNGLPIXELSTOREIPROC, glPixelStorei)                                                         \
    X(PFNGLREADPIXELSPROC, glReadPixels)                                                           \
    X(PFNGLREADBUFFERPROC, glReadBuffer)                                                           \
    X(PFNGLDRAWBUFFERSPROC, glDrawBuffers)                                                         \
    X(PFNGLGENBUFFERSPROC, glGenBuffers)                                                           \
    X(PFNGLDELETEBUFFERSPROC, glDeleteBuffers)                                                     \
    X(PFNGLBINDBUFFERPROC, glBindBuffer)                                                           \
    X(PFNGLBUFFERDATAPROC, glBufferData)                                                           \
    X(PFNGLBUFFERSUBDATAPROC, glBufferSubData)                                                     \
    X(PFNGLGETBUFFERSUBDATAPROC, glGetBufferSubData)                                               \
    X(PFNGLGENVERTEXARRAYSPROC, glGenVertexArrays)                                                 \
    X(PFNGLDELETEVERTEXARRAYSPROC, glDeleteVertexArrays)                                           \
    X(PFNGLBINDVERTEXARRAYPROC, glBindVertexArray)                                                 \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, glEnableVertexAttribArray)                                 \
    X(PFNGLDISABLEVERTEXATTRIBARRAYPROC, glDisableVertexAttribArray)                               \
    X(PFNGLVERTEXATTRIBPOINTERPROC, glVertexAttribPointer)                                         \
    X(PFNGLVERTEXATTRIBIPOINTERPROC, glVertexAttribIPointer)                                       \
    X(PFNGLDRAWARRAYSPROC, glDrawArrays)                                                           \
    X(PFNGLDRAWELEMENTSPROC, glDrawElements)                                                       \
    X(PFNGLCREATESHADERPROC, glCreateShader)                                                       \
    X(PFNGLSHADERSOURCEPROC, glShaderSource)                                                       \
    X(PFNGLCOMPILESHADERPROC, glCompileShader)                                                     \
    X(PFNGLGETSHADERIVPROC, glGetShaderiv)                                                         \
    X(PFNGLGETSHADERINFOLOGPROC, glGetShaderInfoLog)                                               \
    X(PFNGLDELETESHADERPROC, glDeleteShader)                                                       \
    X(PFNGLCREATEPROGRAMPROC, glCreateProgram)                                                     \
    X(PFNGLATTACHSHADERPROC, glAttachShader)                                                       \
    X(PFNGLDETACHSHADERPROC, glDetachShader)                                                       \
    X(PFNGLBINDATTRIBLOCATIONPROC, glBindAttribLocation)                                           \
    X(PFNGLLINKPROGRAMPROC, glLinkProgram)                                                         \
    X(PFNGLGETPROGRAMIVPROC, glGetProgramiv)                                                       \
    X(PFNGLGETPROGRAMINFOLOGPROC, glGetProgramInfoLog)                                             \
    X(PFNGLDELETEPROGRAMPROC, glDeleteProgram)                                                     \
    X(PFNGLUSEPROGRAMPROC, glUseProgram)                                                           \
    X(PFNGLGETACTIVEATTRIBPROC, glGetActiveAttrib)                                                 \
    X(PFNGLGETATTRIBLOCATIONPROC, glGetAttribLocation)                                             \
    X(PFNGLGETACTIVEUNIFORMPROC, glGetActiveUniform)                                               \
    X(PFNGLGETUNIFORMLOCATIONPROC, glGetUniformLocation)                                           \
    X(PFNGLUNIFORM1IPROC, glUniform1i)                                                             \
    X(PFNGLUNIFORM1IVPROC, glUniform1iv)                                                           \
    X(PFNGLUNIFORM2IVPROC, glUniform2iv)                                                           \
    X(PFNGLUNIFORM3IVPROC, glUniform3iv)                                                           \
    X(PFNGLUNIFORM4IVPROC, glUniform4iv)                                                           \
    X(PFNGLUNIFORM1FVPROC, glUniform1fv)                                                           \
    X(PFNGLUNIFORM2FVPROC, glUniform2fv)                                                           \
    X(PFNGLUNIFORM3FVPROC, glUniform3fv)                                                           \
    X(PFNGLUNIFORM4FVPROC, glUniform4fv)                                                           \
    X(PFNGLUNIFORMMATRIX2FVPROC, glUniformMatrix2fv)                                               \
    X(PFNGLUNIFORMMATRIX3FVPROC, glUniformMatrix3fv)                                               \
    X(PFNGLUNIFORMMATRIX4FVPROC, glUniformMatrix4fv)                                               \
    X(PFNGLGENTEXTURESPROC, glGenTextures)                                                         \
    X(PFNGLDELETETEXTURESPROC, glDeleteTextures)                                                   \
    X(PFNGLBINDTEXTUREPROC, glBindTexture)                                                         \
    X(PFNGLACTIVETEXTUREPROC, glActiveTexture)                                                     \
    X(PFNGLTEXIMAGE2DPROC, glTexImage2D)                                                           \
    X(PFNGLTEXIMAGE2DMULTISAMPLEPROC, glTexImage2DMultisample)                                     \
    X(PFNGLTEXSUBIMAGE2DPROC, glTexSubImage2D)                                                     \
    X(PFNGLGETTEXIMAGEPROC, glGetTexImage)                                                         \
    X(PFNGLTEXPARAMETERIPROC, glTexParameteri)                                                     \
    X(PFNGLGENERATEMIPMAPPROC, glGenerateMipmap)                                                   \
    X(PFNGLGENSAMPLERSPROC, glGenSamplers)                                                         \
    X(PFNGLDELETESAMPLERSPROC, glDeleteSamplers)                                                   \
    X(PFNGLBINDSAMPLERPROC, glBindSampler)                                                         \
    X(PFNGLSAMPLERPARAMETERIPROC, glSamplerParameteri)                                             \
    X(PFNGLSAMPLERPARAMETERFPROC, glSamplerParameterf)                                             \
    X(PFNGLGENFRAMEBUFFERSPROC, glGenFramebuffers)                                                 \
    X(PFNGLDELETEFRAMEBUFFERSPROC, glDeleteFramebuffers)                                           \
    X(PFNGLBINDFRAMEBUFFERPROC, glBindFramebuffer)                                                 \
    X(PFNGLBLITFRAMEBUFFERPROC, glBlitFramebuffer)                                                 \
    X(PFNGLFRAMEBUFFERTEXTURE2DPROC, glFramebufferTexture2D)                                       \
    X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, glCheckFramebufferStatus)                                   \
    X(PFNGLFENCESYNCPROC, glFenceSync)                                                             \
    X(PFNGLDELETESYNCPROC, glDeleteSync)                                                           \
    X(PFNGLCLIENTWAITSYNCPROC, glClientWaitSync)                                                   \
    X(PFNGLWAITSYNCPROC, glWaitSync)                                                               \
    X(PFNGLGETSYNCIVPROC, glGetSynciv)                                                             \
    X(PFNGLTRANSFORMFEEDBACKVARYINGSPROC, glTransformFeedbackVaryings)                             \
    X(PFNGLGETTRANSFORMFEEDBACKVARYINGPROC, glGetTransformFeedbackVarying)                         \
    X(PFNGLBEGINTRANSFORMFEEDBACKPROC, glBeginTransformFeedback)                                   \
    X(PFNGLENDTRANSFORMFEEDBACKPROC, glEndTransformFeedback)                                       \
    X(PFNGLBINDBUFFERBASEPROC, glBindBufferBase)

/// KHR_debug (core in 4.3): used when present, for messages and object labels. ARB_clip_control
/// (core in 4.5): complementary depth with a 0..1 clip-space depth range. ARB_sparse_texture with
/// immutable storage (core in 4.2) and format queries (4.2): partially resident textures.
#define ORBIS_GL_OPTIONAL_FUNCTIONS(X)                                                             \
    X(PFNGLDEBUGMESSAGECALLBACKPROC, glDebugMessageCallback)                                       \
    X(PFNGLDEBUGMESSAGECONTROLPROC, glDebugMessageControl)                                         \
    X(PFNGLOBJECTLABELPROC, glObjectLabel)                                                         \
    X(PFNGLCLIPCONTROLPROC, glClipControl)                                                         \
    X(PFNGLTEXSTORAGE2DPROC, glTexStorage2D)                                                       \
    X(PFNGLGETINTERNALFORMATIVPROC, glGetInternalformativ)                                         \
    X(PFNGLGETTEXPARAMETERIVPROC, glGetTexParameteriv)                                             \
    X(PFNGLTEXPAGECOMMITMENTARBPROC, glTexPageCommitmentARB)
// clang-format on

class GlApi;

/// GL calls made on this thread, all contexts together (read by the statistics).
extern thread_local std::uint64_t tlsGlCallCount;

/// One GL entry point. Calling it counts the call and, when the GlApi's checks are on, calls
/// glGetError afterwards and throws orbis::Error naming the function. `unchecked` never throws
/// (for destructors).
template <typename Pointer>
class GlFunction;

template <typename R, typename... Args>
class GlFunction<R (*)(Args...)> {
public:
    using Pointer = R (*)(Args...);

    R operator()(Args... args) const
    {
        ++tlsGlCallCount;
        if constexpr (std::is_void_v<R>) {
            _pointer(args...);
            if (*_checks) [[unlikely]] {
                check();
            }
        } else {
            R result = _pointer(args...);
            if (*_checks) [[unlikely]] {
                check();
            }
            return result;
        }
    }

    R unchecked(Args... args) const noexcept
    {
        ++tlsGlCallCount;
        return _pointer(args...);
    }

    /// The raw driver entry point: the benchmark's baseline calls it directly.
    Pointer pointer() const noexcept { return _pointer; }
    explicit operator bool() const noexcept { return _pointer != nullptr; }

private:
    friend class GlApi;
    void check() const;

    Pointer _pointer = nullptr;
    const char* _name = "";
    const GlApi* _api = nullptr;
    const bool* _checks = nullptr;
};

/// The loaded entry points of one device (every context of the device shares them).
class GlApi {
public:
    /// Resolves every function; throws orbis::Error naming the first required one that is missing.
    /// `checks` turns the glGetError check after every call on.
    GlApi(GetProcAddressFunction getProcAddress, const std::string& backendName, bool checks);
    GlApi(const GlApi&) = delete;
    GlApi& operator=(const GlApi&) = delete;

#define ORBIS_GL_DECLARE(type, name) GlFunction<type> name;
    ORBIS_GL_REQUIRED_FUNCTIONS(ORBIS_GL_DECLARE)
    ORBIS_GL_OPTIONAL_FUNCTIONS(ORBIS_GL_DECLARE)
#undef ORBIS_GL_DECLARE

    bool checks() const noexcept { return _checks; }
    /// Calls glGetError until it reports no error; throws orbis::Error naming `function` and the
    /// first error when there was one.
    void checkError(const char* function) const;

private:
    bool _checks = false;
};

template <typename R, typename... Args>
void GlFunction<R (*)(Args...)>::check() const
{
    _api->checkError(_name);
}

/// "GL_INVALID_ENUM" and so on; the number in hex for an unknown code.
std::string glErrorName(GLenum error);

} // namespace orbis::renderer::detail
