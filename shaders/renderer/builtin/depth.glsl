// Depth strategies (the scene layer's DepthStrategy sets the defines; book chapter 6):
//   OG_DEPTH_LOGARITHMIC         window depth log2(w / near) / log2(far / near), written per fragment
//                                from the eye depth w = 1 / gl_FragCoord.w: right at every pixel,
//                                but the depth test runs after the fragment shader
//   OG_DEPTH_LOGARITHMIC_VERTEX  the same depth written per vertex into gl_Position.z: free, but
//                                interpolated linearly across each triangle, so too far between the
//                                vertices of large ones (the logarithm is concave)
//   OG_DEPTH_COMPLEMENTARY       clip depth 0..1 reversed (SceneState::depthConvention); only
//                                og_windowDepth needs to know
//   OG_DEPTH_OWNED_RANGE         for blended draws where frustums overlap: fragments whose eye depth
//                                lies outside og_ownedDepthRange are discarded, so none is blended
//                                twice
// A shader takes part by calling
//   gl_Position = og_depthVertex(gl_Position);   last in its vertex shader
//   og_depthFragment();                          first in its fragment shader
// and a fragment shader that computes its own depth (a ray caster) writes og_windowDepth(clip) for
// the clip-space position of its surface. With none of the defines these change nothing.
// A geometry shader that makes or clips its primitives calls og_depthVertex on the positions it
// emits instead (its vertex shader does not), or og_depthPrimitiveVertex, which also keeps the
// per-vertex logarithm from drawing the primitive behind its true depth between its corners. A
// shader that moves its vertices by a distance that differs between frustums (the vector depth
// offset) passes the eye depth before the move to og_depthFragment(eyeDepth), so that overlapping
// frustums agree on which of them owns a fragment.
//
// The near plane: log2 of w <= 0 (a vertex behind the eye) is undefined, and a NaN or infinite z
// gets the whole triangle dropped. The clipper cuts an edge where z + w, interpolated linearly,
// reaches 0; with a logarithmic z that is not where w = near, and with z = 0 behind the eye it
// would be behind the eye too (w < 0: the triangle vanishes). The vertex variant therefore gives a
// vertex behind the eye z = 2 w: then z + w = 3 w, and since z + w <= 2 w in front (depth <= 1),
// the cut falls between the vertex in front and the eye plane: a triangle reaching behind the eye
// is clipped, not lost, though cut short of the near plane (by this arithmetic about 30 m out for
// ground from 50 m behind the eye to 20 km ahead). The per-fragment variant keeps the projection's own z for clipping: it clips
// exactly at near and far.

#if defined(OG_DEPTH_LOGARITHMIC) || defined(OG_DEPTH_LOGARITHMIC_VERTEX)
uniform vec2 og_logarithmicDepth; // 1 / near, 1 / log2(far / near)

// Window depth 0..1 (unclamped) of eye depth w > 0. log2(w / near) is taken apart into its
// exponent and the log2 of a mantissa in [1, 2), scaled separately and added once they are in 0..1:
// a log2 near 23 held in one float keeps only 2^-19 of it, coarser than the 2^-24 steps of a 24-bit
// depth buffer.
float og_logarithmicWindowDepth(float w)
{
    float x = w * og_logarithmicDepth.x;
    float exponent = floor(log2(x));
    float mantissa = x * exp2(-exponent); // exact: a power of two
    return exponent * og_logarithmicDepth.y + log2(mantissa) * og_logarithmicDepth.y;
}
#endif

#if defined(OG_DEPTH_OWNED_RANGE)
uniform vec2 og_ownedDepthRange;
#endif

#if defined(OG_VERTEX_SHADER) || defined(OG_GEOMETRY_SHADER)
vec4 og_depthVertex(vec4 clip)
{
#if defined(OG_DEPTH_LOGARITHMIC_VERTEX)
    float ndc = clip.w > 0.0 ? 2.0 * og_logarithmicWindowDepth(clip.w) - 1.0 : 0.0;
    clip.z = clip.w > 0.0 ? ndc * clip.w : 2.0 * clip.w;
#endif
    return clip;
}
#endif

