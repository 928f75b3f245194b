#include "XmlScanner.h"

#include "orbis/world/FileAccess.h"

#include <orbis/core/Error.h>

#include <charconv>
#include <cstdint>

namespace orbis::world::detail {

std::optional<std::string_view> XmlElement::attribute(std::string_view attributeName) const noexcept
{
    for (const auto& [key, value] : attributes) {
        if (key == attributeName) {
            return std::string_view(value);
        }
    }
    return std::nullopt;
}

const XmlElement* XmlDocument::child(const XmlElement& element, std::string_view name) const noexcept
{
    for (const int index : element.children) {
        if (elements[static_cast<std::size_t>(index)].name == name) {
            return &elements[static_cast<std::size_t>(index)];
        }
    }
    return nullptr;
}

std::vector<const XmlElement*> XmlDocument::children(const XmlElement& element, std::string_view name) const
{
    std::vector<const XmlElement*> found;
    for (const int index : element.children) {
        if (elements[static_cast<std::size_t>(index)].name == name) {
            found.push_back(&elements[static_cast<std::size_t>(index)]);
        }
    }
    return found;
}

namespace {

bool isSpace(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

bool isNameStart(char c)
{
    const auto u = static_cast<unsigned char>(c);
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_' || c == ':' || u >= 0x80;
}

bool isNameChar(char c)
{
    return isNameStart(c) || (c >= '0' && c <= '9') || c == '-' || c == '.';
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

class Scanner {
public:
    Scanner(std::string_view text, std::string_view name, const XmlLimits& limits)
        : _text(text), _name(cutForMessage(name)), _limits(limits)
    {
    }

    XmlDocument run()
    {
        if (_text.size() > _limits.maximumBytes) {
            throw Error(_name + ": " + std::to_string(_text.size()) + " bytes, more than the " +
                        std::to_string(_limits.maximumBytes) + " a description may have");
        }
        if (_text.find('\0') != std::string_view::npos) {
            _position = _text.find('\0');
            fail("a NUL byte");
        }
        if (_text.starts_with("\xEF\xBB\xBF")) {
            _position = 3;
        }
        while (_position < _text.size()) {
            if (_text[_position] == '<') {
                markup();
            } else {
                characters();
            }
        }
        if (!_open.empty()) {
            fail("the file ends inside <" + _document.elements[static_cast<std::size_t>(_open.back())].name + ">");
        }
        if (_document.elements.empty()) {
            fail("no root element");
        }
        return std::move(_document);
    }

private:
    [[noreturn]] void fail(const std::string& what) const
    {
        int line = 1;
        std::size_t lineStart = 0;
        const std::size_t end = std::min(_position, _text.size());
        for (std::size_t i = 0; i < end; ++i) {
            if (_text[i] == '\n') {
                ++line;
                lineStart = i + 1;
            }
        }
        throw Error(_name + ":" + std::to_string(line) + ":" + std::to_string(end - lineStart + 1) + ": " + what);
    }

    /// The line of `offset`; offsets asked for only grow, so lines are counted once.
    int lineAt(std::size_t offset)
    {
        for (; _lineCountedTo < offset; ++_lineCountedTo) {
            _lines += _text[_lineCountedTo] == '\n' ? 1 : 0;
        }
        return _lines + 1;
    }

    bool startsWith(std::string_view prefix) const { return _text.substr(_position).starts_with(prefix); }

    /// Moves past `terminator`, which must come; fails naming `what` otherwise.
    std::string_view until(std::string_view terminator, const char* what)
    {
        const std::size_t end = _text.find(terminator, _position);
        if (end == std::string_view::npos) {
            fail(std::string("unterminated ") + what);
        }
        const std::string_view inside = _text.substr(_position, end - _position);
        _position = end + terminator.size();
        return inside;
    }

    void skipSpace()
    {
        while (_position < _text.size() && isSpace(_text[_position])) {
            ++_position;
        }
    }

    std::string name(const char* what)
    {
        const std::size_t start = _position;
        if (_position >= _text.size() || !isNameStart(_text[_position])) {
            fail(std::string("expected ") + what);
        }
        while (_position < _text.size() && isNameChar(_text[_position])) {
            ++_position;
        }
        if (_position - start > 256) {
            _position = start;
            fail(std::string(what) + " longer than 256 characters");
        }
        return std::string(_text.substr(start, _position - start));
    }

    /// `raw` with entity and character references resolved.
    std::string resolve(std::string_view raw, std::size_t rawStart)
    {
        std::string out;
        out.reserve(raw.size());
        for (std::size_t i = 0; i < raw.size(); ++i) {
            if (raw[i] != '&') {
                out += raw[i];
                continue;
            }
            const std::size_t end = raw.find(';', i);
            if (end == std::string_view::npos || end - i > 12) {
                _position = rawStart + i;
                fail("an '&' that starts no entity (write &amp;)");
            }
            const std::string_view entity = raw.substr(i + 1, end - i - 1);
            if (entity == "lt") {
                out += '<';
            } else if (entity == "gt") {
                out += '>';
            } else if (entity == "amp") {
                out += '&';
            } else if (entity == "quot") {
                out += '"';
            } else if (entity == "apos") {
                out += '\'';
            } else if (entity.size() >= 2 && entity[0] == '#') {
                const bool hex = entity[1] == 'x';
                const std::string_view digits = entity.substr(hex ? 2 : 1);
                std::uint32_t codePoint = 0;
                const auto [rest, error] = std::from_chars(digits.data(), digits.data() + digits.size(), codePoint, hex ? 16 : 10);
                if (error != std::errc() || rest != digits.data() + digits.size() || digits.empty() || codePoint == 0 ||
                    codePoint > 0x10FFFF || (codePoint >= 0xD800 && codePoint <= 0xDFFF)) {
                    _position = rawStart + i;
                    fail("an invalid character reference &" + std::string(entity) + ";");
                }
                appendUtf8(out, codePoint);
            } else {
                _position = rawStart + i;
                fail("unknown entity &" + cutForMessage(entity, 12) + ";");
            }
            i = end;
        }
        return out;
    }

    XmlElement* current() { return _open.empty() ? nullptr : &_document.elements[static_cast<std::size_t>(_open.back())]; }

    void characters()
    {
        const std::size_t start = _position;
        const std::size_t end = std::min(_text.find('<', _position), _text.size());
        const std::string_view raw = _text.substr(start, end - start);
        XmlElement* element = current();
        if (!element) {
            for (const char c : raw) {
                if (!isSpace(c)) {
                    _position = start;
                    fail("text outside the root element");
                }
            }
            _position = end;
            return;
        }
        element->text += resolve(raw, start);
        _position = end;
    }

    void markup()
    {
        if (startsWith("<?")) {
            until("?>", "processing instruction");
        } else if (startsWith("<!--")) {
            _position += 4;
            until("-->", "comment");
        } else if (startsWith("<![CDATA[")) {
            XmlElement* element = current();
            if (!element) {
                fail("CDATA outside the root element");
            }
            _position += 9;
            element->text += until("]]>", "CDATA section");
        } else if (startsWith("<!DOCTYPE")) {
            if (!_document.elements.empty()) {
                fail("a DOCTYPE after the root element");
            }
            const std::size_t start = _position;
            const std::string_view declaration = until(">", "DOCTYPE");
            if (declaration.find('[') != std::string_view::npos) {
                _position = start;
                fail("a DOCTYPE with declarations (entities are not expanded here)");
            }
        } else if (startsWith("</")) {
            endTag();
        } else {
            startTag();
        }
    }

    void endTag()
    {
        const std::size_t start = _position;
        _position += 2;
        const std::string tag = name("an element name after </");
        skipSpace();
        if (_position >= _text.size() || _text[_position] != '>') {
            fail("expected '>' to close </" + tag);
        }
        ++_position;
        if (_open.empty() || _document.elements[static_cast<std::size_t>(_open.back())].name != tag) {
            _position = start;
            fail("</" + tag + "> closes " +
                 (_open.empty() ? std::string("nothing")
                                : "<" + _document.elements[static_cast<std::size_t>(_open.back())].name + ">"));
        }
        _open.pop_back();
    }

    void startTag()
    {
        const std::size_t start = _position;
        ++_position;
        if (_rootClosed()) {
            fail("a second root element");
        }
        if (_document.elements.size() >= _limits.maximumElements) {
            fail("more than " + std::to_string(_limits.maximumElements) + " elements");
        }
        if (_open.size() >= static_cast<std::size_t>(_limits.maximumDepth)) {
            fail("elements nested deeper than " + std::to_string(_limits.maximumDepth));
        }
        XmlElement element;
        element.name = name("an element name after <");
        element.line = lineAt(start);
        element.parent = _open.empty() ? -1 : _open.back();
        bool selfClosing = false;
        while (true) {
            const std::size_t before = _position;
            skipSpace();
            if (_position >= _text.size()) {
                fail("the file ends inside the tag <" + element.name);
            }
            if (_text[_position] == '>') {
                ++_position;
                break;
            }
            if (startsWith("/>")) {
                _position += 2;
                selfClosing = true;
                break;
            }
            if (_position == before) {
                fail("expected a space, '>' or '/>' in <" + element.name);
            }
            if (element.attributes.size() >= _limits.maximumAttributes) {
                fail("more than " + std::to_string(_limits.maximumAttributes) + " attributes in <" + element.name + ">");
            }
            std::string key = name("an attribute name");
            skipSpace();
            if (_position >= _text.size() || _text[_position] != '=') {
                fail("expected '=' after the attribute " + key);
            }
            ++_position;
            skipSpace();
            if (_position >= _text.size() || (_text[_position] != '"' && _text[_position] != '\'')) {
                fail("expected a quoted value for the attribute " + key);
            }
            const char quote = _text[_position++];
            const std::size_t valueStart = _position;
            const std::size_t valueEnd = _text.find(quote, _position);
            if (valueEnd == std::string_view::npos) {
                fail("unterminated value of the attribute " + key);
            }
            const std::string_view raw = _text.substr(valueStart, valueEnd - valueStart);
            if (const std::size_t lessThan = raw.find('<'); lessThan != std::string_view::npos) {
                _position = valueStart + lessThan;
                fail("a '<' in the value of the attribute " + key);
            }
            if (element.attribute(key)) {
                fail("the attribute " + key + " twice in <" + element.name + ">");
            }
            std::string value = resolve(raw, valueStart);
            _position = valueEnd + 1;
            element.attributes.emplace_back(std::move(key), std::move(value));
        }
        const int index = static_cast<int>(_document.elements.size());
        if (element.parent >= 0) {
            _document.elements[static_cast<std::size_t>(element.parent)].children.push_back(index);
        }
        _document.elements.push_back(std::move(element));
        if (!selfClosing) {
            _open.push_back(index);
        }
    }

    bool _rootClosed() const { return !_document.elements.empty() && _open.empty(); }

    std::string_view _text;
    std::string _name;
    XmlLimits _limits;
    std::size_t _position = 0;
    std::size_t _lineCountedTo = 0;
    int _lines = 0;
    XmlDocument _document;
    std::vector<int> _open; ///< indices of the elements open around the position
};

} // namespace

XmlDocument parseXml(std::string_view text, std::string_view nameForMessages, const XmlLimits& limits)
{
    return Scanner(text, nameForMessages, limits).run();
}

std::string escapeXml(std::string_view text)
{
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
        switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        default: out += c;
        }
    }
    return out;
}

} // namespace orbis::world::detail
