#include "JsonLocator.h"

#include <cstdint>
#include <unordered_map>

namespace orbis::world::detail {

namespace {

constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";

bool isWhitespace(char c) noexcept
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

int hexValue(char c) noexcept
{
    if (c >= '0' && c <= '9') {
        return c - '0';
    }
    if (c >= 'a' && c <= 'f') {
        return c - 'a' + 10;
    }
    if (c >= 'A' && c <= 'F') {
        return c - 'A' + 10;
    }
    return -1;
}

void appendUtf8(std::string& out, std::uint32_t codePoint)
{
    if (codePoint < 0x80) {
        out += static_cast<char>(codePoint);
    } else if (codePoint < 0x800) {
        out += static_cast<char>(0xC0 | (codePoint >> 6));
        out += static_cast<char>(0x80 | (codePoint & 0x3F));
    } else if (codePoint < 0x10000) {
        out += static_cast<char>(0xE0 | (codePoint >> 12));
        out += static_cast<char>(0x80 | ((codePoint >> 6) & 0x3F));
        out += static_cast<char>(0x80 | (codePoint & 0x3F));
    } else {
        out += static_cast<char>(0xF0 | (codePoint >> 18));
        out += static_cast<char>(0x80 | ((codePoint >> 12) & 0x3F));
        out += static_cast<char>(0x80 | ((codePoint >> 6) & 0x3F));
        out += static_cast<char>(0x80 | (codePoint & 0x3F));
    }
}

// Walks JSON text once, telling a visitor where each key and value starts, with the path of
// reference tokens leading to it (object keys decoded as nlohmann decodes them, array indices in
// decimal). An explicit stack instead of recursion, so depth costs heap, not stack.
class Scanner {
public:
    explicit Scanner(std::string_view text) : _text(text)
    {
        if (_text.starts_with(kByteOrderMark)) {
            _pos = kByteOrderMark.size();
        }
    }

    // Visitor: bool key(path, offset), bool value(path, offset), bool duplicate(path, offset,
    // firstOffset); each returns true to stop. trackKeys: remember keys per object for duplicate().
    template <class Visitor>
    void run(Visitor& visitor, bool trackKeys)
    {
        enum class State { Value, FirstKey, Key, AfterValue };
        struct Frame {
            bool isObject;
            std::size_t index;
            std::unordered_map<std::string, std::size_t> keys;
        };
        std::vector<Frame> frames;
        std::vector<std::string> path;
        State state = State::Value;
        while (true) {
            skipWhitespace();
            if (_pos >= _text.size()) {
                return;
            }
            const char c = _text[_pos];
            switch (state) {
            case State::Value:
                if (visitor.value(path, _pos)) {
                    return;
                }
                if (c == '{') {
                    frames.push_back({true, 0, {}});
                    ++_pos;
                    state = State::FirstKey;
                } else if (c == '[') {
                    frames.push_back({false, 0, {}});
                    ++_pos;
                    skipWhitespace();
                    if (_pos < _text.size() && _text[_pos] == ']') {
                        ++_pos;
                        frames.pop_back();
                        state = State::AfterValue;
                    } else {
                        path.emplace_back("0");
                    }
                } else if (c == '"') {
                    if (!readString(nullptr)) {
                        return;
                    }
                    state = State::AfterValue;
                } else {
                    if (!skipScalar()) {
                        return;
                    }
                    state = State::AfterValue;
                }
                break;
            case State::FirstKey:
                if (c == '}') {
                    ++_pos;
                    frames.pop_back();
                    state = State::AfterValue;
                } else {
                    state = State::Key;
                }
                break;
            case State::Key: {
                if (c != '"') {
                    return;
                }
                const std::size_t keyOffset = _pos;
                std::string key;
                if (!readString(&key)) {
                    return;
                }
                path.push_back(key);
                if (visitor.key(path, keyOffset)) {
                    return;
                }
                if (trackKeys) {
                    auto [it, inserted] = frames.back().keys.emplace(std::move(key), keyOffset);
                    if (!inserted && visitor.duplicate(path, keyOffset, it->second)) {
                        return;
                    }
                }
                skipWhitespace();
                if (_pos >= _text.size() || _text[_pos] != ':') {
                    return;
                }
                ++_pos;
                state = State::Value;
                break;
            }
            case State::AfterValue: {
                if (frames.empty()) {
                    return;
                }
                Frame& frame = frames.back();
                if (c == ',') {
                    ++_pos;
                    path.pop_back();
                    if (frame.isObject) {
                        state = State::Key;
                    } else {
                        ++frame.index;
                        path.push_back(std::to_string(frame.index));
                        state = State::Value;
                    }
                } else if ((c == '}' && frame.isObject) || (c == ']' && !frame.isObject)) {
                    ++_pos;
                    path.pop_back();
                    frames.pop_back();
                } else {
                    return;
                }
                break;
            }
            }
        }
    }

private:
    void skipWhitespace() noexcept
    {
        while (_pos < _text.size() && isWhitespace(_text[_pos])) {
            ++_pos;
        }
    }

    // Numbers, true, false, null: up to the next delimiter.
    bool skipScalar() noexcept
    {
        const std::size_t start = _pos;
        while (_pos < _text.size()) {
            const char c = _text[_pos];
            if (isWhitespace(c) || c == ',' || c == ']' || c == '}' || c == ':' || c == '"' || c == '[' ||
                c == '{') {
                break;
            }
            ++_pos;
        }
        return _pos > start;
    }

