#include "orbis/world/SceneFile.h"

namespace orbis::world {

SceneDescription parseDefaultScene(const SceneParseOptions& options)
{
    // Its text is generated from data/scenes/default.json (DefaultSceneText.cpp.in).
    return parseSceneText(defaultSceneText(), "<default scene>", std::filesystem::path("."), options);
}

} // namespace orbis::world
