// The feedback pass as one rectangle around the globe's outline on the screen (or the whole
// view): each pixel casts its own ray at the ellipsoid (virtual_texture.frag.glsl, VT_FEEDBACK),
// so the pass costs its pixels, not the surface's triangles. The ray's direction is linear across
// the screen (w is 1 everywhere), so interpolating it is exact.

in vec3 position; // the rectangle's corner: 0 or 1 in x and y

out vec3 v_ray; // Earth-fixed, not normalized: the view's axis plus the pixel's offsets

uniform vec4 u_bounds;    // the rectangle in clip coordinates: x and y of its lower left, upper right
uniform vec3 u_rayCentre; // the view's axis, unit length
uniform vec3 u_rayRight;  // the ray's change from the view's centre to its right edge
uniform vec3 u_rayUp;     // and to its top edge

void main()
{
    vec2 clip = mix(u_bounds.xy, u_bounds.zw, position.xy);
    v_ray = u_rayCentre + clip.x * u_rayRight + clip.y * u_rayUp;
    gl_Position = vec4(clip, 0.0, 1.0);
}
