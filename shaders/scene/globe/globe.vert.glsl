// The globe's geometry, relative to the eye on the GPU (book section 5.4): a bounding box for
// ray casting (RAY_CAST) or a tessellated ellipsoid. Positions come as two floats each.

in vec3 positionHigh;
in vec3 positionLow;

out vec3 v_positionRelativeToEye;

uniform vec3 og_cameraEyeHigh;
uniform vec3 og_cameraEyeLow;
uniform mat4 og_modelViewProjectionMatrixRelativeToEye;

void main()
{
    vec3 position = og_emulatedDoubleSubtract(positionHigh, positionLow, og_cameraEyeHigh, og_cameraEyeLow);
    v_positionRelativeToEye = position;
    gl_Position = og_modelViewProjectionMatrixRelativeToEye * vec4(position, 1.0);
#ifdef RAY_CAST
    // The fragment shader writes the depth of the hit, so the box's own depth does not matter:
    // keeping it mid-range stops the near and far planes from clipping the box away.
    gl_Position.z = 0.0;
#endif
}
