#include "orbis/world/FileAccess.h"

#include <orbis/core/Error.h>

#include <algorithm>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <mutex>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace orbis::world {

namespace {

/// A file descriptor closed on scope exit.
class FileDescriptor {
public:
    explicit FileDescriptor(int fd) noexcept : _fd(fd) {}
    ~FileDescriptor()
    {
        if (_fd >= 0) {
            ::close(_fd);
        }
    }
    FileDescriptor(const FileDescriptor&) = delete;
    FileDescriptor& operator=(const FileDescriptor&) = delete;
    int get() const noexcept { return _fd; }
    /// Closes now, reporting the error close() gives (a write that failed late).
    int close() noexcept
    {
        const int result = ::close(_fd);
        _fd = -1;
        return result;
    }

private:
    int _fd;
};

std::string describe(const std::filesystem::path& path, std::string_view kind)
{
    return cutForMessage(path.string()) + ": " + std::string(kind);
}

const char* fileTypeName(mode_t mode)
{
    if (S_ISDIR(mode)) {
        return "a folder";
    }
    if (S_ISFIFO(mode)) {
        return "a named pipe";
    }
    if (S_ISSOCK(mode)) {
        return "a socket";
    }
    if (S_ISCHR(mode) || S_ISBLK(mode)) {
        return "a device";
    }
    return "not a regular file";
}

std::mutex sandboxMutex;
std::optional<std::filesystem::path> sandboxFolder; // canonical

/// Empty when the file does not exist; throws for every other failure.
std::optional<std::vector<std::uint8_t>> readRegularFile(const std::filesystem::path& given, std::string_view kind,
                                                         std::size_t maximumBytes)
{
    // The resolved path is what is opened, so the file read is the one checked.
    const std::filesystem::path path = fileSandbox() ? resolveInSandbox(given, kind) : given;
    // O_NONBLOCK: opening a named pipe for reading then returns at once instead of waiting for a
    // writer; fstat on the open descriptor then refuses it without a race against a rename.
    FileDescriptor fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY));
    if (fd.get() < 0) {
        const int error = errno;
        if (error == ENOENT || error == ENOTDIR) {
            return std::nullopt;
        }
        throw Error(describe(path, kind) + ": cannot open: " + std::strerror(error));
    }
    struct stat status {};
    if (::fstat(fd.get(), &status) != 0) {
        throw Error(describe(path, kind) + ": cannot read: " + std::strerror(errno));
    }
    if (!S_ISREG(status.st_mode)) {
        throw Error(describe(path, kind) + " is " + fileTypeName(status.st_mode) + ", not a regular file");
    }
    if (status.st_size < 0 || static_cast<std::uint64_t>(status.st_size) > maximumBytes) {
        throw Error(describe(path, kind) + " is " + std::to_string(status.st_size) + " bytes, more than the " +
                    std::to_string(maximumBytes) + " allowed");
    }
    const int flags = ::fcntl(fd.get(), F_GETFL);
    if (flags >= 0) {
        ::fcntl(fd.get(), F_SETFL, flags & ~O_NONBLOCK);
    }
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(status.st_size));
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t count = ::read(fd.get(), bytes.data() + done, bytes.size() - done);
        if (count < 0 && errno == EINTR) {
            continue;
        }
        if (count < 0) {
            throw Error(describe(path, kind) + ": cannot read: " + std::strerror(errno));
        }
        if (count == 0) {
            // The file shrank while being read: keep what it holds now.
            bytes.resize(done);
            break;
        }
        done += static_cast<std::size_t>(count);
    }
    return bytes;
}

} // namespace

void setFileSandbox(const std::optional<std::filesystem::path>& folder)
{
    std::optional<std::filesystem::path> canonical;
    if (folder) {
        std::error_code error;
        canonical = std::filesystem::canonical(*folder, error);
        if (error || !std::filesystem::is_directory(*canonical, error)) {
            throw Error(cutForMessage(folder->string()) + ": sandbox: no such folder");
        }
    }
    const std::lock_guard lock(sandboxMutex);
    sandboxFolder = std::move(canonical);
}

std::optional<std::filesystem::path> fileSandbox()
{
    const std::lock_guard lock(sandboxMutex);
    return sandboxFolder;
}

std::filesystem::path resolveInSandbox(const std::filesystem::path& path, std::string_view kind)
{
    std::error_code error;
    const std::filesystem::path absolute = std::filesystem::absolute(path, error);
    std::filesystem::path resolved = std::filesystem::weakly_canonical(error ? path : absolute, error);
    if (error) {
        // weakly_canonical fails on a loop of symbolic links (ELOOP) and little else.
        throw Error(describe(path, kind) + ": cannot resolve: " + error.message());
    }
    const std::optional<std::filesystem::path> sandbox = fileSandbox();
    if (sandbox) {
        const auto [inside, rest] = std::mismatch(sandbox->begin(), sandbox->end(), resolved.begin(), resolved.end());
        if (inside != sandbox->end()) {
            throw Error(describe(path, kind) + ": outside the sandbox " + cutForMessage(sandbox->string()) +
                        (resolved == path ? std::string() : " (it resolves to " + cutForMessage(resolved.string()) + ")"));
        }
    }
    return resolved;
}

std::vector<std::uint8_t> readFileBytes(const std::filesystem::path& path, std::string_view kind, std::size_t maximumBytes)
{
    auto bytes = readRegularFile(path, kind, maximumBytes);
    if (!bytes) {
        throw Error(describe(path, kind) + ": no such file");
    }
    return std::move(*bytes);
}

std::optional<std::vector<std::uint8_t>> readFileBytesIfExists(const std::filesystem::path& path, std::string_view kind,
                                                               std::size_t maximumBytes)
{
    return readRegularFile(path, kind, maximumBytes);
}

void writeFileAtomically(const std::filesystem::path& path, std::span<const std::uint8_t> bytes)
{
    static std::atomic<std::uint64_t> counter{0};
    const std::string where = cutForMessage(path.string());
    std::error_code error;
    if (path.has_parent_path()) {
        std::filesystem::create_directories(path.parent_path(), error);
        if (error) {
            throw Error(where + ": cannot create its folder: " + error.message());
        }
    }
    std::filesystem::path temporary = path;
    temporary += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1));
    FileDescriptor fd(::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644));
    if (fd.get() < 0) {
        throw Error(where + ": cannot write: " + std::strerror(errno));
    }
    auto fail = [&](int code) {
        ::unlink(temporary.c_str());
        return Error(where + ": cannot write: " + std::strerror(code));
    };
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t count = ::write(fd.get(), bytes.data() + done, bytes.size() - done);
        if (count < 0 && errno == EINTR) {
            continue;
        }
        if (count < 0) {
            throw fail(errno);
        }
        done += static_cast<std::size_t>(count);
    }
    if (fd.close() != 0) {
        throw fail(errno);
    }
    if (::rename(temporary.c_str(), path.c_str()) != 0) {
        throw fail(errno);
    }
}

void writeFileAtomically(const std::filesystem::path& path, std::string_view text)
{
    writeFileAtomically(path, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

} // namespace orbis::world