    // At an opening quote: moves past the closing quote, decoding into out when given.
    bool readString(std::string* out)
    {
        ++_pos;
        while (_pos < _text.size()) {
            const char c = _text[_pos++];
            if (c == '"') {
                return true;
            }
            if (c != '\\') {
                if (out != nullptr) {
                    *out += c;
                }
                continue;
            }
            if (_pos >= _text.size()) {
                return false;
            }
            const char escape = _text[_pos++];
            char decoded = 0;
            switch (escape) {
            case '"': decoded = '"'; break;
            case '\\': decoded = '\\'; break;
            case '/': decoded = '/'; break;
            case 'b': decoded = '\b'; break;
            case 'f': decoded = '\f'; break;
            case 'n': decoded = '\n'; break;
            case 'r': decoded = '\r'; break;
            case 't': decoded = '\t'; break;
            case 'u': {
                std::optional<std::uint32_t> unit = readHex4();
                if (!unit) {
                    return false;
                }
                std::uint32_t codePoint = *unit;
                if (codePoint >= 0xD800 && codePoint <= 0xDBFF && _pos + 1 < _text.size() && _text[_pos] == '\\' &&
                    _text[_pos + 1] == 'u') {
                    _pos += 2;
                    const std::optional<std::uint32_t> low = readHex4();
                    if (!low) {
                        return false;
                    }
                    codePoint = 0x10000 + ((codePoint - 0xD800) << 10) + (*low - 0xDC00);
                }
                if (out != nullptr) {
                    appendUtf8(*out, codePoint);
                }
                continue;
            }
            default:
                return false;
            }
            if (out != nullptr) {
                *out += decoded;
            }
        }
        return false;
    }

    std::optional<std::uint32_t> readHex4() noexcept
    {
        if (_text.size() - _pos < 4) {
            return std::nullopt;
        }
        std::uint32_t value = 0;
        for (int i = 0; i < 4; ++i) {
            const int digit = hexValue(_text[_pos++]);
            if (digit < 0) {
                return std::nullopt;
            }
            value = value * 16 + static_cast<std::uint32_t>(digit);
        }
        return value;
    }

    std::string_view _text;
    std::size_t _pos = 0;
};

} // namespace

TextPosition textPositionOf(std::string_view text, std::size_t offset) noexcept
{
    const std::size_t end = offset < text.size() ? offset : text.size();
    std::size_t start = text.starts_with(kByteOrderMark) ? kByteOrderMark.size() : 0;
    TextPosition position;
    for (std::size_t i = start; i < end; ++i) {
        const auto byte = static_cast<unsigned char>(text[i]);
        if (byte == '\n') {
            ++position.line;
            position.column = 1;
        } else if ((byte & 0xC0) != 0x80) { // not a UTF-8 continuation byte
            ++position.column;
        }
    }
    return position;
}

std::string appendToPointer(std::string_view pointer, std::string_view token)
{
    std::string result(pointer);
    result += '/';
    for (const char c : token) {
        if (c == '~') {
            result += "~0";
        } else if (c == '/') {
            result += "~1";
        } else {
            result += c;
        }
    }
    return result;
}

std::vector<std::string> splitPointer(std::string_view pointer)
{
    std::vector<std::string> tokens;
    if (pointer.empty()) {
        return tokens;
    }
    std::size_t i = pointer.front() == '/' ? 1 : 0;
    std::string token;
    for (; i <= pointer.size(); ++i) {
        if (i == pointer.size() || pointer[i] == '/') {
            tokens.push_back(std::move(token));
            token.clear();
        } else if (pointer[i] == '~' && i + 1 < pointer.size() && (pointer[i + 1] == '0' || pointer[i + 1] == '1')) {
            token += pointer[i + 1] == '0' ? '~' : '/';
            ++i;
        } else {
            token += pointer[i];
        }
    }
    return tokens;
}

std::optional<std::size_t> locateInJson(std::string_view text, std::string_view pointer, bool atKey)
{
    struct Finder {
        std::vector<std::string> target;
        bool atKey;
        std::optional<std::size_t> found;

        bool key(const std::vector<std::string>& path, std::size_t offset)
        {
            if (atKey && path == target) {
                found = offset;
                return true;
            }
            return false;
        }
        bool value(const std::vector<std::string>& path, std::size_t offset)
        {
            if (path == target) {
                // A key's location stands in for its value's only when the key is asked for.
                if (!atKey || target.empty()) {
                    found = offset;
                }
                return true;
            }
            return false;
        }
        bool duplicate(const std::vector<std::string>&, std::size_t, std::size_t) { return false; }
    };
    Finder finder{splitPointer(pointer), atKey, std::nullopt};
    Scanner(text).run(finder, false);
    return finder.found;
}

std::optional<DuplicateKey> findDuplicateKey(std::string_view text)
{
    struct Finder {
        std::optional<DuplicateKey> found;

        bool key(const std::vector<std::string>&, std::size_t) { return false; }
        bool value(const std::vector<std::string>&, std::size_t) { return false; }
        bool duplicate(const std::vector<std::string>& path, std::size_t offset, std::size_t firstOffset)
        {
            std::string pointer;
            for (const std::string& token : path) {
                pointer = appendToPointer(pointer, token);
            }
            found = DuplicateKey{std::move(pointer), offset, firstOffset};
            return true;
        }
    };
    Finder finder;
    Scanner(text).run(finder, true);
    return finder.found;
}

} // namespace orbis::world::detail
