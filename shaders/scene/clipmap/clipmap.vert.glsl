// A level of geometry-clipmap terrain (book 13.3, 13.4, 13.7). Each vertex is a post of the
// level's n x n lattice; its height and slope come from the level's textures (post (X, Y) in
// texel (X, Y) modulo the size: toroidal), blended with the next coarser level's over the outer
// band. Positions are relative to the eye: the level's centre relative to the eye comes from the
// CPU in double, each post's offset from that centre is formed here from small-angle
// differences, which keep float's relative precision however far the level is from the origin.

in vec2 position; // the post's column and row in the level's lattice

out vec3 v_normal;       // of the terrain, Earth-fixed
out vec2 v_fineTexel;    // the post's texel in this level's colour texture (repeating)
out vec2 v_coarseTexel;  // and in the coarser level's
out float v_blend;       // 0: this level, 1: the coarser level
out float v_height;      // metres, the exaggeration taken out
out vec3 v_up;           // the ellipsoid's normal, Earth-fixed

uniform mat4 og_modelViewProjectionMatrixRelativeToEye;
uniform sampler2D og_texture0; // heights, metres (R32F)
uniform sampler2D og_texture1; // height gradient east and north, metres per metre (RG32F)
uniform sampler2D og_texture3; // the coarser level's heights
uniform sampler2D og_texture4; // the coarser level's gradients

uniform ivec2 u_levelOrigin;     // the level's post 0, modulo twice the texture size
uniform int u_textureSize;       // a power of two, n + 1
uniform float u_centerPost;      // (n - 1) / 2
uniform float u_spacing;         // radians between posts
uniform vec4 u_centerTrig;       // cos, sin of the centre's grid latitude; cos, sin of its grid longitude
uniform vec3 u_centerNormal;     // Earth-fixed geodetic normal at the centre
uniform vec3 u_centerRelativeToEye; // the centre at u_referenceHeight minus the eye
uniform float u_referenceHeight; // the eye's height: heights are drawn as differences from it
uniform float u_centerRadius;    // the prime vertical radius of curvature at the centre
// The same four and the spacing of the coarser level, and where this level's post 0 lies on it
// (post m or m - 1): the outer posts on coarser posts are placed as the coarser level places
// them, bit for bit, so that the degenerate triangles meet its edges exactly.
uniform vec4 u_coarserCenterTrig;
uniform vec3 u_coarserCenterNormal;
uniform vec3 u_coarserCenterRelativeToEye;
uniform float u_coarserCenterRadius;
uniform float u_coarserSpacing;
uniform ivec2 u_originOnCoarser;
uniform bool u_hasCoarser;
uniform float u_eccentricitySquared;
uniform mat3 u_frame;            // grid directions to Earth-fixed ones (a permutation of axes)
uniform vec2 u_blend;            // the band: from u_blend.x posts off the centre, u_blend.y posts wide
uniform float u_exaggeration;

// sin(x) for |x| up to about 1 with float's relative precision (a GPU's sin is only absolutely
// accurate, a metre at Earth's radius for the small angles here).
float sinSmall(float x)
{
    float x2 = x * x;
    return x * (1.0 - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0 * (1.0 - x2 / 72.0 * (1.0 - x2 / 110.0)))));
}

// cos(x) - 1, without the cancellation.
float cosMinusOne(float x)
{
    float sinHalf = sinSmall(0.5 * x);
    return -2.0 * sinHalf * sinHalf;
}

// The coarser level's value at this post: on the coarser edge or diagonal the post lies on, as
// the coarser triangles would interpolate it.
ivec2 coarseTexel(ivec2 global, ivec2 step)
{
    return (((global & (2 * u_textureSize - 1)) >> 1) + step) & (u_textureSize - 1);
}

