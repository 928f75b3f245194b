#include "orbis/scene/TileQuadtree.h"

#include <orbis/core/ScreenSpaceError.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

namespace orbis::scene {

TileQuadtree::TileQuadtree(const Ellipsoid& ellipsoid, const TilingScheme& scheme, int samplesAcross,
                           TileCreated onCreated)
    : _ellipsoid(ellipsoid)
    , _scheme(scheme)
    , _samplesAcross(samplesAcross)
    , _onCreated(std::move(onCreated))
    , _occluder(ellipsoid, glm::dvec3(0.0))
{
    for (std::uint32_t y = 0; y < scheme.tilesY(0); ++y) {
        for (std::uint32_t x = 0; x < scheme.tilesX(0); ++x) {
            const TileKey key{0, x, y};
            _roots.push_back(std::make_unique<QuadtreeTile>(key, nullptr, regionOf(key, 0.0, 0.0), geometricErrorOf(0)));
            if (_onCreated) {
                _onCreated(*_roots.back());
            }
        }
    }
}

BoundingRegion TileQuadtree::regionOf(const TileKey& key, double minimumHeight, double maximumHeight) const noexcept
{
    return BoundingRegion(_ellipsoid, _scheme.tileExtent(key), minimumHeight, maximumHeight);
}

double TileQuadtree::geometricErrorOf(std::uint32_t level) const noexcept
{
    return _scheme.geometricError(_ellipsoid, level, _samplesAcross);
}

double TileQuadtree::screenSpaceError(const QuadtreeTile& tile, const TileView& view) noexcept
{
    return orbis::screenSpaceError(tile.geometricError, tile.region.distanceTo(view.eye), view.viewportHeightPixels,
                                   view.fieldOfViewY);
}

void TileQuadtree::createChildren(QuadtreeTile& tile)
{
    for (int i = 0; i < 4; ++i) {
        const TileKey key = tile.key.child(i);
        tile.children[i] = std::make_unique<QuadtreeTile>(
            key, &tile, regionOf(key, tile.region.minimumHeight(), tile.region.maximumHeight()),
            geometricErrorOf(key.level));
        if (_onCreated) {
            _onCreated(*tile.children[i]);
        }
    }
}

double TileQuadtree::loadPriority(const QuadtreeTile& tile, const TileView& view, double distance) const noexcept
{
    // Near tiles first, and at equal distance those towards the middle of the view.
    const glm::dvec3 toTile = tile.region.boundingSphere().centre - view.eye;
    const double length = glm::length(toTile);
    const double cosine = length > 0.0 ? glm::dot(toTile, view.direction) / length : 1.0;
    return distance * (2.0 - cosine);
}

void TileQuadtree::select(const TileView& view, const TileSelectionOptions& options, std::uint64_t frameNumber,
                          TileSelection& selection, const TileVisited& refresh)
{
    selection = TileSelection{};
    _occluder.setCameraPosition(view.eye);
    std::vector<std::pair<double, QuadtreeTile*>> order;
    for (const auto& root : _roots) {
        order.emplace_back(root->region.distanceTo(view.eye), root.get());
    }
    std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    // The screen-space error of book equation 12.1, its view part taken out of the traversal's loop.
    const double halfHeight = std::tan(0.5 * std::clamp(view.fieldOfViewY, 1e-9, kPi - 1e-9));
    Traversal traversal{view, options, frameNumber, selection, refresh, view.viewportHeightPixels / (2.0 * halfHeight)};
    for (const auto& [distance, root] : order) {
        visit(*root, distance, traversal);
    }
}

TileQuadtree::Coverage TileQuadtree::visit(QuadtreeTile& tile, double distance, Traversal& traversal)
{
    const TileView& view = traversal.view;
    const TileSelectionOptions& options = traversal.options;
    TileSelection& selection = traversal.selection;
    const std::uint64_t frameNumber = traversal.frameNumber;
    const TileVisited& refresh = traversal.refresh;
    ++selection.visited;
    tile.lastVisitedFrame = frameNumber;
    if (refresh) {
        refresh(tile);
    }
    if (view.frustum.intersect(tile.region.orientedBox()) == Intersect::Outside) {
        ++selection.culledByFrustum;
        return Coverage::Culled;
    }
    const auto& occlusionPoint = tile.region.horizonOcclusionPoint();
    if (occlusionPoint && !_occluder.isScaledSpacePointVisible(*occlusionPoint, tile.region.minimumHeight())) {
        ++selection.culledByHorizon;
        return Coverage::Culled;
    }

    // As orbis::screenSpaceError, with the field of view's tangent taken once per traversal.
    const double error = distance > 0.0 ? tile.geometricError * traversal.errorPerMeter / distance
                                        : std::numeric_limits<double>::infinity();
    // A tile at the level asked for is drawn when it can be, and loads what it still lacks (its
    // own imagery, say) while it is drawn; a stand-in loads only when asked to (loadSelf) and it
    // cannot be drawn at all.
    auto drawOrRequest = [&](bool standIn, bool loadSelf) {
        const bool wanted = tile.wantsLoad && (!standIn || (loadSelf && !tile.renderable));
        if (wanted) {
            selection.loads.push_back({&tile, loadPriority(tile, view, distance)});
        }
        if (tile.renderable) {
            selection.drawn.push_back(&tile);
            selection.drawnScreenSpaceErrors.push_back(error);
            return Coverage::Covered;
        }
        return Coverage::Uncovered;
    };

    const bool refine = error > options.maximumScreenSpaceError && tile.refinable && tile.key.level < options.maximumLevel;
    if (!refine) {
        ++selection.selected;
        return drawOrRequest(false, true);
    }

    if (!tile.hasChildren()) {
        createChildren(tile);
    }
    std::array<QuadtreeTile*, 4> children{};
    std::array<double, 4> distances{};
    for (int i = 0; i < 4; ++i) {
        children[i] = tile.children[i].get();
        distances[i] = children[i]->region.distanceTo(view.eye);
    }
    std::array<int, 4> order{0, 1, 2, 3};
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return distances[a] < distances[b]; });

    const std::size_t drawnBefore = selection.drawn.size();
    const std::size_t loadsBefore = selection.loads.size();
    bool covered = true;
    for (const int i : order) {
        covered = visit(*children[i], distances[i], traversal) != Coverage::Uncovered && covered;
    }
    if (covered) {
        return Coverage::Covered;
    }

    // A descendant cannot be drawn yet: this tile stands in for all of them (never a hole), while
    // their loads go ahead, straight to the level the view asks for. Only when more of them wait
    // than the limit (after a jump) does this tile load too, so that something finer than its
    // drawn ancestor shows sooner; and only the most urgent of the descendants' loads go ahead.
    selection.drawn.resize(drawnBefore);
    selection.drawnScreenSpaceErrors.resize(drawnBefore);
    const auto firstLoad = selection.loads.begin() + static_cast<std::ptrdiff_t>(loadsBefore);
    const bool manyWaiting = selection.loads.size() - loadsBefore > options.loadingDescendantLimit;
    if (manyWaiting) {
        const auto keep = firstLoad + static_cast<std::ptrdiff_t>(options.loadingDescendantLimit);
        std::nth_element(firstLoad, keep, selection.loads.end(), [](const TileLoadCandidate& a, const TileLoadCandidate& b) {
            return a.priority < b.priority;
        });
        selection.loads.erase(keep, selection.loads.end());
    }
    const Coverage coverage = drawOrRequest(true, manyWaiting);
    if (coverage == Coverage::Covered) {
        ++selection.standIns;
    }
    return coverage;
}

