#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace orbis::scene {

/// A command's extent along the view direction, in metres from the eye.
struct DepthInterval {
    double nearDistance;
    double farDistance;
};

/// One frustum's near and far distances, in metres from the eye.
struct FrustumRange {
    double nearDistance;
    double farDistance;
};

struct MultiFrustumOptions {
    double farToNearRatio = 1000.0; ///< at most this far/near per frustum (24-bit depth)
    double nearLimit = 1.0;          ///< no frustum starts closer than this
    double farLimit = 1e10;          ///< nor ends farther than this (10 million km)
    /// Each frustum but the nearest starts this fraction closer, so neighbours overlap and no
    /// tear shows where they meet (course notes, "Multiple Frustum Artifacts").
    double overlap = 0.01;

    friend bool operator==(const MultiFrustumOptions&, const MultiFrustumOptions&) = default;
};

/// Dynamic multiple frustums (SIGGRAPH 2013 course, chapter 2): the near and far distances come
/// from the commands' depth intervals, clamped to the limits, and are split into the fewest
/// frustums whose far/near stays under the ratio: ceil(log(far/near) / log(ratio)). Each command
/// is binned into every frustum it overlaps. Binning is one pass over the commands while last
/// frame's frustums still fit (desired near >= previous near, desired far <= previous far, same
/// frustum count); otherwise the frustums are recomputed and the commands binned again.
class MultiFrustum final {
public:
    explicit MultiFrustum(const MultiFrustumOptions& options = {}) : _options(options) {}

    const MultiFrustumOptions& options() const noexcept { return _options; }
    void setOptions(const MultiFrustumOptions& options);

    /// Bins the commands; bins()[f] lists, in submission order, the indices of the commands that
    /// overlap frustum f. Frustum 0 is the nearest. No commands: no frustums.
    void bin(std::span<const DepthInterval> commands);

    const std::vector<FrustumRange>& frustums() const noexcept { return _frustums; }
    const std::vector<std::vector<std::uint32_t>>& bins() const noexcept { return _bins; }
    /// Whether the last bin() kept the previous frustums (one pass) or recomputed them.
    bool reused() const noexcept { return _reused; }
    /// The near and far distances the last bin() found the commands to span, clamped to the
    /// limits (the frustums may be wider when last frame's were reused); 0..0 with no commands.
    FrustumRange desiredRange() const noexcept { return _desired; }
    /// Commands binned into more than one frustum by the last bin(), each counted once.
    std::size_t commandsInSeveralFrustums() const noexcept { return _commandsInSeveralFrustums; }

    /// The number of frustums for a depth range: ceil(log(far / near) / log(ratio)), at least 1.
    static std::size_t frustumCount(double nearDistance, double farDistance, double farToNearRatio) noexcept;

private:
    void computeFrustums(double nearDistance, double farDistance);
    void clearBins();
    void binCommand(std::uint32_t index, const DepthInterval& interval);

    MultiFrustumOptions _options;
    std::vector<FrustumRange> _frustums;
    std::vector<std::vector<std::uint32_t>> _bins;
    double _near = 0.0; ///< the unclamped-by-overlap range the frustums were computed for
    double _far = 0.0;
    bool _reused = false;
    std::size_t _commandsInSeveralFrustums = 0;
    FrustumRange _desired{0.0, 0.0};
};

} // namespace orbis::scene
