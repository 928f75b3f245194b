// The fill floor of the globe benchmark: a full-screen quad, given in clip coordinates.
in vec3 position;
out vec2 v_textureCoordinate;

void main()
{
    v_textureCoordinate = position.xy * 0.5 + 0.5;
    gl_Position = vec4(position.xy, 0.0, 1.0);
}
