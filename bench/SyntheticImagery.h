#pragma once

// An imagery source as deep as a benchmark needs, for the streamed globe's and the virtual
// texture's sections.

#include <orbis/world/TileSource.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace orbis::bench {

/// One real JPEG (the Blue Marble's level-4 tile over the Alps) served for every tile of a
/// geographic pyramid `maximumLevel` deep: the fetches and decodes are real work, and the data does
/// not run out above level 4 as the shipped pyramid does. Counts what was asked of it.
class SyntheticImagery final : public world::TileSource {
public:
    explicit SyntheticImagery(std::uint32_t maximumLevel);
    const world::TileSourceInfo& info() const noexcept override { return _info; }
    world::TileFetch fetch(const TileKey&) override;
    std::string locate(const TileKey& key) const override;

    std::atomic<std::size_t> fetches{0};
    std::atomic<std::size_t> bytesRead{0};

private:
    world::TileSourceInfo _info;
    std::vector<std::uint8_t> _bytes;
};

} // namespace orbis::bench
