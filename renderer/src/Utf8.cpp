#include "orbis/renderer/Utf8.h"

namespace orbis::renderer {

std::u32string decodeUtf8(std::string_view text)
{
    constexpr char32_t kReplacement = 0xFFFD;
    std::u32string codepoints;
    codepoints.reserve(text.size());
    const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
    for (std::size_t i = 0; i < text.size();) {
        const unsigned char lead = byte(i);
        if (lead < 0x80) {
            codepoints.push_back(lead);
            ++i;
            continue;
        }
        // Sequence length and the smallest value it may encode (anything less is overlong).
        std::size_t length = 0;
        char32_t value = 0;
        char32_t minimum = 0;
        if ((lead & 0xE0) == 0xC0) {
            length = 2;
            value = lead & 0x1Fu;
            minimum = 0x80;
        } else if ((lead & 0xF0) == 0xE0) {
            length = 3;
            value = lead & 0x0Fu;
            minimum = 0x800;
        } else if ((lead & 0xF8) == 0xF0) {
            length = 4;
            value = lead & 0x07u;
            minimum = 0x10000;
        } else {
            codepoints.push_back(kReplacement); // a continuation byte or 0xF8..0xFF as lead
            ++i;
            continue;
        }
        std::size_t j = 1;
        for (; j < length && i + j < text.size() && (byte(i + j) & 0xC0) == 0x80; ++j) {
            value = (value << 6) | (byte(i + j) & 0x3Fu);
        }
        if (j < length || value < minimum || value > 0x10FFFF || (value >= 0xD800 && value <= 0xDFFF)) {
            codepoints.push_back(kReplacement);
            i += j; // skip the bytes that looked like part of the sequence
            continue;
        }
        codepoints.push_back(value);
        i += length;
    }
    return codepoints;
}

} // namespace orbis::renderer
