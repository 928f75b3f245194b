// A tile's colour: a base colour, then each imagery texture in layer order (course 3.5), each only
// inside its rectangle of the tile, adjusted (brightness, contrast, gamma) and blended by its alpha
// (imagery_over.glsl, put before this text);
// then the terrain's shading options (TERRAIN_SHADING, terrain_shading.glsl put before this text)
// and sunlight (LIGHTING), with water where the terrain's mask says so (WATER_MASK: the mask is
// WATER_MASK_TEXTURE, declared in place of OG_IMAGERY_UNIFORMS). The TiledGlobe writes one block of uniforms and one call per texture
// in place of the two OG_IMAGERY lines below (og_textureN, u_textureTransformN, ...): GLSL 3.30
// indexes sampler arrays only with constants, and per-draw uniforms are not arrays.

in vec2 v_tileCoordinates;
in vec3 v_normal;
#ifdef TERRAIN_SHADING
in float v_height;
#endif
#if defined(TERRAIN_SHADING) || defined(WATER_MASK)
in vec3 v_up;
#endif
#ifdef WATER_MASK
in vec3 v_toEye;
#endif
out vec4 fragmentColor;

uniform vec4 u_baseColor;
#ifdef LIGHTING
uniform vec3 og_sunDirection;
#endif

// transform: translation (xy) and scale (zw) from tile to texture coordinates; rectangle: minimum
// u, v and maximum u, v within the tile; adjustment: alpha, brightness, contrast, 1 / gamma.
vec3 blendImagery(vec3 color, sampler2D imagery, vec4 transform, vec4 rectangle, vec4 adjustment)
{
    vec2 uv = v_tileCoordinates;
    if (uv.x < rectangle.x || uv.x > rectangle.z || uv.y < rectangle.y || uv.y > rectangle.w) {
        return color;
    }
    return imageryOver(color, texture(imagery, transform.xy + transform.zw * uv), adjustment); // imagery_over.glsl
}

// OG_IMAGERY_UNIFORMS

void main()
{
    og_depthFragment();
    vec3 color = u_baseColor.rgb;
#ifdef TERRAIN_SHADING
    vec3 normal = normalize(v_normal);
    vec3 up = normalize(v_up);
    color = terrainBaseColor(color, v_height, normal, up);
#endif
    // OG_IMAGERY_BLENDS
#ifdef TERRAIN_SHADING
    color = terrainOverlays(color, v_height, normal, up);
#endif
#ifdef LIGHTING
    // In linear space, as models are lit: the imagery and colours are sRGB-encoded.
    vec3 lightNormal = normalize(v_normal);
    vec3 glint = vec3(0.0);
#ifdef WATER_MASK
    // Water is level whatever the sea floor under it does, and mirrors the Sun (Blinn-Phong): a
    // glint where the eye sees the Sun's reflection, none on land.
    float water = texture(WATER_MASK_TEXTURE, v_tileCoordinates).r;
    vec3 level = normalize(v_up);
    lightNormal = normalize(mix(lightNormal, level, water));
    vec3 halfway = normalize(og_sunDirection + normalize(v_toEye));
    float sunUp = step(0.0, dot(level, og_sunDirection));
    glint = vec3(water * sunUp * 0.8 * pow(max(dot(level, halfway), 0.0), 80.0));
#endif
    color = og_linearToSrgb(og_srgbToLinear(color) * (0.2 + 0.8 * max(dot(lightNormal, og_sunDirection), 0.0)) + glint);
#endif
    fragmentColor = vec4(color, 1.0);
}
