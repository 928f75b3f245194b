// Billboards and label glyphs, stage 2 of 3: each point becomes a screen-aligned quad of whole
// pixels. The anchor snaps to the nearest pixel corner and the size rounds to whole pixels, so
// at scale 1 every fragment centre samples a texel centre: the image is drawn texel for pixel.
// The corners keep the depth point's clip z and w (the quad is flat at that depth), so that the
// depth strategy applies to them as to any vertex (og_depthVertex here, og_depthFragment after).
// The depth test is the anchor's, here (u_anchorDepthTest): the depth point against the depth the
// frustum's opaque commands wrote around the anchor (og_texture1, a copy); a quad that passes is
// drawn whole, not cut by the ground it stands on (the command's own depth test is off).

layout(points) in;
layout(triangle_strip, max_vertices = 4) out;

in vec4 v_anchorClip[];
in vec2 v_depthClip[];
in float v_depthTestOff[];
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
uniform sampler2D og_texture1;  // the scene's depth (FrameState::sceneDepth)
uniform float u_anchorDepthTest; // 1: test the anchors against og_texture1

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
    if (u_anchorDepthTest != 0.0 && v_depthTestOff[0] == 0.0) {
        // The four pixels whose centres surround the anchor; the farthest of their depths. Where
        // they show one plane (the ground the anchor stands on), window depth is affine across
        // the screen, so the anchor's own lies between theirs: the farthest is never nearer than
        // the ground at the anchor, however slanted it is seen.
        ivec2 corner = ivec2(floor(window + 0.5));
        ivec2 size = textureSize(og_texture1, 0);
        // An anchor off the target has no depth to test against: it is not hidden by it.
        if (all(greaterThanEqual(corner, ivec2(0))) && all(lessThanEqual(corner, size))) {
            ivec2 low = clamp(corner - 1, ivec2(0), size - 1);
            ivec2 high = clamp(corner, ivec2(0), size - 1);
            vec4 around = vec4(texelFetch(og_texture1, low, 0).r, texelFetch(og_texture1, ivec2(high.x, low.y), 0).r,
                               texelFetch(og_texture1, ivec2(low.x, high.y), 0).r, texelFetch(og_texture1, high, 0).r);
            float w = v_depthClip[0].y;
            float depth = og_windowDepth(vec4(clip.xy / clip.w * w, v_depthClip[0].x, w));
#if defined(OG_DEPTH_COMPLEMENTARY)
            // Reversed: nearer is larger.
            bool hidden = depth < min(min(around.x, around.y), min(around.z, around.w));
#else
            bool hidden = depth > max(max(around.x, around.y), max(around.z, around.w));
#endif
            if (hidden) {
                return;
            }
        }
    }
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
