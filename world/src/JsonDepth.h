#pragma once

// How deep JSON text nests, found before a parser sees it: parsing, reading and freeing a JSON
// document recurse once per level (nlohmann's and tinygltf's alike), so a hostile file nested a
// hundred thousand deep would exhaust the stack. Internal to orbis::world.

#include <cstddef>
#include <string_view>

namespace orbis::world::detail {

/// Byte offset of the first '[' or '{' (outside strings) nested deeper than limit, or npos. One
/// pass, no allocation: linear in the text whatever it holds, valid JSON or not.
std::size_t firstBracketDeeperThan(std::string_view text, std::size_t limit) noexcept;

} // namespace orbis::world::detail