#if defined(OG_GEOMETRY_SHADER)
// og_depthVertex for a corner of a segment or triangle whose corners' eye depths (clip w) lie in
// wRange (nearest, farthest). Per vertex (OG_DEPTH_LOGARITHMIC_VERTEX), the window interpolates
// depth linearly between the corners' logarithms and 1 / w linearly too; the logarithm is convex in
// 1 / w, so the interpolated depth lies behind the true one, by at most the largest gap between
// -ln(u) and its chord over [1 / farthest, 1 / nearest]: t^2 / 8 with t = ln(farthest / nearest)
// (ln units; t/(1 - e^-t) - 1 + ln((1 - e^-t)/t) exactly, which t^2 / 8 bounds for every t). Each
// corner is moved that much nearer, so that no point of the primitive is drawn behind its depth
// (and at most that much in front, at its corners). No corner is moved to the near plane, where
// it would be clipped: a primitive spanning decades of distance from close to the eye (a line from
// beside the eye to the horizon) keeps its corners just beyond it and is drawn nearer than its true
// depth rather than lost. Corners behind the eye are left as they are. Under the other strategies
// this is og_depthVertex.
vec4 og_depthPrimitiveVertex(vec4 clip, vec2 wRange)
{
    clip = og_depthVertex(clip);
#if defined(OG_DEPTH_LOGARITHMIC_VERTEX)
    if (clip.w > 0.0 && wRange.x > 0.0) {
        float t = log(wRange.y / wRange.x);
        float excess = 0.125 * t * t * og_logarithmicDepth.y / 0.6931471805599453; // window depth
        // Not below window depth 2^-10 (for far / near = 1e7, 1.6 % beyond the near plane): a
        // corner that a geometry shader clipped to the near plane lies on it only up to the
        // rounding of its clip coordinates, so the clipper cuts its primitive where the depth
        // interpolated between its corners meets the plane, which must stay close to that corner.
        const float lowest = 1.0 / 1024.0;
        float window = 0.5 * clip.z / clip.w + 0.5;
        clip.z = (2.0 * max(window - excess, min(window, lowest)) - 1.0) * clip.w; // normalised: 2 window - 1
    }
#endif
    return clip;
}
#endif

#if defined(OG_FRAGMENT_SHADER)
// The same as og_depthFragment() with ownership (OG_DEPTH_OWNED_RANGE) decided by `ownedEyeDepth`
// rather than by the fragment's own eye depth: for shaders that move their vertices by a distance
// that depends on the frustum being drawn, which pass the depth before the move, the same in every
// frustum. The written depth is still the fragment's own.
void og_depthFragment(float ownedEyeDepth)
{
#if defined(OG_DEPTH_OWNED_RANGE)
    if (ownedEyeDepth < og_ownedDepthRange.x || ownedEyeDepth >= og_ownedDepthRange.y) {
        discard;
    }
#endif
#if defined(OG_DEPTH_LOGARITHMIC)
    gl_FragDepth = clamp(og_logarithmicWindowDepth(1.0 / gl_FragCoord.w), 0.0, 1.0);
#endif
}

void og_depthFragment()
{
    // The eye depth from gl_FragCoord.w, the rasterizer's own 1 / w interpolated linearly in screen
    // space: better than a varying w, whose perspective-correct interpolation at 10,000 km is off
    // by metres.
    og_depthFragment(1.0 / gl_FragCoord.w);
}
#endif

#if defined(OG_FRAGMENT_SHADER) || defined(OG_GEOMETRY_SHADER)
// The window depth of a clip-space position under the program's depth strategy; outside 0..1 when
// the position is outside the frustum's depth range. A geometry shader compares it with a copy of
// the depth buffer (the billboards' anchor test).
float og_windowDepth(vec4 clip)
{
#if defined(OG_DEPTH_LOGARITHMIC) || defined(OG_DEPTH_LOGARITHMIC_VERTEX)
    return clip.w > 0.0 ? og_logarithmicWindowDepth(clip.w) : -1.0;
#elif defined(OG_DEPTH_COMPLEMENTARY)
    return gl_DepthRange.near + gl_DepthRange.diff * (clip.z / clip.w);
#else
    return 0.5 * (gl_DepthRange.diff * (clip.z / clip.w) + gl_DepthRange.near + gl_DepthRange.far);
#endif
}
#endif
