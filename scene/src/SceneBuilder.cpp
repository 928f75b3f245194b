#include "orbis/scene/SceneBuilder.h"

#include "orbis/scene/BillboardCollection.h"
#include "orbis/scene/ClipmapTerrain.h"
#include "orbis/scene/FeaturePrimitives.h"
#include "orbis/scene/Globe.h"
#include "orbis/scene/LabelCollection.h"
#include "orbis/scene/ModelPrimitive.h"
#include "orbis/scene/PolylineCollection.h"
#include "orbis/scene/TiledGlobe.h"
#include "orbis/scene/VirtualTextureGlobe.h"

#include "VectorSupport.h"

#include <orbis/core/Error.h>
#include <orbis/world/Diagnostics.h>
#include <orbis/world/GeoJson.h>
#include <orbis/world/ImageFile.h>
#include <orbis/world/SceneData.h>
#include <orbis/world/TerrainHeight.h>
#include <orbis/world/TerrainSource.h>
#include <orbis/world/TileSource.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <variant>

namespace orbis::scene {

namespace {

PolylineStyle polylineStyle(const world::StrokeStyle& stroke)
{
    PolylineStyle style;
    style.color = stroke.color;
    style.widthPixels = static_cast<float>(stroke.widthPixels);
    style.outlineColor = stroke.outlineColor;
    style.outlineWidthPixels = static_cast<float>(stroke.outlineWidthPixels);
    return style;
}

/// The ground a layer's heightReference measures from: the globe's terrain under a point, at its
/// most detailed (world::TerrainHeightQuery, tiles loaded as needed) and times the exaggeration,
/// as the surface is drawn once it has converged; 0 m without terrain.
class Ground {
public:
    Ground(std::shared_ptr<world::TerrainSource> terrain, double exaggeration)
        : _terrain(std::move(terrain)), _exaggeration(exaggeration)
    {
    }

    double heightAt(const Geodetic2D& position)
    {
        if (!_terrain) {
            return 0.0;
        }
        if (!_query) {
            _query = std::make_unique<world::TerrainHeightQuery>(*_terrain);
        }
        const std::optional<world::TerrainHeight> height = _query->at(position);
        return height ? height->height * _exaggeration : 0.0;
    }

    /// The angle between the terrain's finest samples (infinite without terrain): a line on the
    /// ground needs a vertex that often to follow it.
    double sampleSpacingRadians() const
    {
        if (!_terrain) {
            return std::numeric_limits<double>::infinity();
        }
        const world::TerrainSourceInfo& info = _terrain->info();
        const int samples = info.gridSize > 1 ? info.gridSize : 65; // meshes: about a 65 x 65 grid's detail
        return kPi / std::ldexp(1.0, static_cast<int>(info.maximumLevel)) / (samples - 1);
    }

    bool hasTerrain() const noexcept { return _terrain != nullptr; }

