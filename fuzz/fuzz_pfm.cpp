// Fuzzes the portable float map reader behind `--environment FILE.pfm` (core/src/image/PfmFile.cpp,
// read without the OpenImageIO module) and the map built from what it reads.
#include "FuzzInput.h"
#include "vastray/core/EnvironmentMap.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = vastray::fuzz::writeInput(data, size, "input.pfm");
    (void)vastray::readEnvironmentMap(path);
    return 0;
}
