#include <orbis/world/TileLoader.h>

#include <orbis/core/Error.h>

#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

using orbis::world::TileContent;
using orbis::world::TileLoader;
using orbis::world::TileLoaderOptions;
using orbis::world::TileLoadResult;

namespace {

struct Number final : TileContent {
    explicit Number(std::uint64_t value_) : value(value_) {}
    std::size_t byteSize() const noexcept override { return sizeof value; }
    std::uint64_t value;
};

/// Busy work of a length that varies per ticket, so that loads finish out of order on threads.
std::uint64_t spin(std::uint64_t ticket)
{
    std::uint64_t x = ticket * 2654435761u + 1;
    const std::uint64_t rounds = 2000 + (ticket * 7919) % 40000;
    for (std::uint64_t i = 0; i < rounds; ++i) {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
    }
    return x;
}

/// What a loader delivered: frame, ticket and value, in delivery order.
struct Delivery {
    std::uint64_t frame;
    std::uint64_t ticket;
    TileLoadResult::Status status;
    std::uint64_t value;
    friend bool operator==(const Delivery&, const Delivery&) = default;
};

/// Drives a loader for `frames` frames: each frame offers the tickets the script names, with
/// priorities from a seeded generator; returns every delivery.
std::vector<Delivery> drive(TileLoaderOptions options, int frames, std::uint64_t seed)
{
    TileLoader loader(options);
    std::mt19937_64 random(seed);
    std::vector<Delivery> deliveries;
    std::uint64_t next = 1;
    for (int frame = 0; frame < frames; ++frame) {
        for (TileLoadResult& result : loader.beginFrame(frame)) {
            const std::uint64_t value = result.content ? static_cast<const Number&>(*result.content).value : 0;
            deliveries.push_back({static_cast<std::uint64_t>(frame), result.ticket, result.status, value});
        }
        // New tickets and some old ones offered again (they were deferred).
        const int offers = static_cast<int>(random() % 12);
        for (int i = 0; i < offers; ++i) {
            const std::uint64_t ticket = random() % 3 == 0 && next > 8 ? 1 + random() % (next - 1) : next++;
            if (loader.isLoading(ticket)) {
                continue;
            }
            const double priority = static_cast<double>(random() % 5);
            loader.request(ticket, priority, [ticket]() -> std::unique_ptr<TileContent> {
                const std::uint64_t value = spin(ticket);
                if (ticket % 11 == 0) {
                    return nullptr;
                }
                if (ticket % 13 == 0) {
                    throw orbis::Error("tile " + std::to_string(ticket) + ": corrupt");
                }
                return std::make_unique<Number>(value);
            });
        }
        loader.endFrame();
        // Now and then the newest load is cancelled (if it started).
        if (frame % 7 == 3) {
            loader.cancel(next - 1);
        }
    }
    return deliveries;
}

} // namespace

TEST_CASE("TileLoader delivers the same results in the same frames with 0, 1, 2 and 4 threads", "[world][loader]")
{
    for (int latency : {1, 3}) {
        TileLoaderOptions options;
        options.latencyFrames = latency;
        options.maximumStartsPerFrame = 4;
        options.maximumInFlight = 9;
        options.workerThreads = 0;
        const std::vector<Delivery> reference = drive(options, 120, 99);
        REQUIRE(reference.size() > 100);
        for (int threads : {1, 2, 4}) {
            options.workerThreads = threads;
            INFO("latency " << latency << ", threads " << threads);
            CHECK(drive(options, 120, 99) == reference);
        }
    }
}

