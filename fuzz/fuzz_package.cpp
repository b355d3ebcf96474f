// Fuzzes the package reader: open (header, materials, top-level tree, directory) and, when
// that succeeds, every chunk's read and decode and every volume's (`info --verify`: from format 6
// the brick tables, then each brick through the source a render reads them with).
#include "FuzzInput.h"
#include "vastray/streamer/ScenePackage.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = vastray::fuzz::writeInput(data, size, "input.vast");
    auto reader = vastray::PackageReader::open(path);
    if (reader) (void)(*reader)->verify();
    return 0;
}
