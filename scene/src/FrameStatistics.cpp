#include "orbis/scene/FrameStatistics.h"

#include "orbis/scene/Effect.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace orbis::scene {

namespace {

std::string number(double value)
{
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", value);
    return text;
}

} // namespace

void TileStatistics::add(const TileStatistics& other) noexcept
{
    visited += other.visited;
    culledByFrustum += other.culledByFrustum;
    culledByHorizon += other.culledByHorizon;
    selected += other.selected;
    drawn += other.drawn;
    standIns += other.standIns;
    fallbackImagery += other.fallbackImagery;
    morphing += other.morphing;
    imageryDrawn += other.imageryDrawn;
    requested += other.requested;
    loadedThisFrame += other.loadedThisFrame;
    pending += other.pending;
    failed += other.failed;
    missing += other.missing;
    evicted += other.evicted;
    residentBytesCpu += other.residentBytesCpu;
    residentBytesGpu += other.residentBytesGpu;
    uploadedBytes += other.uploadedBytes;
    residentTiles += other.residentTiles;
    residentImageryTiles += other.residentImageryTiles;
    deepestLevelDrawn = std::max(deepestLevelDrawn, other.deepestLevelDrawn);
    largestScreenSpaceErrorDrawn = std::max(largestScreenSpaceErrorDrawn, other.largestScreenSpaceErrorDrawn);
    maximumScreenSpaceError = std::max(maximumScreenSpaceError, other.maximumScreenSpaceError);
    memoryLimited = memoryLimited || other.memoryLimited;
    converged = converged && other.converged;
}

void VirtualTextureStatistics::add(const VirtualTextureStatistics& other) noexcept
{
    pagesWanted += other.pagesWanted;
    pagesRequested += other.pagesRequested;
    pagesLoaded += other.pagesLoaded;
    pagesEvicted += other.pagesEvicted;
    pagesResident += other.pagesResident;
    physicalPages += other.physicalPages;
    pagesPending += other.pagesPending;
    pagesMissing += other.pagesMissing;
    pagesFailed += other.pagesFailed;
    fallbackPixels += other.fallbackPixels;
    feedbackPixels += other.feedbackPixels;
    fallbackFraction = feedbackPixels == 0 ? 0.0 : static_cast<double>(fallbackPixels) / static_cast<double>(feedbackPixels);
    feedbackLatencyFrames = std::max(feedbackLatencyFrames, other.feedbackLatencyFrames);
    feedbackWidth = std::max(feedbackWidth, other.feedbackWidth);
    feedbackHeight = std::max(feedbackHeight, other.feedbackHeight);
    uploadedBytes += other.uploadedBytes;
    lodBias = std::max(lodBias, other.lodBias);
    lodBiasRaised = lodBiasRaised || other.lodBiasRaised;
    gpuBytes += other.gpuBytes;
    tilesWithMipTail += other.tilesWithMipTail;
    tilesBlendingLevels += other.tilesBlendingLevels;
    sparse = sparse || other.sparse;
    converged = converged && other.converged;
}

std::vector<std::string> FrameStatistics::effectsRun() const
{
    std::vector<std::string> names = effectNames(effects);
    if (virtualTexture && virtualTexture->feedbackWidth > 0) {
        names.emplace_back("feedback pass");
    }
    if (translucentPasses > 0) {
        names.emplace_back("translucent pass");
    }
    if (overlayPasses > 0) {
        names.emplace_back("overlay pass");
    }
    if (frustums.size() > 1) {
        names.emplace_back("multi-frustum");
    }
    if (samples > 1) {
        names.emplace_back("multisampling");
    }
    if (depthStrategy == DepthStrategy::Logarithmic) {
        names.emplace_back("logarithmic depth");
    } else if (depthStrategy == DepthStrategy::LogarithmicVertex) {
        names.emplace_back("logarithmic depth (per vertex)");
    } else if (depthStrategy == DepthStrategy::Complementary) {
        names.emplace_back("complementary depth");
    }
    return names;
}

