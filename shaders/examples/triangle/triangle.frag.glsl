// One colour for the whole triangle, set by the application.
out vec4 fragmentColor;
uniform vec4 u_color;

void main()
{
    fragmentColor = u_color;
}
