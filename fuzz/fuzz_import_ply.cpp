// Fuzzes the .ply importer: any input is a mesh or an error value, never a crash, a hang,
// an unbounded allocation or undefined behaviour (ASan + UBSan).
#include "FuzzInput.h"
#include "vastray/streamer/Import.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = vastray::fuzz::writeInput(data, size, "input.ply");
    (void)vastray::importMesh(path);
    return 0;
}
