// Fuzzes the formats read through assimp (kAssimpFormats): the first byte picks the
// extension, the rest is the file. Any input is a mesh or an error value, never a crash or
// a hang. Debian's libassimp is not built with the sanitizers: ASan sees its allocations
// through the interceptors only and libFuzzer has no coverage inside it, so this finds
// crashes and hangs from mutated seeds rather than exploring assimp's readers.
#include <iterator>
#include <string>

#include "FuzzInput.h"
#include "vastray/streamer/Import.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    constexpr size_t formats = std::size(vastray::kAssimpFormats);
    const std::string name = std::string("input.") + vastray::kAssimpFormats[data[0] % formats];
    const std::string path = vastray::fuzz::writeInput(data + 1, size - 1, name.c_str());
    (void)vastray::importMesh(path);
    return 0;
}