TEST_CASE("TileLoader starts the smallest priorities first, ties by ticket, within its limits", "[world][loader]")
{
    TileLoaderOptions options;
    options.workerThreads = 0;
    options.latencyFrames = 1;
    options.maximumStartsPerFrame = 3;
    options.maximumInFlight = 5;
    TileLoader loader(options);
    auto work = [](std::uint64_t value) {
        return [value] { return std::unique_ptr<TileContent>(std::make_unique<Number>(value)); };
    };
    REQUIRE(loader.beginFrame(0).empty());
    loader.request(40, 2.0, work(40));
    loader.request(10, 1.0, work(10));
    loader.request(30, 0.5, work(30));
    loader.request(20, 1.0, work(20));
    loader.endFrame();
    CHECK(loader.startedLastFrame() == 3);
    CHECK(loader.deferred() == 1);
    CHECK(loader.inFlight() == 3);

    // Frame 1: the three started in frame 0 arrive in start order (30, 10, 20); 40 was forgotten.
    std::vector<TileLoadResult> results = loader.beginFrame(1);
    REQUIRE(results.size() == 3);
    CHECK(results[0].ticket == 30);
    CHECK(results[1].ticket == 10);
    CHECK(results[2].ticket == 20);
    CHECK(loader.inFlight() == 0);
    CHECK(loader.beginFrame(2).empty());

    // The in-flight limit: five at most, whatever is offered.
    for (std::uint64_t t = 100; t < 110; ++t) {
        loader.request(t, 0.0, work(t));
    }
    loader.endFrame();
    CHECK(loader.startedLastFrame() == 3);
    for (std::uint64_t t = 103; t < 110; ++t) {
        loader.request(t, 0.0, work(t));
    }
    // Still frame 2: the loader has not begun a new frame, so nothing was delivered.
    loader.endFrame();
    CHECK(loader.startedLastFrame() == 2);
    CHECK(loader.inFlight() == 5);
    CHECK(loader.deferred() == 5);
}

TEST_CASE("TileLoader holds deterministic results until their frame, and reports missing and failed tiles",
          "[world][loader]")
{
    TileLoaderOptions options;
    options.workerThreads = 2;
    options.latencyFrames = 3;
    TileLoader loader(options);
    REQUIRE(loader.beginFrame(10).empty());
    loader.request(1, 0.0, [] { return std::unique_ptr<TileContent>(std::make_unique<Number>(7)); });
    loader.request(2, 0.0, []() -> std::unique_ptr<TileContent> { return nullptr; });
    loader.request(3, 0.0, []() -> std::unique_ptr<TileContent> { throw orbis::Error("http://127.0.0.1/3.png: HTTP 500"); });
    loader.endFrame();
    CHECK(loader.beginFrame(11).empty());
    CHECK(loader.beginFrame(12).empty());
    const std::vector<TileLoadResult> results = loader.beginFrame(13);
    REQUIRE(results.size() == 3);
    CHECK(results[0].status == TileLoadResult::Status::Loaded);
    CHECK(static_cast<const Number&>(*results[0].content).value == 7);
    CHECK(results[1].status == TileLoadResult::Status::Missing);
    CHECK(results[2].status == TileLoadResult::Status::Failed);
    CHECK(results[2].message == "http://127.0.0.1/3.png: HTTP 500");
}

TEST_CASE("TileLoader drops cancelled loads, skips their work if it has not begun, and takes the ticket again",
          "[world][loader]")
{
    TileLoaderOptions options;
    options.workerThreads = 0;
    options.latencyFrames = 1;
    TileLoader loader(options);
    std::atomic<int> ran{0};
    auto work = [&ran] {
        ++ran;
        return std::unique_ptr<TileContent>(std::make_unique<Number>(1));
    };
    loader.beginFrame(0);
    loader.request(5, 0.0, work);
    loader.request(6, 0.0, work);
    loader.endFrame();
    loader.cancel(5);
    CHECK(loader.inFlight() == 1);
    loader.request(5, 0.0, work); // wanted again: a new load
    loader.endFrame();
    const std::vector<TileLoadResult> results = loader.beginFrame(1);
    REQUIRE(results.size() == 2);
    CHECK(results[0].ticket == 6);
    CHECK(results[1].ticket == 5);
    CHECK(ran == 2); // the cancelled load never ran
    CHECK(loader.inFlight() == 0);
}

TEST_CASE("TileLoader in asynchronous timing delivers each result once, whenever it is done", "[world][loader]")
{
    TileLoaderOptions options;
    options.workerThreads = 2;
    options.latencyFrames = 0;
    options.maximumStartsPerFrame = 64;
    TileLoader loader(options);
    loader.beginFrame(0);
    for (std::uint64_t t = 0; t < 50; ++t) {
        loader.request(t, static_cast<double>(t), [t] { return std::unique_ptr<TileContent>(std::make_unique<Number>(spin(t))); });
    }
    loader.endFrame();
    std::map<std::uint64_t, int> seen;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    for (std::uint64_t frame = 1; seen.size() < 50 && std::chrono::steady_clock::now() < deadline; ++frame) {
        for (const TileLoadResult& result : loader.beginFrame(frame)) {
            ++seen[result.ticket];
            CHECK(static_cast<const Number&>(*result.content).value == spin(result.ticket));
        }
        std::this_thread::yield();
    }
    REQUIRE(seen.size() == 50);
    for (const auto& [ticket, count] : seen) {
        CHECK(count == 1);
    }
}
