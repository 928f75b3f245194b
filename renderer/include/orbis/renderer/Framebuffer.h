#pragma once

#include "orbis/renderer/Texture2D.h"

#include <array>
#include <cstdint>
#include <memory>

namespace orbis::renderer {

namespace detail {
class ContextState;
}

/// Colour attachments and a depth (or depth-stencil) attachment to render into: one GL framebuffer
/// object, move-only. It belongs to the Context that created it (GL does not share framebuffers).
/// Attachments are textures, shared with whoever samples them later. Completeness is checked when
/// the framebuffer is first used after a change; an incomplete one throws orbis::Error saying why.
///
/// ```
/// Framebuffer target = context.createFramebuffer(256, 256); // RGBA8 colour, depth-stencil
/// context.setFramebuffer(&target);
/// ```
class Framebuffer final {
public:
    static constexpr int kMaxColorAttachments = 8;

    Framebuffer() noexcept = default;
    ~Framebuffer();
    Framebuffer(Framebuffer&& other) noexcept;
    Framebuffer& operator=(Framebuffer&& other) noexcept;
    Framebuffer(const Framebuffer&) = delete;
    Framebuffer& operator=(const Framebuffer&) = delete;

    /// Attaches a colour texture at index 0..7 (null detaches). Throws orbis::Error for a depth
    /// format or an index out of range.
    void setColorAttachment(int index, std::shared_ptr<Texture2D> texture);
    /// Attaches a Depth24, Depth32F, Depth24Stencil8 or Depth32FStencil8 texture (null detaches). Throws for colour
    /// formats.
    void setDepthAttachment(std::shared_ptr<Texture2D> texture);

    const std::shared_ptr<Texture2D>& colorAttachment(int index) const;
    const std::shared_ptr<Texture2D>& depthAttachment() const noexcept { return _depth; }
    /// The size drawn into: the smallest over the attachments; 0 x 0 without attachments.
    int width() const noexcept { return _width; }
    int height() const noexcept { return _height; }
    bool valid() const noexcept { return _name != 0; }

private:
    friend class Context;
    Framebuffer(detail::ContextState& owner, unsigned name) noexcept;
    void updateSize() noexcept;

    detail::ContextState* _owner = nullptr;
    unsigned _name = 0;
    std::uint64_t _serial = 0;
    std::array<std::shared_ptr<Texture2D>, kMaxColorAttachments> _colors;
    std::shared_ptr<Texture2D> _depth;
    bool _dirty = true;
    int _width = 0;
    int _height = 0;
};

} // namespace orbis::renderer
