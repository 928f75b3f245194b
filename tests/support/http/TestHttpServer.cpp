#include "TestHttpServer.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

namespace orbis::test {

namespace {

bool sendAll(int connection, const void* data, std::size_t size)
{
    const auto* bytes = static_cast<const char*>(data);
    while (size > 0) {
        const ssize_t sent = ::send(connection, bytes, size, MSG_NOSIGNAL);
        if (sent < 0 && errno == EINTR) {
            continue;
        }
        if (sent <= 0) {
            return false;
        }
        bytes += sent;
        size -= static_cast<std::size_t>(sent);
    }
    return true;
}

const char* reason(int status)
{
    switch (status) {
    case 200: return "OK";
    case 204: return "No Content";
    case 403: return "Forbidden";
    case 404: return "Not Found";
    case 429: return "Too Many Requests";
    case 500: return "Internal Server Error";
    case 503: return "Service Unavailable";
    default: return "Status";
    }
}

} // namespace

TestHttpServer::TestHttpServer()
{
    _listener = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (_listener < 0) {
        throw std::runtime_error(std::string("test server: socket: ") + std::strerror(errno));
    }
    const int yes = 1;
    ::setsockopt(_listener, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    address.sin_port = 0; // the system picks a free port
    if (::bind(_listener, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 || ::listen(_listener, 64) != 0) {
        ::close(_listener);
        throw std::runtime_error(std::string("test server: bind/listen: ") + std::strerror(errno));
    }
    socklen_t length = sizeof address;
    ::getsockname(_listener, reinterpret_cast<sockaddr*>(&address), &length);
    _port = ntohs(address.sin_port);
    _acceptor = std::thread([this] { acceptLoop(); });
}

TestHttpServer::~TestHttpServer()
{
    stop();
    if (_acceptor.joinable()) {
        _acceptor.join();
    }
    std::vector<std::thread> threads;
    {
        const std::lock_guard lock(_mutex);
        threads.swap(_threads);
    }
    for (std::thread& thread : threads) {
        thread.join();
    }
}

std::string TestHttpServer::url(const std::string& path) const
{
    return "http://127.0.0.1:" + std::to_string(_port) + path;
}

void TestHttpServer::set(const std::string& path, ScriptedResponse response)
{
    const std::lock_guard lock(_mutex);
    _responses[path] = std::move(response);
}

void TestHttpServer::stop()
{
    const std::lock_guard lock(_mutex);
    if (_stopping) {
        return;
    }
    _stopping = true;
    // shutdown() wakes the accept and recv calls blocked on these sockets; each thread closes its own.
    ::shutdown(_listener, SHUT_RDWR);
    for (const int connection : _connections) {
        ::shutdown(connection, SHUT_RDWR);
    }
    _stopped.notify_all();
}

int TestHttpServer::requests(const std::string& path) const
{
    const std::lock_guard lock(_mutex);
    const auto found = _requests.find(path);
    return found == _requests.end() ? 0 : found->second;
}

int TestHttpServer::totalRequests() const
{
    const std::lock_guard lock(_mutex);
    return _total;
}

int TestHttpServer::maximumConcurrent() const
{
    const std::lock_guard lock(_mutex);
    return _maximumConcurrent;
}

void TestHttpServer::acceptLoop()
{
    while (true) {
        const int connection = ::accept4(_listener, nullptr, nullptr, SOCK_CLOEXEC);
        const std::lock_guard lock(_mutex);
        if (connection < 0) {
            if (_stopping || (errno != EINTR && errno != ECONNABORTED)) {
                break;
            }
            continue;
        }
        if (_stopping) {
            ::close(connection);
            break;
        }
        _connections.push_back(connection);
        _threads.emplace_back([this, connection] { serve(connection); });
    }
    ::close(_listener);
}

void TestHttpServer::serve(int connection)
{
    std::string buffer;
    char chunk[4096];
    bool open = true;
    while (open) {
        const std::size_t headerEnd = buffer.find("\r\n\r\n");
        if (headerEnd == std::string::npos) {
            const ssize_t received = ::recv(connection, chunk, sizeof chunk, 0);
            if (received < 0 && errno == EINTR) {
                continue;
            }
            if (received <= 0 || buffer.size() > 65536) {
                break;
            }
            buffer.append(chunk, static_cast<std::size_t>(received));
            continue;
        }
        // "GET /path HTTP/1.1": the path is the second word; GET requests carry no body.
        const std::size_t firstSpace = buffer.find(' ');
        const std::size_t secondSpace = buffer.find(' ', firstSpace + 1);
        const std::string path = firstSpace < secondSpace && secondSpace < headerEnd
                                     ? buffer.substr(firstSpace + 1, secondSpace - firstSpace - 1)
                                     : std::string("/");
        const std::string headers = buffer.substr(0, headerEnd);
        buffer.erase(0, headerEnd + 4);
        open = answer(connection, path, headers);
    }
    const std::lock_guard lock(_mutex);
    _connections.erase(std::remove(_connections.begin(), _connections.end(), connection), _connections.end());
    ::close(connection);
}

bool TestHttpServer::answer(int connection, const std::string& path, const std::string& headers)
{
    ScriptedResponse response = ScriptedResponse::withStatus(404);
    {
        std::unique_lock lock(_mutex);
        _headers[path] = headers;
        ++_total;
        const int count = ++_requests[path];
        ++_concurrent;
        _maximumConcurrent = std::max(_maximumConcurrent, _concurrent);
        if (const auto found = _responses.find(path); found != _responses.end()) {
            response = found->second;
        }
        if (count <= response.failuresFirst) {
            response = ScriptedResponse::withStatus(500);
            response.body = {'o', 'o', 'p', 's'};
        } else if (count - response.failuresFirst <= response.truncatedFirst) {
            response.truncateAfter = response.body.size() / 2;
        }
        if (response.delay.count() > 0) {
            _stopped.wait_for(lock, response.delay, [&] { return _stopping; });
        }
        if (_stopping) {
            --_concurrent;
            return false;
        }
    }
    std::string head = "HTTP/1.1 " + std::to_string(response.status) + " " + reason(response.status) + "\r\n";
    head += "Content-Type: " + response.contentType + "\r\n";
    head += "Content-Length: " + std::to_string(response.body.size()) + "\r\n";
    head += response.truncateAfter ? "Connection: close\r\n\r\n" : "\r\n";
    const std::size_t bodyBytes = std::min(response.body.size(), response.truncateAfter.value_or(response.body.size()));
    const bool sent = sendAll(connection, head.data(), head.size()) && sendAll(connection, response.body.data(), bodyBytes);
    {
        const std::lock_guard lock(_mutex);
        --_concurrent;
    }
    return sent && !response.truncateAfter;
}

std::string TestHttpServer::lastRequestHeaders(const std::string& path) const
{
    const std::lock_guard lock(_mutex);
    const auto found = _headers.find(path);
    return found == _headers.end() ? std::string() : found->second;
}

} // namespace orbis::test
