// A filled polygon's colour, per vertex (one per polygon), from the vertex shader or, under
// per-vertex logarithmic depth, through polygon.geom.glsl.

#ifdef DEPTH_IN_GEOMETRY_SHADER
in vec4 g_color;
#else
in vec4 v_color;
#endif
#ifdef OG_DEPTH_OWNED_RANGE
in float v_eyeDepthBeforeOffset;
#endif
out vec4 fragmentColor;

void main()
{
#ifdef OG_DEPTH_OWNED_RANGE
    og_depthFragment(v_eyeDepthBeforeOffset); // the offset differs between frustums (vector.vert.glsl)
#else
    og_depthFragment();
#endif
#ifdef DEPTH_IN_GEOMETRY_SHADER
    fragmentColor = g_color;
#else
    fragmentColor = v_color;
#endif
}
