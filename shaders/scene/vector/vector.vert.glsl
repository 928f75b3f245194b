// Vertices of polylines (POLYLINE: a geometry shader widens them) and filled polygons on the globe.
// Positions arrive relative to the eye as two floats each (GPU RTE, book section 5.4), or with
// RELATIVE_TO_CENTER as float offsets from a centre that the model matrix carries (RTC, 5.2);
// never as world floats.
//
// Against z-fighting with the globe (book section 7.2), each vertex is moved towards the eye along
// its view ray, by a distance rather than by a depth-buffer bias:
//  * The geometry is already lifted on the CPU so that no chord or flat triangle dips below the
//    ellipsoid; what is left to fight over is rounding: the depth buffer's step and float
//    round-off in this shader and in the ray-cast globe's depth. The offset is u_depthOffset.x steps
//    of the depth buffer at the vertex's distance z, and at least u_depthOffset.y of the distance
//    (float round-off is relative). The step depends on the frame's depth strategy (depthStep):
//    z^2 (f - n) / (n f 2^24) for perspective depth (Single, and MultiFrustum, where it differs in
//    each frustum); z ln(f / n) 2^-24 for logarithmic depth, whose 24 bits are spread evenly over
//    log distance; z 2^-23, one float spacing of near / z, for complementary depth. (The perspective
//    step would be z / n times too large under the last two: kilometres at 1,000 km with something
//    1 m from the eye, enough to pull lines through what stands in front of them.)
//  * Per-vertex logarithmic depth is interpolated linearly between the logarithms at the corners and
//    so lies behind the true depth between them: kilometres for a polygon's triangles or a line's
//    segments of a degree seen at a slant. Under it the geometry shader applies the depth function
//    with og_depthPrimitiveVertex, which moves each primitive's corners nearer by that error's bound.
//  * A line is widened in screen space at its centre's depth, but the surface under its sides is
//    nearer or farther: at a grazing angle a (between view ray and surface) the surface changes
//    depth by metersPerPixel / tan(a) per pixel across. The offset adds that for the line's half
//    width, so a wide line is not half-buried on a globe seen obliquely. glPolygonOffset's slope
//    term cannot do it: the widened quad is flat in depth across its width.
//  * u_depthOffset.z adds metres: lines drawn over polygons add the depth a polygon of their
//    granularity may stand above its border's chords.
//  * Moving along the view ray leaves the vertex where it was on the screen, and it works with any
//    depth encoding: the logarithmic depth per fragment is taken from the moved vertex's w.
// Two caps keep the offset harmless. A point hidden behind the limb shows through only when the
// ellipsoid hides it along less than the offset d of its view ray: such rays pass at most
// d^2 / (8 R) below the surface, a band d^2 / (8 R D) wide at distance D. Capping d at
// sqrt(4 R D radiansPerPixel) keeps that band under half a pixel (750 km at 20,000 km away at
// 1280x720, 100 km at 60 km away in a 128-pixel view). And a vertex is never moved in front of the
// near plane of the frustum being drawn, where it would be clipped. The scene also culls whole
// groups below the horizon.
//
// DRAPED: a draped polygon's closed volume (PolygonCollection, docs/terrain.md): its vertices lie on
// the ellipsoid, each moved along its geodetic normal to the volume's bottom or top, heights the
// polygon takes each frame from the ground drawn under it. It is drawn without the offset.
//
// Since the offset differs between multi-frustums, blended draws (OG_DEPTH_OWNED_RANGE) pass the
// eye depth before it on to og_depthFragment, which decides by it which frustum owns a fragment.
// Where a geometry shader follows (DEPTH_IN_GEOMETRY_SHADER) it applies og_depthVertex, once the
// clip positions of its primitives are final.

