// A glTF base colour (factor times texture), lit by the Sun (LIGHTING) as MeshPrimitive lights its
// meshes, in linear space: the texture is sRGB-encoded (glTF 3.9.2) and stored as such, so the GPU
// decodes its texels before filtering; the factor is linear; the result is encoded to sRGB for the
// 8-bit framebuffer.
// ALPHA_MASK discards fragments under u_alphaCutoff; ALPHA_BLEND keeps alpha for blending; otherwise
// the material is opaque and alpha is 1.

#ifdef LIGHTING
in vec3 v_normalEye;
uniform vec3 og_sunDirectionEye;
#endif
#ifdef BASE_COLOR_TEXTURE
in vec2 v_textureCoordinate;
uniform sampler2D og_texture0;
#endif
#ifdef ALPHA_MASK
uniform float u_alphaCutoff;
#endif

uniform vec4 u_baseColorFactor;

out vec4 fragmentColor;

void main()
{
    og_depthFragment();
    vec4 baseColor = u_baseColorFactor;
#ifdef BASE_COLOR_TEXTURE
    // glTF's v runs down the image; Texture2D stores the image upright with t running up.
    vec4 texel = texture(og_texture0, vec2(v_textureCoordinate.x, 1.0 - v_textureCoordinate.y));
    baseColor *= texel; // linear: the texture's format is sRGB
#endif
#ifdef ALPHA_MASK
    if (baseColor.a < u_alphaCutoff) {
        discard;
    }
#endif
#ifdef LIGHTING
    // Back faces of double-sided materials are lit as seen from their side.
    vec3 normal = normalize(v_normalEye) * (gl_FrontFacing ? 1.0 : -1.0);
    float diffuse = max(dot(normal, og_sunDirectionEye), 0.0);
    vec3 color = og_linearToSrgb(baseColor.rgb * (0.3 + 0.7 * diffuse));
#else
    vec3 color = og_linearToSrgb(baseColor.rgb);
#endif
#ifdef ALPHA_BLEND
    fragmentColor = vec4(color, baseColor.a);
#else
    fragmentColor = vec4(color, 1.0);
#endif
}
