in vec4 position;
uniform mat4 og_modelViewProjectionMatrix;
void main() { gl_Position = og_modelViewProjectionMatrix * position; }
