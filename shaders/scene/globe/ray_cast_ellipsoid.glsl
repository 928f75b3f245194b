// A ray from the eye against the ellipsoid (book section 4.3), shared by the globe drawn by ray
// casting (globe.frag.glsl) and the virtual texture's feedback pass (virtual_texture.frag.glsl),
// each of which puts this before its own source. Solved in the ellipsoid's radii's units, where it
// is a unit sphere: the eye there, and |eye|^2 - 1 there worked out in double on the CPU, the
// quadratic's constant term, which float would lose near the surface.

uniform vec3 u_cameraScaled;
uniform float u_cameraScaledLengthSquaredMinusOne;

// How far along a ray the visible surface is, in lengths of the ray's direction, or a negative
// number for a miss: the near root from outside, the exit from inside, each without cancellation.
// scaledDirection: the direction in the radii's units (divided by them).
float rayCastEllipsoid(vec3 scaledDirection)
{
    float a = dot(scaledDirection, scaledDirection);
    float b = dot(u_cameraScaled, scaledDirection);
    float c = u_cameraScaledLengthSquaredMinusOne;
    float discriminant = b * b - a * c;
    if (discriminant < 0.0 || (c > 0.0 && b >= 0.0)) {
        return -1.0;
    }
    float root = sqrt(discriminant);
    if (c > 0.0) {
        return c / (root - b);
    }
    return b <= 0.0 ? (root - b) / a : -c / (root + b);
}
