#pragma once
// Runs the built `vastray` binary (or any command line) as a user would and captures what it prints.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace vastray::test {

struct CommandResult {
    int exitCode = -1;
    std::string output;  // stdout and stderr together
};

// Runs a shell command line; stdout and stderr are captured together.
inline CommandResult runShell(const std::string& commandLine) {
    CommandResult result;
    const std::string command = commandLine + " 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return result;
    std::array<char, 4096> buffer;
    size_t n;
    while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
    const int status = pclose(pipe);
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return result;
}

inline CommandResult runVastray(const std::string& arguments) {
    return runShell(std::string(VASTRAY_BINARY) + " " + arguments);
}

}  // namespace vastray::test
