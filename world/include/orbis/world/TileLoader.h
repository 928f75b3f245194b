#pragma once

#include <orbis/core/MessageQueue.h>

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

namespace orbis::world {

/// What a load made on a worker: CPU-side data (a decoded image, a mesh) for the scene to turn
/// into GPU resources.
class TileContent {
public:
    virtual ~TileContent() = default;
    /// Bytes held in CPU memory, counted against the cache's cap.
    virtual std::size_t byteSize() const noexcept = 0;
};

/// The work of one load, run on a worker: fetch and decode. Returns the content, or null when the
/// tile does not exist (a 404, no such file); throws orbis::Error when it fails (a corrupt tile,
/// a server gone), naming the tile's path or URL.
using TileLoadWork = std::function<std::unique_ptr<TileContent>()>;

/// One finished load, as the scene receives it at a frame boundary.
struct TileLoadResult {
    enum class Status { Loaded, Missing, Failed };
    std::uint64_t ticket = 0;      ///< the caller's name for the load, given to request()
    Status status = Status::Failed;
    std::unique_ptr<TileContent> content; ///< Loaded only
    std::string message;           ///< Failed only: what went wrong
};

struct TileLoaderOptions {
    /// Threads that run loads; 0 runs them on the thread calling beginFrame (tests, benchmarks).
    int workerThreads = 2;
    /// 0: asynchronous, a result enters at the first frame boundary after its load finished (an
    /// interactive viewer). n >= 1: deterministic, a load started during frame f enters at the
    /// start of frame f + n, waiting for it if it has not finished: every run and every thread
    /// count gives the same frames.
    int latencyFrames = 1;
    /// Loads started per frame at most (the best candidates first).
    std::size_t maximumStartsPerFrame = 32;
    /// Loads started and not yet delivered at most.
    std::size_t maximumInFlight = 64;
};

/// Loads tiles on worker threads (book chapter 10, course 3.4): each frame the scene offers
/// candidates with priorities, the loader starts the best of them, workers fetch and decode, and
/// results come back at frame boundaries in the order their loads started. Workers take their work
/// through core MessageQueues and post results to one that the render thread drains.
///
/// Candidates not started in their frame are forgotten: the scene offers again what it still
/// needs, so a request for a tile the view left behind is cancelled by not being repeated.
///
/// ```
/// TileLoader loader({.workerThreads = 2, .latencyFrames = 1});
/// for (;;) {
///     for (TileLoadResult& result : loader.beginFrame(frame)) { ... }
///     loader.request(ticket, distance, [=] { return decode(source->fetch(key)); });
///     loader.endFrame();
/// }
/// ```
class TileLoader final {
public:
    explicit TileLoader(const TileLoaderOptions& options = {});
    /// Stops the workers; loads not yet run are dropped unrun.
    ~TileLoader();

    TileLoader(const TileLoader&) = delete;
    TileLoader& operator=(const TileLoader&) = delete;

    const TileLoaderOptions& options() const noexcept { return _options; }

    /// Frame `frameNumber` begins (numbers increase): returns the results due, loads started
    /// earlier first. Deterministic timing waits here for loads that are due and not finished.
    std::vector<TileLoadResult> beginFrame(std::uint64_t frameNumber);

    /// Offers a load for this frame. Smaller priorities start first, equal ones by ticket, so the
    /// order does not depend on the order of the calls. A ticket must not be offered while a load
    /// with the same ticket is in flight and not cancelled (asserted).
    void request(std::uint64_t ticket, double priority, TileLoadWork work);

    /// Starts the best candidates within the per-frame and in-flight limits; forgets the others.
    void endFrame();

    /// Drops a started load: its result is never delivered, and its work is skipped if it has not
    /// begun. No effect for a ticket not in flight.
    void cancel(std::uint64_t ticket);

    /// True when a load with this ticket is started, not cancelled and not yet delivered.
    bool isLoading(std::uint64_t ticket) const noexcept { return _liveTickets.contains(ticket); }
    /// Loads started and not yet delivered (cancelled ones excluded).
    std::size_t inFlight() const noexcept { return _liveTickets.size(); }
    /// Candidates of the last endFrame that were not started (the limits held them back).
    std::size_t deferred() const noexcept { return _deferred; }
    /// Loads started by the last endFrame.
    std::size_t startedLastFrame() const noexcept { return _started.size(); }
    /// Their tickets, in the order they started.
    const std::vector<std::uint64_t>& startedTickets() const noexcept { return _started; }

private:
    struct Candidate {
        std::uint64_t ticket;
        double priority;
        TileLoadWork work;
    };
    /// A started load, shared by the render thread and the worker running it.
    struct Job {
        std::uint64_t ticket = 0;
        std::uint64_t sequence = 0; ///< start order
        std::uint64_t dueFrame = 0; ///< deterministic timing: the frame its result enters
        TileLoadWork work;
        std::atomic<bool> cancelled{false};
        bool done = false;          ///< guarded by _doneMutex
    };
    /// A result on its way to the render thread.
    struct Finished {
        std::uint64_t sequence = 0;
        std::uint64_t dueFrame = 0;
        bool cancelled = false;
        TileLoadResult result;
    };

    /// Runs the job's work, turning what it returns or throws into a result.
    static Finished run(Job& job);
    /// Worker side: hands the result to the render thread and marks the job done.
    void finish(Job& job, Finished finished);

    TileLoaderOptions _options;
    std::uint64_t _frame = 0;
    std::uint64_t _nextSequence = 0;
    std::vector<Candidate> _candidates;
    /// Started and not delivered, cancelled ones too (until their workers are done with them), by
    /// sequence; _liveTickets names the ones not cancelled.
    std::unordered_map<std::uint64_t, std::shared_ptr<Job>> _inFlight;
    std::unordered_map<std::uint64_t, std::uint64_t> _liveTickets; ///< ticket -> sequence
    std::size_t _deferred = 0;
    std::vector<std::uint64_t> _started;
    std::vector<Finished> _undelivered; ///< render thread: arrived, not yet due

    MessageQueue _results; ///< workers post here; beginFrame drains it on the render thread
    std::mutex _doneMutex;
    std::condition_variable _doneChanged;
    std::vector<std::unique_ptr<MessageQueue>> _workers; ///< last member: stopped first
};

} // namespace orbis::world
