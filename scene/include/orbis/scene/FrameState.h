#pragma once

#include "orbis/scene/Camera.h"
#include "orbis/scene/DepthStrategy.h"
#include "orbis/scene/SceneCommand.h"

#include <orbis/core/Ellipsoid.h>
#include <orbis/core/EllipsoidalOccluder.h>
#include <orbis/core/Frustum.h>
#include <orbis/core/Geodetic.h>
#include <orbis/core/GeodeticExtent.h>
#include <orbis/core/Ray.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace orbis::renderer {
class Context;
class Device;
class Texture2D;
} // namespace orbis::renderer

namespace orbis::scene {

struct TileStatistics;
struct VirtualTextureStatistics;
struct ClipmapStatistics;
class Primitive;

/// Heights above the ellipsoid (metres), lowest <= highest.
struct HeightInterval {
    double lowest = 0.0;
    double highest = 0.0;
};

/// The smallest interval holding both; `b` alone when there is no `a`.
inline HeightInterval enclose(const std::optional<HeightInterval>& a, const HeightInterval& b) noexcept
{
    return a ? HeightInterval{std::min(a->lowest, b.lowest), std::max(a->highest, b.highest)} : b;
}

/// What a primitive sees of the frame it takes part in (docs/architecture.md, "One frame, as data").
struct FrameState {
    renderer::Context& context;
    renderer::Device& device;
    const Camera& camera;
    const Ellipsoid& ellipsoid;
    int width;
    int height;
    glm::dvec3 sunDirection; ///< unit, Earth-fixed, towards the Sun
    double clockSeconds;     ///< the shaders' clock (Scene::setClockSeconds), not the Sun's time
    std::uint64_t frameNumber;
    Frustum cullingVolume;   ///< the whole view: side planes and the near and far limits
    EllipsoidalOccluder occluder;
    /// How depth is resolved this frame (never Auto): programs take depthStrategyDefines() of it.
    DepthStrategy depthStrategy = DepthStrategy::MultiFrustum;
    /// What a translucent command with SceneCommand::readsSceneDepth reads (texelFetch, window
    /// pixels): the depth the opaque commands of the frustum being drawn wrote, in the frame's
    /// convention. Null when the frame's target has no depth texture to copy (a window's).
    const renderer::Texture2D* sceneDepth = nullptr;
    /// The primitives that draw the ground (Primitive::drawsGround) this frame, already updated:
    /// the scene updates them before the others, so that those can ask what ground they stand on.
    std::span<const Primitive* const> ground = {};

    /// Size in metres of one pixel at a distance from the eye (vertical field of view).
    double metersPerPixel(double distance) const noexcept;
    /// The heights of the ground drawn this frame over an extent: the union of the ground
    /// primitives' drawnHeights; empty where none draws any.
    std::optional<HeightInterval> groundHeights(const GeodeticExtent& extent) const;
};

/// The commands primitives append to during Scene::render.
using CommandList = std::vector<SceneCommand>;

/// Something drawn in a Scene. update() creates or refreshes its GPU resources lazily and appends
/// SceneCommands; a primitive with nothing to show appends nothing and allocates nothing.
class Primitive {
public:
    virtual ~Primitive() = default;

    /// The world bounding sphere of everything the primitive draws, when known. The scene skips
    /// update() for a primitive whose sphere is culled, so it creates no GPU resources.
    virtual std::optional<BoundingSphere> boundingSphere() const { return std::nullopt; }

    virtual void update(FrameState& frameState, CommandList& commands) = 0;

    /// Whether the primitive's shaders write logarithmic depth when frameState.depthStrategy asks
    /// (they call og_depthVertex and og_depthFragment of the built-in depth.glsl); every primitive
    /// of the scene layer does. Complementary depth needs little of a primitive (the projection and
    /// the Context carry it), logarithmic depth does: the scene will not pick it automatically for a
    /// frame with a primitive that answers false, and throws when it is asked for.
    virtual bool supportsLogarithmicDepth() const { return false; }

    /// The streamed tiles' figures of the last update, for primitives that stream tiles (a
    /// TiledGlobe); null for the others. Scene::render adds them up into FrameStatistics::tiles.
    virtual const TileStatistics* tileStatistics() const { return nullptr; }

    /// The virtual texture's figures of the last update, for primitives drawn with one (a
    /// VirtualTextureGlobe); null for the others. Scene::render reports them in
    /// FrameStatistics::virtualTexture.
    virtual const VirtualTextureStatistics* virtualTextureStatistics() const { return nullptr; }

    /// The clipmap's figures of the last update, for clipmap terrain; null for the others.
    /// Scene::render reports them in FrameStatistics::clipmap.
    virtual const ClipmapStatistics* clipmapStatistics() const { return nullptr; }

    /// For a primitive that is the ground (a TiledGlobe): the distance along the ray (unit
    /// direction) to the surface it drew in the last frame, where the ray first meets it; empty
    /// where it misses, and for every other primitive.
    virtual std::optional<double> pickGround(const Ray&) const { return std::nullopt; }
    /// For a primitive that is the ground: the height above the ellipsoid (metres, as drawn,
    /// exaggeration included) of the surface it drew in the last frame at a point; empty where it
    /// drew none, and for every other primitive.
    virtual std::optional<double> groundHeight(const Geodetic2D&) const { return std::nullopt; }
    /// True for a primitive that is the ground: the scene updates it before the others in each
    /// frame, so that they see this frame's drawnHeights (FrameState::groundHeights).
    virtual bool drawsGround() const { return false; }
    /// For a primitive that is the ground, once updated in this frame: the lowest and highest
    /// heights above the ellipsoid (metres, exaggeration included) of every point of the surface
    /// it draws over an extent, as drawn (its triangles are flat: their sag below their corners is
    /// in the lowest); empty where it draws nothing there, and for every other primitive.
    virtual std::optional<HeightInterval> drawnHeights(const GeodeticExtent&) const { return std::nullopt; }
};

} // namespace orbis::scene
