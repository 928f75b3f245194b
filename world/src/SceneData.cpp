#include "orbis/world/SceneData.h"

#include "orbis/world/CsvPoints.h"
#include "orbis/world/Diagnostics.h"
#include "orbis/world/GeoJson.h"
#include "orbis/world/GltfModel.h"
#include "orbis/world/ImageFile.h"
#include "orbis/world/SceneFile.h"
#include "orbis/world/TileMapService.h"

#include "JsonText.h"

#include <orbis/core/Error.h>

#include <fstream>
#include <sstream>
#include <type_traits>
#include <variant>

namespace orbis::world {

PointsData readPointsData(const PointsLayer& layer)
{
    PointsData points;
    const std::string field = layer.label ? layer.label->field : std::string();
    if (layer.format == PointsLayer::Format::Csv) {
        CsvPointsOptions options;
        options.longitudeColumn.clear(); // any accepted name
        options.latitudeColumn.clear();
        CsvPoints csv = loadCsvPoints(layer.source, options);
        points.positions = std::move(csv.positions);
        if (!field.empty()) {
            const std::vector<std::string>* texts = csv.column(field);
            if (!texts) {
                throw Error("label field: " + layer.source.string() + " has no column " + quote(field));
            }
            points.texts = *texts;
        }
        return points;
    }
    for (const Feature& feature : loadGeoJson(layer.source).features) {
        if (!feature.geometry) {
            continue;
        }
        std::vector<Geodetic3D> positions;
        if (const auto* point = std::get_if<Point>(&feature.geometry->value)) {
            positions.push_back(point->position);
        } else if (const auto* multi = std::get_if<MultiPoint>(&feature.geometry->value)) {
            positions = multi->positions;
        }
        const std::string text = field.empty() ? std::string() : feature.stringProperty(field).value_or("");
        for (const Geodetic3D& position : positions) {
            points.positions.push_back(position);
            if (!field.empty()) {
                points.texts.push_back(text);
            }
        }
    }
    return points;
}

void readLayerSource(const LayerDescription& layer)
{
    std::visit(
        [](const auto& description) {
            using Layer = std::decay_t<decltype(description)>;
            if constexpr (std::is_same_v<Layer, GeoJsonLayer>) {
                loadGeoJson(description.source);
            } else if constexpr (std::is_same_v<Layer, PointsLayer>) {
                readPointsData(description);
            } else if constexpr (std::is_same_v<Layer, ModelLayer>) {
                const GltfModel model = GltfModel::read(description.source);
                for (std::size_t i = 0; i < model.images.size(); ++i) {
                    model.decodeImage(i);
                }
            }
        },
        layer);
}

TileSourceOptions tileSourceOptions(const ImageryLayerDescription& layer)
{
    TileSourceOptions options;
    if (layer.scheme) {
        options.scheme = *layer.scheme == TilingProjection::WebMercator ? TilingScheme::webMercator()
                                                                        : TilingScheme::geographic();
    }
    options.minimumLevel = layer.minimumLevel.value_or(options.minimumLevel);
    options.maximumLevel = layer.maximumLevel.value_or(options.maximumLevel);
    if (layer.cacheFolder) {
        options.cacheFolder = *layer.cacheFolder;
    }
    return options;
}

TerrainSourceOptions terrainSourceOptions(const TerrainDescription& terrain)
{
    TerrainSourceOptions options;
    options.format = terrain.format;
    if (terrain.cacheFolder) {
        options.tiles.cacheFolder = *terrain.cacheFolder;
    }
    return options;
}

DiagnosticList validateSceneFile(const std::filesystem::path& path, SceneDescription* description)
{
    DiagnosticList faults;
    SceneParseOptions options;
    options.diagnostics = &faults;
    const SceneDescription scene = parseSceneFile(path, options);
    if (description) {
        *description = scene;
    }
    if (!faults.empty()) {
        return faults;
    }
    // The file read whole, so its text is there to place the faults of the files it names.
    std::ifstream file(path, std::ios::binary);
    std::ostringstream contents;
    contents << file.rdbuf();
    const std::string text = contents.str();
    auto check = [&](const std::string& pointer, auto&& read) {
        try {
            read();
        } catch (const Error& error) {
            const detail::TextPosition position = detail::positionOf(text, pointer, false);
            faults.add({path.string(), position.line, position.column, pointer, error.what()});
        }
    };
    if (scene.globe && scene.globe->texture) {
        check("/globe/texture", [&] { readGlobeImage(scene.globe->texture->path); });
    }
    if (scene.globe && scene.globe->nightTexture) {
        check("/globe/nightTexture", [&] { readGlobeImage(*scene.globe->nightTexture); });
    }
    for (std::size_t i = 0; scene.globe && i < scene.globe->imagery.size(); ++i) {
        const ImageryLayerDescription& layer = scene.globe->imagery[i];
        check("/globe/imagery/" + std::to_string(i) + "/source",
              [&] { openTileSource(layer.source, tileSourceOptions(layer)); });
    }
    if (scene.globe && scene.globe->terrain) {
        const TerrainDescription& terrain = *scene.globe->terrain;
        check("/globe/terrain/source", [&] { openTerrainSource(terrain.source, terrainSourceOptions(terrain)); });
    }
    for (std::size_t i = 0; i < scene.layers.size(); ++i) {
        const std::string pointer = "/layers/" + std::to_string(i);
        if (!std::holds_alternative<PolylineLayer>(scene.layers[i])) {
            check(pointer + "/source", [&] { readLayerSource(scene.layers[i]); });
        }
        const auto* points = std::get_if<PointsLayer>(&scene.layers[i]);
        if (points && points->billboard.image) {
            check(pointer + "/billboard/image", [&] { readImage(*points->billboard.image); });
        }
    }
    return faults;
}

} // namespace orbis::world
