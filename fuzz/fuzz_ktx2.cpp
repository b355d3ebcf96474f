// Fuzzes the KTX2 texture reader (core/src/image/Ktx2*.cpp, read without the OpenImageIO module):
// the container (header, level index, DFD, key/value data), Zstandard supercompression, the
// uncompressed formats, and Basis Universal's transcoder behind it (ETC1S/BasisLZ, UASTC).
// An image that decodes must have the texels its sides promise.
#include <cstdlib>
#include <vector>

#include "vastray/core/ImageFile.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::vector<uint8_t> bytes(data, data + size);
    (void)vastray::describeKtx2Image("fuzz.ktx2", bytes);
    // 4 Mi texels: the container is what is fuzzed, not the allocator (import allows 16384^2).
    auto image = vastray::decodeRgba8Image("fuzz.ktx2", ".ktx2", bytes, uint64_t(1) << 22);
    if (image && image->texels.size() != uint64_t(image->width) * image->height * 4) std::abort();
    return 0;
}
