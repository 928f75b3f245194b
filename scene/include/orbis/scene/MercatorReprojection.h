#pragma once

#include <orbis/core/GeodeticExtent.h>

#include <memory>
#include <optional>

namespace orbis::renderer {
class Context;
class Framebuffer;
class Sampler;
class ShaderProgram;
class Texture2D;
class VertexArray;
class VertexBuffer;
} // namespace orbis::renderer

namespace orbis::scene {

/// Reprojects Web Mercator textures to rows linear in latitude on the GPU (Rendering Massive
/// Virtual Worlds, 3.7): a strip with a pair of vertices at each output row's centre, each
/// carrying the Mercator row coordinate of its latitude computed in doubles on the CPU
/// (mercatorReprojectionRows), so the GPU never subtracts two nearby Mercator values in float.
/// The columns map one to one.
///
/// ```
/// MercatorReprojection reprojection(context);
/// reprojection.reproject(mercatorTile, scheme.tileExtent(key), geographicTexture); // same extent
/// ```
class MercatorReprojection final {
public:
    explicit MercatorReprojection(renderer::Context& context);
    ~MercatorReprojection();
    MercatorReprojection(const MercatorReprojection&) = delete;
    MercatorReprojection& operator=(const MercatorReprojection&) = delete;

    /// Draws `source` (a Web Mercator tile over `extent`) into every texel of level 0 of `target`
    /// (any colour format, any size), whose rows run linearly in latitude over the same extent.
    /// Sampled linearly, clamped at the edges. Mipmaps of target are left to the caller.
    void reproject(const renderer::Texture2D& source, const GeodeticExtent& extent,
                   const std::shared_ptr<renderer::Texture2D>& target);

private:
    renderer::Context& _context;
    std::shared_ptr<renderer::ShaderProgram> _program;
    std::unique_ptr<renderer::Sampler> _sampler;
    std::unique_ptr<renderer::VertexBuffer> _strip;
    std::unique_ptr<renderer::VertexArray> _array;
    std::unique_ptr<renderer::Framebuffer> _target;
};

} // namespace orbis::scene
