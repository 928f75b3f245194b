// A filled polygon's colour, per vertex (one per polygon).

in vec4 v_color;
out vec4 fragmentColor;

void main()
{
    fragmentColor = v_color;
}
