#include "orbis/scene/VertexTransform.h"

#include "orbis/scene/FrameState.h"

#include <orbis/core/EmulatedDouble.h>
#include <orbis/renderer/Context.h>
#include <orbis/renderer/Device.h>

#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace orbis::scene {

namespace {

/// Float's unit roundoff: half the spacing at 1.
constexpr double kUnitRoundoff = 5.9604644775390625e-8; // 2^-24

int indexOf(VertexTransform transform) noexcept
{
    return static_cast<int>(transform);
}

std::span<const std::byte> bytesOf(const std::vector<float>& floats) noexcept
{
    return std::as_bytes(std::span(floats));
}

} // namespace

const char* vertexTransformName(VertexTransform transform) noexcept
{
    switch (transform) {
    case VertexTransform::RelativeToWorld: return "relative to world";
    case VertexTransform::RelativeToCenter: return "relative to centre";
    case VertexTransform::RelativeToEyeCpu: return "relative to eye, CPU";
    case VertexTransform::RelativeToEyeGpu: return "relative to eye, GPU (split at 65536 m)";
    case VertexTransform::RelativeToEyeDsfun90: return "relative to eye, GPU (DSFUN90)";
    case VertexTransform::Automatic: return "automatic (centre, then DSFUN90 near)";
    }
    return "?";
}

const char* vertexTransformDefine(VertexTransform transform) noexcept
{
    switch (transform) {
    case VertexTransform::RelativeToWorld: return "OG_RELATIVE_TO_WORLD";
    case VertexTransform::RelativeToCenter: return "OG_RELATIVE_TO_CENTER";
    case VertexTransform::RelativeToEyeCpu: return "OG_RELATIVE_TO_EYE_CPU";
    case VertexTransform::RelativeToEyeGpu: return "OG_RELATIVE_TO_EYE_GPU";
    case VertexTransform::RelativeToEyeDsfun90: return "OG_RELATIVE_TO_EYE_DSFUN90";
    case VertexTransform::Automatic: break;
    }
    return "";
}

void addVertexTransformDefines(VertexTransform transform, const renderer::DeviceInfo& device,
                               renderer::ShaderProgramDescription& description)
{
    if (transform == VertexTransform::Automatic) {
        return;
    }
    description.defines.push_back({vertexTransformDefine(transform)});
    const bool gpuSubtraction =
        transform == VertexTransform::RelativeToEyeGpu || transform == VertexTransform::RelativeToEyeDsfun90;
    if (gpuSubtraction && device.gpuShader5) {
        description.defines.push_back({"OG_PRECISE"});
        description.extensions.push_back("GL_ARB_gpu_shader5");
    }
}

double predictedVertexErrorMeters(VertexTransform transform, const BoundingSphere& sphere,
                                  const glm::dvec3& eye) noexcept
{
    // Each float rounding costs up to 2^-24 of the magnitude rounded; a matrix-vector product
    // in float sums terms as large as its inputs, so its error follows the largest of them.
    // Three coordinates and a factor 2 to spare: 2 sqrt(3) ~ 3.5.
    constexpr double margin = 3.5;
    const double centreDistance = glm::length(sphere.centre - eye);
    const double farthest = centreDistance + sphere.radius;
    const double fromOrigin = glm::length(sphere.centre) + sphere.radius;
    switch (transform) {
    case VertexTransform::RelativeToWorld:
        // float(position), then a product whose terms reach |position| and |eye|.
        return margin * kUnitRoundoff * (2.0 * fromOrigin + glm::length(eye));
    case VertexTransform::RelativeToCenter:
        // float(position - centre), then a product whose translation is the centre's distance.
        return margin * kUnitRoundoff * (2.0 * sphere.radius + centreDistance);
    case VertexTransform::RelativeToEyeCpu:
    case VertexTransform::RelativeToEyeDsfun90:
        return margin * kUnitRoundoff * 2.0 * farthest;
    case VertexTransform::RelativeToEyeGpu:
        // The lows' spacing, 2^-8 m near 65536, half of it each for position and eye.
        return margin * (std::ldexp(1.0, -8) + kUnitRoundoff * 2.0 * farthest);
    case VertexTransform::Automatic: break;
    }
    return std::numeric_limits<double>::infinity();
}

VertexTransform resolveVertexTransform(VertexTransform requested, const BoundingSphere& sphere,
                                       const FrameState& frameState, double thresholdPixels,
                                       double minimumDistance) noexcept
{
    if (requested != VertexTransform::Automatic) {
        return requested;
    }
    const glm::dvec3& eye = frameState.camera.eye();
    const double nearest = std::max(sphere.distanceTo(eye), minimumDistance);
    const double pixels = predictedVertexErrorMeters(VertexTransform::RelativeToCenter, sphere, eye) /
                          frameState.metersPerPixel(nearest);
    return pixels <= thresholdPixels ? VertexTransform::RelativeToCenter : VertexTransform::RelativeToEyeDsfun90;
}

VertexTransformArrays::VertexTransformArrays(Mesh mesh, const glm::dvec3& center, VertexTransform requested)
    : _mesh(std::move(mesh))
    , _center(center)
    , _requested(requested)
{
}

VertexTransformArrays::~VertexTransformArrays() = default;