std::string FrameStatistics::toText() const
{
    std::ostringstream out;
    out << "frame " << frameNumber << ": " << primitivesUpdated << " primitives updated, " << primitivesCulled
        << " culled whole\n"
        << "commands: " << commandsSubmitted << " submitted, " << commandsCulledByFrustum << " culled by the frustum, "
        << commandsCulledByHorizon << " by the horizon, " << commandsExecuted << " draw calls, "
        << commandsExecutedMoreThanOnce << " commands drawn in more than one frustum\n"
        << "depth: " << depthStrategyName(depthStrategy) << (depthStrategyAutomatic ? " (chosen by auto)" : "")
        << "\n"
        << "frustums: " << frustums.size() << (frustumsReused ? " (reused)" : "") << "\n";
    for (std::size_t f = 0; f < frustums.size(); ++f) {
        out << "  " << f << ": " << number(frustums[f].nearDistance) << " m .. " << number(frustums[f].farDistance)
            << " m, " << drawCallsPerFrustum[f] << " draw calls\n";
    }
    out << "effects:";
    const std::vector<std::string> names = effectsRun();
    for (std::size_t i = 0; i < names.size(); ++i) {
        out << (i ? ", " : " ") << names[i];
    }
    out << "\n";
    out << "passes: " << opaquePasses << " opaque, " << translucentPasses << " translucent, " << overlayPasses
        << " overlay; programs compiled: " << programsCompiled << "\n"
        << "renderer: " << renderer.drawCalls << " draws, " << renderer.primitives << " primitives, "
        << renderer.stateChangesMade << " state changes made, " << renderer.stateChangesAvoided << " avoided\n"
        << "time: update " << number(updateMilliseconds) << " ms, cull and bin " << number(cullMilliseconds)
        << " ms, draw " << number(drawMilliseconds) << " ms\n";
    if (tiles) {
        const TileStatistics& t = *tiles;
        out << "tiles: " << t.visited << " visited, " << t.culledByFrustum << " culled by the frustum, "
            << t.culledByHorizon << " by the horizon, " << t.selected << " selected, " << t.drawn << " drawn ("
            << t.standIns << " standing in for finer ones, " << t.fallbackImagery << " with an ancestor's imagery, "
            << t.morphing << " morphing; "
            << t.imageryDrawn << " imagery tiles read)\n"
            << "  loads: " << t.requested << " started, " << t.loadedThisFrame << " arrived, " << t.pending
            << " pending, " << t.failed << " failed, " << t.missing << " missing, " << t.evicted << " evicted\n"
            << "  deepest level drawn " << t.deepestLevelDrawn << ", largest screen-space error "
            << number(t.largestScreenSpaceErrorDrawn) << " px (limit " << number(t.maximumScreenSpaceError) << " px"
            << (t.memoryLimited ? ", raised: the cache is full" : "") << ")\n"
            << "  resident: " << number(static_cast<double>(t.residentBytesCpu) / 1048576.0) << " MiB CPU, "
            << number(static_cast<double>(t.residentBytesGpu) / 1048576.0) << " MiB GPU, " << t.residentTiles
            << " surface and " << t.residentImageryTiles << " imagery tiles; uploaded "
            << number(static_cast<double>(t.uploadedBytes) / 1048576.0) << " MiB; "
            << (t.converged ? "converged" : "not converged") << "\n";
    }
    if (virtualTexture) {
        const VirtualTextureStatistics& v = *virtualTexture;
        out << "virtual texture: " << v.pagesResident << " of " << v.physicalPages << " pages resident, "
            << v.pagesWanted << " wanted; " << v.pagesRequested << " requested, " << v.pagesLoaded << " loaded, "
            << v.pagesEvicted << " evicted, " << v.pagesPending << " pending, " << v.pagesMissing << " missing, "
            << v.pagesFailed << " failed\n"
            << "  fallback " << number(100.0 * v.fallbackFraction) << "% (" << v.fallbackPixels << " of "
            << v.feedbackPixels << " feedback pixels, " << v.feedbackWidth << "x" << v.feedbackHeight << "), read back "
            << v.feedbackLatencyFrames << " frames late; LOD bias " << number(v.lodBias)
            << (v.lodBiasRaised ? " (raised: the view needs more pages than fit)" : "") << "\n"
            << "  uploaded " << number(static_cast<double>(v.uploadedBytes) / 1048576.0) << " MiB; GPU "
            << number(static_cast<double>(v.gpuBytes) / 1048576.0) << " MiB; " << v.tilesWithMipTail
            << " tiles with the mip tail, " << v.tilesBlendingLevels << " blending two levels; "
            << (v.sparse ? "sparse texture; " : "") << (v.converged ? "converged" : "not converged") << "\n";
    }
    if (clipmap) {
        const ClipmapStatistics& c = *clipmap;
        out << "clipmap: " << c.levels << " levels, finest drawn " << c.finestLevelDrawn << ", grid "
            << c.parameterization << "; " << c.drawCalls << " draws, " << c.trianglesSubmitted << " triangles, "
            << c.piecesCulled << " pieces culled" << (c.backdropDrawn ? ", the backdrop beyond" : "") << "\n"
            << "  update: " << c.postsUpdated << " posts in " << number(c.updateMilliseconds) << " ms, "
            << c.postsPending << " pending over " << c.levelsPending << " levels; uploaded "
            << number(static_cast<double>(c.bytesUploaded) / 1048576.0) << " MiB; loads: " << c.tilesRequested
            << " started, " << c.tilesLoaded << " arrived, " << c.tilesPending << " pending; GPU "
            << number(static_cast<double>(c.gpuBytes) / 1048576.0) << " MiB; " << (c.converged ? "converged" : "not converged") << "\n";
    }
    return out.str();
}

