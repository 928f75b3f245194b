// A tile of the globe's surface (course 3.5): positions relative to the tile's centre, drawn with
// the model-view-projection matrix the Context makes in doubles from the centre (book 5.2), so
// nothing jitters however close the eye comes.

in vec3 position;                 // metres from u_tileCentre
in vec3 textureCoordinatesHeight; // u and v within the tile (0..1 west to east, south to north), height

out vec2 v_tileCoordinates;
out vec3 v_normal; // geodetic surface normal, Earth-fixed

uniform mat4 og_modelViewProjectionMatrix;
uniform vec3 u_tileCentre;          // Earth-fixed, metres (float: its half-metre steps tilt a normal by 1e-7)
uniform vec3 u_oneOverRadiiSquared;

void main()
{
    v_tileCoordinates = textureCoordinatesHeight.xy;
    v_normal = normalize((u_tileCentre + position) * u_oneOverRadiiSquared);
    gl_Position = og_depthVertex(og_modelViewProjectionMatrix * vec4(position, 1.0));
}
