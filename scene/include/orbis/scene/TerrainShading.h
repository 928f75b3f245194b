#pragma once

#include <orbis/renderer/ShaderProgram.h>
#include <orbis/renderer/UniformValue.h>

#include <glm/vec3.hpp>

#include <string>

#include <vector>

namespace orbis::scene {

/// How a surface with heights is coloured and shaded (book chapter 11), beside the Sun's
/// lighting: a colour ramp by height or by slope in place of the base colour (imagery layers are
/// still blended over it), contour lines, and a hillshade from a fixed light. Each option a
/// surface leaves off costs its shader nothing: it is compiled out.
struct TerrainShading {
    enum class Color {
        Base,   ///< the surface's base colour
        Height, ///< a hypsometric ramp over heightRange: blues below 0 m, greens to white above
        Slope,  ///< a ramp by the angle from the ellipsoid's normal: pale at 0 degrees, red at 60 and steeper
    };
    Color color = Color::Base;
    double minimumHeight = -6000.0; ///< metres: the ramp's deepest blue
    double maximumHeight = 6000.0;  ///< metres: the ramp's white
    double contourInterval = 0.0;   ///< metres between contour lines; 0: none
    glm::vec3 contourColor{1.0f, 1.0f, 1.0f};
    double contourWidth = 1.0;      ///< pixels
    bool hillshade = false;
    double hillshadeAzimuth = 315.0;  ///< degrees clockwise from north: where the light comes from
    double hillshadeAltitude = 45.0;  ///< degrees above the horizon

    /// Whether any option is on (the shader needs the heights and frames then).
    bool any() const noexcept { return color != Color::Base || contourInterval > 0.0 || hillshade; }

    friend bool operator==(const TerrainShading&, const TerrainShading&) = default;
};

/// Throws orbis::Error naming `owner` and the option when one is out of range (heights not finite
/// or not increasing, an interval below 0, a width or an altitude outside (0, 90] degrees).
void validateTerrainShading(const TerrainShading& shading, const std::string& owner);

/// The GLSL of shaders/scene/terrain/terrain_shading.glsl, for a fragment shader to put before its
/// own text: terrainBaseColor() and terrainOverlays() (see there).
std::string terrainShadingSource();

/// The defines that switch on the options in use (TERRAIN_SHADING and one per option).
void addTerrainShadingDefines(const TerrainShading& shading, std::vector<renderer::ShaderDefine>& defines);

/// The uniforms the options in use read.
void setTerrainShadingUniforms(const TerrainShading& shading, renderer::UniformValues& uniforms);

} // namespace orbis::scene
