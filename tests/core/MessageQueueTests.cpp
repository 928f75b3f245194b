// Also built with -fsanitize=thread as orbis_message_queue_tsan (label "tsan"): every test here
// must pass there too, so shared state is either guarded or ordered by the queue itself, which
// is what ThreadSanitizer checks. Catch2 assertions are made on the test's own thread only.

#include <orbis/core/MessageQueue.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <future>
#include <numeric>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

using namespace orbis;
using namespace std::chrono_literals;

namespace {

std::string messageOf(const std::exception_ptr& error)
{
    try {
        std::rethrow_exception(error);
    } catch (const std::exception& e) {
        return e.what();
    } catch (...) {
        return "not a std::exception";
    }
}

/// Spins (politely) until condition holds; false after ten seconds, so a bug fails instead of hanging.
template <typename Condition>
bool eventually(Condition condition)
{
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    while (!condition()) {
        if (std::chrono::steady_clock::now() > deadline) {
            return false;
        }
        std::this_thread::sleep_for(1ms);
    }
    return true;
}

} // namespace

TEST_CASE("MessageQueue processQueue runs posted messages in order in the calling thread", "[core][queue]")
{
    MessageQueue queue;
    std::vector<int> order;
    const std::thread::id caller = std::this_thread::get_id();
    bool sameThread = true;
    for (int i = 0; i < 100; ++i) {
        queue.post([&order, &sameThread, caller, i] {
            order.push_back(i);
            sameThread = sameThread && std::this_thread::get_id() == caller;
        });
    }
    REQUIRE(queue.pendingCount() == 100);
    REQUIRE(order.empty());
    REQUIRE(queue.processQueue() == 100);
    std::vector<int> expected(100);
    std::iota(expected.begin(), expected.end(), 0);
    REQUIRE(order == expected);
    REQUIRE(sameThread);
    REQUIRE(queue.pendingCount() == 0);
    REQUIRE(queue.processQueue() == 0);
}

TEST_CASE("MessageQueue worker runs posted messages in order on another thread", "[core][queue]")
{
    MessageQueue queue;
    REQUIRE_FALSE(queue.isRunning());
    queue.start();
    REQUIRE(queue.isRunning());
    std::vector<int> order; // touched only by the worker until stop() has joined it
    std::thread::id worker;
    for (int i = 0; i < 1000; ++i) {
        queue.post([&order, &worker, i] {
            order.push_back(i);
            worker = std::this_thread::get_id();
        });
    }
    queue.stop();
    REQUIRE_FALSE(queue.isRunning());
    std::vector<int> expected(1000);
    std::iota(expected.begin(), expected.end(), 0);
    REQUIRE(order == expected);
    REQUIRE(worker != std::this_thread::get_id());
}

TEST_CASE("MessageQueue processQueue leaves messages posted while it runs for the next call", "[core][queue]")
{
    MessageQueue queue;
    int runs = 0;
    std::function<void()> repost = [&] {
        ++runs;
        queue.post(repost);
    };
    queue.post(repost);
    REQUIRE(queue.processQueue() == 1);
    REQUIRE(runs == 1);
    REQUIRE(queue.pendingCount() == 1);
    REQUIRE(queue.processQueue() == 1);
    REQUIRE(runs == 2);
}

TEST_CASE("MessageQueue send returns only after the message has run", "[core][queue]")
{
    MessageQueue queue;
    queue.start();
    for (int i = 0; i < 20; ++i) {
        // A plain int, no atomic: the queue must order the write before send returns (TSan checks).
        int value = 0;
        queue.post([] { std::this_thread::sleep_for(100us); });
        queue.send([&value, i] {
            std::this_thread::sleep_for(1ms);
            value = i + 1;
        });
        REQUIRE(value == i + 1);
    }
}

TEST_CASE("MessageQueue send without a worker waits for another thread's processQueue", "[core][queue]")
{
    MessageQueue queue;
    int value = 0;
    std::atomic<bool> returned{false};
    std::thread sender([&] {
        queue.send([&value] { value = 42; });
        returned = true;
    });
    REQUIRE(eventually([&] { return queue.pendingCount() == 1; }));
    std::this_thread::sleep_for(5ms);
    REQUIRE_FALSE(returned.load()); // nothing processed yet: still waiting
    REQUIRE(queue.processQueue() == 1);
    sender.join();
    REQUIRE(returned.load());
    REQUIRE(value == 42);
}