#ifdef RELATIVE_TO_CENTER
in vec3 position;
uniform mat4 og_modelViewMatrix;
#else
in vec3 positionHigh;
in vec3 positionLow;
uniform vec3 og_cameraEyeHigh;
uniform vec3 og_cameraEyeLow;
uniform mat4 og_modelViewMatrixRelativeToEye;
#endif
in vec4 color;
out vec4 v_color;
#ifdef POLYLINE
// Fixed locations (PolylineCollection.cpp), so that one vertex array serves every depth variant.
layout(location = 6) in vec4 outlineColor;
layout(location = 7) in vec2 widths; // line width, outline width on each side: pixels
out vec4 v_outlineColor;
out vec2 v_widths;
#endif
#ifdef DRAPED
layout(location = 6) in vec4 drape; // the geodetic normal; 0 at the volume's bottom, 1 at its top
uniform vec2 u_drapeHeights;        // the bottom's and the top's heights above the ellipsoid, metres
#endif
#ifdef OG_DEPTH_OWNED_RANGE
out float v_eyeDepthBeforeOffset;
#endif

uniform mat4 og_viewMatrix;
uniform mat4 og_projectionMatrix;
uniform float og_nearDistance;
uniform float og_farDistance;
uniform vec4 og_viewport;
// Steps of the depth buffer, least fraction of the distance, metres, and the ellipsoid's largest radius.
uniform vec4 u_depthOffset;

// The depth buffer's step at distance z under the frame's depth strategy, metres.
float depthStep(float z)
{
#if defined(OG_DEPTH_LOGARITHMIC) || defined(OG_DEPTH_LOGARITHMIC_VERTEX)
    // og_logarithmicDepth.y is 1 / log2(f / n) (built-in depth.glsl).
    return z * (0.6931471805599453 / og_logarithmicDepth.y) / 16777216.0;
#elif defined(OG_DEPTH_COMPLEMENTARY)
    return z / 8388608.0;
#else
    return z * (z / og_nearDistance) * (1.0 - og_nearDistance / og_farDistance) / 16777216.0;
#endif
}

void main()
{
#ifdef DRAPED
    vec3 lift = drape.xyz * mix(u_drapeHeights.x, u_drapeHeights.y, drape.w);
#else
    const vec3 lift = vec3(0.0);
#endif
#ifdef RELATIVE_TO_CENTER
    // The model matrix only translates: the lift adds in world axes.
    vec3 positionEye = (og_modelViewMatrix * vec4(position + lift, 1.0)).xyz;
#else
    vec3 relativeToEye = og_emulatedDoubleSubtract(positionHigh, positionLow, og_cameraEyeHigh, og_cameraEyeLow);
    vec3 positionEye = (og_modelViewMatrixRelativeToEye * vec4(relativeToEye + lift, 1.0)).xyz;
#endif
#ifdef OG_DEPTH_OWNED_RANGE
    v_eyeDepthBeforeOffset = -positionEye.z;
#endif
    float distance = length(positionEye);
    if (distance > 0.0) {
        float offset = max(u_depthOffset.x * depthStep(distance), u_depthOffset.y * distance) + u_depthOffset.z;
        float radiansPerPixel = 2.0 / (og_projectionMatrix[1][1] * og_viewport.w);
#ifdef POLYLINE
        if (u_depthOffset.x > 0.0) {
            // Up at the vertex, from the ellipsoid's centre (og_viewMatrix[3] in eye coordinates).
            vec3 up = normalize(positionEye - og_viewMatrix[3].xyz);
            float sine = clamp(dot(up, -positionEye / distance), 0.05, 1.0);
            float halfWidth = 0.5 * widths.x + widths.y + 1.0;
            offset += halfWidth * distance * radiansPerPixel * sqrt(1.0 - sine * sine) / sine;
        }
#endif
        // Caps: the band behind the limb where hidden points could show stays under half a pixel,
        // and the vertex stays beyond this frustum's near plane.
        float limbCap = sqrt(4.0 * u_depthOffset.w * distance * radiansPerPixel);
        float nearCap = distance * max(0.0, 1.0 - 1.001 * og_nearDistance / max(-positionEye.z, 1e-30));
        positionEye *= 1.0 - min(offset, min(limbCap, nearCap)) / distance;
    }
#ifdef DEPTH_IN_GEOMETRY_SHADER
    gl_Position = og_projectionMatrix * vec4(positionEye, 1.0);
#else
    gl_Position = og_depthVertex(og_projectionMatrix * vec4(positionEye, 1.0));
#endif
    v_color = color;
#ifdef POLYLINE
    v_outlineColor = outlineColor;
    v_widths = widths;
#endif
}
