#include <orbis/scene/TerrainShading.h>

#include <orbis/core/Error.h>
#include <orbis/core/Math.h>

#include <glm/vec2.hpp>

#include <cmath>

namespace orbis::scene {

void validateTerrainShading(const TerrainShading& shading, const std::string& owner)
{
    const auto fail = [&](const std::string& what) { throw Error(owner + ": terrain shading: " + what); };
    if (!(std::isfinite(shading.minimumHeight) && std::isfinite(shading.maximumHeight) &&
          shading.minimumHeight < shading.maximumHeight)) {
        fail("the height range must be two finite heights, the first below the second");
    }
    if (!(std::isfinite(shading.contourInterval) && shading.contourInterval >= 0.0)) {
        fail("the contour interval must be 0 (none) or more metres");
    }
    if (!(std::isfinite(shading.contourWidth) && shading.contourWidth > 0.0 && shading.contourWidth <= 64.0)) {
        fail("the contour width must be above 0 and at most 64 pixels");
    }
    if (!(std::isfinite(shading.hillshadeAzimuth) && std::isfinite(shading.hillshadeAltitude) &&
          shading.hillshadeAltitude > 0.0 && shading.hillshadeAltitude <= 90.0)) {
        fail("the hillshade's azimuth must be finite and its altitude above 0 and at most 90 degrees");
    }
}

std::string terrainShadingSource()
{
    return renderer::ShaderSource::embedded("scene/terrain/terrain_shading.glsl").text;
}

void addTerrainShadingDefines(const TerrainShading& shading, std::vector<renderer::ShaderDefine>& defines)
{
    if (!shading.any()) {
        return;
    }
    defines.push_back({"TERRAIN_SHADING"});
    if (shading.color == TerrainShading::Color::Height) {
        defines.push_back({"SHADING_HEIGHT_COLOR"});
    } else if (shading.color == TerrainShading::Color::Slope) {
        defines.push_back({"SHADING_SLOPE_COLOR"});
    }
    if (shading.contourInterval > 0.0) {
        defines.push_back({"SHADING_CONTOURS"});
    }
    if (shading.hillshade) {
        defines.push_back({"SHADING_HILLSHADE"});
    }
}

void setTerrainShadingUniforms(const TerrainShading& shading, renderer::UniformValues& uniforms)
{
    if (shading.color == TerrainShading::Color::Height) {
        uniforms.set("u_shadingHeightRange",
                     glm::vec2(static_cast<float>(shading.minimumHeight), static_cast<float>(shading.maximumHeight)));
    }
    if (shading.contourInterval > 0.0) {
        uniforms.set("u_contourInterval", static_cast<float>(shading.contourInterval));
        uniforms.set("u_contourColor", shading.contourColor);
        uniforms.set("u_contourWidth", static_cast<float>(shading.contourWidth));
    }
    if (shading.hillshade) {
        // The direction towards the light in the local east, north, up frame.
        const double azimuth = toRadians(shading.hillshadeAzimuth);
        const double altitude = toRadians(shading.hillshadeAltitude);
        uniforms.set("u_hillshadeLight", glm::vec3(static_cast<float>(std::cos(altitude) * std::sin(azimuth)),
                                                   static_cast<float>(std::cos(altitude) * std::cos(azimuth)),
                                                   static_cast<float>(std::sin(altitude))));
    }
}

} // namespace orbis::scene
