#pragma once

// Small helpers for rendering tests: a device shared by the tests of one process, simple meshes
// and programs, and pixel checks.

#include "GoldenImage.h"

#include <orbis/renderer/Device.h>

#include <glm/vec4.hpp>

#include <string>

namespace orbis::test {

/// One device for the tests of this process (EGL, or OSMesa when EGL fails), its main context made
/// current on the calling thread.
renderer::Device& sharedDevice();

/// The golden tolerance of an image llvmpipe renders exactly: 2 a channel and not one pixel beyond
/// on llvmpipe (where CI runs and the goldens were made, so a misspelt label fails), `elsewhere` on
/// other drivers, which round edges and blend their own way.
GoldenTolerance exactOnLlvmpipe(const renderer::Device& device, const GoldenTolerance& elsewhere);

/// A quad covering [x0, x1] x [y0, y1] at depth z (clip coordinates with the default SceneState),
/// counter-clockwise, indexed.
Mesh quad(double x0, double y0, double x1, double y1, double z = 0.0);
/// The whole viewport at depth z.
inline Mesh fullScreenQuad(double z = 0.0)
{
    return quad(-1.0, -1.0, 1.0, 1.0, z);
}

/// "position" transformed by og_modelViewProjectionMatrix, coloured by uniform vec4 u_color.
renderer::ShaderProgramDescription solidColorDescription();

/// "position" as it is (clip coordinates), coloured by og_texture0 at "textureCoordinate" times
/// uniform float u_scale (1: the texture once over a quad).
renderer::ShaderProgramDescription texturedDescription();

/// A size x size framebuffer on the shared device, a program and a full-screen quad for it: where
/// most drawing tests start.
///
///     test::QuadFixture quad(16);
///     auto& [device, context, framebuffer, program, array] = quad;
struct QuadFixture {
    explicit QuadFixture(int size, const renderer::ShaderProgramDescription& description = solidColorDescription());

    renderer::Device& device;
    renderer::Context& context;
    renderer::Framebuffer framebuffer;
    renderer::ShaderProgram program;
    renderer::VertexArray array;
};

/// A pixel of an RGBA image (x from the left, y from the top).
glm::ivec4 pixelAt(const Image& image, int x, int y);

/// True when every channel is within tolerance of expected.
bool pixelNear(const Image& image, int x, int y, const glm::ivec4& expected, int tolerance = 1);

/// "(r, g, b, a)" of a pixel, for messages.
std::string describePixel(const Image& image, int x, int y);

/// A command drawing `array` with `program` into `framebuffer`, the book's default render state.
renderer::DrawCommand makeCommand(const renderer::VertexArray& array, renderer::ShaderProgram& program, renderer::Framebuffer& framebuffer,
                        const glm::vec4& color, const char* name = "test");

} // namespace orbis::test
