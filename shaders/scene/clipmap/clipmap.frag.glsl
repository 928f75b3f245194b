// Clipmap terrain's colour: the imagery draped on the level's posts (or the level's colour with
// COLOR_BY_LEVEL), blended with the coarser level's across the band, then the terrain's shading
// options (TERRAIN_SHADING, terrain_shading.glsl put before this text: a ramp in place of the
// base colour where there is no IMAGERY over it, hillshade and contours over everything), lit by
// the Sun (LIGHTING).

in vec3 v_normal;
in vec2 v_fineTexel;
in vec2 v_coarseTexel;
in float v_blend;
in float v_height;
in vec3 v_up;
out vec4 fragmentColor;

uniform sampler2D og_texture2; // this level's colours (RGBA8, repeating: toroidal)
uniform sampler2D og_texture5; // the coarser level's
uniform vec4 u_levelColor;
uniform vec4 u_coarserLevelColor;
#ifdef LIGHTING
uniform vec3 og_sunDirection;
#endif

void main()
{
    og_depthFragment();
#ifdef COLOR_BY_LEVEL
    vec3 color = mix(u_levelColor.rgb, u_coarserLevelColor.rgb, v_blend);
#else
    vec3 color = mix(texture(og_texture2, v_fineTexel).rgb, texture(og_texture5, v_coarseTexel).rgb, v_blend);
#endif
#ifdef TERRAIN_SHADING
    vec3 normal = normalize(v_normal);
    vec3 up = normalize(v_up);
#if !defined(IMAGERY) && !defined(COLOR_BY_LEVEL)
    color = terrainBaseColor(color, v_height, normal, up);
#endif
    color = terrainOverlays(color, v_height, normal, up);
#endif
#ifdef LIGHTING
    color *= 0.2 + 0.8 * max(dot(normalize(v_normal), og_sunDirection), 0.0);
#endif
    fragmentColor = vec4(color, 1.0);
}
