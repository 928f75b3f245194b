#pragma once

#include "orbis/scene/ClipmapStatistics.h"
#include "orbis/scene/DepthStrategy.h"
#include "orbis/scene/MultiFrustum.h"
#include "orbis/scene/TileStatistics.h"
#include "orbis/scene/VirtualTextureStatistics.h"

#include <orbis/renderer/RenderStatistics.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace orbis::scene {

/// What one Scene::render did, so that tests can assert that a scene pays only for what it
/// contains.
struct FrameStatistics {
    std::uint64_t frameNumber = 0;
    std::size_t primitivesUpdated = 0;
    std::size_t primitivesCulled = 0;          ///< culled whole, before update(): no resources made
    std::size_t commandsSubmitted = 0;
    std::size_t commandsCulledByFrustum = 0;
    std::size_t commandsCulledByHorizon = 0;
    std::size_t commandsExecuted = 0;          ///< draw calls, counting repeats across frustums
    std::size_t commandsExecutedMoreThanOnce = 0;
    DepthStrategy depthStrategy = DepthStrategy::MultiFrustum; ///< what ran (never Auto)
    bool depthStrategyAutomatic = false;       ///< chosen by DepthStrategy::Automatic
    int samples = 1;                           ///< per pixel: above 1, drawn multisampled and resolved
    std::vector<FrustumRange> frustums;        ///< near to far; one for the single-frustum strategies
    std::vector<std::size_t> drawCallsPerFrustum; ///< parallel to frustums
    bool frustumsReused = false;
    std::size_t opaquePasses = 0;              ///< passes that drew at least one command
    std::size_t translucentPasses = 0;
    std::size_t overlayPasses = 0;
    std::uint64_t programsCompiled = 0;        ///< shader variants compiled during this frame
    std::uint32_t effects = 0;                 ///< Effect bits of the commands drawn
    double updateMilliseconds = 0.0;           ///< primitives' update()
    double cullMilliseconds = 0.0;             ///< culling and binning
    double drawMilliseconds = 0.0;             ///< executing commands, GPU finished
    renderer::RenderStatistics renderer;                 ///< the context's own counts for the frame
    /// The streamed surface's figures; empty in a scene without a TiledGlobe, which does none of
    /// that work.
    std::optional<TileStatistics> tiles;
    /// The virtual texture's figures; empty in a scene without one, which compiles no virtual
    /// texture program and runs no feedback pass.
    std::optional<VirtualTextureStatistics> virtualTexture;
    /// Clipmap terrain's figures (its update's posts, budget and draws); empty in a scene without
    /// one, which compiles none of its programs.
    std::optional<ClipmapStatistics> clipmap;
    /// Set by a caller that renders a still picture until its tiles converge (`orbis render`): how
    /// many frames that took; empty when it did not.
    std::optional<std::uint64_t> framesToConverge;

    /// The effects drawn, by name, and "feedback pass" (a virtual texture's), "translucent pass",
    /// "overlay pass", "multi-frustum",
    /// "logarithmic depth", "logarithmic depth (per vertex)" and "complementary depth" when those
    /// ran: what the frame paid for.
    std::vector<std::string> effectsRun() const;

    /// One readable block of text, as `orbis render` prints it.
    std::string toText() const;
    /// A JSON object with every figure, for --stats files.
    std::string toJson() const;
};

} // namespace orbis::scene
