// The first example of the book's chapter 3: one triangle. "position" is the mesh's position
// attribute (w = 1 is supplied), transformed by the automatic model-view-projection matrix.
in vec4 position;
uniform mat4 og_modelViewProjectionMatrix;

void main()
{
    gl_Position = og_modelViewProjectionMatrix * position;
}
