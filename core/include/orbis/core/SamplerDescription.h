#pragma once

#include <cstdint>

namespace orbis {

// How an image is read between and beyond its texels, as plain values: a model file states it for
// its textures (the world layer reads it) and the renderer's Sampler applies it.

enum class TextureWrap : std::uint8_t { Clamp, Repeat, MirroredRepeat }; ///< Clamp: to the edge texel
enum class TextureMinificationFilter : std::uint8_t {
    Nearest, Linear, NearestMipmapNearest, LinearMipmapNearest, NearestMipmapLinear, LinearMipmapLinear
};
enum class TextureMagnificationFilter : std::uint8_t { Nearest, Linear };

struct SamplerDescription {
    TextureMinificationFilter minificationFilter = TextureMinificationFilter::Linear;
    TextureMagnificationFilter magnificationFilter = TextureMagnificationFilter::Linear;
    TextureWrap wrapS = TextureWrap::Clamp;
    TextureWrap wrapT = TextureWrap::Clamp;
    /// 1: none. Clamped to the device's maximum; ignored where anisotropic filtering is missing.
    float maximumAnisotropy = 1.0f;
};

} // namespace orbis
