#include "orbis/renderer/Framebuffer.h"

#include "ContextState.h"

#include "orbis/core/Error.h"
#include "orbis/renderer/Context.h"
#include "orbis/renderer/Device.h"

#include <algorithm>
#include <utility>

namespace orbis::renderer {

Framebuffer::Framebuffer(detail::ContextState& owner, unsigned name) noexcept
    : _owner(&owner), _name(name), _serial(detail::nextObjectSerial())
{
}

Framebuffer::~Framebuffer()
{
    if (_name && detail::currentState() == _owner) {
        _owner->gl.glDeleteFramebuffers.unchecked(1, &_name);
    }
}

Framebuffer::Framebuffer(Framebuffer&& other) noexcept
    : _owner(other._owner)
    , _name(std::exchange(other._name, 0u))
    , _serial(std::exchange(other._serial, 0u))
    , _colors(std::move(other._colors))
    , _depth(std::move(other._depth))
    , _dirty(other._dirty)
    , _width(other._width)
    , _height(other._height)
{
}

Framebuffer& Framebuffer::operator=(Framebuffer&& other) noexcept
{
    if (this != &other) {
        Framebuffer moved(std::move(other));
        std::swap(_owner, moved._owner);
        std::swap(_name, moved._name);
        std::swap(_serial, moved._serial);
        std::swap(_colors, moved._colors);
        std::swap(_depth, moved._depth);
        std::swap(_dirty, moved._dirty);
        std::swap(_width, moved._width);
        std::swap(_height, moved._height);
    }
    return *this;
}

void Framebuffer::setColorAttachment(int index, std::shared_ptr<Texture2D> texture)
{
    if (index < 0 || index >= kMaxColorAttachments) {
        throw Error("Framebuffer::setColorAttachment: index " + std::to_string(index) + " is outside 0.." +
                    std::to_string(kMaxColorAttachments - 1));
    }
    if (texture && isDepthFormat(texture->format())) {
        throw Error(std::string("Framebuffer::setColorAttachment: a ") + textureFormatName(texture->format()) +
                    " texture cannot be a colour attachment (use setDepthAttachment)");
    }
    if (texture && !texture->valid()) {
        throw Error("Framebuffer::setColorAttachment: empty texture");
    }
    _colors[index] = std::move(texture);
    _dirty = true;
    updateSize();
}

void Framebuffer::setDepthAttachment(std::shared_ptr<Texture2D> texture)
{
    if (texture && !isDepthFormat(texture->format())) {
        throw Error(std::string("Framebuffer::setDepthAttachment: a ") + textureFormatName(texture->format()) +
                    " texture cannot be a depth attachment (Depth24, Depth32F, Depth24Stencil8 or Depth32FStencil8 can)");
    }
    if (texture && !texture->valid()) {
        throw Error("Framebuffer::setDepthAttachment: empty texture");
    }
    _depth = std::move(texture);
    _dirty = true;
    updateSize();
}

const std::shared_ptr<Texture2D>& Framebuffer::colorAttachment(int index) const
{
    if (index < 0 || index >= kMaxColorAttachments) {
        throw Error("Framebuffer::colorAttachment: index " + std::to_string(index) + " is outside 0.." +
                    std::to_string(kMaxColorAttachments - 1));
    }
    return _colors[index];
}

void Framebuffer::updateSize() noexcept
{
    bool any = false;
    _width = 0;
    _height = 0;
    auto take = [&](const std::shared_ptr<Texture2D>& texture) {
        if (texture) {
            _width = any ? std::min(_width, texture->width()) : texture->width();
            _height = any ? std::min(_height, texture->height()) : texture->height();
            any = true;
        }
    };
    for (const auto& color : _colors) {
        take(color);
    }
    take(_depth);
}

Framebuffer Context::createFramebuffer()
{
    detail::ContextState& state = *_state;
    if (!state.isCurrent()) {
        throw Error("Context::createFramebuffer: the context is not current on this thread");
    }
    GLuint name = 0;
    state.gl.glGenFramebuffers(1, &name);
    return Framebuffer(state, name);
}

Framebuffer Context::createFramebuffer(int width, int height, const FramebufferOptions& options)
{
    Framebuffer framebuffer = createFramebuffer();
    Device& d = device();
    framebuffer.setColorAttachment(0, std::make_shared<Texture2D>(d.createTexture2D({width, height, options.colorFormat})));
    if (options.hasDepth) {
        framebuffer.setDepthAttachment(std::make_shared<Texture2D>(d.createTexture2D({width, height, options.depthFormat})));
    }
    return framebuffer;
}

} // namespace orbis::renderer
