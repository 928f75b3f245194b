// Wide polylines (book section 7.3): each segment, with its neighbours for the joins
// (lines_adjacency), becomes a quad of the line's width plus its outline on both sides, measured in
// pixels. At a shared vertex both segments take the same mitred offset, so they meet without gap
// or overlap (turns sharper than 120 degrees fall back to square ends). The quad extends one pixel
// further for anti-aliasing. Segments are clipped at the near plane before the division by w.
//
// The signed distance from the centre in pixels varies linearly across the screen. It is sent as
// (distance * w, w), interpolated perspective-correctly, and divided in the fragment shader, which
// gives the screen-linear value. A noperspective varying would say the same more simply, but with
// Mesa 22.3's llvmpipe it came out wrong on quads that needed clipping, and whole segments with
// an end near the near plane were discarded (the test "A line running behind the eye...").
//
// The depth strategy is applied here, to the corners emitted (the vertex shader leaves it): the
// segment is clipped at the near plane by the projection's own z first (z = -w, or z = w in the
// 0..1 clip depth of complementary depth), and under per-vertex logarithmic depth each quad's
// corners are moved nearer by the bound on its interpolation error (og_depthPrimitiveVertex), so
// that the depth offset keeps the line in front of the globe along the whole segment, not only at
// its ends.

layout(lines_adjacency) in;
layout(triangle_strip, max_vertices = 4) out;

in vec4 v_color[];
in vec4 v_outlineColor[];
in vec2 v_widths[];

flat out vec4 g_color;
flat out vec4 g_outlineColor;
flat out vec2 g_halfWidths; // the line's, and the line's with its outline
out vec2 g_distanceTimesW; // (signed distance in pixels * w, w)
#ifdef OG_DEPTH_OWNED_RANGE
in float v_eyeDepthBeforeOffset[];
out float g_eyeDepthBeforeOffset;
#endif

uniform vec4 og_viewport;

// Signed distance to the near plane, positive in front, linear in clip coordinates: z = -w in GL's
// clip space; under complementary depth (clip depth 0..1 with z = near) z = w.
float nearPlaneDistance(vec4 clip)
{
#ifdef OG_DEPTH_COMPLEMENTARY
    return clip.w - clip.z;
#else
    return clip.z + clip.w;
#endif
}

vec2 toWindow(vec4 clip)
{
    return (clip.xy / clip.w * 0.5 + 0.5) * og_viewport.zw;
}

// The offset direction at a joint, scaled so that its component along `normal` is 1: the miter of
// this segment's normal and the neighbouring segment's (neighbourAlong: that segment in window
// coordinates, in the line's direction), or `normal` itself at an end, a clipped end or a sharp turn.
vec2 jointOffset(vec2 normal, vec2 neighbourAlong, bool joined)
{
    if (!joined || dot(neighbourAlong, neighbourAlong) < 1e-6) {
        return normal;
    }
    vec2 neighbourDirection = normalize(neighbourAlong);
    vec2 neighbourNormal = vec2(-neighbourDirection.y, neighbourDirection.x);
    vec2 sum = normal + neighbourNormal;
    if (dot(sum, sum) < 1e-6) {
        return normal;
    }
    vec2 miter = normalize(sum);
    float cosine = dot(miter, normal);
    return cosine < 0.5 ? normal : miter / cosine;
}

// wRange: the segment's nearest and farthest w; eyeDepth: the end's eye depth before the depth
// offset (used with OG_DEPTH_OWNED_RANGE only).
void emit(vec4 clip, vec2 offsetPixels, float distance, vec2 wRange, float eyeDepth)
{
    vec4 corner = vec4(clip.xy + offsetPixels / (0.5 * og_viewport.zw) * clip.w, clip.zw);
    gl_Position = og_depthPrimitiveVertex(corner, wRange);
    g_distanceTimesW = vec2(distance * clip.w, clip.w);
#ifdef OG_DEPTH_OWNED_RANGE
    g_eyeDepthBeforeOffset = eyeDepth;
#endif
    EmitVertex();
}

void main()
{
    vec2 widths = v_widths[1];
    float halfLine = 0.5 * widths.x;
    float halfTotal = halfLine + widths.y;
    if (halfTotal <= 0.0) {
        return; // hidden
    }
    vec4 p0 = gl_in[0].gl_Position;
    vec4 p1 = gl_in[1].gl_Position;
    vec4 p2 = gl_in[2].gl_Position;
    vec4 p3 = gl_in[3].gl_Position;

    float d1 = nearPlaneDistance(p1);
    float d2 = nearPlaneDistance(p2);
    if (d1 <= 0.0 && d2 <= 0.0) {
        return;
    }
    bool clipped1 = false;
    bool clipped2 = false;
    float eyeDepth1 = 0.0;
    float eyeDepth2 = 0.0;
#ifdef OG_DEPTH_OWNED_RANGE
    eyeDepth1 = v_eyeDepthBeforeOffset[1];
    eyeDepth2 = v_eyeDepthBeforeOffset[2];
#endif
    if (d1 <= 0.0) {
        p1 = mix(p1, p2, d1 / (d1 - d2));
        eyeDepth1 = mix(eyeDepth1, eyeDepth2, d1 / (d1 - d2));
        clipped1 = true;
    } else if (d2 <= 0.0) {
        p2 = mix(p2, p1, d2 / (d2 - d1));
        eyeDepth2 = mix(eyeDepth2, eyeDepth1, d2 / (d2 - d1));
        clipped2 = true;
    }
    vec2 w1 = toWindow(p1);
    vec2 w2 = toWindow(p2);
    vec2 along = w2 - w1;
    if (dot(along, along) < 1e-8) {
        return; // seen end-on: the neighbours meet at the same pixel
    }
    vec2 direction = normalize(along);
    vec2 normal = vec2(-direction.y, direction.x);
    bool joined0 = !clipped1 && nearPlaneDistance(p0) > 0.0;
    bool joined3 = !clipped2 && nearPlaneDistance(p3) > 0.0;
    vec2 offset1 = jointOffset(normal, joined0 ? w1 - toWindow(p0) : vec2(0.0), joined0);
    vec2 offset2 = jointOffset(normal, joined3 ? toWindow(p3) - w2 : vec2(0.0), joined3);

    g_color = v_color[1];
    g_outlineColor = v_outlineColor[1];
    g_halfWidths = vec2(halfLine, halfTotal);
    float extent = halfTotal + 1.0;
    vec2 wRange = vec2(min(p1.w, p2.w), max(p1.w, p2.w));
    emit(p1, offset1 * extent, extent, wRange, eyeDepth1);
    emit(p1, -offset1 * extent, -extent, wRange, eyeDepth1);
    emit(p2, offset2 * extent, extent, wRange, eyeDepth2);
    emit(p2, -offset2 * extent, -extent, wRange, eyeDepth2);
    EndPrimitive();
}
