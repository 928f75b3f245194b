#pragma once

// Helpers for the polyline and polygon tests: Natural Earth's countries, a plain blue globe, a
// camera looking straight down, and counting pixels of a colour.

#include "RendererTestSupport.h"

#include <orbis/scene/Globe.h>
#include <orbis/scene/Scene.h>
#include <orbis/world/GeoJson.h>

#include <glm/common.hpp>

#include <memory>

namespace orbis::test {

/// data/natural-earth/countries-110m.geojson, loaded once per process.
inline const world::FeatureCollection& countries110m()
{
    static const world::FeatureCollection countries =
        world::loadGeoJson(ORBIS_SOURCE_DIR "/data/natural-earth/countries-110m.geojson");
    return countries;
}

/// The colour these tests draw the unlit globe in, and its pixel.
inline const glm::vec4 kBlue(0.0f, 0.0f, 1.0f, 1.0f);
inline const glm::ivec4 kBluePixel(0, 0, 255, 255);

/// The ray-cast (or tessellated) globe in one unlit colour.
inline std::shared_ptr<scene::Globe> unlitGlobe(const Ellipsoid& ellipsoid, const glm::vec4& color,
                                         world::GlobeMethod method = world::GlobeMethod::RayCast)
{
    scene::GlobeOptions options;
    options.method = method;
    options.color = color;
    return std::make_shared<scene::Globe>(ellipsoid, options);
}

/// The camera `height` metres straight above a point on the scene's ellipsoid, looking at it, +z up.
inline void lookDownAt(scene::Scene& scene, const Geodetic3D& below, double height)
{
    const Ellipsoid& ellipsoid = scene.ellipsoid();
    scene.camera().lookAt(ellipsoid.toCartesian(Geodetic3D(below.longitude, below.latitude, height)),
                          ellipsoid.toCartesian(below), {0, 0, 1});
}

/// Pixels whose every channel is within tolerance of the colour, in [x0, x1) x [y0, y1).
inline int countPixelsNear(const Image& image, const glm::ivec4& color, int tolerance, int x0, int y0, int x1, int y1)
{
    int count = 0;
    for (int y = std::max(y0, 0); y < std::min(y1, image.height); ++y) {
        for (int x = std::max(x0, 0); x < std::min(x1, image.width); ++x) {
            count += pixelNear(image, x, y, color, tolerance) ? 1 : 0;
        }
    }
    return count;
}

inline int countPixelsNear(const Image& image, const glm::ivec4& color, int tolerance = 2)
{
    return countPixelsNear(image, color, tolerance, 0, 0, image.width, image.height);
}

} // namespace orbis::test
