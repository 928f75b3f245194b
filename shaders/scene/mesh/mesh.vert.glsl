// A mesh under one of book chapter 5's vertex transforms: the built-in og_vertexTransformClip
// (shaders/renderer/builtin/vertex_transform.glsl) with the define MeshPrimitive's VertexTransform
// chooses, and the depth strategy's og_depthVertex.

#ifdef LIGHTING
in vec3 normal;
out vec3 v_normal;
uniform mat3 og_normalMatrix;
#endif

void main()
{
#ifdef LIGHTING
    v_normal = og_normalMatrix * normal;
#endif
    gl_Position = og_depthVertex(og_vertexTransformClip());
}
