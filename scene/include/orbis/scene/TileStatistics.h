#pragma once

#include <cstddef>
#include <cstdint>

namespace orbis::scene {

/// What the streamed surface of the globe did in one frame (FrameStatistics::tiles), and where it
/// stands: its names are those of `orbis render --stats`.
struct TileStatistics {
    std::size_t visited = 0;          ///< tiles the selection reached
    std::size_t culledByFrustum = 0;
    std::size_t culledByHorizon = 0;
    std::size_t selected = 0;         ///< visible tiles at the level the screen-space error asks for
    std::size_t drawn = 0;            ///< tiles drawn, stand-ins for unloaded children included
    std::size_t standIns = 0;         ///< drawn in place of finer tiles not loaded yet
    std::size_t fallbackImagery = 0;  ///< drawn tiles showing an ancestor's imagery, scaled
    std::size_t morphing = 0;         ///< drawn tiles still moving from their ancestor's surface to their own
    std::size_t imageryDrawn = 0;     ///< imagery tiles the drawn tiles read (each counted once)
    std::size_t requested = 0;        ///< loads started this frame
    std::size_t loadedThisFrame = 0;  ///< loads that arrived this frame with data
    std::size_t pending = 0;          ///< loads in flight, waiting to be uploaded, or held back by the limits
    std::size_t failed = 0;           ///< tiles that failed to load, since the start (each named once)
    std::size_t missing = 0;          ///< tiles the sources do not have (a 404), since the start
    std::size_t evicted = 0;          ///< tiles dropped from the cache this frame
    std::size_t residentBytesCpu = 0; ///< loaded data not yet on the GPU, and tile data kept in memory
    std::size_t residentBytesGpu = 0; ///< vertex buffers and textures
    std::size_t uploadedBytes = 0;    ///< sent to the GPU this frame
    std::size_t residentTiles = 0;    ///< surface tiles whose mesh is on the GPU
    std::size_t residentImageryTiles = 0; ///< imagery tiles on the GPU (a virtual texture: its pages)
    std::uint32_t deepestLevelDrawn = 0;
    double largestScreenSpaceErrorDrawn = 0.0; ///< pixels
    /// The limit the selection used: the one asked for, or higher when the cache's cap binds.
    double maximumScreenSpaceError = 0.0;
    bool memoryLimited = false;       ///< the cap made the selection coarser than asked
    /// Every drawn tile is at the level its error asks for, with its own imagery, and nothing is
    /// pending: rendering again would change nothing.
    bool converged = false;

    /// Adds another globe's figures (flags: all converged, any memory-limited).
    void add(const TileStatistics& other) noexcept;
};

} // namespace orbis::scene
