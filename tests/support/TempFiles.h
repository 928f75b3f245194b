#pragma once

// A scratch folder for tests that write small files; removed with everything in it at the end.

#include <orbis/core/Error.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include <unistd.h>

namespace orbis::test {

class TempDirectory {
public:
    TempDirectory()
    {
        static std::atomic<int> counter{0};
        _path = std::filesystem::temp_directory_path() /
                ("orbis-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
        std::filesystem::create_directories(_path);
    }
    ~TempDirectory()
    {
        std::error_code ignored;
        std::filesystem::remove_all(_path, ignored);
    }
    TempDirectory(const TempDirectory&) = delete;
    TempDirectory& operator=(const TempDirectory&) = delete;

    /// Writes `contents` byte for byte to `name` in the folder and returns its path.
    std::filesystem::path write(const std::string& name, std::string_view contents) const
    {
        const std::filesystem::path file = _path / name;
        std::ofstream out(file, std::ios::binary);
        out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
        return file;
    }

    const std::filesystem::path& path() const noexcept { return _path; }

private:
    std::filesystem::path _path;
};

/// The message of the orbis::Error that `f` throws, or "no error"; other exceptions pass through.
template <typename F>
std::string errorMessage(F&& f)
{
    try {
        f();
    } catch (const orbis::Error& error) {
        return error.what();
    }
    return "no error";
}

} // namespace orbis::test
