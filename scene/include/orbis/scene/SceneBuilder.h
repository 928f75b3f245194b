#pragma once

#include "orbis/scene/Scene.h"
#include <orbis/world/SceneDescription.h>

#include <orbis/world/TileLoader.h>

#include <string>
#include <vector>

namespace orbis::scene {

/// How a scene built from a file streams its tiles.
struct SceneBuildOptions {
    /// The tile loader's threads and timing (TileLoaderOptions): deterministic by default, so that
    /// `orbis render` writes the same picture every run; an interactive viewer asks for
    /// asynchronous timing (latencyFrames 0).
    world::TileLoaderOptions loader;
};

/// Fills a Scene from a scene file's description: camera, Sun, background, globe and layers,
/// creating only what the description asks for (GPU resources follow on the first render).
/// Model layers read their glTF file here, and imagery layers open their tile sources. Throws
/// orbis::Error naming the layer ("/layers/2", "/globe/imagery/0") for a file or source it cannot
/// read (the reader's message follows), or a depth strategy this build cannot draw yet. Returns
/// the warnings, one line each naming the layer and the file: what a layer left out (features and
/// polygons refused, with "invalid": "skip") or repaired (rings a TopoJSON file's quantization
/// collapsed).
std::vector<std::string> populateScene(const world::SceneDescription& description, Scene& scene,
                                       const SceneBuildOptions& options = {});

} // namespace orbis::scene