    /// A position with its height made absolute.
    Geodetic3D place(Geodetic3D position, world::HeightReference reference)
    {
        if (reference == world::HeightReference::Absolute) {
            return position;
        }
        const double ground = heightAt(Geodetic2D(position.longitude, position.latitude));
        position.height = reference == world::HeightReference::ClampToGround ? ground : position.height + ground;
        return position;
    }

private:
    std::shared_ptr<world::TerrainSource> _terrain;
    double _exaggeration;
    std::unique_ptr<world::TerrainHeightQuery> _query; ///< made at the first question
};

/// Borders and fills of a GeoJSON file; with neither style given, lines and outlines in the
/// default stroke. With a ground reference the lines follow the ground as a polyline layer's do,
/// and over terrain the fills are draped on it (either reference: a fill can only lie on it).
void addGeoJsonLayer(const world::GeoJsonLayer& layer, const std::shared_ptr<Ground>& ground, Scene& scene,
                     std::vector<std::string>& warnings)
{
    FeatureStyle style;
    style.borders = layer.stroke.has_value() || !layer.fill.has_value();
    style.border = polylineStyle(layer.stroke.value_or(world::StrokeStyle{}));
    style.fill = layer.fill.has_value();
    if (layer.fill) {
        style.fillColor = layer.fill->color;
    }
    style.granularityRadians = layer.path.granularityRadians;
    style.curve = layer.path.curve;
    if (layer.heightReference != world::HeightReference::Absolute) {
        style.clampLinesToGround = layer.heightReference == world::HeightReference::ClampToGround;
        if (ground->hasTerrain()) {
            style.groundHeight = [ground](const Geodetic2D& position) { return ground->heightAt(position); };
            style.groundSpacingRadians = ground->sampleSpacingRadians();
            style.drapeFills = true;
            style.raiseFillsByHeight = layer.heightReference == world::HeightReference::RelativeToGround;
        }
    }
    style.skipInvalidPolygons = layer.skipInvalid;
    world::GeoJsonOptions reading;
    reading.skipInvalidFeatures = layer.skipInvalid;
    const world::FeatureCollection features = world::loadGeoJson(layer.source, reading);
    warnings.insert(warnings.end(), features.warnings.begin(), features.warnings.end()); // these name the file
    const std::string file = world::cutForMessage(layer.source.string());
    try {
        const FeaturePrimitives primitives = buildFeaturePrimitives(scene.ellipsoid(), features, style);
        primitives.addTo(scene);
        for (const std::string& warning : primitives.warnings) {
            warnings.push_back(file + ": " + warning);
        }
    } catch (const Error& error) {
        // What the triangulation refuses names the feature; the file is named here.
        const char* hint = layer.skipInvalid ? "" : " (with \"invalid\": \"skip\" the layer leaves out faulty holes and polygons, each named in a warning)";
        throw Error(file + ": " + error.what() + hint);
    }
}

void addPolylineLayer(const world::PolylineLayer& layer, const std::shared_ptr<Ground>& ground, Scene& scene)
{
    world::StrokeStyle stroke;
    stroke.color = layer.color;
    stroke.widthPixels = layer.widthPixels;
    PolylineCollectionOptions options;
    options.granularityRadians = layer.path.granularityRadians;
    options.curve = layer.path.curve;
    std::vector<Geodetic3D> positions = layer.positions;
    if (layer.heightReference != world::HeightReference::Absolute) {
        // Every drawn vertex on the ground, not only the positions given, and as many as the
        // terrain has samples.
        options.groundHeight = [ground](const Geodetic2D& position) { return ground->heightAt(position); };
        options.granularityRadians = std::min(options.granularityRadians, ground->sampleSpacingRadians());
        if (layer.heightReference == world::HeightReference::ClampToGround) {
            for (Geodetic3D& position : positions) {
                position.height = 0.0;
            }
        }
    }
    auto lines = std::make_shared<PolylineCollection>(scene.ellipsoid(), options);
    lines->add(std::span<const Geodetic3D>(positions), polylineStyle(stroke));
    scene.add(std::move(lines));
}

std::pair<HorizontalOrigin, VerticalOrigin> splitOrigin(world::Origin origin)
{
    switch (origin) {
    case world::Origin::Center: return {HorizontalOrigin::Center, VerticalOrigin::Center};
    case world::Origin::Top: return {HorizontalOrigin::Center, VerticalOrigin::Top};
    case world::Origin::Bottom: return {HorizontalOrigin::Center, VerticalOrigin::Bottom};
    case world::Origin::Left: return {HorizontalOrigin::Left, VerticalOrigin::Center};
    case world::Origin::Right: return {HorizontalOrigin::Right, VerticalOrigin::Center};
    case world::Origin::TopLeft: return {HorizontalOrigin::Left, VerticalOrigin::Top};
    case world::Origin::TopRight: return {HorizontalOrigin::Right, VerticalOrigin::Top};
    case world::Origin::BottomLeft: return {HorizontalOrigin::Left, VerticalOrigin::Bottom};
    case world::Origin::BottomRight: return {HorizontalOrigin::Right, VerticalOrigin::Bottom};
    }
    return {HorizontalOrigin::Center, VerticalOrigin::Center};
}

/// A billboard for every point, and a label when the layer asks for one.
void addPointsLayer(const world::PointsLayer& layer, Ground& ground, Scene& scene)
{
    world::PointsData points = world::readPointsData(layer);
    for (Geodetic3D& position : points.positions) {
        position = ground.place(position, layer.heightReference);
    }
    const Ellipsoid& ellipsoid = scene.ellipsoid();
    const world::BillboardStyle& style = layer.billboard;
    const int size = std::max(1, static_cast<int>(std::lround(style.sizePixels)));

    BillboardCollectionOptions billboardOptions;
    billboardOptions.depth.disableDepthTestDistance = style.disableDepthTestDistance;
    auto billboards = std::make_shared<BillboardCollection>(billboardOptions);
    Image image = style.image ? world::readImage(*style.image) : billboardShapeImage(style.shape, size);
    const float scale = static_cast<float>(style.sizePixels / std::max(image.width, image.height));
    const std::size_t imageIndex = [&] {
        try {
            return billboards->addImage(image);
        } catch (const Error& error) {
            // Too large for the atlas: the message names the image file and its key.
            throw Error(style.image ? world::cutForMessage(style.image->string()) + ": billboard image: " + error.what()
                                    : std::string("billboard: ") + error.what());
        }
    }();
    const auto [horizontal, vertical] = splitOrigin(style.origin);
    const glm::ivec2 offset(static_cast<int>(std::lround(style.offsetPixels.x)),
                            static_cast<int>(std::lround(style.offsetPixels.y)));
    billboards->reserve(points.positions.size());
    for (const Geodetic3D& position : points.positions) {
        Billboard billboard;
        billboard.position = ellipsoid.toCartesian(position);
        billboard.image = imageIndex;
        billboard.pixelOffset = offset;
        billboard.horizontalOrigin = horizontal;
        billboard.verticalOrigin = vertical;
        billboard.color = style.color;
        billboard.scale = style.image ? scale : 1.0f;
        billboards->add(billboard);
    }
    scene.add(billboards);

    if (!layer.label) {
        return;
    }
    LabelCollectionOptions options;
    options.haloPixels = static_cast<int>(std::lround(layer.label->outlineWidthPixels));
    options.declutter = layer.label->declutter;
    options.depth.disableDepthTestDistance = layer.label->disableDepthTestDistance;
    auto labels = std::make_shared<LabelCollection>(options);
    for (std::size_t i = 0; i < points.positions.size(); ++i) {
        if (points.texts[i].empty()) {
            continue;
        }
        Label label;
        label.position = ellipsoid.toCartesian(points.positions[i]);
        label.text = points.texts[i];
        label.fontSizePixels = static_cast<float>(layer.label->fontSizePixels);
        label.fillColor = layer.label->color;
        label.haloColor = layer.label->outlineColor;
        // Centred above the marker, clear of it.
        label.pixelOffset = {offset.x, offset.y - (size + 1) / 2 - 2};
        labels->add(label);
    }
    scene.add(labels);
}

/// The file is read now (geometry, and its errors); GPU resources wait for the first frame.
void addModelLayer(const world::ModelLayer& layer, bool lighting, Ground& ground, Scene& scene)
{
    ModelOptions options;
    options.lighting = lighting;
    const Geodetic3D position = ground.place(layer.position, layer.heightReference);
    scene.add(ModelPrimitive::fromFile(layer.source, scene.ellipsoid(),
                                       ModelPlacement{position, layer.orientation, layer.scale}, options));
}

/// The tiled globe a description asks for, its tile sources opened.
TiledGlobeOptions tiledGlobeOptions(const world::GlobeDescription& globe, const world::SunDescription& sun,
                                    const SceneBuildOptions& build)
{
    TiledGlobeOptions options;
    options.maximumScreenSpaceError = globe.maximumScreenSpaceError;
    options.cacheBytes = static_cast<std::size_t>(globe.cacheMegabytes * 1048576.0);
    options.loader = build.loader;
    options.lighting = sun.source != world::SunSource::Camera;
    for (std::size_t i = 0; i < globe.imagery.size(); ++i) {
        const world::ImageryLayerDescription& layer = globe.imagery[i];
        ImageryLayer imagery;
        try {
            imagery.source = world::openTileSource(layer.source, world::tileSourceOptions(layer));
        } catch (const Error& error) {
            throw Error("/globe/imagery/" + std::to_string(i) + ": " + error.what());
        }
        imagery.style.alpha = layer.alpha;
        imagery.style.brightness = layer.brightness;
        imagery.style.contrast = layer.contrast;
        imagery.style.gamma = layer.gamma;
        imagery.style.rectangle = layer.rectangle;
        options.imagery.push_back(std::move(imagery));
    }
    if (globe.terrain) {
        try {
            options.terrain = world::openTerrainSource(globe.terrain->source, world::terrainSourceOptions(*globe.terrain));
        } catch (const Error& error) {
            throw Error("/globe/terrain: " + std::string(error.what()));
        }
        options.terrainExaggeration = globe.terrain->exaggeration;
        options.morphFrames = globe.terrain->morphFrames;
        const world::TerrainShadingDescription& shading = globe.terrain->shading;
        using ShadingColor = world::TerrainShadingDescription::Color;
        options.shading.color = shading.color == ShadingColor::Height  ? TerrainShading::Color::Height
                                : shading.color == ShadingColor::Slope ? TerrainShading::Color::Slope
                                                                       : TerrainShading::Color::Base;
        options.shading.minimumHeight = shading.minimumHeight;
        options.shading.maximumHeight = shading.maximumHeight;
        options.shading.contourInterval = shading.contourInterval;
        options.shading.contourColor = glm::vec3(shading.contourColor);
        options.shading.contourWidth = shading.contourWidth;
        options.shading.hillshade = shading.hillshade;
        options.shading.hillshadeAzimuth = shading.hillshadeAzimuth;
        options.shading.hillshadeAltitude = shading.hillshadeAltitude;
        options.water = shading.water;
    }
    return options;
}

/// The virtual texture a description's one imagery layer asks for (the parser allows no other
/// layer beside it), its tile source opened.
VirtualTextureGlobeOptions virtualTextureGlobeOptions(const world::GlobeDescription& globe,
                                                      const world::SunDescription& sun, const SceneBuildOptions& build)
{
    const world::ImageryLayerDescription& layer = globe.imagery.front();
    const world::VirtualTextureDescription& vt = *layer.virtualTexture;
    VirtualTextureGlobeOptions options;
    try {
        options.source = world::openTileSource(layer.source, world::tileSourceOptions(layer));
    } catch (const Error& error) {
        throw Error("/globe/imagery/0: " + std::string(error.what()));
    }
    options.style.alpha = layer.alpha;
    options.style.brightness = layer.brightness;
    options.style.contrast = layer.contrast;
    options.style.gamma = layer.gamma;
    VirtualTextureOptions& pages = options.virtualTexture;
    pages.pageSize = vt.pageSize;
    pages.border = vt.border;
    pages.physicalPages = vt.physicalPages;
    pages.feedbackDivisor = vt.feedbackDivisor;
    pages.feedbackLatencyFrames = vt.feedbackLatencyFrames;
    pages.requestOrder = vt.priorities ? RequestOrder::PixelCount : RequestOrder::Unsorted;
    pages.trilinear = vt.trilinear;
    pages.maximumAnisotropy = static_cast<float>(vt.maximumAnisotropy);
    pages.lodBias = vt.lodBias;
    pages.dynamicLodBias = vt.dynamicLodBias;
    pages.sparse = vt.sparse;
    pages.uploadBytesPerFrame = static_cast<std::size_t>(vt.uploadMegabytesPerFrame * 1048576.0);
    // The cap on the tiles' memory holds the decoded source tiles here: the GPU's is the physical texture's.
    pages.tileCacheBytes = static_cast<std::size_t>(globe.cacheMegabytes * 1048576.0);
    options.maximumScreenSpaceError = globe.maximumScreenSpaceError;
    options.loader = build.loader;
    options.lighting = sun.source != world::SunSource::Camera;
    return options;
}

bool hasVirtualTexture(const world::GlobeDescription& globe)
{
    return std::any_of(globe.imagery.begin(), globe.imagery.end(),
                       [](const world::ImageryLayerDescription& layer) { return layer.virtualTexture.has_value(); });
}

} // namespace

std::vector<std::string> populateScene(const world::SceneDescription& description, Scene& scene,
                                       const SceneBuildOptions& build)
{
    std::vector<std::string> warnings;
    scene.options().depthStrategy = description.depth;
    scene.camera() = makeCamera(description.camera, scene.ellipsoid());
    scene.setSunDirection(description.sun.directionEarthFixed);
    scene.options().background = description.background;
    scene.options().samples = description.samples;

    auto ground = std::make_shared<Ground>(nullptr, 1.0); // the terrain's, when the globe has one
    if (description.globe && hasVirtualTexture(*description.globe)) {
        VirtualTextureGlobeOptions options = virtualTextureGlobeOptions(*description.globe, description.sun, build);
        try {
            scene.add(std::make_shared<VirtualTextureGlobe>(scene.ellipsoid(), std::move(options)));
        } catch (const Error& error) {
            throw Error("/globe/imagery/0/virtualTexture: " + std::string(error.what()));
        }
    } else if (description.globe && description.globe->terrain &&
               description.globe->terrain->method == world::TerrainMethod::Clipmap) {
        // The same sources as the tiles would read, drawn as clipmaps.
        TiledGlobeOptions tiles = tiledGlobeOptions(*description.globe, description.sun, build);
        ground = std::make_shared<Ground>(tiles.terrain, tiles.terrainExaggeration);
        ClipmapTerrainOptions options;
        options.terrain = std::move(tiles.terrain);
        options.imagery = std::move(tiles.imagery);
        options.posts = description.globe->terrain->posts;
        options.exaggeration = description.globe->terrain->exaggeration;
        options.loader = build.loader;
        options.cacheBytes = tiles.cacheBytes;
        options.lighting = tiles.lighting;
        options.shading = tiles.shading;
        scene.add(std::make_shared<ClipmapTerrain>(scene.ellipsoid(), std::move(options)));
    } else if (description.globe && (!description.globe->imagery.empty() || description.globe->terrain)) {
        TiledGlobeOptions options = tiledGlobeOptions(*description.globe, description.sun, build);
        ground = std::make_shared<Ground>(options.terrain, options.terrainExaggeration);
        scene.add(std::make_shared<TiledGlobe>(scene.ellipsoid(), std::move(options)));
    } else if (description.globe) {
        GlobeOptions options;
        options.method = description.globe->method;
        if (description.globe->texture) {
            options.dayTexture = description.globe->texture->path;
        }
        if (description.globe->nightTexture) {
            options.nightTexture = *description.globe->nightTexture;
        }
        options.grid = description.globe->grid;
        // Lighting costs only when the file places the Sun.
        options.lighting = description.sun.source != world::SunSource::Camera;
        scene.add(std::make_shared<Globe>(scene.ellipsoid(), options));
    }
    for (std::size_t i = 0; i < description.layers.size(); ++i) {
        try {
            std::visit(
                [&](const auto& layer) {
                    using Layer = std::decay_t<decltype(layer)>;
                    if constexpr (std::is_same_v<Layer, world::GeoJsonLayer>) {
                        std::vector<std::string> layerWarnings;
                        addGeoJsonLayer(layer, ground, scene, layerWarnings);
                        for (const std::string& warning : layerWarnings) {
                            warnings.push_back("/layers/" + std::to_string(i) + ": " + warning);
                        }
                    } else if constexpr (std::is_same_v<Layer, world::PolylineLayer>) {
                        addPolylineLayer(layer, ground, scene);
                    } else if constexpr (std::is_same_v<Layer, world::PointsLayer>) {
                        addPointsLayer(layer, *ground, scene);
                    } else {
                        // Lit, as the globe is, only when the file places the Sun.
                        addModelLayer(layer, description.sun.source != world::SunSource::Camera, *ground, scene);
                    }
                },
                description.layers[i]);
        } catch (const Error& error) {
            throw Error("/layers/" + std::to_string(i) + ": " + error.what());
        }
    }
    return warnings;
}

} // namespace orbis::scene
