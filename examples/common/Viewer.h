#pragma once

// The interactive window shared by `orbis view` and the scene examples' --view.

#include <orbis/renderer/Device.h>
#include <orbis/scene/Scene.h>

#include <optional>
#include <string>

namespace orbis::examples {

struct ViewerOptions {
    int width = 800;
    int height = 600;
    std::string title = "Orbis";
    std::optional<int> frames;         ///< stop after this many frames; empty: until closed
    std::optional<std::string> output; ///< with frames: the last frame as the window showed it
};

/// A window device of the options' size, for the scene the viewer will show.
renderer::Device createViewerDevice(const ViewerOptions& options);

/// Shows `scene` in the window of `device` (from createViewerDevice) until Escape or closing, or
/// for options.frames frames. Drag turns the globe and the wheel zooms (orbiting the centre); F
/// switches to flying (drag to look around, W A S D to move, E and Q up and down) and back; H flies
/// back to the starting view (CameraFlight; any drag or wheel step takes over from it). While tiles
/// stream, the title bar shows how many are drawn and pending. The
/// scene's camera stays as it is until the first input. Each frame is rendered offscreen, where
/// the scene may have the float depth buffer a window lacks, and copied to the window. Prints the
/// first frame's statistics. Throws orbis::Error as Scene::render does.
void runViewer(renderer::Device& device, scene::Scene& scene, const ViewerOptions& options);

} // namespace orbis::examples
