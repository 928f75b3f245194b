// A tile's colour: a base colour, then each imagery texture in layer order (course 3.5), each
// applying only inside its rectangle of the tile, adjusted (brightness, contrast, gamma) and blended
// by its alpha; then sunlight (LIGHTING). TEXTURE_COUNT (0 to 15) textures, unrolled: GLSL 3.30
// indexes sampler arrays only with constants.

in vec2 v_tileCoordinates;
in vec3 v_normal;
out vec4 fragmentColor;

uniform vec4 u_baseColor;
#if TEXTURE_COUNT > 0
uniform sampler2D u_textures[TEXTURE_COUNT];
uniform vec4 u_textureTransforms[TEXTURE_COUNT];  // translation (xy), scale (zw): tile uv to texture uv
uniform vec4 u_textureRectangles[TEXTURE_COUNT];  // minimum u, v and maximum u, v within the tile
uniform vec4 u_textureAdjustments[TEXTURE_COUNT]; // alpha, brightness, contrast, 1 / gamma
#endif
#ifdef LIGHTING
uniform vec3 og_sunDirection;
#endif

vec3 blendImagery(vec3 color, sampler2D imagery, vec4 transform, vec4 rectangle, vec4 adjustment)
{
    vec2 uv = v_tileCoordinates;
    if (uv.x < rectangle.x || uv.x > rectangle.z || uv.y < rectangle.y || uv.y > rectangle.w) {
        return color;
    }
    vec4 texel = texture(imagery, transform.xy + transform.zw * uv);
    vec3 adjusted = texel.rgb * adjustment.y;
    adjusted = mix(vec3(0.5), adjusted, adjustment.z);
    adjusted = pow(max(adjusted, vec3(0.0)), vec3(adjustment.w));
    return mix(color, adjusted, texel.a * adjustment.x);
}

#define OG_BLEND(i) color = blendImagery(color, u_textures[i], u_textureTransforms[i], u_textureRectangles[i], u_textureAdjustments[i])

void main()
{
    og_depthFragment();
    vec3 color = u_baseColor.rgb;
#if TEXTURE_COUNT > 0
    OG_BLEND(0);
#endif
#if TEXTURE_COUNT > 1
    OG_BLEND(1);
#endif
#if TEXTURE_COUNT > 2
    OG_BLEND(2);
#endif
#if TEXTURE_COUNT > 3
    OG_BLEND(3);
#endif
#if TEXTURE_COUNT > 4
    OG_BLEND(4);
#endif
#if TEXTURE_COUNT > 5
    OG_BLEND(5);
#endif
#if TEXTURE_COUNT > 6
    OG_BLEND(6);
#endif
#if TEXTURE_COUNT > 7
    OG_BLEND(7);
#endif
#if TEXTURE_COUNT > 8
    OG_BLEND(8);
#endif
#if TEXTURE_COUNT > 9
    OG_BLEND(9);
#endif
#if TEXTURE_COUNT > 10
    OG_BLEND(10);
#endif
#if TEXTURE_COUNT > 11
    OG_BLEND(11);
#endif
#if TEXTURE_COUNT > 12
    OG_BLEND(12);
#endif
#if TEXTURE_COUNT > 13
    OG_BLEND(13);
#endif
#if TEXTURE_COUNT > 14
    OG_BLEND(14);
#endif
#ifdef LIGHTING
    color *= 0.2 + 0.8 * max(dot(normalize(v_normal), og_sunDirection), 0.0);
#endif
    fragmentColor = vec4(color, 1.0);
}
