#pragma once

// HTTP GET over libcurl for tile sources: a pool of easy handles (kept alive between requests)
// whose size bounds the requests in flight, timeouts, retries with exponential backoff. Private to
// orbis::world.

#include "orbis/world/TileSource.h"

#include <condition_variable>
#include <mutex>
#include <string>
#include <vector>

namespace orbis::world::detail {

class HttpClient {
public:
    HttpClient(const HttpOptions& options, std::size_t maximumBytes);
    ~HttpClient();
    HttpClient(const HttpClient&) = delete;
    HttpClient& operator=(const HttpClient&) = delete;

    /// Ok with the body for 2xx (204 No Content is Missing), Missing for 404 and 410, Failed with
    /// a message naming the URL otherwise, after the retries HttpOptions allows. Thread-safe;
    /// never throws for the response's trouble.
    TileFetch get(const std::string& url);

private:
    void* acquire();
    void release(void* handle);

    HttpOptions _options;
    std::size_t _maximumBytes;
    std::mutex _mutex;
    std::condition_variable _available;
    std::vector<void*> _idle;
    int _created = 0;
    void* _headers = nullptr; ///< curl_slist of HttpOptions::headers
};

/// True for http:// and https:// URLs.
bool isHttpUrl(std::string_view text) noexcept;

} // namespace orbis::world::detail
