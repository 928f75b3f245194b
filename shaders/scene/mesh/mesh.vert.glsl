// A mesh drawn relative to its centre (book section 5.2): positions are float offsets from a
// centre that the model matrix carries, so the model-view-projection product, formed in double
// on the CPU, keeps them precise near the eye.

in vec3 position;
#ifdef LIGHTING
in vec3 normal;
out vec3 v_normal;
uniform mat3 og_normalMatrix;
#endif

uniform mat4 og_modelViewProjectionMatrix;

void main()
{
#ifdef LIGHTING
    v_normal = og_normalMatrix * normal;
#endif
    gl_Position = og_modelViewProjectionMatrix * vec4(position, 1.0);
}