TEST_CASE("MessageQueue runs every message of many producers exactly once, each producer in order", "[core][queue]")
{
    constexpr int kProducers = 4;
    constexpr int kPerProducer = 10000;
    MessageQueue queue;
    queue.start();
    // Touched only by the worker; read after stop() joins it.
    std::vector<int> runs(kProducers * kPerProducer, 0);
    std::vector<int> last(kProducers, -1);
    bool inOrder = true;
    std::vector<std::thread> producers;
    for (int p = 0; p < kProducers; ++p) {
        producers.emplace_back([&, p] {
            for (int i = 0; i < kPerProducer; ++i) {
                queue.post([&, p, i] {
                    ++runs[static_cast<std::size_t>(p * kPerProducer + i)];
                    inOrder = inOrder && last[static_cast<std::size_t>(p)] == i - 1;
                    last[static_cast<std::size_t>(p)] = i;
                });
            }
        });
    }
    for (std::thread& producer : producers) {
        producer.join();
    }
    queue.stop(); // drains: every post happened before this call
    REQUIRE(queue.pendingCount() == 0);
    REQUIRE(inOrder);
    REQUIRE(std::count(runs.begin(), runs.end(), 1) == kProducers * kPerProducer);
}

TEST_CASE("MessageQueue many producers with send and a processQueue caller alongside the worker", "[core][queue]")
{
    MessageQueue queue;
    queue.start();
    std::atomic<int> total{0};
    std::atomic<bool> producing{true};
    std::vector<std::thread> producers;
    for (int p = 0; p < 3; ++p) {
        producers.emplace_back([&, p] {
            for (int i = 0; i < 2000; ++i) {
                if (i % 100 == p) {
                    queue.send([&] { ++total; });
                } else {
                    queue.post([&] { ++total; });
                }
            }
        });
    }
    // A second consumer competing with the worker: each message still runs once.
    std::thread helper([&] {
        while (producing) {
            queue.processQueue();
        }
    });
    for (std::thread& producer : producers) {
        producer.join();
    }
    producing = false;
    helper.join();
    queue.stop();
    REQUIRE(total == 3 * 2000);
}

TEST_CASE("MessageQueue survives stop and start cycles and stop drains what was posted before it", "[core][queue]")
{
    MessageQueue queue;
    int count = 0; // worker-only while running; read after stop() joins
    for (int cycle = 0; cycle < 50; ++cycle) {
        queue.start();
        queue.start(); // a second start does nothing
        for (int i = 0; i < 100; ++i) {
            queue.post([&count] { ++count; });
        }
        queue.stop();
        queue.stop(); // a second stop does nothing
        REQUIRE(count == 100 * (cycle + 1));
        REQUIRE(queue.pendingCount() == 0);
    }
    // Posted while stopped: kept, and run first by the next worker.
    std::vector<int> order;
    queue.post([&order] { order.push_back(1); });
    queue.post([&order] { order.push_back(2); });
    REQUIRE(queue.pendingCount() == 2);
    queue.start();
    queue.send([&order] { order.push_back(3); });
    REQUIRE(order == std::vector<int>{1, 2, 3});
}

TEST_CASE("MessageQueue send from a message runs inline instead of deadlocking", "[core][queue]")
{
    SECTION("on the worker thread")
    {
        MessageQueue queue;
        queue.start();
        std::vector<std::string> order;
        std::thread::id inner;
        queue.post([&] { order.push_back("queued before"); });
        queue.send([&] {
            order.push_back("outer begins");
            queue.post([&] { order.push_back("posted from outer"); });
            queue.send([&] {
                order.push_back("inner");
                inner = std::this_thread::get_id();
            });
            order.push_back("outer ends");
        });
        queue.send([] {});
        REQUIRE(order == std::vector<std::string>{"queued before", "outer begins", "inner", "outer ends",
                                                  "posted from outer"});
        REQUIRE(inner != std::this_thread::get_id());
    }
    SECTION("inside processQueue")
    {
        MessageQueue queue;
        std::vector<std::string> order;
        queue.post([&] {
            queue.send([&] { order.push_back("inner"); });
            order.push_back("outer");
        });
        REQUIRE(queue.processQueue() == 1);
        REQUIRE(order == std::vector<std::string>{"inner", "outer"});
    }
    SECTION("through a second queue processed inside the first")
    {
        MessageQueue first;
        MessageQueue second;
        int value = 0;
        first.post([&] {
            second.post([&] { first.send([&] { value = 7; }); });
            second.processQueue();
        });
        REQUIRE(first.processQueue() == 1);
        REQUIRE(value == 7);
    }
}

