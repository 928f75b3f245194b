// The backdrop's colour where no clipmap level is: its fragments inside the coarsest level, less
// that level's outer band (where both draw, so that no sliver opens between them), are discarded.
// Shaded and lit as the levels are (surface_color.glsl, put before this text), on level ground:
// the backdrop has no slopes.

in vec3 v_position;
in vec2 v_texel;
in float v_height;
out vec4 fragmentColor;

uniform sampler2D og_texture0; // the imagery, equirectangular (RGBA8)
uniform mat3 u_toGrid;         // Earth-fixed directions to the clipmap grid's
uniform vec2 u_coarsestCenter; // the coarsest level's centre: grid longitude, latitude (radians)
uniform float u_coarsestHalfWidth; // radians; 0 while no level is drawn

const float kPi = 3.14159265358979;

void main()
{
    og_depthFragment();
    vec3 u = u_toGrid * normalize(v_position);
    float dLongitude = atan(u.y, u.x) - u_coarsestCenter.x;
    dLongitude -= 2.0 * kPi * floor(dLongitude / (2.0 * kPi) + 0.5);
    float dLatitude = asin(clamp(u.z, -1.0, 1.0)) - u_coarsestCenter.y;
    if (abs(dLongitude) < u_coarsestHalfWidth && abs(dLatitude) < u_coarsestHalfWidth) {
        discard;
    }
    // Level ground: the ellipsoid's normal (the geocentric direction, a fraction of a degree off)
    // is the terrain's.
    vec3 up = normalize(v_position);
    fragmentColor = vec4(surfaceColor(texture(og_texture0, v_texel).rgb, v_height, up, up), 1.0);
}
