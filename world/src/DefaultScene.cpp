#include "orbis/world/SceneFile.h"

namespace orbis::world {

SceneDescription parseDefaultScene(const std::filesystem::path& scenesDirectory, const SceneParseOptions& options)
{
    // Its text is generated from data/scenes/default.json (DefaultSceneText.cpp.in).
    return parseSceneText(defaultSceneText(), "<default scene>", scenesDirectory, options);
}

} // namespace orbis::world
