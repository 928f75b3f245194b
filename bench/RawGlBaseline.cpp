#include "RawGlBaseline.h"

// The renderer's private headers (bench/CMakeLists.txt adds renderer/src for this file's sake).
#include "ContextState.h"
#include "GlEnums.h"
#include "ShaderProgramAccess.h"

#include <orbis/core/Error.h>
#include <orbis/renderer/Device.h>

#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <vector>

// The friend Context and VertexArray name for this file: it reads their GL names and state.
namespace orbis::renderer::detail {

struct RawGlBaselineAccess {
    static std::uint64_t run(Context& context, Framebuffer& framebuffer, std::span<ShaderProgram* const> programs,
                             std::span<const VertexArray* const> arrays, std::span<const bench::BaselineDraw> draws);
};

std::uint64_t RawGlBaselineAccess::run(Context& context, Framebuffer& framebuffer,
                                       std::span<ShaderProgram* const> programs,
                                       std::span<const VertexArray* const> arrays, std::span<const bench::BaselineDraw> draws)
{
    // Bind the framebuffer the way a draw would (attachments checked), then leave Orbis aside.
    ClearState clear;
    clear.buffers = ClearBuffers::None;
    context.clear(clear, &framebuffer);
    const GlApi& gl = context._state->gl;
    std::uint64_t calls = 0;

    // The driver's entry points, called directly: no counting, no error checks.
    const auto useProgram = gl.glUseProgram.pointer();
    const auto bindVertexArray = gl.glBindVertexArray.pointer();
    const auto enable = gl.glEnable.pointer();
    const auto disable = gl.glDisable.pointer();
    const auto depthFunc = gl.glDepthFunc.pointer();
    const auto uniform2fv = gl.glUniform2fv.pointer();
    const auto uniform4fv = gl.glUniform4fv.pointer();
    const auto drawElements = gl.glDrawElements.pointer();

    // Setup: uniform locations, the identity matrix, the blend function, the viewport.
    struct ProgramInfo {
        GLuint handle;
        GLint offset;
        GLint color;
    };
    std::vector<ProgramInfo> programInfo;
    const glm::mat4 identity(1.0f);
    for (ShaderProgram* program : programs) {
        const GLuint handle = ShaderProgramAccess::handle(*program);
        ProgramInfo info{handle, gl.glGetUniformLocation.pointer()(handle, "u_offset"),
                         gl.glGetUniformLocation.pointer()(handle, "u_color")};
        useProgram(handle);
        const GLint matrix = gl.glGetUniformLocation.pointer()(handle, "og_modelViewProjectionMatrix");
        if (matrix >= 0) {
            gl.glUniformMatrix4fv.pointer()(matrix, 1, GL_FALSE, glm::value_ptr(identity));
            ++calls;
        }
        calls += 4;
        programInfo.push_back(info);
    }
    struct ArrayInfo {
        GLuint name;
        GLsizei count;
        GLenum type;
    };
    std::vector<ArrayInfo> arrayInfo;
    for (const VertexArray* array : arrays) {
        arrayInfo.push_back({array->_name, static_cast<GLsizei>(array->indexCount()), toGl(array->indexType())});
    }
    gl.glViewport.pointer()(0, 0, framebuffer.width(), framebuffer.height());
    gl.glBlendFuncSeparate.pointer()(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    gl.glBlendEquationSeparate.pointer()(GL_FUNC_ADD, GL_FUNC_ADD);
    gl.glCullFace.pointer()(GL_BACK);
    gl.glFrontFace.pointer()(GL_CCW);
    enable(GL_DEPTH_TEST);
    gl.glDepthMask.pointer()(GL_TRUE);
    gl.glColorMask.pointer()(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.glDisable.pointer()(GL_SCISSOR_TEST);
    gl.glDisable.pointer()(GL_STENCIL_TEST);
    calls += 10;

    // The loop: change what differs from the previous draw, set the uniforms, draw.
    int program = -1;
    int array = -1;
    glm::vec2 offset{NAN};
    glm::vec4 color{NAN};
    int blending = -1;
    int lessOrEqual = -1;
    int culling = -1;
    for (const bench::BaselineDraw& draw : draws) {
        if (draw.program != program) {
            program = draw.program;
            useProgram(programInfo[program].handle);
            offset = glm::vec2(NAN); // uniforms belong to the program
            color = glm::vec4(NAN);
            ++calls;
        }
        if (draw.vertexArray != array) {
            array = draw.vertexArray;
            bindVertexArray(arrayInfo[array].name);
            ++calls;
        }
        if (int(draw.blending) != blending) {
            blending = draw.blending;
            (draw.blending ? enable : disable)(GL_BLEND);
            ++calls;
        }
        if (int(draw.depthLessOrEqual) != lessOrEqual) {
            lessOrEqual = draw.depthLessOrEqual;
            depthFunc(draw.depthLessOrEqual ? GL_LEQUAL : GL_LESS);
            ++calls;
        }
        if (int(draw.culling) != culling) {
            culling = draw.culling;
            (draw.culling ? enable : disable)(GL_CULL_FACE);
            ++calls;
        }
        if (draw.offset != offset) {
            offset = draw.offset;
            uniform2fv(programInfo[program].offset, 1, glm::value_ptr(draw.offset));
            ++calls;
        }
        if (draw.color != color) {
            color = draw.color;
            uniform4fv(programInfo[program].color, 1, glm::value_ptr(draw.color));
            ++calls;
        }
        drawElements(GL_TRIANGLES, arrayInfo[array].count, arrayInfo[array].type, nullptr);
        ++calls;
    }
    gl.glFinish.pointer()();
    ++calls;

    // Orbis's view of the GL state and of the programs' uniforms is stale now.
    context.resetState();
    for (ShaderProgram* p : programs) {
        ShaderProgramAccess::markAllDirty(*p);
    }
    return calls;
}

} // namespace orbis::renderer::detail

namespace orbis::bench {

renderer::RenderState baselineRenderState(const BaselineDraw& draw) noexcept
{
    renderer::RenderState state;
    if (draw.blending) {
        state.blending = renderer::Blending::alphaBlending();
    }
    state.depthTest.function =
        draw.depthLessOrEqual ? renderer::CompareFunction::LessOrEqual : renderer::CompareFunction::Less;
    state.facetCulling.enabled = draw.culling;
    return state;
}

std::uint64_t drawWithRawGl(renderer::Context& context, renderer::Framebuffer& framebuffer,
                            std::span<renderer::ShaderProgram* const> programs,
                            std::span<const renderer::VertexArray* const> arrays, std::span<const BaselineDraw> draws)
{
    if (!context.isCurrent()) {
        throw Error("drawWithRawGl: the context is not current on this thread");
    }
    for (const BaselineDraw& draw : draws) {
        if (draw.program < 0 || draw.program >= static_cast<int>(programs.size()) || draw.vertexArray < 0 ||
            draw.vertexArray >= static_cast<int>(arrays.size()) || !arrays[draw.vertexArray]->indexed()) {
            throw Error("drawWithRawGl: a draw names a program or an indexed vertex array that is not given");
        }
    }
    return renderer::detail::RawGlBaselineAccess::run(context, framebuffer, programs, arrays, draws);
}

} // namespace orbis::bench
