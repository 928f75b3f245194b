// Samples the Mercator tile where the strip's vertices say; the columns map one to one.

in vec2 v_source;
out vec4 fragmentColor;

uniform sampler2D u_source;

void main()
{
    fragmentColor = texture(u_source, v_source);
}
