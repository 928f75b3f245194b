#include "orbis/core/ClipmapLayout.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace orbis {

namespace {

struct PieceTriangles {
    ClipmapPieceKind kind;
    std::vector<std::uint32_t> indices;
    int minimumX = 0, minimumY = 0, maximumX = 0, maximumY = 0;
};

class PieceBuilder {
public:
    explicit PieceBuilder(int posts)
        : _posts(posts)
    {
    }

    /// The quads between posts x0..x1 and y0..y1, two counter-clockwise triangles each.
    PieceTriangles grid(ClipmapPieceKind kind, int x0, int y0, int x1, int y1) const
    {
        PieceTriangles piece{kind, {}, x0, y0, x1, y1};
        piece.indices.reserve(static_cast<std::size_t>(x1 - x0) * static_cast<std::size_t>(y1 - y0) * 6);
        for (int y = y0; y < y1; ++y) {
            for (int x = x0; x < x1; ++x) {
                const std::uint32_t a = index(x, y), b = index(x + 1, y), c = index(x + 1, y + 1), d = index(x, y + 1);
                piece.indices.insert(piece.indices.end(), {a, b, c, a, c, d});
            }
        }
        return piece;
    }

    std::uint32_t index(int x, int y) const noexcept
    {
        return static_cast<std::uint32_t>(y) * static_cast<std::uint32_t>(_posts) + static_cast<std::uint32_t>(x);
    }

private:
    int _posts;
};

bool contains(const PieceTriangles& piece, int x, int y) noexcept
{
    return x >= piece.minimumX && x <= piece.maximumX && y >= piece.minimumY && y <= piece.maximumY;
}

} // namespace

ClipmapBlockLayout::ClipmapBlockLayout(int posts)
    : _posts(posts)
{
    assert(posts >= 7 && posts <= 2047 && ((posts + 1) & posts) == 0);
    const int n = posts;
    const int m = blockPosts();
    const PieceBuilder builder(n);

    // The ring without its trim: blocks start at 0, m - 1, 2m and 3m - 1 on each axis, the
    // fix-ups fill the two-quad gaps at 2m - 2 .. 2m.
    std::vector<PieceTriangles> common;
    const int starts[4] = {0, m - 1, 2 * m, 3 * m - 1};
    for (int by = 0; by < 4; ++by) {
        for (int bx = 0; bx < 4; ++bx) {
            if (bx == 0 || bx == 3 || by == 0 || by == 3) {
                common.push_back(builder.grid(ClipmapPieceKind::Block, starts[bx], starts[by], starts[bx] + m - 1,
                                              starts[by] + m - 1));
            }
        }
    }
    for (const int start : {0, 3 * m - 1}) {
        common.push_back(builder.grid(ClipmapPieceKind::FixUp, 2 * m - 2, start, 2 * m, start + m - 1));
        common.push_back(builder.grid(ClipmapPieceKind::FixUp, start, 2 * m - 2, start + m - 1, 2 * m));
    }

    // The outer boundary, walked counter-clockwise: each run a, b, c from an even post gets (a, c, b).
    struct Post {
        int x, y;
    };
    std::vector<Post> boundary;
    for (int k = 0; k < n - 1; ++k) boundary.push_back({k, 0});
    for (int k = 0; k < n - 1; ++k) boundary.push_back({n - 1, k});
    for (int k = 0; k < n - 1; ++k) boundary.push_back({n - 1 - k, n - 1});
    for (int k = 0; k < n - 1; ++k) boundary.push_back({0, n - 1 - k});
    for (std::size_t k = 0; k < boundary.size(); k += 2) {
        const Post a = boundary[k], b = boundary[k + 1], c = boundary[(k + 2) % boundary.size()];
        for (PieceTriangles& piece : common) {
            if (contains(piece, b.x, b.y)) {
                piece.indices.insert(piece.indices.end(),
                                     {builder.index(a.x, a.y), builder.index(c.x, c.y), builder.index(b.x, b.y)});
                for (const Post p : {a, c}) {
                    piece.minimumX = std::min(piece.minimumX, p.x);
                    piece.maximumX = std::max(piece.maximumX, p.x);
                    piece.minimumY = std::min(piece.minimumY, p.y);
                    piece.maximumY = std::max(piece.maximumY, p.y);
                }
                break;
            }
        }
    }

    const double center = 0.5 * (n - 1);
    auto angle = [&](const PieceTriangles& piece) {
        return std::atan2(0.5 * (piece.minimumY + piece.maximumY) - center, 0.5 * (piece.minimumX + piece.maximumX) - center);
    };
    for (const ClipmapTrim trim : {ClipmapTrim::SouthWest, ClipmapTrim::SouthEast, ClipmapTrim::NorthWest, ClipmapTrim::NorthEast}) {
        const bool west = trim == ClipmapTrim::SouthWest || trim == ClipmapTrim::NorthWest;
        const bool south = trim == ClipmapTrim::SouthWest || trim == ClipmapTrim::SouthEast;
        const int column = west ? m - 1 : 3 * m - 2;
        const int row = south ? m - 1 : 3 * m - 2;
        std::vector<PieceTriangles> pieces = common;
        pieces.push_back(builder.grid(ClipmapPieceKind::Trim, column, m - 1, column + 1, 3 * m - 1));
        pieces.push_back(builder.grid(ClipmapPieceKind::Trim, west ? m : m - 1, row, west ? 3 * m - 1 : 3 * m - 2, row + 1));
        std::stable_sort(pieces.begin(), pieces.end(),
                         [&](const PieceTriangles& a, const PieceTriangles& b) { return angle(a) < angle(b); });
        std::vector<ClipmapPiece>& ring = _rings[static_cast<std::size_t>(trim)];
        for (const PieceTriangles& piece : pieces) {
            ring.push_back({piece.kind, piece.minimumX, piece.minimumY, piece.maximumX, piece.maximumY, _indices.size(),
                            piece.indices.size()});
            _indices.insert(_indices.end(), piece.indices.begin(), piece.indices.end());
        }
    }
    const PieceTriangles interior = builder.grid(ClipmapPieceKind::Interior, m, m, 3 * m - 1, 3 * m - 1);
    _interior = {interior.kind, m, m, 3 * m - 1, 3 * m - 1, _indices.size(), interior.indices.size()};
    _indices.insert(_indices.end(), interior.indices.begin(), interior.indices.end());
}

