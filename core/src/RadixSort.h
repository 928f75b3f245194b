#pragma once

// Sorting by unsigned 64-bit keys in linear time: a byte at a time, least significant first.
// Internal to orbis::core.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace orbis::detail {

/// Sorts items stably by keyOf(item) >> firstBit (firstBit a multiple of 8), skipping a byte all
/// keys share. scratch: working memory, kept between calls.
template <typename T, typename KeyOf>
void radixSort(std::vector<T>& items, std::vector<T>& scratch, KeyOf&& keyOf, int firstBit = 0)
{
    scratch.resize(items.size());
    for (int shift = firstBit; shift < 64; shift += 8) {
        std::array<std::size_t, 257> start{};
        for (const T& item : items) {
            ++start[((keyOf(item) >> shift) & 0xff) + 1];
        }
        if (std::find(start.begin() + 1, start.end(), items.size()) != start.end()) {
            continue;
        }
        for (std::size_t b = 1; b < start.size(); ++b) {
            start[b] += start[b - 1];
        }
        for (const T& item : items) {
            scratch[start[(keyOf(item) >> shift) & 0xff]++] = item;
        }
        items.swap(scratch);
    }
}

} // namespace orbis::detail
