#pragma once

#include "orbis/core/Ellipsoid.h"
#include "orbis/core/GeodeticExtent.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace orbis {

/// The vertices of one tile of the globe's surface: a regular grid of columns x rows samples over
/// a longitude-latitude rectangle, lifted by heights along the ellipsoid's normal, with an
/// optional skirt (a copy of the edge vertices hanging below it, hiding cracks between tiles of
/// different levels). Positions are relative to `centre` (metres, floats), so that what reaches
/// the GPU stays precise near the tile (book chapter 5, relative to centre).
///
/// Each vertex is kFloatsPerVertex floats: x, y, z relative to the centre, u and v (0..1 west to
/// east and south to north within the tile), and the height in metres. Grid vertex (i, j) (column
/// i from the west, row j from the north) is at index j * columns + i; the skirt's follow: the
/// north edge west to east, then the east edge north to south, the south edge east to west and the
/// west edge south to north (each corner once per edge).
struct TileMesh {
    static constexpr int kFloatsPerVertex = 6;

    glm::dvec3 centre{0.0};
    int columns = 0;
    int rows = 0;
    bool skirt = false;
    std::vector<float> vertices;
    double minimumHeight = 0.0; ///< of the grid, not the skirt
    double maximumHeight = 0.0;

    std::size_t vertexCount() const noexcept { return vertices.size() / kFloatsPerVertex; }
    std::size_t byteSize() const noexcept { return vertices.size() * sizeof(float); }

    /// Builds the mesh. heights: rows x columns metres, row 0 the north edge, or empty for the
    /// ellipsoid itself; skirtDepth: how far below each edge vertex its skirt vertex hangs (> 0
    /// for a skirt, 0 for none). columns and rows >= 2 (asserted). Poles need no special case: a
    /// row on a pole puts its vertices at one point, whose triangles have no area.
    static TileMesh build(const Ellipsoid& ellipsoid, const GeodeticExtent& extent, int columns, int rows,
                          std::span<const float> heights, double skirtDepth);

    /// The triangle indices of every mesh of this size, counter-clockwise seen from above: one list
    /// serves all tiles of one grid size (the course's shared index buffer).
    static std::vector<std::uint32_t> indices(int columns, int rows, bool skirt);
};

} // namespace orbis
