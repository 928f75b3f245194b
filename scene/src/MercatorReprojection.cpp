#include "orbis/scene/MercatorReprojection.h"

#include "orbis/scene/ImageryCoverage.h"

#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>
#include <orbis/renderer/Framebuffer.h>
#include <orbis/renderer/Sampler.h>
#include <orbis/renderer/ShaderCache.h>
#include <orbis/renderer/ShaderProgram.h>
#include <orbis/renderer/Texture2D.h>
#include <orbis/renderer/VertexArray.h>
#include <orbis/renderer/VertexBuffer.h>

#include <span>
#include <vector>

namespace orbis::scene {

MercatorReprojection::MercatorReprojection(renderer::Context& context) : _context(context)
{
    renderer::Device& device = context.device();
    renderer::ShaderProgramDescription description;
    description.name = "Web Mercator reprojection";
    description.vertex = renderer::ShaderSource::embedded("scene/tiles/reproject_mercator.vert.glsl");
    description.fragment = renderer::ShaderSource::embedded("scene/tiles/reproject_mercator.frag.glsl");
    _program = device.shaderCache().get(description);
    _sampler = std::make_unique<renderer::Sampler>(device.createSampler(SamplerDescription{}));
    _target = std::make_unique<renderer::Framebuffer>(context.createFramebuffer());
}

MercatorReprojection::~MercatorReprojection() = default;

void MercatorReprojection::reproject(const renderer::Texture2D& source, const GeodeticExtent& extent,
                                     const std::shared_ptr<renderer::Texture2D>& target)
{
    const std::vector<glm::dvec2> rows = mercatorReprojectionRows(extent, target->height());
    std::vector<float> strip;
    strip.reserve(rows.size() * 6);
    for (const glm::dvec2& row : rows) {
        const float y = static_cast<float>(row.x);
        const float v = static_cast<float>(row.y);
        strip.insert(strip.end(), {0.0f, y, v, 1.0f, y, v});
    }
    const std::span<const std::byte> bytes = std::as_bytes(std::span(strip));
    if (!_strip || _strip->sizeInBytes() < bytes.size()) {
        renderer::Device& device = _context.device();
        _strip = std::make_unique<renderer::VertexBuffer>(
            device.createVertexBuffer(bytes.size(), renderer::BufferUsage::DynamicDraw));
        _array = std::make_unique<renderer::VertexArray>(_context.createVertexArray());
        using renderer::ComponentType;
        constexpr std::size_t stride = 3 * sizeof(float);
        _array->setAttribute(renderer::VertexAttributeLocation::Position, *_strip,
                             {ComponentType::Float, 2, false, false, stride, 0});
        _array->setAttribute(renderer::VertexAttributeLocation::TextureCoordinate, *_strip,
                             {ComponentType::Float, 1, false, false, stride, 2 * sizeof(float)});
    }
    _strip->copyFromSystemMemory(bytes);

    _target->setColorAttachment(0, target);
    renderer::DrawCommand command;
    command.debugName = "Web Mercator reprojection";
    command.vertexArray = _array.get();
    command.primitiveType = PrimitiveType::TriangleStrip;
    command.count = rows.size() * 2;
    command.shaderProgram = _program.get();
    command.framebuffer = _target.get();
    command.renderState.depthTest.enabled = false;
    command.renderState.depthMask = false;
    command.renderState.facetCulling.enabled = false;
    command.textures.push_back({0, &source, _sampler.get()});
    _context.draw(command);
    _target->setColorAttachment(0, nullptr);
}

} // namespace orbis::scene
