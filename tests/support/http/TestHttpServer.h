#pragma once

// An HTTP/1.1 server for tests, on 127.0.0.1 with a port the system picks: one thread accepts,
// one thread serves each connection (keep-alive), and each path answers as the test scripted it.
// It counts requests per path and the most answered at once, so a test can check retries and the
// bound on requests in flight from the server's side.

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace orbis::test {

/// How one path answers.
struct ScriptedResponse {
    int status = 200;
    std::vector<std::uint8_t> body;
    std::string contentType = "application/octet-stream";
    /// Waited before the status line: a slow server. stop() cuts the wait short.
    std::chrono::milliseconds delay{0};
    /// Answer 500 this many times first, then as above.
    int failuresFirst = 0;
    /// Send the full Content-Length but only this many bytes of the body, then close the connection.
    std::optional<std::size_t> truncateAfter;
    /// Cut the first this many answers (after any failures) after half their body; whole from then on.
    int truncatedFirst = 0;

    static ScriptedResponse ok(std::vector<std::uint8_t> body)
    {
        ScriptedResponse response;
        response.body = std::move(body);
        return response;
    }
    static ScriptedResponse withStatus(int code)
    {
        ScriptedResponse response;
        response.status = code;
        return response;
    }
};

class TestHttpServer {
public:
    /// Listens at once; unknown paths answer 404.
    TestHttpServer();
    /// Stops (as stop()) and joins every thread.
    ~TestHttpServer();
    TestHttpServer(const TestHttpServer&) = delete;
    TestHttpServer& operator=(const TestHttpServer&) = delete;

    std::uint16_t port() const noexcept { return _port; }
    /// "http://127.0.0.1:PORT" + path.
    std::string url(const std::string& path = "") const;

    void set(const std::string& path, ScriptedResponse response);

    /// Closes the listening socket and every connection now, ending waits: clients see refused and
    /// broken connections from then on.
    void stop();

    /// Requests received for a path (each attempt counts), and in all.
    int requests(const std::string& path) const;
    int totalRequests() const;
    /// The most requests being answered at the same moment since the start.
    int maximumConcurrent() const;
    /// The header lines of the last request for a path ("" before any).
    std::string lastRequestHeaders(const std::string& path) const;

private:
    void acceptLoop();
    void serve(int connection);
    /// Handles one request; false when the connection must close.
    bool answer(int connection, const std::string& path, const std::string& headers);

    int _listener = -1;
    std::uint16_t _port = 0;
    mutable std::mutex _mutex;
    std::condition_variable _stopped;
    bool _stopping = false;
    std::map<std::string, ScriptedResponse> _responses;
    std::map<std::string, int> _requests;
    std::map<std::string, std::string> _headers;
    int _total = 0;
    int _concurrent = 0;
    int _maximumConcurrent = 0;
    std::vector<int> _connections;
    std::vector<std::thread> _threads;
    std::thread _acceptor;
};

} // namespace orbis::test
