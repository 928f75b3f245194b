#include "TempFiles.h"
#include "WorldTestSupport.h"

#include <orbis/core/Error.h>
#include <orbis/world/FileAccess.h>

#include <catch2/catch.hpp>

#include <chrono>
#include <future>
#include <thread>

#include <sys/stat.h>

using namespace orbis;
using namespace orbis::world;
using orbis::test::TempDirectory;
using Catch::Matchers::Contains;

TEST_CASE("Files are read whole, and a missing one is told apart from a broken one", "[world][files]")
{
    const TempDirectory folder;
    writeFileAtomically(folder.path() / "a/b/tile.bin", std::string_view("hello"));
    const std::vector<std::uint8_t> bytes = readFileBytes(folder.path() / "a/b/tile.bin", "tile");
    REQUIRE(std::string(bytes.begin(), bytes.end()) == "hello");
    REQUIRE_FALSE(readFileBytesIfExists(folder.path() / "a/b/none.bin", "tile"));
    REQUIRE_FALSE(readFileBytesIfExists(folder.path() / "a/b/tile.bin/below", "tile")); // a file on the path
    REQUIRE_THROWS_WITH(readFileBytes(folder.path() / "none.bin", "tile"), Contains("none.bin: tile: no such file"));
    REQUIRE_THROWS_WITH(readFileBytes(folder.path() / "a/b/tile.bin", "tile", 4),
                        Contains("tile.bin: tile is 5 bytes, more than the 4 allowed"));
    REQUIRE(readFileBytes(folder.path() / "a/b/tile.bin", "tile", 5).size() == 5);
}

TEST_CASE("A folder, a named pipe and a symlink loop are refused without blocking", "[world][files][hostile]")
{
    const TempDirectory folder;
    REQUIRE_THROWS_WITH(readFileBytes(folder.path(), "tile"), Contains("is a folder, not a regular file"));
    REQUIRE(::mkfifo((folder.path() / "pipe").c_str(), 0600) == 0);
    // Run where a hang would show as a timeout instead of blocking the suite.
    auto reading = std::async(std::launch::async, [&] {
        try {
            readFileBytesIfExists(folder.path() / "pipe", "tile");
        } catch (const Error& error) {
            return std::string(error.what());
        }
        return std::string("read");
    });
    REQUIRE(reading.wait_for(std::chrono::seconds(10)) == std::future_status::ready);
    REQUIRE_THAT(reading.get(), Contains("pipe: tile is a named pipe, not a regular file"));
    std::filesystem::create_symlink(folder.path() / "loop", folder.path() / "loop");
    REQUIRE_THROWS_WITH(readFileBytes(folder.path() / "loop", "tile"), Contains("loop: tile: cannot open: Too many levels of symbolic links"));
}

TEST_CASE("Files are written whole or not at all, and nothing temporary stays", "[world][files]")
{
    const TempDirectory folder;
    const std::vector<std::uint8_t> large(1 << 20, 7);
    std::vector<std::thread> writers;
    for (int t = 0; t < 4; ++t) {
        writers.emplace_back([&] {
            for (int i = 0; i < 10; ++i) {
                writeFileAtomically(folder.path() / "same.bin", large);
            }
        });
    }
    for (std::thread& writer : writers) {
        writer.join();
    }
    REQUIRE(readFileBytes(folder.path() / "same.bin", "tile") == large);
    int entries = 0;
    for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(folder.path())) {
        ++entries;
    }
    REQUIRE(entries == 1);
    // A folder where the file should go: an error naming the path, no temporary file left.
    std::filesystem::create_directories(folder.path() / "taken");
    REQUIRE_THROWS_WITH(writeFileAtomically(folder.path() / "taken", std::string_view("x")), Contains("taken: cannot write"));
    entries = 0;
    for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(folder.path())) {
        ++entries;
    }
    REQUIRE(entries == 2);
}

TEST_CASE("Values quoted in messages are cut, not UTF-8 sequences", "[world][files]")
{
    REQUIRE(cutForMessage("short") == "short");
    const std::string longValue(1000, 'x');
    REQUIRE(cutForMessage(longValue, 10) == "xxxxxxxxxx... (1000 bytes)");
    // "é" is two bytes; a cut inside it moves back before it.
    REQUIRE(cutForMessage("abcdefghié", 10) == "abcdefghi... (11 bytes)");
}

TEST_CASE("A sandbox refuses files outside its folder, symbolic links and .. followed", "[world][files][sandbox]")
{
    const TempDirectory scratch;
    const std::filesystem::path& folder = scratch.path();
    writeFileAtomically(folder / "inside/data.txt", std::string_view("in"));
    writeFileAtomically(folder / "outside/secret.txt", std::string_view("out"));
    std::filesystem::create_symlink(folder / "outside/secret.txt", folder / "inside/link.txt");
    std::filesystem::create_symlink(folder / "inside/data.txt", folder / "outside/in-link.txt");
    setFileSandbox(folder / "inside");
    struct Reset {
        ~Reset() { setFileSandbox(std::nullopt); }
    } reset;
    CHECK(readFileBytes(folder / "inside/data.txt", "data").size() == 2);
    CHECK(readFileBytes(folder / "inside/../inside/data.txt", "data").size() == 2);
    CHECK_THROWS_WITH(readFileBytes(folder / "outside/secret.txt", "data"), Contains("outside the sandbox"));
    CHECK_THROWS_WITH(readFileBytes(folder / "inside/../outside/secret.txt", "data"), Contains("outside the sandbox"));
    // A link inside pointing out is refused; a link outside pointing in is the file inside.
    CHECK_THROWS_WITH(readFileBytes(folder / "inside/link.txt", "data"),
                      Contains("outside the sandbox") && Contains("(it resolves to"));
    CHECK(readFileBytes(folder / "outside/in-link.txt", "data").size() == 2);
    // A sibling whose name begins like the sandbox's is outside it.
    writeFileAtomically(folder / "inside-not/x.txt", std::string_view("x"));
    CHECK_THROWS_WITH(readFileBytes(folder / "inside-not/x.txt", "data"), Contains("outside the sandbox"));
    CHECK_THROWS_WITH(setFileSandbox(folder / "nowhere"), Contains("sandbox: no such folder"));
    setFileSandbox(std::nullopt);
    CHECK(readFileBytes(folder / "outside/secret.txt", "data").size() == 3);
}
