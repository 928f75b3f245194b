#pragma once

#include <cstddef>
#include <cstdint>

namespace orbis::scene {

/// What a virtual texture did in one frame (FrameStatistics::virtualTexture) and where it stands;
/// its names are those of `orbis render --stats`.
struct VirtualTextureStatistics {
    std::size_t pagesWanted = 0;     ///< pages the latest feedback asks for, their ancestors included
    std::size_t pagesRequested = 0;  ///< loads started this frame
    std::size_t pagesLoaded = 0;     ///< pages put in the physical texture this frame
    std::size_t pagesEvicted = 0;    ///< pages that gave up their slot this frame
    std::size_t pagesResident = 0;   ///< pages in the physical texture
    std::size_t physicalPages = 0;   ///< slots of the physical texture
    std::size_t pagesPending = 0;    ///< loads in flight, and pages loaded and waiting for their upload
    std::size_t pagesMissing = 0;    ///< pages the source does not have, since the start
    std::size_t pagesFailed = 0;     ///< pages that failed to load, since the start (each named once)
    /// Of the frame the latest feedback describes: its pixels drawn from a coarser page than they
    /// asked for, and their share of all its pixels.
    std::size_t fallbackPixels = 0;
    std::size_t feedbackPixels = 0;
    double fallbackFraction = 0.0;
    /// How many frames ago the feedback read this frame was drawn; 0 when none was read.
    std::uint64_t feedbackLatencyFrames = 0;
    /// The feedback pass's size, pixels; 0 in a frame that drew none: one whose view, tiles and
    /// page table are those the last pass drew from, whose feedback then stands for it.
    int feedbackWidth = 0;
    int feedbackHeight = 0;
    std::size_t uploadedBytes = 0;   ///< pages, page-table and LOD-clamp texels sent this frame
    /// Levels added to every pixel's level of detail (coarser), the dynamic part included: above
    /// the configured bias while the view needs more pages than the physical texture holds.
    double lodBias = 0.0;
    bool lodBiasRaised = false;      ///< the dynamic bias is above the configured one
    /// Physical texture, page table, LOD clamp, feedback buffers: fixed. On the sparse path the
    /// pages committed (at most physicalPages) and the levels below level 0 in place of the
    /// physical texture.
    std::size_t gpuBytes = 0;
    /// Tiles with rows drawn with the mip tail's lookup compiled in: the rows with pixels that may
    /// be coarser than level 0 (near the horizon, a pole, or from afar); the others leave it out.
    std::size_t tilesWithMipTail = 0;
    /// Tiles with rows drawn blending two levels (trilinear filtering: two reads of the physical
    /// texture a pixel); the other rows have every pixel magnifying the finest level, which they
    /// read alone.
    std::size_t tilesBlendingLevels = 0;
    /// Drawn through a sparse texture (VirtualTextureOptions::sparse, on a device that has it);
    /// false on the software path (physical texture and page table).
    bool sparse = false;
    /// Every page the view asks for is resident (or missing from the source), no load is pending,
    /// and the latest feedback, of the present view, shows no fallback.
    bool converged = false;

    /// Adds another virtual texture's figures: counts and bytes summed, the fallback fraction
    /// of all their pixels, the larger latency and bias, flags: all converged, any raised or sparse.
    void add(const VirtualTextureStatistics& other) noexcept;
};

} // namespace orbis::scene
