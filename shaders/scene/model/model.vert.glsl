// A glTF model drawn relative to its origin (book section 5.2): positions are float offsets in the
// model's own frame (metres, glTF axes); the model matrix, in double on the CPU, carries the
// placement, the scale and the Earth-scale translation into og_modelViewProjectionMatrix. The frame's
// depth strategy: og_depthVertex here, og_depthFragment in model.frag.glsl.

in vec3 position;
#ifdef LIGHTING
in vec3 normal;
out vec3 v_normalEye;
uniform mat3 og_normalMatrix;
#endif
#ifdef BASE_COLOR_TEXTURE
in vec2 textureCoordinate;
out vec2 v_textureCoordinate;
#endif

uniform mat4 og_modelViewProjectionMatrix;

void main()
{
#ifdef LIGHTING
    v_normalEye = og_normalMatrix * normal;
#endif
#ifdef BASE_COLOR_TEXTURE
    v_textureCoordinate = textureCoordinate;
#endif
    gl_Position = og_depthVertex(og_modelViewProjectionMatrix * vec4(position, 1.0));
}
