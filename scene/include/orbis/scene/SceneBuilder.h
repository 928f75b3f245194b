#pragma once

#include "orbis/scene/Scene.h"
#include <orbis/world/SceneDescription.h>

namespace orbis::scene {

/// Fills a Scene from a scene file's description: camera, Sun, background, globe and layers,
/// creating only what the description asks for (GPU resources follow on the first render).
/// Model layers read their glTF file here. Throws orbis::Error naming the layer ("/layers/2") for
/// a file it cannot read (the model reader's message follows), or a depth strategy this build
/// cannot draw yet.
void populateScene(const world::SceneDescription& description, Scene& scene);

} // namespace orbis::scene
