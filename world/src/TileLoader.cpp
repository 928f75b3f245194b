#include "orbis/world/TileLoader.h"

#include <orbis/core/Error.h>

#include <algorithm>
#include <cassert>
#include <exception>

namespace orbis::world {

TileLoader::TileLoader(const TileLoaderOptions& options) : _options(options)
{
    assert(options.workerThreads >= 0 && options.latencyFrames >= 0);
    for (int i = 0; i < options.workerThreads; ++i) {
        _workers.push_back(std::make_unique<MessageQueue>());
        _workers.back()->start();
    }
}

TileLoader::~TileLoader()
{
    // Loads still queued are skipped, not run: mark them, then stop the workers (which drains).
    for (auto& [ticket, job] : _inFlight) {
        job->cancelled = true;
    }
    _workers.clear();
}

TileLoader::Finished TileLoader::run(Job& job)
{
    Finished finished;
    finished.sequence = job.sequence;
    finished.dueFrame = job.dueFrame;
    finished.result.ticket = job.ticket;
    if (job.cancelled) {
        finished.cancelled = true;
        return finished;
    }
    try {
        finished.result.content = job.work();
        finished.result.status =
            finished.result.content ? TileLoadResult::Status::Loaded : TileLoadResult::Status::Missing;
    } catch (const std::exception& error) {
        finished.result.status = TileLoadResult::Status::Failed;
        finished.result.message = error.what();
    }
    job.work = nullptr; // release what the work captured on the thread that ran it
    return finished;
}

void TileLoader::finish(Job& job, Finished finished)
{
    // The message is queued before the job is marked done, so a render thread that sees it done
    // finds the result in _results.
    auto moved = std::make_shared<Finished>(std::move(finished));
    _results.post([this, moved] { _undelivered.push_back(std::move(*moved)); });
    {
        const std::lock_guard lock(_doneMutex);
        job.done = true;
    }
    _doneChanged.notify_all();
}

std::vector<TileLoadResult> TileLoader::beginFrame(std::uint64_t frameNumber)
{
    assert(frameNumber >= _frame);
    _frame = frameNumber;
    const bool deterministic = _options.latencyFrames > 0;
    auto isDue = [&](const Job& job) { return !deterministic || job.dueFrame <= frameNumber; };

    if (_workers.empty()) {
        // No threads: run what is due here, in start order.
        std::vector<std::shared_ptr<Job>> due;
        for (auto& [ticket, job] : _inFlight) {
            if (!job->done && isDue(*job)) {
                due.push_back(job);
            }
        }
        std::sort(due.begin(), due.end(), [](const auto& a, const auto& b) { return a->sequence < b->sequence; });
        for (const std::shared_ptr<Job>& job : due) {
            finish(*job, run(*job));
        }
    } else if (deterministic) {
        std::unique_lock lock(_doneMutex);
        _doneChanged.wait(lock, [&] {
            return std::all_of(_inFlight.begin(), _inFlight.end(), [&](const auto& entry) {
                const Job& job = *entry.second;
                return job.done || job.cancelled || !isDue(job);
            });
        });
    }
    _results.processQueue();

    // Deliver what is due, in start order; drop what was cancelled.
    std::sort(_undelivered.begin(), _undelivered.end(),
              [](const Finished& a, const Finished& b) { return a.sequence < b.sequence; });
    std::vector<TileLoadResult> delivered;
    std::vector<Finished> later;
    for (Finished& finished : _undelivered) {
        const auto job = _inFlight.find(finished.sequence);
        assert(job != _inFlight.end());
        if (job->second->cancelled) {
            _inFlight.erase(job);
        } else if (!deterministic || finished.dueFrame <= frameNumber) {
            _inFlight.erase(job);
            _liveTickets.erase(finished.result.ticket);
            delivered.push_back(std::move(finished.result));
        } else {
            later.push_back(std::move(finished));
        }
    }
    _undelivered = std::move(later);
    return delivered;
}

void TileLoader::request(std::uint64_t ticket, double priority, TileLoadWork work)
{
    assert(!_liveTickets.contains(ticket) && "a load with this ticket is in flight");
    _candidates.push_back({ticket, priority, std::move(work)});
}

void TileLoader::endFrame()
{
    std::sort(_candidates.begin(), _candidates.end(), [](const Candidate& a, const Candidate& b) {
        return a.priority < b.priority || (a.priority == b.priority && a.ticket < b.ticket);
    });
    const std::size_t room = _options.maximumInFlight > inFlight() ? _options.maximumInFlight - inFlight() : 0;
    const std::size_t starts = std::min({_candidates.size(), _options.maximumStartsPerFrame, room});
    _started.clear();
    for (std::size_t i = 0; i < starts; ++i) {
        auto job = std::make_shared<Job>();
        job->ticket = _candidates[i].ticket;
        job->sequence = _nextSequence++;
        job->dueFrame = _frame + static_cast<std::uint64_t>(_options.latencyFrames);
        job->work = std::move(_candidates[i].work);
        _inFlight.emplace(job->sequence, job);
        _liveTickets.emplace(job->ticket, job->sequence);
        _started.push_back(job->ticket);
        if (!_workers.empty()) {
            // The least busy worker; which one runs a load never changes what is delivered.
            MessageQueue* worker = _workers.front().get();
            for (const auto& candidate : _workers) {
                if (candidate->pendingCount() < worker->pendingCount()) {
                    worker = candidate.get();
                }
            }
            worker->post([this, job] { finish(*job, run(*job)); });
        }
    }
    _deferred = _candidates.size() - starts;
    _candidates.clear();
}

void TileLoader::cancel(std::uint64_t ticket)
{
    const auto live = _liveTickets.find(ticket);
    if (live == _liveTickets.end()) {
        return;
    }
    _inFlight.at(live->second)->cancelled = true;
    _liveTickets.erase(live);
}

} // namespace orbis::world
