// One mipmapped texture read per pixel: what any textured full-screen draw pays at least.
in vec2 v_textureCoordinate;
out vec4 fragmentColor;
uniform sampler2D og_texture0;

void main()
{
    fragmentColor = texture(og_texture0, v_textureCoordinate);
}
