// A polyline's colour across its width: the line, its outline beyond, and one pixel of
// anti-aliasing at each boundary (g_distanceTimesW gives the distance from the centre in pixels,
// see polyline.geom.glsl).

flat in vec4 g_color;
flat in vec4 g_outlineColor;
flat in vec2 g_halfWidths;
in vec2 g_distanceTimesW;
#ifdef OG_DEPTH_OWNED_RANGE
in float g_eyeDepthBeforeOffset;
#endif

out vec4 fragmentColor;

void main()
{
#ifdef OG_DEPTH_OWNED_RANGE
    og_depthFragment(g_eyeDepthBeforeOffset); // the offset differs between frustums (vector.vert.glsl)
#else
    og_depthFragment();
#endif
    float distance = abs(g_distanceTimesW.x / g_distanceTimesW.y);
    vec4 color = g_color;
    if (g_halfWidths.y > g_halfWidths.x) {
        color = mix(g_color, g_outlineColor, clamp(distance - g_halfWidths.x + 0.5, 0.0, 1.0));
    }
    color.a *= clamp(g_halfWidths.y + 0.5 - distance, 0.0, 1.0);
    if (color.a < 1.0 / 255.0) {
        discard;
    }
    fragmentColor = color;
}
