// Globe shading (book chapter 4). With RAY_CAST the fragment belongs to the bounding box drawn
// with front-face culling: a ray from the eye finds the ellipsoid (ray_cast_ellipsoid.glsl, put
// before this source), or the fragment is discarded, and the depth of the hit is written, as the
// frame's depth strategy maps it (og_windowDepth). Variants: DAY_TEXTURE, NIGHT_TEXTURE, LIGHTING,
// GRID.

in vec3 v_positionRelativeToEye;
out vec4 fragmentColor;

uniform vec3 og_cameraEye;
uniform vec3 u_oneOverRadii;
uniform vec3 u_oneOverRadiiSquared;
uniform vec4 u_color; // without a day texture

#ifdef RAY_CAST
uniform mat4 og_projectionMatrix;
uniform mat4 og_modelViewMatrixRelativeToEye;
#endif
#if defined(LIGHTING) || defined(NIGHT_TEXTURE)
uniform vec3 og_sunDirection;
#endif
#ifdef DAY_TEXTURE
uniform sampler2D og_texture0;
#endif
#ifdef NIGHT_TEXTURE
uniform sampler2D og_texture1;
#endif
#ifdef GRID
uniform float u_gridSpacing;    // radians between lines
uniform vec4 u_gridColor;
#endif

// Longitude and latitude texture coordinates of a unit normal, and their screen derivatives.
// The u derivative is taken from whichever of u and u + 1/2 is continuous here, so the
// antimeridian shows no seam, and scaled by cos(latitude), the width a texel of an
// equirectangular image really covers, so the converging meridians do not blur the poles.
vec2 textureCoordinates(vec3 normal, out vec2 dx, out vec2 dy)
{
    vec2 uv = vec2(atan(normal.y, normal.x) * og_oneOverTwoPi + 0.5, asin(clamp(normal.z, -1.0, 1.0)) * og_oneOverPi + 0.5);
    float shifted = fract(uv.x + 0.5);
    dx = dFdx(uv);
    dy = dFdy(uv);
    float dxShifted = dFdx(shifted);
    float dyShifted = dFdy(shifted);
    if (abs(dxShifted) + abs(dyShifted) < abs(dx.x) + abs(dy.x)) {
        dx.x = dxShifted;
        dy.x = dyShifted;
    }
    float cosLatitude = sqrt(max(1.0 - normal.z * normal.z, 0.0));
    dx.x *= cosLatitude;
    dy.x *= cosLatitude;
    return uv;
}

vec3 shade(vec3 normal)
{
    vec2 dx;
    vec2 dy;
    vec2 uv = textureCoordinates(normal, dx, dy);
#ifdef DAY_TEXTURE
    vec3 color = textureGrad(og_texture0, uv, dx, dy).rgb;
#else
    vec3 color = u_color.rgb;
#endif
#if defined(LIGHTING) || defined(NIGHT_TEXTURE)
    float sunCosine = dot(normal, og_sunDirection);
#endif
#ifdef LIGHTING
    // In linear space, as models are lit: the texture and colour are sRGB-encoded.
    color = og_linearToSrgb(og_srgbToLinear(color) * (0.2 + 0.8 * max(sunCosine, 0.0)));
#endif
#ifdef NIGHT_TEXTURE
    // City lights where the Sun is down, blended across a band about 5 degrees wide at the terminator.
    vec3 night = textureGrad(og_texture1, uv, dx, dy).rgb;
    color = mix(night, color, smoothstep(-0.04, 0.04, sunCosine));
#endif
#ifdef GRID
    // Lines of constant pixel width: distance to the nearest line in units of the screen-space
    // derivative of the angle.
    vec2 angles = vec2(atan(normal.y, normal.x), asin(clamp(normal.z, -1.0, 1.0))) / u_gridSpacing;
    vec2 width = fwidth(angles);
    vec2 distanceToLine = abs(fract(angles - 0.5) - 0.5) / max(width, vec2(1e-6));
    float line = 1.0 - clamp(min(distanceToLine.x, distanceToLine.y) - 0.5, 0.0, 1.0);
    color = mix(color, u_gridColor.rgb, line * u_gridColor.a);
#endif
    return color;
}

void main()
{
#ifdef RAY_CAST
    vec3 direction = normalize(v_positionRelativeToEye);
    float t = rayCastEllipsoid(direction * u_oneOverRadii); // ray_cast_ellipsoid.glsl
    vec3 hitRelativeToEye = max(t, 0.0) * direction;
    vec3 normal = normalize((u_cameraScaled + max(t, 0.0) * direction * u_oneOverRadii) * u_oneOverRadii);
    vec4 clip = og_projectionMatrix * (og_modelViewMatrixRelativeToEye * vec4(hitRelativeToEye, 1.0));
    float depth = og_windowDepth(clip); // under the frame's depth strategy (built-in depth.glsl)
    vec3 color = shade(normal); // before discarding, so neighbours' derivatives stay defined
    // A miss, or a hit outside this frustum's depth range (multi-frustum draws the globe once per
    // frustum it spans), writes nothing.
    if (t < 0.0 || clip.w <= 0.0 || depth < 0.0 || depth > 1.0) {
        discard;
    }
    gl_FragDepth = depth;
    fragmentColor = vec4(color, 1.0);
#else
    og_depthFragment();
    vec3 normal = normalize((og_cameraEye + v_positionRelativeToEye) * u_oneOverRadiiSquared);
    fragmentColor = vec4(shade(normal), 1.0);
#endif
}
