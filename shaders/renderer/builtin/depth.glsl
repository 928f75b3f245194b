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

#if defined(OG_VERTEX_SHADER)
vec4 og_depthVertex(vec4 clip)
{
#if defined(OG_DEPTH_LOGARITHMIC_VERTEX)
    float ndc = clip.w > 0.0 ? 2.0 * og_logarithmicWindowDepth(clip.w) - 1.0 : 0.0;
    clip.z = clip.w > 0.0 ? ndc * clip.w : 2.0 * clip.w;
#endif
    return clip;
}
#endif

#if defined(OG_FRAGMENT_SHADER)
void og_depthFragment()
{
    // The eye depth from gl_FragCoord.w, the rasterizer's own 1 / w interpolated linearly in screen
    // space: better than a varying w, whose perspective-correct interpolation at 10,000 km is off
    // by metres.
#if defined(OG_DEPTH_OWNED_RANGE)
    float w = 1.0 / gl_FragCoord.w;
    if (w < og_ownedDepthRange.x || w >= og_ownedDepthRange.y) {
        discard;
    }
#endif
#if defined(OG_DEPTH_LOGARITHMIC)
    gl_FragDepth = clamp(og_logarithmicWindowDepth(1.0 / gl_FragCoord.w), 0.0, 1.0);
#endif
}

// The window depth of a clip-space position under the program's depth strategy; outside 0..1 when
// the position is outside the frustum's depth range.
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