TEST_CASE("MessageQueue send rethrows the message's exception and the worker keeps going", "[core][queue]")
{
    MessageQueue queue;
    queue.start();
    REQUIRE_THROWS_WITH(queue.send([] { throw std::runtime_error("sent failure"); }), "sent failure");
    int value = 0;
    queue.send([&value] { value = 1; });
    REQUIRE(value == 1);
    REQUIRE(queue.isRunning());
    REQUIRE(queue.takeErrors().empty()); // a sent message's exception goes to the sender only

    MessageQueue unstarted;
    std::thread helper([&] {
        while (unstarted.processQueue() == 0) {
            std::this_thread::sleep_for(1ms);
        }
    });
    REQUIRE_THROWS_AS(unstarted.send([] { throw std::logic_error("in processQueue"); }), std::logic_error);
    helper.join();
}

TEST_CASE("MessageQueue keeps the exceptions of posted messages until takeErrors", "[core][queue]")
{
    MessageQueue queue;
    queue.start();
    int after = 0;
    queue.post([] { throw std::runtime_error("first"); });
    queue.post([] { throw 5; });
    queue.post([] { throw std::runtime_error("third"); });
    queue.post([&after] { after = 1; });
    queue.stop();
    REQUIRE(after == 1); // the worker went on after the failures
    const std::vector<std::exception_ptr> errors = queue.takeErrors();
    REQUIRE(errors.size() == 3);
    REQUIRE(messageOf(errors[0]) == "first");
    REQUIRE(messageOf(errors[1]) == "not a std::exception");
    REQUIRE(messageOf(errors[2]) == "third");
    REQUIRE(queue.takeErrors().empty());
}

TEST_CASE("MessageQueue passes the exceptions of posted messages to the error handler", "[core][queue]")
{
    std::vector<std::string> reported; // the handler runs on the worker; read after stop()
    std::thread::id handlerThread;
    MessageQueue queue([&](std::exception_ptr error) {
        reported.push_back(messageOf(error));
        handlerThread = std::this_thread::get_id();
        if (reported.size() == 2) {
            throw std::runtime_error("handler failed");
        }
    });
    queue.start();
    queue.post([] { throw std::runtime_error("a"); });
    queue.post([] { throw std::runtime_error("b"); });
    queue.stop();
    REQUIRE(reported == std::vector<std::string>{"a", "b"});
    REQUIRE(handlerThread != std::this_thread::get_id());
    // What the handler itself threw is kept rather than lost.
    const std::vector<std::exception_ptr> kept = queue.takeErrors();
    REQUIRE(kept.size() == 1);
    REQUIRE(messageOf(kept[0]) == "handler failed");
}

TEST_CASE("MessageQueue stop from inside a message drains earlier messages and keeps later ones", "[core][queue]")
{
    MessageQueue queue;
    queue.start();
    std::vector<std::string> order;
    queue.post([&] { order.push_back("before"); });
    queue.post([&] {
        queue.stop();
        order.push_back("stopper");
        queue.post([&] { order.push_back("after"); });
    });
    REQUIRE(eventually([&] { return !queue.isRunning(); }));
    queue.stop(); // joins the worker that stopped itself
    REQUIRE(order == std::vector<std::string>{"before", "stopper"});
    REQUIRE(queue.pendingCount() == 1);
    queue.start();
    queue.stop();
    REQUIRE(order == std::vector<std::string>{"before", "stopper", "after"});
}

TEST_CASE("MessageQueue destructor drains a running worker and wakes a sender whose message it discards", "[core][queue]")
{
    int count = 0;
    {
        MessageQueue queue;
        queue.start();
        for (int i = 0; i < 100; ++i) {
            queue.post([&count] {
                std::this_thread::sleep_for(10us);
                ++count;
            });
        }
    }
    REQUIRE(count == 100);

    std::future<bool> broken;
    {
        MessageQueue queue; // never started: the destructor discards what is queued
        broken = std::async(std::launch::async, [&queue] {
            try {
                queue.send([] {});
            } catch (const std::future_error& e) {
                return e.code() == std::future_errc::broken_promise;
            }
            return false;
        });
        REQUIRE(eventually([&] { return queue.pendingCount() == 1; }));
    }
    REQUIRE(broken.wait_for(10s) == std::future_status::ready);
    REQUIRE(broken.get());
}
