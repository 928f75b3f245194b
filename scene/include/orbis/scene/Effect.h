#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace orbis::scene {

/// The visual effects a frame can contain. Primitives tag their draw commands with the effects
/// they draw (SceneCommand::tags), and FrameStatistics reports those that ran, so tests can prove
/// that a scene pays only for what it asks for.
enum class Effect : std::uint32_t {
    Globe = 1u << 0,
    Lighting = 1u << 1,
    NightLights = 1u << 2,
    Grid = 1u << 3,
    Meshes = 1u << 4,
    Billboards = 1u << 5,
    Labels = 1u << 6,
    Polylines = 1u << 7,
    Polygons = 1u << 8,
    Models = 1u << 9,
    TiledImagery = 1u << 10, ///< the globe's surface streamed as tiles with imagery layers
    Terrain = 1u << 11,      ///< heights on the streamed tiles
    VirtualTexture = 1u << 12, ///< the globe's surface reading one virtual texture (and its feedback pass)
    TerrainShading = 1u << 13, ///< colour by height or slope, contours or hillshade (TerrainShading)
    ClipmapTerrain = 1u << 14, ///< terrain drawn as geometry clipmaps (with Terrain)
    DrapedPolygons = 1u << 15, ///< polygons draped over the terrain as shadow volumes (with Polygons)
    Water = 1u << 16,          ///< the terrain's water mask, level and mirroring the Sun (TiledGlobeOptions::water)
    ColorAdjustment = 1u << 17, ///< an imagery layer's brightness, contrast or gamma (ImageryLayerStyle::adjustsColors)
};

constexpr std::uint32_t operator|(Effect a, Effect b) noexcept
{
    return static_cast<std::uint32_t>(a) | static_cast<std::uint32_t>(b);
}
constexpr std::uint32_t operator|(std::uint32_t a, Effect b) noexcept
{
    return a | static_cast<std::uint32_t>(b);
}
constexpr bool hasEffect(std::uint32_t effects, Effect effect) noexcept
{
    return (effects & static_cast<std::uint32_t>(effect)) != 0;
}

/// "globe", "lighting", "night lights", ... for each effect in the set, in declaration order.
std::vector<std::string> effectNames(std::uint32_t effects);

} // namespace orbis::scene
