// libFuzzer target for the glTF reader (tinygltf behind GltfModel::read): any input, written to a
// file as .gltf or .glb, either reads into batches whose materials exist and whose images decode
// or fail with orbis::Error, or is refused with an orbis::Error naming the file. Any other
// exception, a crash, a hang or a sanitizer report is a bug. The input's relative buffer and image
// names resolve in the folder the fuzzer runs in (scripts/fuzz.sh copies the seeds' files there).
// Built and run by scripts/fuzz.sh (clang, -fsanitize=fuzzer,address,undefined).
#include <orbis/core/Error.h>
#include <orbis/world/GltfModel.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include <unistd.h>

namespace {

void require(bool condition)
{
    if (!condition) {
        std::abort();
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    // One file per process, so that parallel fuzzing jobs in one folder do not share it.
    static const std::string name = "fuzz-input-" + std::to_string(::getpid()) + ".gltf";
    {
        std::ofstream file(name, std::ios::binary | std::ios::trunc);
        file.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
        require(static_cast<bool>(file));
    }
    try {
        const orbis::world::GltfModel model = orbis::world::GltfModel::read(name);
        for (const orbis::world::GltfBatch& batch : model.batches) {
            require(batch.material < model.materials.size());
        }
        for (std::size_t i = 0; i < model.images.size(); ++i) {
            try {
                model.decodeImage(i);
            } catch (const orbis::Error& error) {
                require(std::string_view(error.what()).find(name) != std::string_view::npos);
            }
        }
    } catch (const orbis::Error& error) {
        require(std::string_view(error.what()).find(name) != std::string_view::npos);
    }
    return 0;
}
