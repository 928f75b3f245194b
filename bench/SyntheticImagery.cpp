#include "SyntheticImagery.h"

#include <orbis/world/FileAccess.h>

#include <filesystem>

namespace orbis::bench {

SyntheticImagery::SyntheticImagery(std::uint32_t maximumLevel)
    : _bytes(world::readFileBytes(std::filesystem::path(ORBIS_SOURCE_DIR) / "data/imagery/BlueMarble/4/17/12.jpg", "tile"))
{
    _info.name = "synthetic imagery";
    _info.maximumLevel = maximumLevel;
    _info.format = "jpg";
}

world::TileFetch SyntheticImagery::fetch(const TileKey&)
{
    ++fetches;
    bytesRead += _bytes.size();
    world::TileFetch fetched;
    fetched.status = world::TileFetch::Status::Ok;
    fetched.bytes = _bytes;
    return fetched;
}

std::string SyntheticImagery::locate(const TileKey& key) const
{
    return "synthetic/" + std::to_string(key.level) + "/" + std::to_string(key.x) + "/" + std::to_string(key.y);
}

} // namespace orbis::bench
