#pragma once

#include <orbis/core/BoundingSphere.h>
#include <orbis/core/Mesh.h>
#include <orbis/renderer/IndexBuffer.h>
#include <orbis/renderer/VertexArray.h>
#include <orbis/renderer/VertexBuffer.h>

#include <glm/mat4x4.hpp>

#include <array>
#include <cstdint>
#include <optional>

namespace orbis::renderer {
class Context;
struct DeviceInfo;
struct ShaderProgramDescription;
} // namespace orbis::renderer

namespace orbis::scene {

struct FrameState;

/// How vertex positions reach the GPU (book chapter 5). Each concrete one is a define for the
/// built-in og_vertexTransformClip() and og_vertexTransformEye()
/// (shaders/renderer/builtin/vertex_transform.glsl), so any primitive's vertex shader can use them.
enum class VertexTransform : std::uint8_t {
    /// float(world position) through the float model-view-projection matrix: the naive baseline,
    /// off by the float spacing at Earth's radius (0.5 m) whatever the distance.
    RelativeToWorld,
    /// float(position - centre) with the centre in the model matrix (section 5.2): exact near the
    /// centre, off by 2^-24 of the object's size plus 2^-24 of the centre's distance.
    RelativeToCenter,
    /// float(position - eye), rewritten by the CPU and uploaded every frame the eye moves (5.3):
    /// 2^-24 of the distance; the CPU pass and upload cost grows with the vertex count.
    RelativeToEyeCpu,
    /// Positions split at multiples of 65536 m and subtracted on the GPU (5.4, after Ohlarik):
    /// the lows' 2^-8 m spacing, millimetres whatever the distance.
    RelativeToEyeGpu,
    /// Double-single positions and DSFUN90's two-sum on the GPU (5.4.2): 2^-24 of the distance,
    /// provided the compiler keeps the two-sum (`precise`, or og_opaqueOne: see functions.glsl).
    RelativeToEyeDsfun90,
    /// The book's level-of-detail switch (5.5): RelativeToCenter while its predicted error at the
    /// object's nearest point stays under a threshold in pixels, RelativeToEyeDsfun90 once the
    /// eye comes closer. Both arrays are uploaded once.
    Automatic,
};

/// The five concrete transforms, cheapest first.
inline constexpr std::array<VertexTransform, 5> kConcreteVertexTransforms = {
    VertexTransform::RelativeToWorld, VertexTransform::RelativeToCenter, VertexTransform::RelativeToEyeGpu,
    VertexTransform::RelativeToEyeDsfun90, VertexTransform::RelativeToEyeCpu};

/// "relative to world", "relative to centre", ..., "automatic".
const char* vertexTransformName(VertexTransform transform) noexcept;
/// The GLSL define that selects it ("OG_RELATIVE_TO_CENTER"); "" for Automatic.
const char* vertexTransformDefine(VertexTransform transform) noexcept;
/// Adds the transform's define to a program description and, for the GPU relative-to-eye
/// variants, what keeps their arithmetic as written: OG_PRECISE with GL_ARB_gpu_shader5 where the
/// device has it, og_opaqueOne otherwise. Automatic adds nothing (resolve it first).
void addVertexTransformDefines(VertexTransform transform, const renderer::DeviceInfo& device,
                               renderer::ShaderProgramDescription& description);

/// An upper estimate, in metres, of the position error a transform gives geometry inside `sphere`
/// seen from `eye`: the rounding of what it sends to float and of the float matrix product, per
/// section 5.1, with a factor 2 to spare. Measured errors (docs/precision.md) stay below it.
double predictedVertexErrorMeters(VertexTransform transform, const BoundingSphere& sphere,
                                  const glm::dvec3& eye) noexcept;

/// Automatic's choice for one frame: RelativeToCenter when its predicted error at the sphere's
/// nearest point (at least minimumDistance away) is under thresholdPixels, RelativeToEyeDsfun90
/// otherwise. A concrete transform is returned as it is.
VertexTransform resolveVertexTransform(VertexTransform requested, const BoundingSphere& sphere,
                                       const FrameState& frameState, double thresholdPixels = 0.5,
                                       double minimumDistance = 1.0) noexcept;

/// The vertex arrays of one mesh under the transforms a primitive may draw with: "position" (or
/// "positionHigh" and "positionLow") per transform, with the mesh's "normal" and indices shared.
/// Made on first use; primitives (MeshPrimitive) and precision measurements use it.
///
/// ```
/// VertexTransformArrays arrays(mesh, sphere.centre, VertexTransform::Automatic);
/// const VertexTransform now = resolveVertexTransform(VertexTransform::Automatic, sphere, frameState);
/// command.vertexArray = &arrays.get(frameState.context, now, frameState.camera.eye());
/// command.modelMatrix = arrays.modelMatrix(now);
/// ```
class VertexTransformArrays final {
public:
    /// `requested` says which arrays get() may be asked for: itself, or RelativeToCenter and
    /// RelativeToEyeDsfun90 for Automatic. The double positions are kept only for
    /// RelativeToEyeCpu, which rewrites them every frame; otherwise they are released once the
    /// arrays exist.
    VertexTransformArrays(Mesh mesh, const glm::dvec3& center, VertexTransform requested);
    ~VertexTransformArrays();
    VertexTransformArrays(const VertexTransformArrays&) = delete;
    VertexTransformArrays& operator=(const VertexTransformArrays&) = delete;

    /// The array for a concrete transform that `requested` covers (asserted). RelativeToEyeCpu
    /// rewrites its positions when the eye differs from the last call's.
    const renderer::VertexArray& get(renderer::Context& context, VertexTransform transform, const glm::dvec3& eye);
    /// The model matrix a command drawing with `transform` needs: a translation to the centre for
    /// RelativeToCenter, identity for the others (their positions are world or eye relative).
    glm::dmat4 modelMatrix(VertexTransform transform) const noexcept;
    const glm::dvec3& center() const noexcept { return _center; }
    /// Floats uploaded by RelativeToEyeCpu since construction (its per-frame cost).
    std::uint64_t floatsRewritten() const noexcept { return _floatsRewritten; }

private:
    struct Variant {
        renderer::VertexBuffer high; ///< "position", or "positionHigh"
        renderer::VertexBuffer low;  ///< "positionLow"
        std::optional<renderer::VertexArray> array;
    };
    void create(renderer::Context& context);
    bool covers(VertexTransform transform) const noexcept;

    Mesh _mesh;
    glm::dvec3 _center;
    VertexTransform _requested;
    bool _created = false;
    PrimitiveType _primitiveType = PrimitiveType::Triangles;
    renderer::VertexBuffer _normals;
    renderer::IndexBuffer _indices;
    bool _hasNormals = false;
    bool _indexed = false;
    std::array<Variant, 5> _variants; ///< by VertexTransform value
    std::vector<float> _scratch;
    std::optional<glm::dvec3> _lastEye;
    std::uint64_t _floatsRewritten = 0;
};

} // namespace orbis::scene
