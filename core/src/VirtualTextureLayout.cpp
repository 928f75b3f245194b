#include "orbis/core/VirtualTextureLayout.h"

#include <algorithm>
#include <cmath>

namespace orbis {

PageKey VirtualTextureLayout::pageOfIndex(std::uint64_t index) noexcept
{
    std::uint32_t level = 0;
    while (level < kMaximumTileLevel && firstIndexOfLevel(level + 1) <= index) {
        ++level;
    }
    const std::uint64_t within = index - firstIndexOfLevel(level);
    const std::uint64_t columns = pagesX(level);
    return {level, static_cast<std::uint32_t>(within % columns), static_cast<std::uint32_t>(within / columns)};
}

namespace {

/// The column or row of a coordinate 0..1 among `count`, the last one for 1 and beyond.
std::uint32_t cellOf(double coordinate, std::uint32_t count) noexcept
{
    const double scaled = std::floor(std::clamp(coordinate, 0.0, 1.0) * count);
    return static_cast<std::uint32_t>(std::min(scaled, static_cast<double>(count - 1)));
}

} // namespace

PageKey VirtualTextureLayout::pageAt(std::uint32_t level, double u, double v) noexcept
{
    return {level, cellOf(u, pagesX(level)), cellOf(v, pagesY(level))};
}

glm::dvec2 VirtualTextureLayout::positionInPage(const PageKey& page, double u, double v) noexcept
{
    return {u * pagesX(page.level) - page.x, v * pagesY(page.level) - page.y};
}

glm::dvec2 VirtualTextureLayout::contractToSlot(const glm::dvec2& positionInPage) const noexcept
{
    return (glm::dvec2(border) + positionInPage * static_cast<double>(pageSize)) / static_cast<double>(slotSize());
}

glm::dvec2 VirtualTextureLayout::expandFromSlot(const glm::dvec2& positionInSlot) const noexcept
{
    return (positionInSlot * static_cast<double>(slotSize()) - glm::dvec2(border)) / static_cast<double>(pageSize);
}

} // namespace orbis
