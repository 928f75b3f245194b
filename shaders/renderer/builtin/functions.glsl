// Orbis built-in GLSL functions, after constants.glsl. They take what they need as arguments
// (often an og_ uniform the calling shader declares), so that a shader that does not call them
// pays nothing: the compiler drops unused functions.

// Window coordinates (pixels, depth in the depth range) of a model-space position; w keeps the
// clip-space w. Pass og_modelViewProjectionMatrix and og_viewportTransformationMatrix.
vec4 og_transformToWindowCoordinates(mat4 modelViewProjection, mat4 viewportTransformation, vec4 position)
{
    vec4 clip = modelViewProjection * position;
    vec4 window = viewportTransformation * vec4(clip.xyz / clip.w, 1.0);
    return vec4(window.xyz, clip.w);
}

// (aHigh + aLow) - (bHigh + bLow) with about twice float precision, for positions sent as two
// floats (VertexArrayOptions: "positionHigh", "positionLow") and the eye as og_cameraEyeHigh and
// og_cameraEyeLow: GPU relative-to-eye rendering. The difference of the high parts is computed as
// a two-sum, whose rounding error is added back with the low parts.
vec3 og_emulatedDoubleSubtract(vec3 aHigh, vec3 aLow, vec3 bHigh, vec3 bLow)
{
    vec3 sum = aHigh - bHigh;
    vec3 virtualB = sum - aHigh;
    vec3 roundingError = (aHigh - (sum - virtualB)) - (bHigh + virtualB);
    return sum + (roundingError + (aLow - bLow));
}

// Diffuse, specular and ambient light for unit vectors; the weights and the shininess exponent
// in diffuseSpecularAmbientShininess.
float og_lightIntensity(vec3 normal, vec3 toLight, vec3 toEye, vec4 diffuseSpecularAmbientShininess)
{
    vec3 reflected = reflect(-toLight, normal);
    float diffuse = max(dot(toLight, normal), 0.0);
    float specular = pow(max(dot(reflected, toEye), 0.0), diffuseSpecularAmbientShininess.w);
    return diffuseSpecularAmbientShininess.x * diffuse + diffuseSpecularAmbientShininess.y * specular +
           diffuseSpecularAmbientShininess.z;
}
