#include <orbis/scene/MultiFrustum.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

using namespace orbis;
using namespace orbis::scene;

namespace {

std::vector<DepthInterval> randomIntervals(std::mt19937_64& random, std::size_t count)
{
    std::uniform_real_distribution<double> exponent(0.0, 9.0);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<DepthInterval> intervals;
    for (std::size_t i = 0; i < count; ++i) {
        const double centre = std::pow(10.0, exponent(random));
        const double radius = centre * unit(random) * (i % 3 == 0 ? 2.0 : 0.1);
        intervals.push_back({centre - radius, centre + radius});
    }
    return intervals;
}

} // namespace

TEST_CASE("MultiFrustum uses ceil(log(far/near)/log(ratio)) frustums covering the range with overlap", "[scene][multifrustum]")
{
    const auto seed = GENERATE(take(3, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    MultiFrustum multiFrustum;
    const MultiFrustumOptions& options = multiFrustum.options();
    for (int frame = 0; frame < 50; ++frame) {
        const std::vector<DepthInterval> intervals = randomIntervals(random, 20);
        multiFrustum.bin(intervals);
        double nearest = HUGE_VAL;
        double farthest = 0.0;
        for (const DepthInterval& interval : intervals) {
            nearest = std::min(nearest, interval.nearDistance);
            farthest = std::max(farthest, interval.farDistance);
        }
        nearest = std::clamp(nearest, options.nearLimit, options.farLimit);
        farthest = std::clamp(farthest, nearest, options.farLimit);
        const auto& frustums = multiFrustum.frustums();
        if (!multiFrustum.reused()) {
            REQUIRE(frustums.size() ==
                    std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(std::log(farthest / nearest) /
                                                                                 std::log(options.farToNearRatio) -
                                                                                 1e-12))));
            REQUIRE(frustums.front().nearDistance == nearest);
            REQUIRE(frustums.back().farDistance == farthest);
        }
        REQUIRE(frustums.front().nearDistance <= nearest);
        REQUIRE(frustums.back().farDistance >= farthest);
        for (std::size_t f = 0; f < frustums.size(); ++f) {
            // Each ratio stays within the limit, stretched only by the overlap.
            REQUIRE(frustums[f].farDistance / frustums[f].nearDistance <=
                    options.farToNearRatio / (1.0 - options.overlap) * (1 + 1e-12));
            if (f > 0) {
                REQUIRE(frustums[f].nearDistance < frustums[f - 1].farDistance); // overlap, no tear
            }
        }
    }
}

TEST_CASE("MultiFrustum bins every command into exactly the frustums it overlaps", "[scene][multifrustum]")
{
    const auto seed = GENERATE(take(3, random(0u, 1000000u)));
    INFO("seed " << seed);
    std::mt19937_64 random(seed);
    MultiFrustum multiFrustum;
    for (int frame = 0; frame < 30; ++frame) {
        const std::vector<DepthInterval> intervals = randomIntervals(random, 200);
        multiFrustum.bin(intervals);
        const auto& frustums = multiFrustum.frustums();
        const auto& bins = multiFrustum.bins();
        REQUIRE(bins.size() == frustums.size());
        std::size_t several = 0;
        for (std::uint32_t i = 0; i < intervals.size(); ++i) {
            std::size_t in = 0;
            for (std::size_t f = 0; f < frustums.size(); ++f) {
                const bool overlaps = intervals[i].nearDistance < frustums[f].farDistance &&
                                      intervals[i].farDistance > frustums[f].nearDistance;
                const bool binned = std::find(bins[f].begin(), bins[f].end(), i) != bins[f].end();
                REQUIRE(overlaps == binned);
                in += binned ? 1 : 0;
            }
            several += in > 1 ? 1 : 0;
        }
        REQUIRE(multiFrustum.commandsInSeveralFrustums() == several);
    }
}

TEST_CASE("MultiFrustum reuses last frame's frustums when, and only when, they still fit", "[scene][multifrustum]")
{
    MultiFrustum multiFrustum;
    multiFrustum.bin(std::vector<DepthInterval>{{10.0, 20.0}, {1e5, 2e5}});
    REQUIRE_FALSE(multiFrustum.reused()); // the first frame has nothing to reuse
    REQUIRE(multiFrustum.frustums().size() == 2); // 10 .. 2e5: log(2e4)/log(1e3) = 1.43

    multiFrustum.bin(std::vector<DepthInterval>{{10.0, 20.0}, {1e5, 2e5}});
    REQUIRE(multiFrustum.reused()); // same scene

    multiFrustum.bin(std::vector<DepthInterval>{{12.0, 20.0}, {1e5, 1.5e5}});
    REQUIRE(multiFrustum.reused()); // nearer bound moved out, farther moved in, still 2 frustums

    multiFrustum.bin(std::vector<DepthInterval>{{5.0, 20.0}, {1e5, 1.5e5}});
    REQUIRE_FALSE(multiFrustum.reused()); // something came closer than the old near plane
    REQUIRE(multiFrustum.frustums().front().nearDistance == 5.0);

    multiFrustum.bin(std::vector<DepthInterval>{{5.0, 20.0}, {1e5, 3e5}});
    REQUIRE_FALSE(multiFrustum.reused()); // something reached beyond the old far plane

    multiFrustum.bin(std::vector<DepthInterval>{{50.0, 20.0e3}});
    REQUIRE_FALSE(multiFrustum.reused()); // inside the old range, but one frustum now suffices
    REQUIRE(multiFrustum.frustums().size() == 1);
}

TEST_CASE("MultiFrustum draws a command straddling two frustums in both and counts it once", "[scene][multifrustum]")
{
    MultiFrustum multiFrustum;
    // 1 .. 1e6: frustums [1, 1000] and [990, 1e6]. The second command spans the boundary.
    multiFrustum.bin(std::vector<DepthInterval>{{1.0, 2.0}, {500.0, 5000.0}, {1e5, 1e6}});
    REQUIRE(multiFrustum.frustums().size() == 2);
    REQUIRE(multiFrustum.bins()[0] == std::vector<std::uint32_t>{0, 1});
    REQUIRE(multiFrustum.bins()[1] == std::vector<std::uint32_t>{1, 2});
    REQUIRE(multiFrustum.commandsInSeveralFrustums() == 1);
}

TEST_CASE("MultiFrustum clamps to its limits and handles no commands", "[scene][multifrustum][hard]")
{
    MultiFrustum multiFrustum;
    multiFrustum.bin(std::vector<DepthInterval>{});
    REQUIRE(multiFrustum.frustums().empty());
    // A sphere around the eye starts behind it: the near plane stops at the limit.
    multiFrustum.bin(std::vector<DepthInterval>{{-1e7, 1e7}, {1e20, 2e20}});
    REQUIRE(multiFrustum.frustums().front().nearDistance == multiFrustum.options().nearLimit);
    REQUIRE(multiFrustum.frustums().back().farDistance == multiFrustum.options().farLimit);
    REQUIRE(multiFrustum.frustums().size() == 4); // 1 .. 1e10 with ratio 1000: ceil(3.33)
}
