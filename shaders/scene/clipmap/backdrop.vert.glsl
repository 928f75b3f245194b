// The globe beyond clipmap terrain's coarsest level: a coarse geodetic grid, Earth-fixed floats
// (it lies at least 48 degrees from the viewer, thousands of kilometres away, where a float's
// half metre is far below a pixel).

in vec3 position;          // Earth-fixed, metres
in vec3 textureCoordinate; // u, v in the equirectangular colour texture; the height (exaggeration out)

out vec3 v_position;
out vec2 v_texel;
out float v_height;

uniform mat4 og_modelViewProjectionMatrix;

void main()
{
    v_position = position;
    v_texel = textureCoordinate.xy;
    v_height = textureCoordinate.z;
    gl_Position = og_depthVertex(og_modelViewProjectionMatrix * vec4(position, 1.0));
}
