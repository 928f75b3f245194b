out vec4 fragmentColor;
uniform vec4 u_color;
void main() { fragmentColor = u_color; }
