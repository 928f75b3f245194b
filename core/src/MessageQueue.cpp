#include "orbis/core/MessageQueue.h"

#include <cassert>
#include <future>
#include <utility>

namespace orbis {

namespace {

/// The queues whose messages the current thread is running, innermost first: a message run by
/// processQueue may itself call processQueue on another queue, whose message may send to the
/// first. A chain of stack frames, so nesting costs no allocation.
struct ProcessingScope {
    const MessageQueue* queue;
    const ProcessingScope* outer;
};

thread_local const ProcessingScope* tInnermostScope = nullptr;
/// The queue whose worker the current thread is, if any.
thread_local const MessageQueue* tWorkerOf = nullptr;

class ScopeGuard {
public:
    explicit ScopeGuard(const MessageQueue* queue) noexcept : _scope{queue, tInnermostScope}
    {
        tInnermostScope = &_scope;
    }
    ~ScopeGuard() { tInnermostScope = _scope.outer; }
    ScopeGuard(const ScopeGuard&) = delete;
    ScopeGuard& operator=(const ScopeGuard&) = delete;

private:
    ProcessingScope _scope;
};

bool isProcessing(const MessageQueue* queue) noexcept
{
    for (const ProcessingScope* scope = tInnermostScope; scope != nullptr; scope = scope->outer) {
        if (scope->queue == queue) {
            return true;
        }
    }
    return false;
}

} // namespace

/// Shared by a sender and the item it queued. Exceptions cross threads only through `error`,
/// which is moved, never copied, so that the last reference to an exception object is always
/// dropped by the thread that last reads it (libstdc++ counts exception references in code that
/// ThreadSanitizer does not see).
struct MessageQueue::Completion {
    enum class State { Pending, Ran, Discarded };
    std::mutex mutex;
    std::condition_variable changed;
    State state = State::Pending;
    std::exception_ptr error;

    void finish(State newState, std::exception_ptr newError)
    {
        const std::lock_guard lock(mutex);
        state = newState;
        error = std::move(newError);
        changed.notify_all();
    }
};

MessageQueue::MessageQueue(ErrorHandler onError) : _onError(std::move(onError)) {}

MessageQueue::~MessageQueue()
{
    assert(tWorkerOf != this && "a MessageQueue cannot be destroyed by its own worker");
    stop();
    const std::lock_guard lock(_mutex);
    for (Item& item : _queue) {
        if (item.completion) {
            item.completion->finish(Completion::State::Discarded, nullptr);
        }
    }
}

void MessageQueue::enqueue(Item item)
{
    // Notified under the lock: once the item is visible another thread may run it and let the
    // owner destroy the queue, so the sender must not touch the queue after unlocking.
    const std::lock_guard lock(_mutex);
    item.sequence = _nextSequence++;
    _queue.push_back(std::move(item));
    _wake.notify_one();
}

void MessageQueue::post(Message message)
{
    assert(message && "MessageQueue::post needs a callable");
    enqueue(Item{std::move(message), nullptr, 0});
}

void MessageQueue::send(Message message)
{
    assert(message && "MessageQueue::send needs a callable");
    if (isProcessing(this)) {
        message(); // from inside a message of this queue: waiting for ourselves would deadlock
        return;
    }
    const auto completion = std::make_shared<Completion>();
    enqueue(Item{std::move(message), completion, 0});
    std::exception_ptr error;
    {
        std::unique_lock lock(completion->mutex);
        completion->changed.wait(lock, [&] { return completion->state != Completion::State::Pending; });
        if (completion->state == Completion::State::Discarded) {
            throw std::future_error(std::future_errc::broken_promise);
        }
        error = std::move(completion->error);
    }
    if (error) {
        std::rethrow_exception(error);
    }
}

void MessageQueue::run(Item& item)
{
    std::exception_ptr error;
    try {
        // Destroyed before the sender wakes, so that nothing of the message outlives send.
        const Message message = std::move(item.message);
        message();
    } catch (...) {
        error = std::current_exception();
    }
    // Out of the catch block, `error` is this thread's only reference to the exception.
    if (item.completion) {
        item.completion->finish(Completion::State::Ran, std::move(error));
    } else if (error) {
        reportError(std::move(error));
    }
}

void MessageQueue::reportError(std::exception_ptr error)
{
    if (_onError) {
        try {
            _onError(error);
            return;
        } catch (...) {
            error = std::current_exception();
        }
    }
    const std::lock_guard lock(_mutex);
    _errors.push_back(std::move(error));
}

std::size_t MessageQueue::processQueue()
{
    const ScopeGuard scope(this);
    std::uint64_t end = 0;
    {
        const std::lock_guard lock(_mutex);
        end = _nextSequence;
    }
    std::size_t count = 0;
    for (;;) {
        Item item;
        {
            const std::lock_guard lock(_mutex);
            if (_queue.empty() || _queue.front().sequence >= end) {
                break;
            }
            item = std::move(_queue.front());
            _queue.pop_front();
        }
        run(item);
        ++count;
    }
    return count;
}

void MessageQueue::workerLoop()
{
    tWorkerOf = this;
    const ScopeGuard scope(this);
    std::unique_lock lock(_mutex);
    for (;;) {
        _wake.wait(lock, [this] { return !_running || !_queue.empty(); });
        if (!_running && (_queue.empty() || _queue.front().sequence >= _stopSequence)) {
            break;
        }
        Item item = std::move(_queue.front());
        _queue.pop_front();
        lock.unlock();
        run(item);
        lock.lock();
    }
    tWorkerOf = nullptr;
}

void MessageQueue::start()
{
    assert(tWorkerOf != this && "MessageQueue::start called from its own worker");
    const std::lock_guard control(_controlMutex);
    {
        const std::lock_guard lock(_mutex);
        if (_running) {
            return;
        }
    }
    // A worker that stopped itself (stop called from a message) may still be draining.
    if (_worker.joinable()) {
        _worker.join();
    }
    {
        const std::lock_guard lock(_mutex);
        _running = true;
    }
    _worker = std::thread(&MessageQueue::workerLoop, this);
}

void MessageQueue::stop()
{
    const auto requestStop = [this] {
        {
            const std::lock_guard lock(_mutex);
            _running = false;
            _stopSequence = _nextSequence;
        }
        _wake.notify_all();
    };
    if (tWorkerOf == this) {
        // The worker cannot join itself, and the thread calling start or stop may be holding
        // _controlMutex while it waits for this very message: ask, and let others join.
        requestStop();
        return;
    }
    const std::lock_guard control(_controlMutex);
    if (!_worker.joinable()) {
        return;
    }
    requestStop();
    _worker.join();
}

bool MessageQueue::isRunning() const
{
    const std::lock_guard lock(_mutex);
    return _running;
}

std::size_t MessageQueue::pendingCount() const
{
    const std::lock_guard lock(_mutex);
    return _queue.size();
}

std::vector<std::exception_ptr> MessageQueue::takeErrors()
{
    const std::lock_guard lock(_mutex);
    return std::exchange(_errors, {});
}

} // namespace orbis
