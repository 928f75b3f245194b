#pragma once

#include <orbis/core/BoundingRegion.h>
#include <orbis/core/Ellipsoid.h>
#include <orbis/core/EllipsoidalOccluder.h>
#include <orbis/core/Frustum.h>
#include <orbis/core/TileKey.h>
#include <orbis/core/TileMesh.h>
#include <orbis/core/TilingScheme.h>

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <unordered_set>
#include <vector>

namespace orbis::scene {

/// What the owner of a quadtree keeps per tile (meshes, textures); the quadtree only owns it.
class TileData {
public:
    virtual ~TileData() = default;
};

/// One tile of the globe's surface quadtree. The owner sets `renderable`, `refinable` and
/// `wantsLoad` from its data before each selection; the quadtree sets the rest.
struct QuadtreeTile {
    TileKey key;
    QuadtreeTile* parent = nullptr;
    std::array<std::unique_ptr<QuadtreeTile>, 4> children; ///< made on the first refinement
    BoundingRegion region;
    double geometricError = 0.0; ///< metres
    /// Whether it can be drawn this frame (its mesh and imagery are on the GPU).
    bool renderable = false;
    /// Whether finer tiles below it may exist (false where the data ends).
    bool refinable = true;
    /// Whether it has data of its own still to load (false once everything is loaded, missing or
    /// failed). A tile drawn at the level the view asks for keeps asking while this is true (for
    /// its own imagery while it shows an ancestor's, say).
    bool wantsLoad = true;
    std::uint64_t lastVisitedFrame = 0;
    std::unique_ptr<TileData> data;

    QuadtreeTile(const TileKey& key_, QuadtreeTile* parent_, const BoundingRegion& region_, double geometricError_)
        : key(key_), parent(parent_), region(region_), geometricError(geometricError_)
    {
    }
    bool hasChildren() const noexcept { return children[0] != nullptr; }
};

/// The view as tile selection sees it.
struct TileView {
    glm::dvec3 eye{0.0};
    glm::dvec3 direction{0.0, 0.0, -1.0}; ///< unit
    Frustum frustum;
    double viewportHeightPixels = 720.0;
    double fieldOfViewY = 0.7853981633974483; ///< radians
};

struct TileSelectionOptions {
    /// Refine while a tile's screen-space error exceeds this many pixels.
    double maximumScreenSpaceError = 2.0;
    /// Tiles at this level are never refined.
    std::uint32_t maximumLevel = kMaximumTileLevel;
    /// How many loads one drawn tile's descendants may ask for in a frame (CesiumJS's
    /// loadingDescendantLimit): after a jump the nearest ones are asked for first instead of
    /// thousands at once.
    std::size_t loadingDescendantLimit = 20;
};

/// A tile the selection wants loaded, and how soon: smaller first.
struct TileLoadCandidate {
    QuadtreeTile* tile;
    double priority;
};

/// What one selection found.
struct TileSelection {
    std::vector<QuadtreeTile*> drawn;             ///< near to far, no two overlapping
    std::vector<double> drawnScreenSpaceErrors;   ///< parallel to drawn
    std::vector<TileLoadCandidate> loads;         ///< tiles to load, unsorted
    std::size_t visited = 0;
    std::size_t culledByFrustum = 0;
    std::size_t culledByHorizon = 0;
    std::size_t selected = 0;   ///< visible tiles at the level the error asks for, drawn or not
    std::size_t standIns = 0;   ///< drawn tiles that stand in for finer ones not yet loaded
};

/// The globe's surface as a quadtree of tiles (chunked LOD; book 12 and 14, course 3.3): each
/// frame a traversal from the roots culls tiles against the frustum and the horizon, refines
/// while the screen-space error exceeds the limit, nearest children first, and draws a tile in
/// place of its children until all four can be drawn, so that the surface never has a hole.
class TileQuadtree final {
public:
    /// Called for each tile as it is made (the roots at construction, children on the first
    /// refinement), for the owner to attach its data and set the tile's flags.
    using TileCreated = std::function<void(QuadtreeTile&)>;

    /// samplesAcross: the grid size the geometric error of a level is taken for (see
    /// TilingScheme::geometricError); 64 makes it equal to a 256-pixel geographic imagery texel.
    TileQuadtree(const Ellipsoid& ellipsoid, const TilingScheme& scheme, int samplesAcross = 64,
                 TileCreated onCreated = {});

    const Ellipsoid& ellipsoid() const noexcept { return _ellipsoid; }
    const TilingScheme& scheme() const noexcept { return _scheme; }
    std::vector<std::unique_ptr<QuadtreeTile>>& roots() noexcept { return _roots; }
    const std::vector<std::unique_ptr<QuadtreeTile>>& roots() const noexcept { return _roots; }

    /// Called for each tile as the traversal reaches it, before its flags are read: the owner
    /// brings them up to date with its data.
    using TileVisited = std::function<void(QuadtreeTile&)>;

    /// Selects the tiles to draw for the view; frameNumber marks the visited tiles.
    void select(const TileView& view, const TileSelectionOptions& options, std::uint64_t frameNumber,
                TileSelection& selection, const TileVisited& refresh = {});

    /// A new tile's region, between heights the owner expects (its parent's, until it loads).
    BoundingRegion regionOf(const TileKey& key, double minimumHeight, double maximumHeight) const noexcept;
    double geometricErrorOf(std::uint32_t level) const noexcept;

    /// The screen-space error of a tile in pixels for a view.
    static double screenSpaceError(const QuadtreeTile& tile, const TileView& view) noexcept;

private:
    enum class Coverage { Culled, Covered, Uncovered };
    /// What one selection's traversal carries: the view and what follows from it.
    struct Traversal {
        const TileView& view;
        const TileSelectionOptions& options;
        std::uint64_t frameNumber;
        TileSelection& selection;
        const TileVisited& refresh;
        double errorPerMeter; ///< viewport height / (2 tan(fov / 2)): pixels per metre at unit distance
    };
    /// distance: from the eye to the tile's box, computed by the caller (which sorts by it).
    Coverage visit(QuadtreeTile& tile, double distance, Traversal& traversal);
    void createChildren(QuadtreeTile& tile);
    double loadPriority(const QuadtreeTile& tile, const TileView& view, double distance) const noexcept;

    Ellipsoid _ellipsoid;
    TilingScheme _scheme;
    int _samplesAcross;
    TileCreated _onCreated;
    EllipsoidalOccluder _occluder;
    std::vector<std::unique_ptr<QuadtreeTile>> _roots;
};

/// The drawn tiles' keys, for finding each drawn tile's neighbours.
using DrawnTileSet = std::unordered_set<TileKey, TileKeyHash>;

/// How much coarser the tiles drawn across each edge of a drawn tile are: the nearest drawn
/// ancestor of the same-level neighbour across the edge (the antimeridian wraps; nothing lies
/// across a pole). 0 where the neighbour is drawn at the same level or finer, or not at all.
EdgeCoarsening edgeCoarsening(const TilingScheme& scheme, const TileKey& key, const DrawnTileSet& drawn);

} // namespace orbis::scene
