#include "orbis/scene/SceneBuilder.h"

#include "orbis/scene/Globe.h"

#include <orbis/core/Error.h>

namespace orbis {

namespace {

const char* layerKind(const LayerDescription& layer)
{
    switch (layer.index()) {
    case 0: return "geojson";
    case 1: return "points";
    case 2: return "polyline";
    default: return "model";
    }
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
        throw Error("/layers/" + std::to_string(i) + ": " + layerKind(description.layers[i]) +
                    " layers are not drawn by this build yet");
    }
}

} // namespace orbis
