// Book chapter 5's vertex transforms, one chosen per program by a define (the scene layer's
// VertexTransform sets it):
//   OG_RELATIVE_TO_WORLD      float world positions through the float model-view-projection matrix
//                             (the naive baseline: metres of jitter at Earth scale)
//   OG_RELATIVE_TO_CENTER     float offsets from a centre the model matrix carries (section 5.2)
//   OG_RELATIVE_TO_EYE_CPU    float(position - eye), rewritten by the CPU every frame (section 5.3)
//   OG_RELATIVE_TO_EYE_GPU    positions split at multiples of 65536 m, subtracted on the GPU (5.4)
//   OG_RELATIVE_TO_EYE_DSFUN90 double-single positions, DSFUN90's two-sum on the GPU (5.4.2)
// In a vertex shader with one of them defined, this file declares the position attributes and the
// og_ uniforms they need, and
//   vec4 og_vertexTransformEye()   the vertex in eye coordinates
//   vec4 og_vertexTransformClip()  the vertex in clip coordinates
// Other shaders see nothing of it.

#if defined(OG_VERTEX_SHADER) && (defined(OG_RELATIVE_TO_WORLD) || defined(OG_RELATIVE_TO_CENTER) || \
    defined(OG_RELATIVE_TO_EYE_CPU) || defined(OG_RELATIVE_TO_EYE_GPU) || defined(OG_RELATIVE_TO_EYE_DSFUN90))

#if defined(OG_RELATIVE_TO_WORLD) || defined(OG_RELATIVE_TO_CENTER)
// The model matrix holds the centre (the origin for world positions); the model-view and
// model-view-projection products are formed in double on the CPU and sent as floats.
in vec3 position;
uniform mat4 og_modelViewMatrix;
uniform mat4 og_modelViewProjectionMatrix;

vec4 og_vertexTransformEye()
{
    return og_modelViewMatrix * vec4(position, 1.0);
}

vec4 og_vertexTransformClip()
{
    return og_modelViewProjectionMatrix * vec4(position, 1.0);
}

#else
uniform mat4 og_modelViewMatrixRelativeToEye;
uniform mat4 og_modelViewProjectionMatrixRelativeToEye;

#if defined(OG_RELATIVE_TO_EYE_CPU)
in vec3 position; // already relative to the eye

vec3 og_positionRelativeToEye()
{
    return position;
}
#elif defined(OG_RELATIVE_TO_EYE_GPU)
in vec3 positionHigh;
in vec3 positionLow;
uniform vec3 og_cameraEyeHigh65536;
uniform vec3 og_cameraEyeLow65536;

vec3 og_positionRelativeToEye()
{
    return og_subtractSplitAt65536(positionHigh, positionLow, og_cameraEyeHigh65536, og_cameraEyeLow65536);
}
#else
in vec3 positionHigh;
in vec3 positionLow;
uniform vec3 og_cameraEyeHigh;
uniform vec3 og_cameraEyeLow;

vec3 og_positionRelativeToEye()
{
    return og_emulatedDoubleSubtract(positionHigh, positionLow, og_cameraEyeHigh, og_cameraEyeLow);
}
#endif

vec4 og_vertexTransformEye()
{
    return og_modelViewMatrixRelativeToEye * vec4(og_positionRelativeToEye(), 1.0);
}

vec4 og_vertexTransformClip()
{
    return og_modelViewProjectionMatrixRelativeToEye * vec4(og_positionRelativeToEye(), 1.0);
}
#endif

#endif
