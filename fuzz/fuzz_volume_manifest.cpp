// Fuzzes vastray-volumes.json, the manifest of a zip upload's volumes: readVolumeManifest
// (server/src/VolumeManifest.h) on the input as the manifest at the root of an extracted zip
// whose other files are a mesh and two .vdb files it may name (their bytes are never read
// here). Any input gives volumes or a refusal naming the manifest, never a crash.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "FuzzInput.h"
#include "VolumeManifest.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace vastray::server;
    const std::filesystem::path manifest = vastray::fuzz::writeInput(data, size, kVolumeManifestName);
    static const std::vector<std::filesystem::path> files = {kVolumeManifestName, "floor.ply", "fog.vdb",
                                                             "smoke/fog.vdb"};
    (void)readVolumeManifest(manifest.parent_path(), files, "upload.zip");
    return 0;
}