bool VertexTransformArrays::covers(VertexTransform transform) const noexcept
{
    if (_requested == VertexTransform::Automatic) {
        return transform == VertexTransform::RelativeToCenter || transform == VertexTransform::RelativeToEyeDsfun90;
    }
    return transform == _requested;
}

void VertexTransformArrays::create(renderer::Context& context)
{
    renderer::Device& device = context.device();
    _primitiveType = _mesh.primitiveType;
    _hasNormals = !_mesh.normals.empty();
    if (_hasNormals) {
        _normals = device.createVertexBuffer(std::as_bytes(std::span(_mesh.normals)));
    }
    _indexed = !_mesh.indices.empty();
    if (_indexed) {
        const bool small = std::all_of(_mesh.indices.begin(), _mesh.indices.end(),
                                       [](std::uint32_t i) { return i < 0xFFFFu; });
        if (small) {
            std::vector<std::uint16_t> indices(_mesh.indices.begin(), _mesh.indices.end());
            _indices = device.createIndexBuffer(std::span<const std::uint16_t>(indices));
        } else {
            _indices = device.createIndexBuffer(std::span<const std::uint32_t>(_mesh.indices));
        }
    }
    const std::size_t n = _mesh.positions.size();
    for (const VertexTransform transform : kConcreteVertexTransforms) {
        if (!covers(transform)) {
            continue;
        }
        Variant& variant = _variants[indexOf(transform)];
        const bool split =
            transform == VertexTransform::RelativeToEyeGpu || transform == VertexTransform::RelativeToEyeDsfun90;
        std::vector<float> high(3 * n);
        std::vector<float> low(split ? 3 * n : 0);
        switch (transform) {
        case VertexTransform::RelativeToWorld:
        case VertexTransform::RelativeToCenter: {
            const glm::dvec3 origin = transform == VertexTransform::RelativeToCenter ? _center : glm::dvec3(0.0);
            for (std::size_t i = 0; i < n; ++i) {
                const glm::vec3 p(_mesh.positions[i] - origin);
                high[3 * i] = p.x;
                high[3 * i + 1] = p.y;
                high[3 * i + 2] = p.z;
            }
            break;
        }
        case VertexTransform::RelativeToEyeCpu: break; // written by get(), relative to the eye
        case VertexTransform::RelativeToEyeGpu:
        case VertexTransform::RelativeToEyeDsfun90: {
            for (std::size_t i = 0; i < n; ++i) {
                const EmulatedDVec3 p = transform == VertexTransform::RelativeToEyeGpu
                                            ? splitAt65536(_mesh.positions[i])
                                            : EmulatedDVec3::fromDVec3(_mesh.positions[i]);
                for (int k = 0; k < 3; ++k) {
                    high[3 * i + k] = p.high[k];
                    low[3 * i + k] = p.low[k];
                }
            }
            break;
        }
        case VertexTransform::Automatic: break;
        }
        const renderer::BufferUsage usage =
            transform == VertexTransform::RelativeToEyeCpu ? renderer::BufferUsage::StreamDraw : renderer::BufferUsage::StaticDraw;
        variant.high = device.createVertexBuffer(bytesOf(high), usage);
        renderer::VertexArray array = context.createVertexArray();
        const renderer::VertexAttributeFormat vec3{renderer::ComponentType::Float, 3};
        if (low.empty()) {
            array.setAttribute("position", variant.high, vec3);
        } else {
            variant.low = device.createVertexBuffer(bytesOf(low));
            array.setAttribute("positionHigh", variant.high, vec3);
            array.setAttribute("positionLow", variant.low, vec3);
        }
        if (_hasNormals) {
            array.setAttribute("normal", _normals, vec3);
        }
        if (_indexed) {
            array.setIndexBuffer(&_indices);
        }
        variant.array = std::move(array);
    }
    _created = true;
    if (_requested != VertexTransform::RelativeToEyeCpu) {
        _mesh = Mesh(); // on the GPU now
    } else {
        _mesh.normals.clear();
        _mesh.normals.shrink_to_fit();
        _mesh.indices.clear();
        _mesh.indices.shrink_to_fit();
    }
}

const renderer::VertexArray& VertexTransformArrays::get(renderer::Context& context, VertexTransform transform, const glm::dvec3& eye)
{
    assert(covers(transform) && transform != VertexTransform::Automatic);
    if (!_created) {
        create(context);
    }
    Variant& variant = _variants[indexOf(transform)];
    if (transform == VertexTransform::RelativeToEyeCpu && _lastEye != eye) {
        // Book section 5.3: the subtraction in double, once per vertex per frame the eye moves.
        const std::size_t n = _mesh.positions.size();
        _scratch.resize(3 * n);
        for (std::size_t i = 0; i < n; ++i) {
            const glm::vec3 p(_mesh.positions[i] - eye);
            _scratch[3 * i] = p.x;
            _scratch[3 * i + 1] = p.y;
            _scratch[3 * i + 2] = p.z;
        }
        variant.high.copyFromSystemMemory(bytesOf(_scratch));
        _floatsRewritten += _scratch.size();
        _lastEye = eye;
    }
    return *variant.array;
}

glm::dmat4 VertexTransformArrays::modelMatrix(VertexTransform transform) const noexcept
{
    return transform == VertexTransform::RelativeToCenter ? glm::translate(glm::dmat4(1.0), _center) : glm::dmat4(1.0);
}

} // namespace orbis::scene
