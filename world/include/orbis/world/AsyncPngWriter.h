#pragma once

#include <orbis/core/Image.h>

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <filesystem>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace orbis::world {

/// Writes PNGs (writePng) on worker threads, so that a program rendering a sequence of frames
/// draws the next while the last is encoded. At most `maximumQueued` images wait; write() blocks
/// for room beyond that, which bounds the memory. The first failure is rethrown by the next
/// write() or by finish(), and nothing more is written after it.
///
/// ```
/// AsyncPngWriter writer(2);
/// for (int i = 0; i < frames; ++i) { writer.write(context.readPixels(), framePath(i)); }
/// writer.finish(); // every file written, or the first error thrown
/// ```
class AsyncPngWriter final {
public:
    /// threads >= 1 (at least one is started); maximumQueued >= 1.
    explicit AsyncPngWriter(int threads, std::size_t maximumQueued = 4, int compressionLevel = 1);
    /// Waits for the queued images to be written; errors then are dropped (call finish() to see them).
    ~AsyncPngWriter();

    AsyncPngWriter(const AsyncPngWriter&) = delete;
    AsyncPngWriter& operator=(const AsyncPngWriter&) = delete;

    /// Queues the image for `path`, waiting while the queue is full. Throws the first failure of
    /// an earlier image.
    void write(Image image, std::filesystem::path path);
    /// Returns once every queued image is written; throws the first failure. The writer can be
    /// used again afterwards, as long as nothing failed.
    void finish();

private:
    void work();
    void rethrowFailure(std::unique_lock<std::mutex>& lock);

    int _compressionLevel;
    std::size_t _maximumQueued;
    std::mutex _mutex;
    std::condition_variable _changed; ///< a job queued or done, or stopping
    std::deque<std::pair<Image, std::filesystem::path>> _queue;
    std::size_t _writing = 0;
    std::exception_ptr _failure;
    bool _stopping = false;
    std::vector<std::thread> _threads;
};

} // namespace orbis::world