ClipmapTrim ClipmapBlockLayout::trimFor(int fineOriginX, int fineOriginY, int blockPosts) noexcept
{
    assert((fineOriginX == blockPosts - 1 || fineOriginX == blockPosts) &&
           (fineOriginY == blockPosts - 1 || fineOriginY == blockPosts));
    const bool west = fineOriginX == blockPosts;
    const bool south = fineOriginY == blockPosts;
    if (south) {
        return west ? ClipmapTrim::SouthWest : ClipmapTrim::SouthEast;
    }
    return west ? ClipmapTrim::NorthWest : ClipmapTrim::NorthEast;
}

std::vector<std::int64_t> clipmapOrigins(double centerX, double centerY, int levels, int posts)
{
    const int m = (posts + 1) / 4;
    const double half = 0.5 * (posts - 1);
    std::vector<std::int64_t> origins;
    origins.reserve(2 * static_cast<std::size_t>(levels));
    // Level 0: the even origin nearest to putting the viewer at the centre post.
    origins.push_back(2 * static_cast<std::int64_t>(std::llround(0.5 * (centerX - half))));
    origins.push_back(2 * static_cast<std::int64_t>(std::llround(0.5 * (centerY - half))));
    for (int level = 1; level < levels; ++level) {
        for (int axis = 0; axis < 2; ++axis) {
            // The finer origin halved lands on post m or m - 1 of this level: of the two
            // candidates exactly one is even.
            const std::int64_t candidate = origins[2 * static_cast<std::size_t>(level - 1) + static_cast<std::size_t>(axis)] / 2 - m;
            origins.push_back((candidate % 2 == 0) ? candidate : candidate + 1);
        }
    }
    return origins;
}

} // namespace orbis
