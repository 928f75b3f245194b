// Tile sources over HTTP against a server the test starts on 127.0.0.1 (tests/support/http). Every
// wait is bounded: timeouts of a few hundred milliseconds, backoffs of a few, and each fetch run
// where a hang would show as a failed wait.

#include "TestHttpServer.h"
#include "TempFiles.h"
#include "WorldTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/world/ImageCodec.h>
#include <orbis/world/TileMapResource.h>
#include <orbis/world/TileSource.h>

#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <future>
#include <thread>

using namespace orbis;
using namespace orbis::world;
using orbis::test::TempDirectory;
using orbis::test::ScriptedResponse;
using orbis::test::TestHttpServer;
using Catch::Matchers::Contains;
using Status = TileFetch::Status;

namespace {

std::vector<std::uint8_t> tileBytes(int seed)
{
    return encodePng(orbis::test::testPattern(16, 16 + seed, 3), 1);
}

/// Short timeouts and backoffs, so that every failure here takes well under a second.
TileSourceOptions fastOptions()
{
    TileSourceOptions options;
    options.http.connectTimeout = std::chrono::milliseconds(1000);
    options.http.totalTimeout = std::chrono::milliseconds(2000);
    options.http.retries = 3;
    options.http.backoff = std::chrono::milliseconds(5);
    options.http.maximumBackoff = std::chrono::milliseconds(20);
    return options;
}

/// fetch() where a hang fails the test after `seconds`.
TileFetch fetchWithin(TileSource& source, const TileKey& key, int seconds = 20)
{
    auto future = std::async(std::launch::async, [&] { return source.fetch(key); });
    REQUIRE(future.wait_for(std::chrono::seconds(seconds)) == std::future_status::ready);
    return future.get();
}

double secondsSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

TEST_CASE("HTTP tiles: 200 is Ok, 404 is Missing, each after one request", "[world][http]")
{
    TestHttpServer server;
    server.set("/tiles/1/0/0.png", ScriptedResponse::ok(tileBytes(0)));
    const auto source = openTileSource(server.url("/tiles/{z}/{x}/{y}.png"), fastOptions());
    const TileFetch ok = fetchWithin(*source, {1, 0, 0});
    REQUIRE(ok.status == Status::Ok);
    REQUIRE(ok.bytes == tileBytes(0));
    REQUIRE(ok.attempts == 1);
    const TileFetch missing = fetchWithin(*source, {1, 1, 0});
    REQUIRE(missing.status == Status::Missing);
    REQUIRE(missing.attempts == 1);
    REQUIRE(server.requests("/tiles/1/0/0.png") == 1);
    REQUIRE(server.requests("/tiles/1/1/0.png") == 1);
    // 204 No Content: no tile either.
    server.set("/tiles/1/1/1.png", ScriptedResponse::withStatus(204));
    REQUIRE(fetchWithin(*source, {1, 1, 1}).status == Status::Missing);
}

TEST_CASE("HTTP: a 500 is retried with backoff until it succeeds, and counted", "[world][http]")
{
    TestHttpServer server;
    ScriptedResponse flaky = ScriptedResponse::ok(tileBytes(1));
    flaky.failuresFirst = 2;
    server.set("/0/0/0.png", flaky);
    TileSourceOptions options = fastOptions();
    options.http.backoff = std::chrono::milliseconds(40);
    options.http.maximumBackoff = std::chrono::milliseconds(1000);
    const auto source = openTileSource(server.url("/{z}/{x}/{y}.png"), options);
    const auto start = std::chrono::steady_clock::now();
    const TileFetch fetched = fetchWithin(*source, {0, 0, 0});
    REQUIRE(fetched.status == Status::Ok);
    REQUIRE(fetched.bytes == tileBytes(1));
    REQUIRE(fetched.attempts == 3);
    REQUIRE(server.requests("/0/0/0.png") == 3);
    // Waited 40 ms, then 80 ms: the backoff doubles.
    REQUIRE(secondsSince(start) >= 0.12);
}

TEST_CASE("HTTP: a server that keeps failing gives Failed naming the URL after the retries", "[world][http]")
{
    TestHttpServer server;
    ScriptedResponse broken = ScriptedResponse::withStatus(500);
    broken.failuresFirst = 1000;
    server.set("/0/0/0.png", broken);
    server.set("/1/1/0.png", ScriptedResponse::withStatus(403));
    server.set("/1/0/0.png", ScriptedResponse::withStatus(503));
    const auto source = openTileSource(server.url("/{z}/{x}/{y}.png"), fastOptions());
    const TileFetch failed = fetchWithin(*source, {0, 0, 0});
    REQUIRE(failed.status == Status::Failed);
    REQUIRE_THAT(failed.message, Contains(server.url("/0/0/0.png") + ": HTTP 500 (after 4 attempts)"));
    REQUIRE(server.requests("/0/0/0.png") == 4);
    // A 4xx other than 404 is the client's fault: not retried.
    const TileFetch forbidden = fetchWithin(*source, {1, 1, 0});
    REQUIRE(forbidden.status == Status::Failed);
    REQUIRE_THAT(forbidden.message, Contains(server.url("/1/1/0.png") + ": HTTP 403"));
    REQUIRE(server.requests("/1/1/0.png") == 1);
    REQUIRE(fetchWithin(*source, {1, 0, 0}).attempts == 4);
}

TEST_CASE("HTTP: a truncated body is a broken connection, retried until whole or Failed", "[world][http][hostile]")
{
    TestHttpServer server;
    ScriptedResponse cut = ScriptedResponse::ok(tileBytes(2));
    cut.truncateAfter = 40;
    server.set("/0/0/0.png", cut);
    ScriptedResponse cutTwice = ScriptedResponse::ok(tileBytes(3));
    cutTwice.truncatedFirst = 2;
    server.set("/1/1/0.png", cutTwice);
    const auto source = openTileSource(server.url("/{z}/{x}/{y}.png"), fastOptions());
    const TileFetch failed = fetchWithin(*source, {0, 0, 0});
    REQUIRE(failed.status == Status::Failed);
    REQUIRE_THAT(failed.message, Contains(server.url("/0/0/0.png") + ": the response was cut short"));
    REQUIRE_THAT(failed.message, Contains("(after 4 attempts)"));
    REQUIRE(server.requests("/0/0/0.png") == 4);
    const TileFetch third = fetchWithin(*source, {1, 1, 0});
    REQUIRE(third.bytes == tileBytes(3));
    REQUIRE(third.attempts == 3);
}

TEST_CASE("HTTP: corrupt tile bytes arrive Ok and the decoder names the URL", "[world][http][hostile]")
{
    TestHttpServer server;
    std::vector<std::uint8_t> corrupt = tileBytes(4);
    corrupt[corrupt.size() / 2] ^= 0xFF;
    server.set("/2/1/1.png", ScriptedResponse::ok(corrupt));
    server.set("/2/1/2.png", ScriptedResponse::ok({'<', 'h', 't', 'm', 'l', '>'}));
    const auto source = openTileSource(server.url("/{z}/{x}/{y}.png"), fastOptions());
    for (const TileKey key : {TileKey{2, 1, 1}, TileKey{2, 1, 2}}) {
        const TileFetch fetched = fetchWithin(*source, key);
        REQUIRE(fetched.status == Status::Ok);
        REQUIRE_THROWS_WITH(decodeImage(fetched.bytes, source->locate(key)), Contains(source->locate(key) + ": "));
    }
}

TEST_CASE("HTTP: a slow server times out, is not retried, and nothing hangs", "[world][http][hostile]")
{
    TestHttpServer server;
    ScriptedResponse slow = ScriptedResponse::ok(tileBytes(5));
    slow.delay = std::chrono::milliseconds(10000);
    server.set("/0/0/0.png", slow);
    ScriptedResponse late = ScriptedResponse::ok(tileBytes(5));
    late.delay = std::chrono::milliseconds(100);
    server.set("/1/1/0.png", late);
    TileSourceOptions options = fastOptions();
    options.http.totalTimeout = std::chrono::milliseconds(400);
    const auto source = openTileSource(server.url("/{z}/{x}/{y}.png"), options);
    const auto start = std::chrono::steady_clock::now();
    const TileFetch timedOut = fetchWithin(*source, {0, 0, 0});
    REQUIRE(timedOut.status == Status::Failed);
    REQUIRE_THAT(timedOut.message, Contains(server.url("/0/0/0.png") + ": timed out"));
    REQUIRE(timedOut.attempts == 1);
    REQUIRE(secondsSince(start) < 5.0);
    // Slow but within the limit: Ok.
    REQUIRE(fetchWithin(*source, {1, 1, 0}).status == Status::Ok);
}

TEST_CASE("HTTP: no more requests are in flight than allowed, as the server sees them", "[world][http][threads]")
{
    TestHttpServer server;
    for (int x = 0; x < 16; ++x) {
        ScriptedResponse slow = ScriptedResponse::ok(tileBytes(x));
        slow.delay = std::chrono::milliseconds(40);
        server.set("/4/" + std::to_string(x) + "/0.png", slow);
    }
    TileSourceOptions options = fastOptions();
    options.http.maximumRequestsInFlight = 2;
    const auto source = openTileSource(server.url("/{z}/{x}/{y}.png"), options);
    std::atomic<int> ok{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < 8; ++t) {
        threads.emplace_back([&, t] {
            for (std::uint32_t x = static_cast<std::uint32_t>(t) * 2; x < static_cast<std::uint32_t>(t) * 2 + 2; ++x) {
                ok += source->fetch({4, x, 0}).bytes == tileBytes(static_cast<int>(x)) ? 1 : 0;
            }
        });
    }
    for (std::thread& thread : threads) {
        thread.join();
    }
    REQUIRE(ok == 16);
    REQUIRE(server.totalRequests() == 16);
    // Eight threads wanting 40 ms answers: the two allowed were in use together, never more.
    REQUIRE(server.maximumConcurrent() == 2);
}

TEST_CASE("HTTP: a server stopping mid-run fails the remaining tiles by name, and nothing hangs", "[world][http][hostile]")
{
    auto server = std::make_unique<TestHttpServer>();
    const std::string url = server->url("/{z}/{x}/{y}.png");
    for (int x = 0; x < 64; ++x) {
        ScriptedResponse response = ScriptedResponse::ok(tileBytes(x % 8));
        response.delay = std::chrono::milliseconds(5);
        server->set("/6/" + std::to_string(x) + "/0.png", response);
    }
    TileSourceOptions options = fastOptions();
    options.http.retries = 2;
    const auto source = openTileSource(url, options);
    std::atomic<int> ok{0};
    std::atomic<int> failed{0};
    std::atomic<int> unnamed{0};
    std::atomic<std::uint32_t> next{0};
    auto work = [&] {
        for (std::uint32_t x; (x = next++) < 64;) {
            const TileFetch fetched = source->fetch({6, x, 0});
            if (fetched.status == Status::Ok) {
                ++ok;
            } else {
                ++failed;
                if (fetched.message.find(source->locate({6, x, 0}) + ": ") == std::string::npos) {
                    ++unnamed;
                }
            }
        }
    };
    std::vector<std::future<void>> workers;
    for (int t = 0; t < 4; ++t) {
        workers.push_back(std::async(std::launch::async, work));
    }
    const auto start = std::chrono::steady_clock::now();
    while (server->totalRequests() < 12 && secondsSince(start) < 10.0) {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    server->stop();
    for (auto& worker : workers) {
        REQUIRE(worker.wait_for(std::chrono::seconds(30)) == std::future_status::ready);
    }
    server.reset();
    REQUIRE(ok + failed == 64);
    REQUIRE(ok >= 8);
    REQUIRE(failed >= 40);
    REQUIRE(unnamed == 0);
    // Refused connections are retried too: a server that went away gets the retries, then Failed.
    const TileFetch after = fetchWithin(*source, {6, 63, 0});
    REQUIRE(after.status == Status::Failed);
    REQUIRE(after.attempts == 3);
    REQUIRE_THAT(after.message, Contains("cannot connect"));
}

TEST_CASE("HTTP: keys outside the source are Missing without a request", "[world][http]")
{
    TestHttpServer server;
    TileSourceOptions options = fastOptions();
    options.maximumLevel = 3;
    options.extent = GeodeticExtent::fromDegrees(0.0, 0.0, 10.0, 10.0);
    const auto source = openTileSource(server.url("/{z}/{x}/{y}.png"), options);
    REQUIRE(source->fetch({4, 0, 0}).status == Status::Missing);
    REQUIRE(source->fetch({2, 0, 0}).status == Status::Missing); // the north-west, far from the extent
    REQUIRE(source->fetch({0, 1, 0}).status == Status::Missing); // no such column
    REQUIRE(server.totalRequests() == 0);
}

TEST_CASE("HTTP: the disk cache serves a second run without the server", "[world][http][cache]")
{
    const TempDirectory cache;
    auto server = std::make_unique<TestHttpServer>();
    server->set("/1/0/0.png", ScriptedResponse::ok(tileBytes(6)));
    server->set("/1/1/0.png", ScriptedResponse::ok(tileBytes(7)));
    ScriptedResponse broken = ScriptedResponse::withStatus(500);
    broken.failuresFirst = 1000;
    server->set("/1/1/1.png", broken);
    const std::string url = server->url("/{z}/{x}/{y}.png");
    TileSourceOptions options = fastOptions();
    options.cacheFolder = cache.path();
    {
        const auto source = openTileSource(url, options);
        REQUIRE(fetchWithin(*source, {1, 0, 0}).status == Status::Ok);
        REQUIRE_FALSE(source->fetch({1, 0, 0}).attempts > 0); // the second fetch is the cache's
        REQUIRE(fetchWithin(*source, {1, 1, 0}).status == Status::Ok);
        REQUIRE(fetchWithin(*source, {1, 0, 1}).status == Status::Missing);
        REQUIRE(fetchWithin(*source, {1, 1, 1}).status == Status::Failed);
    }
    REQUIRE(server->requests("/1/0/0.png") == 1);
    server.reset(); // the server is gone: its port refuses connections

    const auto offline = openTileSource(url, options);
    const TileFetch cached = fetchWithin(*offline, {1, 0, 0});
    REQUIRE(cached.status == Status::Ok);
    REQUIRE(cached.fromCache);
    REQUIRE(cached.bytes == tileBytes(6));
    REQUIRE(fetchWithin(*offline, {1, 1, 0}).bytes == tileBytes(7));
    const TileFetch missing = fetchWithin(*offline, {1, 0, 1});
    REQUIRE(missing.status == Status::Missing);
    REQUIRE(missing.fromCache);
    // A failure is not cached: without the server it fails again, by name.
    const TileFetch failed = fetchWithin(*offline, {1, 1, 1});
    REQUIRE(failed.status == Status::Failed);
    REQUIRE_THAT(failed.message, Contains("/1/1/1.png: cannot connect"));
    // Nothing temporary left in the cache.
    for (const auto& entry : std::filesystem::recursive_directory_iterator(cache.path())) {
        REQUIRE(entry.path().string().find(".tmp-") == std::string::npos);
    }

    // The folder belongs to that URL.
    REQUIRE_THROWS_WITH(openTileSource("http://127.0.0.1:9/{z}/{x}/{y}.png", options),
                        Contains("the cache folder belongs to " + url));
}

TEST_CASE("HTTP: a TMS pyramid reads its description from the server, also from the cache later", "[world][http][tms]")
{
    const TempDirectory cache;
    auto server = std::make_unique<TestHttpServer>();
    TileMapResource resource;
    resource.extension = "png";
    resource.attribution = "served";
    resource.tileSets = {{"0", 0, tileMapUnitsPerPixel(TilingScheme::geographic(), 0, 256)},
                         {"1", 1, tileMapUnitsPerPixel(TilingScheme::geographic(), 1, 256)}};
    const std::string xml = formatTileMapResource(resource);
    server->set("/pyramid/tilemapresource.xml", ScriptedResponse::ok({xml.begin(), xml.end()}));
    server->set("/pyramid/1/3/0.png", ScriptedResponse::ok(tileBytes(8)));
    server->set("/bad/tilemapresource.xml", ScriptedResponse::ok({'<', 'T', 'i', 'l', 'e', 'M', 'a', 'p', '>'}));
    const std::string url = server->url("/pyramid");
    TileSourceOptions options = fastOptions();
    options.cacheFolder = cache.path();
    {
        const auto source = openTileSource(url, options);
        REQUIRE(source->info().maximumLevel == 1);
        REQUIRE(source->info().attribution == "served");
        REQUIRE(source->locate({1, 3, 0}) == url + "/1/3/0.png");
        REQUIRE(fetchWithin(*source, {1, 3, 0}).bytes == tileBytes(8));
    }
    REQUIRE(openTileSource(url + "/tilemapresource.xml", fastOptions())->info().maximumLevel == 1);
    REQUIRE_THROWS_WITH(openTileSource(server->url("/none"), fastOptions()),
                        Contains(server->url("/none/tilemapresource.xml") + ": no such file (HTTP 404)"));
    REQUIRE_THROWS_WITH(openTileSource(server->url("/bad"), fastOptions()),
                        Contains(server->url("/bad/tilemapresource.xml") + ":1:") && Contains("the file ends inside <TileMap>"));
    server.reset();
    const auto offline = openTileSource(url, options);
    REQUIRE(fetchWithin(*offline, {1, 3, 0}).bytes == tileBytes(8));
    REQUIRE_THROWS_WITH(openTileSource(url + "x", fastOptions()), Contains("/pyramidx/tilemapresource.xml: cannot connect"));
}
