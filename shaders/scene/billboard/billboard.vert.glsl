// Billboards and label glyphs (book chapter 9), stage 1 of 3: the anchor relative to the eye on
// the GPU (positions come as two floats each), hidden below the ellipsoid's horizon, and the
// attributes unpacked for the geometry shader, which makes the quad. LABEL: glyphs with a halo.

// The attributes without a standard location get fixed ones, so that one vertex array serves the
// program of every depth strategy.
in vec3 positionHigh;
in vec3 positionLow;
layout(location = 6) in vec2 pixelOffset;          // pixels, x right, y down
layout(location = 7) in vec4 textureRectangle;     // atlas texels: x, y (rows from the top), width, height
in vec4 color;
layout(location = 8) in uint scaleOriginVisibility; // bits 0-15 scale x 256, 16-17 horizontal origin, 18-19 vertical, 20 visible
#ifdef LABEL
layout(location = 9) in vec4 haloColor;
#endif

uniform vec3 og_cameraEyeHigh;
uniform vec3 og_cameraEyeLow;
uniform mat4 og_modelViewProjectionMatrixRelativeToEye;
uniform vec3 u_oneOverRadii;
uniform vec3 u_eyeScaled;              // the eye in ellipsoid-scaled space
uniform float u_horizonDistanceSquared; // |eye scaled|^2 - 1, from doubles; negative: no horizon culling
uniform float u_depthScale;            // 1 - the depth offset fraction
uniform float u_disableDepthTestDistance; // metres: nearer anchors pass the depth test whatever it holds

out vec4 v_anchorClip;
out vec2 v_depthClip;                  // clip z and w of the quad's depth point
out float v_depthTestOff;              // 1: the anchor is not depth-tested
out vec2 v_pixelOffset;
out vec4 v_textureRectangle;
out vec3 v_scaleOrigin;                // scale, then the origin as a fraction of the size (0, 0.5, 1)
out float v_visible;
out vec4 v_color;
#ifdef LABEL
out vec4 v_haloColor;
#endif

void main()
{
    vec3 toAnchor = og_emulatedDoubleSubtract(positionHigh, positionLow, og_cameraEyeHigh, og_cameraEyeLow);
    bool visible = (scaleOriginVisibility & 0x100000u) != 0u;
    if (visible && u_horizonDistanceSquared > 0.0) {
        // Hidden when beyond the plane of the horizon and inside the cone tangent to the
        // ellipsoid (EllipsoidalOccluder's test, in scaled space, where it is the unit sphere).
        vec3 toAnchorScaled = toAnchor * u_oneOverRadii;
        float along = -dot(toAnchorScaled, u_eyeScaled);
        visible = !(along > u_horizonDistanceSquared &&
                    along * along > u_horizonDistanceSquared * dot(toAnchorScaled, toAnchorScaled));
    }
    v_anchorClip = og_modelViewProjectionMatrixRelativeToEye * vec4(toAnchor, 1.0);
    v_pixelOffset = pixelOffset;
    v_textureRectangle = textureRectangle;
    uint horizontal = (scaleOriginVisibility >> 16) & 3u;
    uint vertical = (scaleOriginVisibility >> 18) & 3u;
    v_scaleOrigin = vec3(float(scaleOriginVisibility & 0xFFFFu) / 256.0, 0.5 * float(horizontal), 0.5 * float(vertical));
    // Depth from a point on the same line of sight, a little nearer: the screen position stays.
    vec4 depthClip = og_modelViewProjectionMatrixRelativeToEye * vec4(toAnchor * u_depthScale, 1.0);
    v_depthClip = depthClip.zw;
    v_depthTestOff = dot(toAnchor, toAnchor) < u_disableDepthTestDistance * u_disableDepthTestDistance ? 1.0 : 0.0;
    v_visible = visible ? 1.0 : 0.0;
    v_color = color;
#ifdef LABEL
    v_haloColor = haloColor;
#endif
}
