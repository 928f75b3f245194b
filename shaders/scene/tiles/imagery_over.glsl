// An imagery texel over a colour, shared by the tiles' imagery (tile.frag.glsl) and the virtual
// texture (virtual_texture.frag.glsl), each of which puts this before its own source.

// The texel adjusted (brightness, contrast, gamma) and blended over color by its alpha;
// adjustment: alpha, brightness, contrast, 1 / gamma. The adjustment is compiled in only with
// COLOR_ADJUSTMENT, for a globe with a layer that adjusts its colours: llvmpipe runs a branch's
// body for every pixel even where its condition is a uniform, and the pow per channel was a
// quarter of a tile's pixel. Among those layers, the ones left as they are skip it on a GPU.
vec3 imageryOver(vec3 color, vec4 texel, vec4 adjustment)
{
    vec3 adjusted = texel.rgb;
#ifdef COLOR_ADJUSTMENT
    if (any(notEqual(adjustment.yzw, vec3(1.0)))) {
        adjusted = mix(vec3(0.5), adjusted * adjustment.y, adjustment.z);
        adjusted = pow(max(adjusted, vec3(0.0)), vec3(adjustment.w));
    }
#endif
    return mix(color, adjusted, texel.a * adjustment.x);
}
