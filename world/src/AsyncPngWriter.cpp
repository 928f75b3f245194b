#include "orbis/world/AsyncPngWriter.h"

#include "orbis/world/ImageFile.h"

#include <algorithm>

namespace orbis::world {

AsyncPngWriter::AsyncPngWriter(int threads, std::size_t maximumQueued, int compressionLevel)
    : _compressionLevel(compressionLevel)
    , _maximumQueued(std::max<std::size_t>(1, maximumQueued))
{
    for (int i = 0; i < std::max(1, threads); ++i) {
        _threads.emplace_back([this] { work(); });
    }
}

AsyncPngWriter::~AsyncPngWriter()
{
    {
        std::unique_lock lock(_mutex);
        _stopping = true;
    }
    _changed.notify_all();
    for (std::thread& thread : _threads) {
        thread.join();
    }
}

void AsyncPngWriter::rethrowFailure(std::unique_lock<std::mutex>& lock)
{
    if (_failure) {
        const std::exception_ptr failure = _failure;
        lock.unlock();
        std::rethrow_exception(failure);
    }
}

void AsyncPngWriter::write(Image image, std::filesystem::path path)
{
    std::unique_lock lock(_mutex);
    _changed.wait(lock, [&] { return _failure || _queue.size() < _maximumQueued; });
    rethrowFailure(lock);
    _queue.emplace_back(std::move(image), std::move(path));
    lock.unlock();
    _changed.notify_all();
}

void AsyncPngWriter::finish()
{
    std::unique_lock lock(_mutex);
    _changed.wait(lock, [&] { return _failure || (_queue.empty() && _writing == 0); });
    rethrowFailure(lock);
}

void AsyncPngWriter::work()
{
    std::unique_lock lock(_mutex);
    for (;;) {
        // Stopping drains the queue first: the destructor promises the queued images.
        _changed.wait(lock, [&] { return !_queue.empty() || _stopping; });
        if (_queue.empty() || _failure) {
            if (_stopping) {
                return;
            }
            _queue.clear(); // after a failure nothing more is written
            continue;
        }
        auto [image, path] = std::move(_queue.front());
        _queue.pop_front();
        ++_writing;
        lock.unlock();
        _changed.notify_all(); // room in the queue
        std::exception_ptr failure;
        try {
            writePng(image, path, _compressionLevel);
        } catch (...) {
            failure = std::current_exception();
        }
        lock.lock();
        --_writing;
        if (failure && !_failure) {
            _failure = failure;
        }
        _changed.notify_all();
    }
}

} // namespace orbis::world
