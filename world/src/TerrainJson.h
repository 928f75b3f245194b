#pragma once

// What the terrain readers share about JSON: layer.json's availability lists, which the
// quantized-mesh metadata extension repeats for the levels below a tile. Private to orbis::world.

#include "orbis/world/TerrainLayer.h"

#include <cstdint>
#include <string_view>
#include <vector>

namespace orbis::world::detail {

/// The "available" list of a metadata extension's JSON (an object; other keys ignored): element
/// i covers level firstLevel + i of the geographic scheme. Throws orbis::Error naming
/// `nameForMessages` for malformed JSON or rectangles outside their level.
std::vector<LevelAvailability> parseMetadataAvailability(std::string_view json, std::uint32_t firstLevel,
                                                         std::string_view nameForMessages);

} // namespace orbis::world::detail
