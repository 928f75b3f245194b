// Terrain shading (book chapter 11), for any surface with heights: put before a fragment shader
// that defines TERRAIN_SHADING and the options it uses (TerrainShading.cpp). Heights are metres
// with the exaggeration taken out; normal is the terrain's and up the ellipsoid's, both unit and
// Earth-fixed.

#ifdef SHADING_HEIGHT_COLOR
uniform vec2 u_shadingHeightRange; // metres: the deepest blue, the white

// Hypsometric tints: light to deep blue from 0 m down, green, yellow, brown and white up.
vec3 heightColor(float height)
{
    if (height < 0.0 && u_shadingHeightRange.x < 0.0) {
        float depth = clamp(height / u_shadingHeightRange.x, 0.0, 1.0);
        return mix(vec3(0.55, 0.75, 0.92), vec3(0.03, 0.12, 0.38), depth);
    }
    float low = max(u_shadingHeightRange.x, 0.0);
    float t = clamp((height - low) / max(u_shadingHeightRange.y - low, 1.0), 0.0, 1.0);
    if (t < 0.3) {
        return mix(vec3(0.18, 0.48, 0.2), vec3(0.85, 0.8, 0.45), t / 0.3);
    }
    if (t < 0.65) {
        return mix(vec3(0.85, 0.8, 0.45), vec3(0.5, 0.36, 0.22), (t - 0.3) / 0.35);
    }
    return mix(vec3(0.5, 0.36, 0.22), vec3(1.0), (t - 0.65) / 0.35);
}
#endif

#ifdef SHADING_SLOPE_COLOR
// Pale at 0 degrees, orange at 30, red at 60 and steeper.
vec3 slopeColor(vec3 normal, vec3 up)
{
    float slope = acos(clamp(dot(normal, up), -1.0, 1.0)) / radians(60.0);
    slope = clamp(slope, 0.0, 1.0);
    return slope < 0.5 ? mix(vec3(0.95, 0.95, 0.85), vec3(0.95, 0.6, 0.1), slope / 0.5)
                       : mix(vec3(0.95, 0.6, 0.1), vec3(0.6, 0.05, 0.05), (slope - 0.5) / 0.5);
}
#endif

#ifdef SHADING_CONTOURS
uniform float u_contourInterval; // metres
uniform vec3 u_contourColor;
uniform float u_contourWidth;    // pixels
#endif

#ifdef SHADING_HILLSHADE
uniform vec3 u_hillshadeLight; // towards the light, in the local east, north, up frame

// The light in Earth-fixed coordinates. East is undefined at a pole: any horizontal direction
// serves there (the light then comes from a fixed meridian), and no vector is normalised from 0.
vec3 hillshadeLight(vec3 up)
{
    vec3 east = vec3(-up.y, up.x, 0.0);
    east = dot(east, east) > 1e-12 ? normalize(east) : vec3(0.0, 1.0, 0.0);
    vec3 north = cross(up, east);
    return u_hillshadeLight.x * east + u_hillshadeLight.y * north + u_hillshadeLight.z * up;
}
#endif

// The surface's colour before imagery is blended over it.
vec3 terrainBaseColor(vec3 baseColor, float height, vec3 normal, vec3 up)
{
#if defined(SHADING_HEIGHT_COLOR)
    return heightColor(height);
#elif defined(SHADING_SLOPE_COLOR)
    return slopeColor(normal, up);
#else
    return baseColor;
#endif
}

// Hillshade and contour lines, over the blended colour.
vec3 terrainOverlays(vec3 color, float height, vec3 normal, vec3 up)
{
#ifdef SHADING_HILLSHADE
    // Flat ground under the standard 45 degree light keeps about its colour; slopes facing away darken.
    float shade = max(dot(normal, hillshadeLight(up)), 0.0);
    color *= 0.3 + 0.7 * shade / max(u_hillshadeLight.z, 0.05);
    color = min(color, vec3(1.0));
#endif
#ifdef SHADING_CONTOURS
    // The distance to the nearest contour in pixels, from the height's screen-space rate of change.
    // Level ground has no contour through it, even at a contour's height (the sea at 0 m).
    float contours = height / u_contourInterval;
    float rate = fwidth(contours);
    if (rate > 0.0) {
        float pixels = abs(fract(contours + 0.5) - 0.5) / rate;
        color = mix(color, u_contourColor, clamp(0.5 * u_contourWidth + 0.5 - pixels, 0.0, 1.0));
    }
#endif
    return color;
}
