// A solid colour, optionally lit by the Sun (LIGHTING) in eye coordinates.

out vec4 fragmentColor;
uniform vec4 u_color;

#ifdef LIGHTING
in vec3 v_normal;
uniform vec3 og_sunDirectionEye;
#endif

void main()
{
#ifdef LIGHTING
    float diffuse = max(dot(normalize(v_normal), og_sunDirectionEye), 0.0);
    fragmentColor = vec4(u_color.rgb * (0.3 + 0.7 * diffuse), u_color.a);
#else
    fragmentColor = u_color;
#endif
}
