// Clipmap terrain's colour: the imagery draped on the level's posts (or the level's colour with
// COLOR_BY_LEVEL), blended with the coarser level's across the band, then shaded and lit
// (surface_color.glsl, put before this text).

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

void main()
{
    og_depthFragment();
#ifdef COLOR_BY_LEVEL
    vec3 color = mix(u_levelColor.rgb, u_coarserLevelColor.rgb, v_blend);
#else
    vec3 color = mix(texture(og_texture2, v_fineTexel).rgb, texture(og_texture5, v_coarseTexel).rgb, v_blend);
#endif
    fragmentColor = vec4(surfaceColor(color, v_height, normalize(v_normal), normalize(v_up)), 1.0);
}
