// A tile of the globe's surface (course 3.5), relative to the eye on the GPU (book 5.4): each
// position comes as two floats, and a vertex two tiles share has the same two floats in both, so
// both transform it to the same clip position and the tiles meet without a gap.

in vec3 positionHigh;
in vec3 positionLow;
in vec3 textureCoordinate; // u and v within the tile (0..1 west to east, south to north), height (metres)
#ifdef TERRAIN
in vec3 normal; // of the terrain, Earth-fixed
#endif

out vec2 v_tileCoordinates;
out vec3 v_normal; // the surface's normal (the terrain's or the ellipsoid's), Earth-fixed
#ifdef TERRAIN_SHADING
out float v_height; // metres, exaggeration taken out
uniform float u_heightScale; // 1 / exaggeration (0 when it is 0)
#endif
#if defined(TERRAIN_SHADING) || defined(WATER_MASK)
out vec3 v_up;      // the ellipsoid's normal
#endif
#ifdef WATER_MASK
out vec3 v_toEye;   // from the vertex, Earth-fixed axes
#endif

uniform vec3 og_cameraEye;
uniform vec3 og_cameraEyeHigh;
uniform vec3 og_cameraEyeLow;
uniform mat4 og_modelViewProjectionMatrixRelativeToEye;
uniform vec3 u_oneOverRadiiSquared;

void main()
{
    vec3 position = og_emulatedDoubleSubtract(positionHigh, positionLow, og_cameraEyeHigh, og_cameraEyeLow);
    v_tileCoordinates = textureCoordinate.xy;
    // The eye in one float is half a metre off at most: a normal tilted by 1e-7.
    vec3 up = normalize((og_cameraEye + position) * u_oneOverRadiiSquared);
#ifdef TERRAIN
    v_normal = normal;
#else
    v_normal = up;
#endif
#ifdef TERRAIN_SHADING
    v_height = textureCoordinate.z * u_heightScale;
#endif
#if defined(TERRAIN_SHADING) || defined(WATER_MASK)
    v_up = up;
#endif
#ifdef WATER_MASK
    v_toEye = -position;
#endif
    gl_Position = og_depthVertex(og_modelViewProjectionMatrixRelativeToEye * vec4(position, 1.0));
}