EdgeCoarsening edgeCoarsening(const TilingScheme& scheme, const TileKey& key, const DrawnTileSet& drawn)
{
    const std::uint32_t columns = scheme.tilesX(key.level);
    const std::uint32_t rows = scheme.tilesY(key.level);
    const bool rowsFromSouth = scheme.projection() == TilingProjection::Geographic;
    auto levelsCoarser = [&](std::optional<TileKey> neighbour) {
        if (!neighbour) {
            return 0;
        }
        for (std::uint32_t level = key.level; level-- > 0;) {
            if (drawn.contains(neighbour->ancestor(level))) {
                return static_cast<int>(key.level - level);
            }
        }
        return 0;
    };
    auto row = [&](bool towardsNorth) -> std::optional<TileKey> {
        const bool up = towardsNorth == rowsFromSouth; // the direction y grows
        if (up ? key.y + 1 >= rows : key.y == 0) {
            return std::nullopt; // a pole
        }
        return TileKey{key.level, key.x, up ? key.y + 1 : key.y - 1};
    };
    EdgeCoarsening coarsening;
    coarsening.north = levelsCoarser(row(true));
    coarsening.south = levelsCoarser(row(false));
    coarsening.east = levelsCoarser(TileKey{key.level, (key.x + 1) % columns, key.y});
    coarsening.west = levelsCoarser(TileKey{key.level, (key.x + columns - 1) % columns, key.y});
    return coarsening;
}

} // namespace orbis::scene
