#pragma once

// Frame timings the scene sections share: a scene's milliseconds per frame, and the fill floor
// (a full-screen quad reading one mipmapped texture per pixel) that frame times are judged against.

namespace orbis::renderer {
class Context;
class Device;
} // namespace orbis::renderer

namespace orbis::scene {
class Scene;
} // namespace orbis::scene

namespace orbis::bench {

/// Average milliseconds per frame over `frames` frames after one warm-up frame.
double millisecondsPerFrame(scene::Scene& scene, renderer::Context& context, int frames);

/// A full-screen quad with the day texture into the context's framebuffer, drawn `frames` times
/// (GPU finished each time): the fill floor.
double fillFloorMilliseconds(renderer::Device& device, renderer::Context& context, int frames);

} // namespace orbis::bench
