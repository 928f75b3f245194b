#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace orbis {

/// Which corner of a level's hole the interior trim (the one-quad L around the finer level)
/// occupies: the finer level spans 2m - 1 of the hole's 2m quads a side and the trim fills the
/// quad left over on one side in x and one in y.
enum class ClipmapTrim : std::uint8_t { SouthWest, SouthEast, NorthWest, NorthEast };

/// What a piece of a level's ring is (book 13.2, Asirvatham and Hoppe's figure 2-4).
enum class ClipmapPieceKind : std::uint8_t {
    Block,    ///< m x m posts, twelve around the ring (four more fill the finest level)
    FixUp,    ///< m x 3 posts in the middle of each side, where four blocks leave a gap
    Trim,     ///< an arm of the L-shaped interior trim, one quad wide
    Interior, ///< the finest level's centre: what the finer level would cover
};

/// A contiguous range of ClipmapBlockLayout::indices() drawing one piece, and the posts it
/// touches (inclusive bounds in the level's post coordinates, x east, y north).
struct ClipmapPiece {
    ClipmapPieceKind kind = ClipmapPieceKind::Block;
    int minimumX = 0, minimumY = 0, maximumX = 0, maximumY = 0;
    std::size_t firstIndex = 0;
    std::size_t indexCount = 0;
};

/// The shared index buffers of a geometry clipmap of n = 2^k - 1 posts a side (book 13.2): one
/// vertex per post of an n x n lattice (index y * n + x), and triangles for a level's ring in
/// each of the four trim placements, plus the centre a level with no finer level inside fills.
///
/// The ring is m = (n + 1) / 4 posts thick: twelve m x m blocks, four m x 3 fix-ups, the L-shaped
/// trim, and on the outer boundary the degenerate triangles (a, c, b) over each run a, b, c of
/// boundary posts, whose odd post b lies on the midpoint of the coarser level's edge a-c: they
/// have no area while the transition band has pulled b onto that edge, and they close the
/// T-junction whatever the heights. Triangles are counter-clockwise seen from above (x east,
/// y north). The pieces of each ring are in order of angle about the level's centre (from the
/// west, counter-clockwise from -pi), with each boundary degenerate inside the piece that holds
/// its middle post, so that the pieces one view keeps form at most two ranges of indices.
class ClipmapBlockLayout final {
public:
    /// posts: n = 2^k - 1 with 3 <= k <= 11 (asserted; 7 .. 2047).
    explicit ClipmapBlockLayout(int posts);

    int posts() const noexcept { return _posts; }
    /// m = (n + 1) / 4: posts a side of a block.
    int blockPosts() const noexcept { return (_posts + 1) / 4; }

    /// Every piece's triangles, three indices each into the n x n lattice.
    const std::vector<std::uint32_t>& indices() const noexcept { return _indices; }

    /// A ring with the finer level placed for `trim`, its pieces in angular order.
    const std::vector<ClipmapPiece>& ring(ClipmapTrim trim) const noexcept
    {
        return _rings[static_cast<std::size_t>(trim)];
    }
    /// The centre of a level drawn with ring(ClipmapTrim::SouthWest) and no finer level: the
    /// (2m - 1)-quad square from post m to post 3m - 1 on both axes.
    const ClipmapPiece& interior() const noexcept { return _interior; }

    /// The trim a level needs when the finer level's post 0 lies on this level's post
    /// `fineOriginX`, `fineOriginY` (each m - 1 or m, asserted): the trim is on the side the finer
    /// level leaves free.
    static ClipmapTrim trimFor(int fineOriginX, int fineOriginY, int blockPosts) noexcept;

private:
    int _posts;
    std::vector<std::uint32_t> _indices;
    std::vector<ClipmapPiece> _rings[4];
    ClipmapPiece _interior;
};

/// Where each level of a clipmap lies: level 0 the finest, level l's post spacing 2^l times
/// level 0's. The origins are global post numbers (level l's post i at i * 2^l finest spacings),
/// each even so that it lies on a post of the next coarser level, and each finer level's post 0
/// on post m - 1 or m of its coarser level (as ClipmapBlockLayout's hole requires).
///
/// `centerX`, `centerY`: the viewer in finest spacings (any real; far from zero works as well as
/// near). Level 0 is placed with the viewer within about a post of its centre, and each coarser
/// one as near as the nesting allows. Returns 2 * levels numbers: x and y of each level's origin.
std::vector<std::int64_t> clipmapOrigins(double centerX, double centerY, int levels, int posts);

} // namespace orbis
