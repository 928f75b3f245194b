#include "HttpClient.h"

#include "orbis/world/FileAccess.h"

#include <orbis/core/Error.h>

#include <curl/curl.h>

#include <algorithm>
#include <thread>

namespace orbis::world::detail {

namespace {

/// curl_global_init is not safe alongside other threads' curl calls: done once, before any handle.
void initialiseCurl()
{
    static const CURLcode initialised = curl_global_init(CURL_GLOBAL_DEFAULT);
    if (initialised != CURLE_OK) {
        throw Error(std::string("cannot initialise libcurl: ") + curl_easy_strerror(initialised));
    }
}

struct Body {
    std::vector<std::uint8_t> bytes;
    std::size_t maximum = 0;
    bool tooLarge = false;
};

std::size_t appendBody(char* data, std::size_t size, std::size_t count, void* user)
{
    auto* body = static_cast<Body*>(user);
    const std::size_t length = size * count;
    if (body->bytes.size() + length > body->maximum) {
        body->tooLarge = true;
        return 0; // curl then stops with CURLE_WRITE_ERROR
    }
    body->bytes.insert(body->bytes.end(), data, data + length);
    return length;
}

/// Failures worth another attempt: the server's or the connection's, which may pass.
bool isTransient(CURLcode code)
{
    switch (code) {
    case CURLE_COULDNT_CONNECT:
    case CURLE_RECV_ERROR:
    case CURLE_SEND_ERROR:
    case CURLE_PARTIAL_FILE:
    case CURLE_GOT_NOTHING:
    case CURLE_HTTP2:
    case CURLE_HTTP2_STREAM:
    case CURLE_SSL_CONNECT_ERROR: return true;
    default: return false;
    }
}

std::string attemptsNote(int attempts)
{
    return attempts > 1 ? " (after " + std::to_string(attempts) + " attempts)" : "";
}

} // namespace

bool isHttpUrl(std::string_view text) noexcept
{
    return text.starts_with("http://") || text.starts_with("https://");
}

HttpClient::HttpClient(const HttpOptions& options, std::size_t maximumBytes)
    : _options(options), _maximumBytes(maximumBytes)
{
    initialiseCurl();
    _options.maximumRequestsInFlight = std::max(_options.maximumRequestsInFlight, 1);
    _options.retries = std::max(_options.retries, 0);
    for (const std::string& header : _options.headers) {
        _headers = curl_slist_append(static_cast<curl_slist*>(_headers), header.c_str());
    }
}

HttpClient::~HttpClient()
{
    for (void* handle : _idle) {
        curl_easy_cleanup(static_cast<CURL*>(handle));
    }
    curl_slist_free_all(static_cast<curl_slist*>(_headers));
}

void* HttpClient::acquire()
{
    std::unique_lock lock(_mutex);
    _available.wait(lock, [&] { return !_idle.empty() || _created < _options.maximumRequestsInFlight; });
    if (!_idle.empty()) {
        void* handle = _idle.back();
        _idle.pop_back();
        return handle;
    }
    CURL* handle = curl_easy_init();
    if (handle) {
        ++_created;
    }
    return handle;
}

void HttpClient::release(void* handle)
{
    {
        const std::lock_guard lock(_mutex);
        _idle.push_back(handle);
    }
    _available.notify_one();
}

TileFetch HttpClient::get(const std::string& url)
{
    TileFetch result;
    const std::string where = cutForMessage(url);
    for (int attempt = 1;; ++attempt) {
        result.attempts = attempt;
        CURL* curl = static_cast<CURL*>(acquire());
        if (!curl) {
            result.message = where + ": cannot start a libcurl request";
            return result;
        }
        Body body;
        body.maximum = _maximumBytes;
        char errorText[CURL_ERROR_SIZE] = {};
        curl_easy_setopt(curl, CURLOPT_URL, url.c_str());
        curl_easy_setopt(curl, CURLOPT_PROTOCOLS_STR, "http,https");
        curl_easy_setopt(curl, CURLOPT_REDIR_PROTOCOLS_STR, "http,https");
        curl_easy_setopt(curl, CURLOPT_FOLLOWLOCATION, 1L);
        curl_easy_setopt(curl, CURLOPT_MAXREDIRS, 5L);
        curl_easy_setopt(curl, CURLOPT_NOSIGNAL, 1L); // timeouts without SIGALRM: other threads run on
        curl_easy_setopt(curl, CURLOPT_CONNECTTIMEOUT_MS, static_cast<long>(_options.connectTimeout.count()));
        curl_easy_setopt(curl, CURLOPT_TIMEOUT_MS, static_cast<long>(_options.totalTimeout.count()));
        curl_easy_setopt(curl, CURLOPT_ACCEPT_ENCODING, ""); // whatever libcurl decodes (gzip for terrain)
        curl_easy_setopt(curl, CURLOPT_USERAGENT, _options.userAgent.c_str());
        curl_easy_setopt(curl, CURLOPT_HTTPHEADER, static_cast<curl_slist*>(_headers));
        curl_easy_setopt(curl, CURLOPT_MAXFILESIZE_LARGE, static_cast<curl_off_t>(_maximumBytes));
        curl_easy_setopt(curl, CURLOPT_WRITEFUNCTION, appendBody);
        curl_easy_setopt(curl, CURLOPT_WRITEDATA, &body);
        curl_easy_setopt(curl, CURLOPT_ERRORBUFFER, errorText);
        const CURLcode code = curl_easy_perform(curl);
        long status = 0;
        curl_easy_getinfo(curl, CURLINFO_RESPONSE_CODE, &status);
        curl_easy_setopt(curl, CURLOPT_ERRORBUFFER, nullptr);
        curl_easy_setopt(curl, CURLOPT_WRITEDATA, nullptr);
        release(curl);

        bool retry = false;
        if (code == CURLE_OK) {
            if (status >= 200 && status < 300 && status != 204) {
                result.status = TileFetch::Status::Ok;
                result.bytes = std::move(body.bytes);
                return result;
            }
            if (status == 204 || status == 404 || status == 410) {
                result.status = TileFetch::Status::Missing;
                return result;
            }
            retry = status >= 500 || status == 429;
            result.message = where + ": HTTP " + std::to_string(status);
        } else if (body.tooLarge || code == CURLE_FILESIZE_EXCEEDED) {
            result.message = where + ": the response is larger than the " + std::to_string(_maximumBytes) +
                             " bytes a tile may have";
        } else {
            retry = isTransient(code);
            const std::string detail = errorText[0] ? std::string(errorText) : curl_easy_strerror(code);
            const char* what = code == CURLE_OPERATION_TIMEDOUT ? "timed out"
                               : code == CURLE_PARTIAL_FILE    ? "the response was cut short"
                               : code == CURLE_COULDNT_CONNECT ? "cannot connect"
                                                               : "request failed";
            result.message = where + ": " + what + ": " + detail;
        }
        if (!retry || attempt > _options.retries) {
            result.status = TileFetch::Status::Failed;
            result.message += attemptsNote(attempt);
            return result;
        }
        // Exponential backoff, so a struggling server is not hammered; no handle is held meanwhile.
        const auto wait = std::min(_options.backoff * (std::int64_t{1} << std::min(attempt - 1, 20)), _options.maximumBackoff);
        std::this_thread::sleep_for(wait);
    }
}

} // namespace orbis::world::detail
