#include "orbis/scene/MultiFrustum.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace orbis::scene {

void MultiFrustum::setOptions(const MultiFrustumOptions& options)
{
    assert(options.farToNearRatio > 1.0 && options.nearLimit > 0.0 && options.farLimit > options.nearLimit);
    _options = options;
    _frustums.clear(); // the next bin() computes afresh
}

std::size_t MultiFrustum::frustumCount(double nearDistance, double farDistance, double farToNearRatio) noexcept
{
    if (!(farDistance > nearDistance) || !(nearDistance > 0.0)) {
        return 1;
    }
    // The small relative slack keeps an exact power of the ratio from rounding up to one more.
    const double count = std::ceil(std::log(farDistance / nearDistance) / std::log(farToNearRatio) - 1e-12);
    return static_cast<std::size_t>(std::max(1.0, count));
}

void MultiFrustum::computeFrustums(double nearDistance, double farDistance)
{
    _near = nearDistance;
    _far = farDistance;
    const std::size_t count = frustumCount(nearDistance, farDistance, _options.farToNearRatio);
    _frustums.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
        const double start = nearDistance * std::pow(_options.farToNearRatio, static_cast<double>(i));
        const double end = std::min(farDistance, start * _options.farToNearRatio);
        _frustums[i] = {i == 0 ? start : start * (1.0 - _options.overlap), i + 1 == count ? farDistance : end};
    }
}

void MultiFrustum::clearBins()
{
    _bins.resize(_frustums.size());
    for (auto& bin : _bins) {
        bin.clear(); // keeps last frame's capacity
    }
    _commandsInSeveralFrustums = 0;
}

void MultiFrustum::binCommand(std::uint32_t index, const DepthInterval& interval)
{
    std::size_t binned = 0;
    for (std::size_t f = 0; f < _frustums.size(); ++f) {
        if (interval.nearDistance < _frustums[f].farDistance && interval.farDistance > _frustums[f].nearDistance) {
            _bins[f].push_back(index);
            ++binned;
        }
    }
    _commandsInSeveralFrustums += binned > 1 ? 1 : 0;
}

void MultiFrustum::bin(std::span<const DepthInterval> commands)
{
    if (commands.empty()) {
        _frustums.clear();
        _bins.clear();
        _reused = false;
        _commandsInSeveralFrustums = 0;
        _desired = {0.0, 0.0};
        return;
    }

    // One pass: bin into last frame's frustums while finding the range this frame wants.
    double nearest = std::numeric_limits<double>::infinity();
    double farthest = 0.0;
    const bool havePrevious = !_frustums.empty();
    clearBins();
    for (std::uint32_t index = 0; index < commands.size(); ++index) {
        nearest = std::min(nearest, commands[index].nearDistance);
        farthest = std::max(farthest, commands[index].farDistance);
        if (havePrevious) {
            binCommand(index, commands[index]);
        }
    }
    const double desiredNear = std::clamp(nearest, _options.nearLimit, _options.farLimit);
    const double desiredFar = std::clamp(farthest, desiredNear, _options.farLimit);
    _desired = {desiredNear, desiredFar};

    _reused = havePrevious && desiredNear >= _near && desiredFar <= _far &&
              frustumCount(desiredNear, desiredFar, _options.farToNearRatio) == _frustums.size();
    if (!_reused) {
        computeFrustums(desiredNear, desiredFar);
        clearBins();
        for (std::uint32_t index = 0; index < commands.size(); ++index) {
            binCommand(index, commands[index]);
        }
    }
}

} // namespace orbis::scene
