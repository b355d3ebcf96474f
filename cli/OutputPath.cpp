#include "OutputPath.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace vastray::cli {

// access(2) asks the kernel with the caller's real ids, which is what the later open uses;
// nothing is created, so a refused run leaves no empty file behind.
Status checkWritableOutput(const std::string& flag, const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code error;
    const fs::path target(path);
    const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
    if (!fs::is_directory(folder, error))
        return Status::error(flag + " " + path + ": folder '" + folder.string() + "' does not exist");
    if (::access(folder.c_str(), W_OK | X_OK) != 0)
        return Status::error(flag + " " + path + ": folder '" + folder.string() + "' is not writable (" +
                             std::strerror(errno) + ")");
    const fs::file_status status = fs::status(target, error);
    if (!fs::exists(status)) return Status::ok();
    if (!fs::is_regular_file(status)) return Status::error(flag + " " + path + ": exists and is not a regular file");
    if (::access(path.c_str(), W_OK) != 0)
        return Status::error(flag + " " + path + ": is not writable (" + std::strerror(errno) + ")");
    return Status::ok();
}

}  // namespace vastray::cli
