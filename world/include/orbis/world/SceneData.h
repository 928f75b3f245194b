#pragma once

// The data files a scene description names, read the one way both the scene layer (when it builds
// a scene: orbis::scene::populateScene) and `orbis validate` (validateSceneFile) read them, GL-free.

#include "orbis/world/Diagnostics.h"
#include "orbis/world/SceneDescription.h"
#include "orbis/world/TerrainSource.h"
#include "orbis/world/TileSource.h"

#include <orbis/core/Geodetic.h>

#include <filesystem>
#include <string>
#include <vector>

namespace orbis::world {

/// A points layer's positions and, when it has a label, each point's text ("" where a GeoJSON
/// feature lacks the property).
struct PointsData {
    std::vector<Geodetic3D> positions;
    std::vector<std::string> texts; ///< empty without a label; else one per position
};

/// Reads a points layer's CSV (longitude and latitude from any accepted column name) or GeoJSON
/// (Point and MultiPoint features). Throws orbis::Error naming the file and what is wrong, or the
/// label's field when the CSV has no such column.
PointsData readPointsData(const PointsLayer& layer);

/// Reads the file a layer's "source" names as building the scene would (a polyline has none), and
/// decodes a model's images, which rendering does only later: throws orbis::Error where building or
/// drawing the layer would fail on it.
void readLayerSource(const LayerDescription& layer);

/// The options a globe's imagery layer opens its tile source with (openTileSource): the layer's
/// scheme, levels and cache folder.
TileSourceOptions tileSourceOptions(const ImageryLayerDescription& layer);

/// How a scene's terrain source is opened (format, cache folder).
TerrainSourceOptions terrainSourceOptions(const TerrainDescription& terrain);

/// What `orbis validate` checks: every fault of a scene file (parseSceneFile, collecting), and when
/// the file itself has none, every file it names read as building and drawing the scene would
/// (readLayerSource, billboard images, a globe's textures through readGlobeImage, its imagery's tile
/// sources opened with tileSourceOptions), each such fault
/// stated at the key that names the file. Empty when rendering the scene would find nothing wrong
/// with its input. `description`, when given, receives what the file describes.
DiagnosticList validateSceneFile(const std::filesystem::path& path, SceneDescription* description = nullptr);

} // namespace orbis::world
