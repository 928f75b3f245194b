// The colour both clipmap surfaces (the levels and the backdrop beyond them) end with: the
// terrain's shading options (TERRAIN_SHADING: a ramp in place of the base colour where neither
// IMAGERY nor COLOR_BY_LEVEL gives one, hillshade and contours over everything), then the Sun
// (LIGHTING). Put before each surface's fragment shader, after terrain_shading.glsl.

#ifdef LIGHTING
uniform vec3 og_sunDirection;
#endif

// normal and up: unit vectors, Earth-fixed; height: metres, the exaggeration taken out.
vec3 surfaceColor(vec3 color, float height, vec3 normal, vec3 up)
{
#ifdef TERRAIN_SHADING
#if !defined(IMAGERY) && !defined(COLOR_BY_LEVEL)
    color = terrainBaseColor(color, height, normal, up);
#endif
    color = terrainOverlays(color, height, normal, up);
#endif
#ifdef LIGHTING
    color *= 0.2 + 0.8 * max(dot(normal, og_sunDirection), 0.0);
#endif
    return color;
}
