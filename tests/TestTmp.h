#pragma once
// A scratch folder per test process: CTest runs every test in its own process, several at a
// time, and fixtures that write the same file names must not race.
#include <unistd.h>

#include <filesystem>
#include <string>

namespace vastray::test {

inline std::filesystem::path testTmpDir(const std::string& area) {
    const std::filesystem::path dir =
        std::filesystem::path(VASTRAY_TEST_TMP) / area / ("pid-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    return dir;
}

}  // namespace vastray::test
