#pragma once
// Shared by the command-line tests: reading back what a command wrote.
#include <fstream>
#include <sstream>
#include <string>

namespace vastray::test {

// The whole file (empty when it cannot be read).
inline std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace vastray::test
