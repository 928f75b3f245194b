#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace orbis {

/// A thread-safe first-in, first-out queue of messages (book appendix A): any thread posts or
/// sends callables; one worker thread (start) or any thread calling processQueue runs them.
///
/// ```
/// MessageQueue queue;
/// queue.start();                                  // a worker thread runs messages as they arrive
/// queue.post([&] { tile.decode(); });             // returns at once
/// queue.send([&] { cache.clear(); });             // returns once the message has run
/// queue.stop();                                   // runs what was posted before, then joins
/// ```
///
/// Messages run one at a time on the worker, in the order they were posted. Exceptions: one
/// thrown by a sent message is rethrown by send in the sender's thread; one thrown by a posted
/// message goes to the error handler given to the constructor (called on the thread that ran
/// the message), or, without a handler, is kept until takeErrors(). A failing message never
/// stops the worker.
class MessageQueue final {
public:
    /// A message: any callable, run once on whichever thread processes it.
    using Message = std::function<void()>;
    /// Receives the exception of a posted message; must not throw (what it throws is kept for
    /// takeErrors() instead).
    using ErrorHandler = std::function<void(std::exception_ptr)>;

    /// A stopped queue; errors of posted messages go to onError, or are kept when it is empty.
    explicit MessageQueue(ErrorHandler onError = {});
    /// Stops the worker as stop() does (draining what was posted before), then discards what is
    /// still queued: a send still waiting for a discarded message throws std::future_error
    /// (broken_promise) instead of hanging. Must not run on the worker thread (asserted).
    ~MessageQueue();

    MessageQueue(const MessageQueue&) = delete;
    MessageQueue& operator=(const MessageQueue&) = delete;

    /// Queues message (must not be empty, asserted) and returns at once.
    void post(Message message);

    /// Runs message and returns when it has run, rethrowing what it threw. From a thread that
    /// is running this queue's messages (the worker, or a processQueue caller, i.e. from inside
    /// a message) it runs message inline at once, ahead of anything queued, so it cannot
    /// deadlock. Otherwise it queues message and waits: with no worker running, until another
    /// thread calls processQueue or start.
    void send(Message message);

    /// Runs, in the calling thread, the messages posted before the call (those posted while it
    /// runs wait for the next call, so a message that posts itself cannot keep it busy); returns
    /// how many ran. Meant for a queue without a worker; with one, both take messages from the
    /// front and each message still runs exactly once.
    std::size_t processQueue();

    /// Starts a worker thread that runs messages as they arrive, the pending ones first. Does
    /// nothing when one is running. Must not be called from the worker thread (asserted).
    void start();

    /// Stops the worker after it has run every message posted before the call (drains); later
    /// messages stay queued for processQueue or the next start. Waits for the worker to end,
    /// except from the worker thread itself (from inside a message), where it only asks it to
    /// stop; the next start, stop or the destructor then joins it. Does nothing without a worker.
    void stop();

    /// True between start and stop.
    bool isRunning() const;

    /// Number of messages queued and not yet taken by a thread.
    std::size_t pendingCount() const;

    /// The exceptions of posted messages kept since the last call (none when an error handler
    /// was given), oldest first.
    std::vector<std::exception_ptr> takeErrors();

private:
    struct Completion; ///< how a sender learns that its message ran
    struct Item {
        Message message;
        std::shared_ptr<Completion> completion; ///< set for send, empty for post
        std::uint64_t sequence = 0;
    };

    void enqueue(Item item);
    void run(Item& item);
    void workerLoop();
    void reportError(std::exception_ptr error);

    const ErrorHandler _onError;

    mutable std::mutex _mutex; ///< guards everything below except _worker
    std::condition_variable _wake;
    std::deque<Item> _queue;
    std::uint64_t _nextSequence = 0;
    bool _running = false;          ///< a worker exists and has not been asked to stop
    std::uint64_t _stopSequence = 0; ///< when !_running: the worker runs items below this, then ends
    std::vector<std::exception_ptr> _errors;

    std::mutex _controlMutex; ///< serialises start, stop and the destructor; guards _worker
    std::thread _worker;
};

} // namespace orbis