// The position relative to the eye of the surface point `fromCenter` posts (spacing apart) from a
// level's centre, `height` above the ellipsoid, and the terrain normal for a height gradient.
vec3 positionRelativeToEye(vec2 fromCenter, float height, vec2 gradient, float spacing, vec4 centerTrig,
                           vec3 centerNormal, vec3 centerRelativeToEye, float centerRadius, out vec3 terrainNormal,
                           out vec3 up)
{
    // The grid direction's change from the centre's, from the angle differences.
    float dLongitude = fromCenter.x * spacing;
    float dLatitude = fromCenter.y * spacing;
    float cosLatC = centerTrig.x, sinLatC = centerTrig.y, cosLonC = centerTrig.z, sinLonC = centerTrig.w;
    float sinDLat = sinSmall(dLatitude), cosDLatM1 = cosMinusOne(dLatitude);
    float sinDLon = sinSmall(dLongitude), cosDLonM1 = cosMinusOne(dLongitude);
    float dCosLat = cosLatC * cosDLatM1 - sinLatC * sinDLat;
    float dSinLat = sinLatC * cosDLatM1 + cosLatC * sinDLat;
    float dCosLon = cosLonC * cosDLonM1 - sinLonC * sinDLon;
    float dSinLon = sinLonC * cosDLonM1 + cosLonC * sinDLon;
    float cosLat = cosLatC + dCosLat, sinLat = sinLatC + dSinLat;
    float cosLon = cosLonC + dCosLon, sinLon = sinLonC + dSinLon;
    vec3 dGrid = vec3(dCosLat * cosLon + cosLatC * dCosLon, dCosLat * sinLon + cosLatC * dSinLon, dSinLat);
    vec3 dNormal = u_frame * dGrid;
    vec3 normal = centerNormal + dNormal;

    // The ellipsoid point with that geodetic normal, N(n) (n.x, n.y, (1 - e^2) n.z), minus the
    // centre's: N - N0 from the change of 1 - e^2 n.z^2 without cancellation.
    float w0 = 1.0 - u_eccentricitySquared * centerNormal.z * centerNormal.z;
    float t = -u_eccentricitySquared * dNormal.z * (2.0 * centerNormal.z + dNormal.z) / w0;
    float root = sqrt(1.0 + t);
    float dRadius = -centerRadius * t / (root * (1.0 + root));
    vec3 k = vec3(1.0, 1.0, 1.0 - u_eccentricitySquared);
    // height * normal less the reference height along the centre's normal, which the centre's
    // position carries: small terms near the eye, however high the ground.
    vec3 offset = dRadius * (k * normal) + centerRadius * (k * dNormal) + (height - u_referenceHeight) * normal +
                  u_referenceHeight * dNormal;

    vec3 east = u_frame * vec3(-sinLon, cosLon, 0.0);
    vec3 north = u_frame * vec3(-sinLat * cosLon, -sinLat * sinLon, cosLat);
    terrainNormal = normalize(normal - gradient.x * east - gradient.y * north);
    up = normal;
    return centerRelativeToEye + offset;
}

void main()
{
    ivec2 post = ivec2(position);
    ivec2 global = u_levelOrigin + post;
    ivec2 fine = global & (u_textureSize - 1);
    ivec2 odd = global & 1;

    vec2 fromCenter = position - vec2(u_centerPost);
    float distance = max(abs(fromCenter.x), abs(fromCenter.y));
    float blend = u_hasCoarser ? clamp((distance - u_blend.x) / u_blend.y, 0.0, 1.0) : 0.0;

    float height = texelFetch(og_texture0, fine, 0).r;
    vec2 gradient = texelFetch(og_texture1, fine, 0).rg;
    float coarseHeight = 0.0;
    if (blend > 0.0) {
        ivec2 a = coarseTexel(global, ivec2(0));
        ivec2 b = coarseTexel(global, odd);
        coarseHeight = 0.5 * (texelFetch(og_texture3, a, 0).r + texelFetch(og_texture3, b, 0).r);
        vec2 coarseGradient = 0.5 * (texelFetch(og_texture4, a, 0).rg + texelFetch(og_texture4, b, 0).rg);
        height = mix(height, coarseHeight, blend);
        gradient = mix(gradient, coarseGradient, blend);
    }
    gradient *= u_exaggeration;

    int last = 2 * int(u_centerPost);
    bool outer = post.x == 0 || post.y == 0 || post.x == last || post.y == last;
    vec3 positionFromEye;
    if (u_hasCoarser && outer && odd == ivec2(0)) {
        // A coarser post (its own height: the coarser level has no blend there).
        vec2 coarsePost = vec2(u_originOnCoarser + post / 2);
        positionFromEye = positionRelativeToEye(coarsePost - vec2(u_centerPost), coarseHeight * u_exaggeration, gradient,
                                                u_coarserSpacing, u_coarserCenterTrig, u_coarserCenterNormal,
                                                u_coarserCenterRelativeToEye, u_coarserCenterRadius, v_normal, v_up);
    } else {
        positionFromEye = positionRelativeToEye(fromCenter, height * u_exaggeration, gradient, u_spacing, u_centerTrig,
                                                u_centerNormal, u_centerRelativeToEye, u_centerRadius, v_normal, v_up);
    }
    float size = float(u_textureSize);
    // Unwrapped (the origin is below twice the size), so that a triangle across the texture's
    // seam does not interpolate backwards over it; the sampler repeats.
    v_fineTexel = (vec2(global) + 0.5) / size;
    v_coarseTexel = (vec2(global) * 0.5 + 0.5) / size;
    v_blend = blend;
    v_height = height; // the coarser height on the outer posts (the blend is 1 there)
    gl_Position = og_depthVertex(og_modelViewProjectionMatrixRelativeToEye * vec4(positionFromEye, 1.0));
}
