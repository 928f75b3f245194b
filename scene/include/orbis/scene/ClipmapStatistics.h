#pragma once

#include <cstddef>
#include <cstdint>

namespace orbis::scene {

/// What a clipmap terrain did in one frame (FrameStatistics::clipmap).
struct ClipmapStatistics {
    int levels = 0;                  ///< levels of the pyramid
    /// Levels finer than this were skipped (finer than the eye needs, or strips not written yet);
    /// `levels` when none was drawn (the coarsest level not written yet).
    int finestLevelDrawn = 0;
    int parameterization = 0;        ///< 0: geodetic; 1, 2: the rotated grids used near the poles
    std::size_t postsUpdated = 0;    ///< heights, normals and colours written this frame
    std::size_t postsPending = 0;    ///< still to write, held back by the budget
    std::size_t levelsPending = 0;   ///< levels with writes pending (not drawn until done)
    std::size_t bytesUploaded = 0;   ///< texels sent to the GPU this frame
    std::size_t drawCalls = 0;       ///< commands appended (before the scene's culling)
    std::size_t piecesCulled = 0;    ///< blocks, fix-ups and trims outside the view
    std::size_t trianglesSubmitted = 0;
    std::size_t tilesRequested = 0;  ///< terrain and imagery loads started this frame
    std::size_t tilesLoaded = 0;     ///< arrived this frame
    std::size_t tilesPending = 0;    ///< in flight
    std::size_t gpuBytes = 0;        ///< level textures, the shared buffers and the backdrop: fixed
    /// The backdrop was drawn: the globe beyond the coarsest level (which reaches 48 degrees from
    /// the viewer), when the eye sees past it.
    bool backdropDrawn = false;
    double updateMilliseconds = 0.0; ///< CPU time (this thread's) of this frame's level writes and uploads
    /// Nothing pending: every level written from the finest data loaded, no load in flight.
    bool converged = false;
};

} // namespace orbis::scene
