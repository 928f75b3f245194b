#include "orbis/scene/Effect.h"

namespace orbis::scene {

std::vector<std::string> effectNames(std::uint32_t effects)
{
    static constexpr const char* kNames[] = {"globe",      "lighting", "night lights", "grid",     "meshes",
                                             "billboards", "labels",   "polylines",    "polygons", "models",
                                             "tiled imagery", "terrain", "virtual texture", "terrain shading", "clipmap terrain",
                                             "draped polygons", "water", "colour adjustment"};
    std::vector<std::string> names;
    for (std::uint32_t bit = 0; bit < std::size(kNames); ++bit) {
        if (effects & (1u << bit)) {
            names.emplace_back(kNames[bit]);
        }
    }
    return names;
}

} // namespace orbis::scene
