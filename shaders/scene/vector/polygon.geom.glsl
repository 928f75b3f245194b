// Filled polygons under per-vertex logarithmic depth (OG_DEPTH_LOGARITHMIC_VERTEX; VectorBatch adds
// this stage for it alone): each triangle passes through with og_depthPrimitiveVertex applied to
// its corners, so that the depth interpolated between their logarithms nowhere lies behind the
// triangle's true depth and the depth offset of vector.vert.glsl keeps it in front of the globe
// across the whole triangle (a degree-wide triangle seen at a slant would otherwise sink
// kilometres into it between its corners).

layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

in vec4 v_color[];
out vec4 g_color;

void main()
{
    float w0 = gl_in[0].gl_Position.w;
    float w1 = gl_in[1].gl_Position.w;
    float w2 = gl_in[2].gl_Position.w;
    vec2 wRange = vec2(min(w0, min(w1, w2)), max(w0, max(w1, w2)));
    for (int i = 0; i < 3; ++i) {
        gl_Position = og_depthPrimitiveVertex(gl_in[i].gl_Position, wRange);
        g_color = v_color[i];
        EmitVertex();
    }
    EndPrimitive();
}
