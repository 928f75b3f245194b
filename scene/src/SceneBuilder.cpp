#include "orbis/scene/SceneBuilder.h"

#include "orbis/scene/FeaturePrimitives.h"
#include "orbis/scene/GeoJson.h"
#include "orbis/scene/Globe.h"

#include <orbis/core/Error.h>

#include <type_traits>
#include <variant>

namespace orbis {

namespace {

PolylineStyle polylineStyle(const StrokeStyle& stroke)
{
    PolylineStyle style;
    style.color = stroke.color;
    style.widthPixels = static_cast<float>(stroke.widthPixels);
    style.outlineColor = stroke.outlineColor;
    style.outlineWidthPixels = static_cast<float>(stroke.outlineWidthPixels);
    return style;
}

/// Borders and fills of a GeoJSON file; with neither style given, lines and outlines in the
/// default stroke.
void addGeoJsonLayer(const GeoJsonLayer& layer, Scene& scene)
{
    FeatureStyle style;
    style.borders = layer.stroke.has_value() || !layer.fill.has_value();
    style.border = polylineStyle(layer.stroke.value_or(StrokeStyle{}));
    style.fill = layer.fill.has_value();
    if (layer.fill) {
        style.fillColor = layer.fill->color;
    }
    buildFeaturePrimitives(scene.ellipsoid(), loadGeoJson(layer.source), style).addTo(scene);
}

void addPolylineLayer(const PolylineLayer& layer, Scene& scene)
{
    StrokeStyle stroke;
    stroke.color = layer.color;
    stroke.widthPixels = layer.widthPixels;
    auto lines = std::make_shared<PolylineCollection>(scene.ellipsoid());
    lines->add(std::span<const Geodetic3D>(layer.positions), polylineStyle(stroke));
    scene.add(std::move(lines));
}

} // namespace

void populateScene(const SceneDescription& description, Scene& scene)
{
    if (description.depth != DepthStrategy::Automatic && description.depth != DepthStrategy::MultiFrustum) {
        throw Error("/depth: only \"auto\" and \"multifrustum\" are drawn by this build");
    }
    scene.camera() = makeCamera(description.camera, scene.ellipsoid());
    scene.setSunDirection(description.sun.directionEarthFixed);
    scene.options().background = description.background;

    if (description.globe) {
        GlobeOptions options;
        options.method = description.globe->method;
        if (description.globe->texture) {
            options.dayTexture = description.globe->texture->path;
        }
        if (description.globe->nightTexture) {
            options.nightTexture = *description.globe->nightTexture;
        }
        options.grid = description.globe->grid;
        scene.add(std::make_shared<Globe>(scene.ellipsoid(), options));
    }
    for (std::size_t i = 0; i < description.layers.size(); ++i) {
        const LayerDescription& layer = description.layers[i];
        const std::string pointer = "/layers/" + std::to_string(i);
        try {
            std::visit(
                [&](const auto& value) {
                    using Layer = std::decay_t<decltype(value)>;
                    if constexpr (std::is_same_v<Layer, GeoJsonLayer>) {
                        addGeoJsonLayer(value, scene);
                    } else if constexpr (std::is_same_v<Layer, PolylineLayer>) {
                        addPolylineLayer(value, scene);
                    } else {
                        const char* kind = std::is_same_v<Layer, PointsLayer> ? "points" : "model";
                        throw Error(std::string(kind) + " layers are not drawn by this build yet");
                    }
                },
                layer);
        } catch (const Error& error) {
            throw Error(pointer + ": " + error.what());
        }
    }
}

} // namespace orbis
