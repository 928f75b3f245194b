// Samples the Mercator tile where the strip's vertices say; the columns map one to one.

in vec2 v_source;
out vec4 fragmentColor;

uniform sampler2D og_texture0; // the Mercator tile

void main()
{
    fragmentColor = texture(og_texture0, v_source);
}
