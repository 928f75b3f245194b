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

// og_precise and og_keep: how a two-sum survives the compiler. A compiler may reassociate float
// arithmetic it is not told to keep, and (a - b) - a is -b to an algebraist: Mesa's does, which
// turns the two-sum's rounding error into 0 (measured in docs/precision.md). Three ways:
//   OG_PRECISE (with the extension GL_ARB_gpu_shader5 required: DeviceInfo::gpuShader5): GLSL's
//     `precise` on every step;
//   otherwise each intermediate is multiplied by og_opaqueOne, an automatic uniform that is 1.0 at
//     run time but unknown to the compiler, so nothing folds (the product by 1 is exact, and fused
//     into a multiply-add it still is);
//   OG_UNPROTECTED_TWO_SUM: neither, for measuring what the compiler does to the plain text.
#if defined(OG_PRECISE)
#define og_precise precise
#define og_keep(x) (x)
#elif defined(OG_UNPROTECTED_TWO_SUM)
#define og_precise
#define og_keep(x) (x)
#else
#define og_precise
uniform float og_opaqueOne;
#define og_keep(x) ((x) * og_opaqueOne)
#endif

// (aHigh + aLow) - (bHigh + bLow) with about twice float precision, for positions sent as two
// floats (VertexArrayOptions: "positionHigh", "positionLow") and the eye as og_cameraEyeHigh and
// og_cameraEyeLow: GPU relative-to-eye rendering after DSFUN90 (book section 5.4.2). The difference
// of the high parts is computed as a two-sum, whose rounding error is added back with the low parts.
// orbis::relativeToEye (core/EmulatedDouble.h) computes the same on the CPU, operation for operation,
// so the two agree bit for bit when the compiler keeps the order (tests/renderer).
vec3 og_emulatedDoubleSubtract(vec3 aHigh, vec3 aLow, vec3 bHigh, vec3 bLow)
{
    og_precise vec3 sum = og_keep(aHigh - bHigh);
    og_precise vec3 virtualB = og_keep(sum - aHigh);
    og_precise vec3 roundingError = og_keep(aHigh - og_keep(sum - virtualB)) - og_keep(bHigh + virtualB);
    og_precise vec3 result = sum + og_keep(og_keep(roundingError + aLow) - bLow);
    return result;
}

// The book's first GPU relative-to-eye difference (section 5.4, after Ohlarik): positions and eye
// split at multiples of 65536 m (orbis::splitAt65536; the eye as og_cameraEyeHigh65536 and
// og_cameraEyeLow65536). The highs' difference is exact; the lows carry 2^-8 m, so the result is
// good to millimetres whatever the distance. orbis::relativeToEyeSplitAt65536 on the CPU.
vec3 og_subtractSplitAt65536(vec3 aHigh, vec3 aLow, vec3 bHigh, vec3 bLow)
{
    og_precise vec3 result = (aHigh - bHigh) + (aLow - bLow);
    return result;
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


// The sRGB transfer function (IEC 61966-2-1) each way, per channel, on values clamped to 0..1:
// lighting is computed on linear values, textures and 8-bit framebuffers hold encoded ones.
vec3 og_srgbToLinear(vec3 c)
{
    c = clamp(c, 0.0, 1.0);
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(vec3(0.04045), c));
}

vec3 og_linearToSrgb(vec3 c)
{
    c = clamp(c, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}
