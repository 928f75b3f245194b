// Web Mercator imagery reprojected to rows linear in latitude (course 3.7): a strip with a pair of
// vertices at each output row's centre (and at the edges), each carrying the exact Mercator row
// coordinate of its latitude computed in doubles on the CPU (mercatorReprojectionRows), so no
// float subtraction of nearby Mercator values is needed here.

in vec2 position;           // output texture coordinates, 0..1
in float textureCoordinate; // where that output row samples the Mercator tile, 0..1 south to north

out vec2 v_source;

void main()
{
    v_source = vec2(position.x, textureCoordinate);
    gl_Position = vec4(2.0 * position - 1.0, 0.0, 1.0);
}
