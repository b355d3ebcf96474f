#pragma once
// libFuzzer targets read paths, not buffers (the importers and the package reader take a
// file): each input is written to a file in a private folder first. The folder is empty
// besides it, so that a glTF buffer URI or an OBJ mtllib the fuzzer invents finds nothing.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

namespace vastray::fuzz {

inline std::string writeInput(const uint8_t* data, size_t size, const char* name) {
    static const std::filesystem::path folder = [] {
        auto dir = std::filesystem::temp_directory_path() / ("vastray-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir);
        return dir;
    }();
    const std::string path = (folder / name).string();
    FILE* file = std::fopen(path.c_str(), "wb");
    if (!file) std::abort();
    if (size > 0 && std::fwrite(data, 1, size, file) != size) std::abort();
    std::fclose(file);
    return path;
}

}  // namespace vastray::fuzz
