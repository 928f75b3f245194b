// Billboards and label glyphs, stage 2 of 3: each point becomes a screen-aligned quad of whole
// pixels. The anchor snaps to the nearest pixel corner and the size rounds to whole pixels, so
// at scale 1 every fragment centre samples a texel centre: the image is drawn texel for pixel.
// The corners keep the depth point's clip z and w (the quad is flat at that depth), so that the
// depth strategy applies to them as to any vertex (og_depthVertex here, og_depthFragment after).

layout(points) in;
layout(triangle_strip, max_vertices = 4) out;

in vec4 v_anchorClip[];
in vec2 v_depthClip[];
in vec2 v_pixelOffset[];
in vec4 v_textureRectangle[];
in vec3 v_scaleOrigin[];
in float v_visible[];
in vec4 v_color[];
#ifdef LABEL
in vec4 v_haloColor[];
#endif

uniform vec4 og_viewport;
uniform vec2 u_inverseAtlasSize;

out vec2 g_textureCoordinate;
flat out vec4 g_color;
#ifdef LABEL
flat out vec4 g_haloColor;
#endif

void corner(vec2 ndc, vec2 textureCoordinate)
{
    float w = v_depthClip[0].y;
    gl_Position = og_depthVertex(vec4(ndc * w, v_depthClip[0].x, w));
    g_textureCoordinate = textureCoordinate;
    g_color = v_color[0];
#ifdef LABEL
    g_haloColor = v_haloColor[0];
#endif
    EmitVertex();
}

void main()
{
    vec4 clip = v_anchorClip[0];
    if (v_visible[0] == 0.0 || clip.w <= 0.0) {
        return;
    }
    vec2 window = (clip.xy / clip.w * 0.5 + 0.5) * og_viewport.zw + og_viewport.xy;
    vec2 anchor = floor(window + 0.5);
    vec4 texels = v_textureRectangle[0];
    vec2 size = floor(texels.zw * v_scaleOrigin[0].x + 0.5);
    // Window y grows upwards; the offset's y grows downwards.
    vec2 lowerLeft = anchor + vec2(v_pixelOffset[0].x, -v_pixelOffset[0].y) - floor(v_scaleOrigin[0].yz * size);
    vec2 upperRight = lowerLeft + size;
    vec2 viewportEnd = og_viewport.xy + og_viewport.zw;
    if (size.x < 1.0 || size.y < 1.0 || any(greaterThanEqual(lowerLeft, viewportEnd)) ||
        any(lessThanEqual(upperRight, og_viewport.xy))) {
        return;
    }
    vec2 toNdc = 2.0 / og_viewport.zw;
    vec2 low = (lowerLeft - og_viewport.xy) * toNdc - 1.0;
    vec2 high = (upperRight - og_viewport.xy) * toNdc - 1.0;
    // The image's top row (texel y) goes to the quad's top edge.
    float u0 = texels.x * u_inverseAtlasSize.x;
    float u1 = (texels.x + texels.z) * u_inverseAtlasSize.x;
    float vTop = texels.y * u_inverseAtlasSize.y;
    float vBottom = (texels.y + texels.w) * u_inverseAtlasSize.y;
    corner(low, vec2(u0, vBottom));
    corner(vec2(high.x, low.y), vec2(u1, vBottom));
    corner(vec2(low.x, high.y), vec2(u0, vTop));
    corner(high, vec2(u1, vTop));
    EndPrimitive();
}