std::string FrameStatistics::toJson() const
{
    std::ostringstream out;
    out << "{\n"
        << "  \"frameNumber\": " << frameNumber << ",\n"
        << "  \"primitivesUpdated\": " << primitivesUpdated << ",\n"
        << "  \"primitivesCulled\": " << primitivesCulled << ",\n"
        << "  \"commandsSubmitted\": " << commandsSubmitted << ",\n"
        << "  \"commandsCulledByFrustum\": " << commandsCulledByFrustum << ",\n"
        << "  \"commandsCulledByHorizon\": " << commandsCulledByHorizon << ",\n"
        << "  \"commandsExecuted\": " << commandsExecuted << ",\n"
        << "  \"commandsExecutedMoreThanOnce\": " << commandsExecutedMoreThanOnce << ",\n"
        << "  \"depthStrategy\": \"" << depthStrategyName(depthStrategy) << "\",\n"
        << "  \"depthStrategyAutomatic\": " << (depthStrategyAutomatic ? "true" : "false") << ",\n"
        << "  \"samples\": " << samples << ",\n"
        << "  \"frustumsReused\": " << (frustumsReused ? "true" : "false") << ",\n"
        << "  \"frustums\": [";
    for (std::size_t f = 0; f < frustums.size(); ++f) {
        out << (f ? ", " : "") << "{\"near\": " << number(frustums[f].nearDistance)
            << ", \"far\": " << number(frustums[f].farDistance) << ", \"drawCalls\": " << drawCallsPerFrustum[f] << "}";
    }
    out << "],\n"
        << "  \"passes\": {\"opaque\": " << opaquePasses << ", \"translucent\": " << translucentPasses
        << ", \"overlay\": " << overlayPasses << "},\n"
        << "  \"programsCompiled\": " << programsCompiled << ",\n"
        << "  \"effects\": [";
    const std::vector<std::string> names = effectsRun();
    for (std::size_t i = 0; i < names.size(); ++i) {
        out << (i ? ", " : "") << "\"" << names[i] << "\"";
    }
    out << "],\n"
        << "  \"milliseconds\": {\"update\": " << number(updateMilliseconds) << ", \"cullAndBin\": "
        << number(cullMilliseconds) << ", \"draw\": " << number(drawMilliseconds) << "},\n"
        << "  \"renderer\": {\"drawCalls\": " << renderer.drawCalls << ", \"primitives\": " << renderer.primitives
        << ", \"stateChangesMade\": " << renderer.stateChangesMade
        << ", \"stateChangesAvoided\": " << renderer.stateChangesAvoided << ", \"programBinds\": " << renderer.programBinds
        << ", \"textureBinds\": " << renderer.textureBinds << "}";
    if (tiles) {
        const TileStatistics& t = *tiles;
        out << ",\n  \"tiles\": {\"visited\": " << t.visited << ", \"culledByFrustum\": " << t.culledByFrustum
            << ", \"culledByHorizon\": " << t.culledByHorizon << ", \"selected\": " << t.selected
            << ", \"drawn\": " << t.drawn << ", \"standIns\": " << t.standIns
            << ", \"fallbackImagery\": " << t.fallbackImagery << ", \"morphing\": " << t.morphing << ", \"imageryDrawn\": " << t.imageryDrawn
            << ", \"requested\": " << t.requested
            << ", \"loadedThisFrame\": " << t.loadedThisFrame << ", \"pending\": " << t.pending
            << ", \"failed\": " << t.failed << ", \"missing\": " << t.missing << ", \"evicted\": " << t.evicted
            << ", \"residentBytesCpu\": " << t.residentBytesCpu << ", \"residentBytesGpu\": " << t.residentBytesGpu
            << ", \"uploadedBytes\": " << t.uploadedBytes << ", \"residentTiles\": " << t.residentTiles
            << ", \"residentImageryTiles\": " << t.residentImageryTiles << ", \"deepestLevelDrawn\": " << t.deepestLevelDrawn
            << ", \"largestScreenSpaceErrorDrawn\": " << number(t.largestScreenSpaceErrorDrawn)
            << ", \"maximumScreenSpaceError\": " << number(t.maximumScreenSpaceError)
            << ", \"memoryLimited\": " << (t.memoryLimited ? "true" : "false")
            << ", \"converged\": " << (t.converged ? "true" : "false") << "}";
    }
    if (virtualTexture) {
        const VirtualTextureStatistics& v = *virtualTexture;
        out << ",\n  \"virtualTexture\": {\"pagesWanted\": " << v.pagesWanted << ", \"pagesRequested\": " << v.pagesRequested
            << ", \"pagesLoaded\": " << v.pagesLoaded << ", \"pagesEvicted\": " << v.pagesEvicted
            << ", \"pagesResident\": " << v.pagesResident << ", \"physicalPages\": " << v.physicalPages
            << ", \"pagesPending\": " << v.pagesPending << ", \"pagesMissing\": " << v.pagesMissing
            << ", \"pagesFailed\": " << v.pagesFailed << ", \"fallbackPixels\": " << v.fallbackPixels
            << ", \"feedbackPixels\": " << v.feedbackPixels << ", \"fallbackFraction\": " << number(v.fallbackFraction)
            << ", \"feedbackLatencyFrames\": " << v.feedbackLatencyFrames << ", \"feedbackWidth\": " << v.feedbackWidth
            << ", \"feedbackHeight\": " << v.feedbackHeight << ", \"uploadedBytes\": " << v.uploadedBytes
            << ", \"lodBias\": " << number(v.lodBias) << ", \"lodBiasRaised\": " << (v.lodBiasRaised ? "true" : "false")
            << ", \"gpuBytes\": " << v.gpuBytes << ", \"tilesWithMipTail\": " << v.tilesWithMipTail
            << ", \"tilesBlendingLevels\": " << v.tilesBlendingLevels << ", \"sparse\": " << (v.sparse ? "true" : "false")
            << ", \"converged\": " << (v.converged ? "true" : "false") << "}";
    }
    if (clipmap) {
        const ClipmapStatistics& c = *clipmap;
        out << ",\n  \"clipmap\": {\"levels\": " << c.levels << ", \"finestLevelDrawn\": " << c.finestLevelDrawn
            << ", \"parameterization\": " << c.parameterization << ", \"postsUpdated\": " << c.postsUpdated
            << ", \"postsPending\": " << c.postsPending << ", \"levelsPending\": " << c.levelsPending
            << ", \"bytesUploaded\": " << c.bytesUploaded << ", \"drawCalls\": " << c.drawCalls
            << ", \"piecesCulled\": " << c.piecesCulled << ", \"trianglesSubmitted\": " << c.trianglesSubmitted
            << ", \"tilesRequested\": " << c.tilesRequested << ", \"tilesLoaded\": " << c.tilesLoaded
            << ", \"tilesPending\": " << c.tilesPending << ", \"gpuBytes\": " << c.gpuBytes
            << ", \"backdropDrawn\": " << (c.backdropDrawn ? "true" : "false")
            << ", \"updateMilliseconds\": " << number(c.updateMilliseconds)
            << ", \"converged\": " << (c.converged ? "true" : "false") << "}";
    }
    if (framesToConverge) {
        out << ",\n  \"framesToConverge\": " << *framesToConverge;
    } else if (tiles) {
        out << ",\n  \"framesToConverge\": null";
    }
    out << "\n}\n";
    return out.str();
}

} // namespace orbis::scene
