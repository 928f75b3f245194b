// Billboards and label glyphs, stage 3 of 3: the atlas texel (premultiplied) times the colour
// (straight alpha); LABEL: the glyph's coverage (red) in the fill colour over its halo (green) in
// the halo colour. The output is premultiplied, blended "over" (one, one minus source alpha).

in vec2 g_textureCoordinate;
flat in vec4 g_color;
#ifdef LABEL
flat in vec4 g_haloColor;
#endif

uniform sampler2D og_texture0;

out vec4 fragmentColor;

void main()
{
    og_depthFragment();
#ifdef LABEL
    vec2 coverage = texture(og_texture0, g_textureCoordinate).rg;
    float fillAlpha = g_color.a * coverage.x;
    float haloAlpha = g_haloColor.a * coverage.y * (1.0 - fillAlpha);
    float alpha = fillAlpha + haloAlpha;
    if (alpha <= 0.0) {
        discard;
    }
    fragmentColor = vec4(g_color.rgb * fillAlpha + g_haloColor.rgb * haloAlpha, alpha);
#else
    vec4 texel = texture(og_texture0, g_textureCoordinate) * vec4(g_color.rgb * g_color.a, g_color.a);
    if (texel.a <= 0.0) {
        discard;
    }
    fragmentColor = texel;
#endif
}
