#pragma once

#include <string>
#include <string_view>

namespace orbis::renderer {

/// The Unicode code points of UTF-8 text. Malformed sequences (stray continuation bytes,
/// truncated or overlong sequences, surrogates, values beyond U+10FFFF) each become U+FFFD, the
/// replacement character, and decoding goes on with the next byte; it never throws.
std::u32string decodeUtf8(std::string_view text);

} // namespace orbis::renderer
