#include "import/ImportCommon.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <memory>

namespace vastray::import {

std::string fileNameOf(const std::string& path) {
    const size_t slash = path.find_last_of("/\\");
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string directoryOf(const std::string& path) {
    const size_t slash = path.find_last_of("/\\");
    if (slash == std::string::npos) return ".";
    return slash == 0 ? "/" : path.substr(0, slash);
}

std::string lowerExtension(const std::string& path) {
    const std::string name = fileNameOf(path);
    const size_t dot = name.find_last_of('.');
    if (dot == std::string::npos) return {};
    std::string ext = name.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

static const char* fileKindOf(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISSOCK(mode)) return "a socket";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    return "not a regular file";
}

// O_NONBLOCK: opening a FIFO without a writer returns at once instead of waiting for one;
// fstat on the open descriptor then refuses it (no race between a check and the open).
Result<int> openRegularFile(const std::string& path) {
    const std::string name = fileNameOf(path);
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) return errorIn(name, std::string("cannot open: ") + std::strerror(errno));
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        const std::string kind = fileKindOf(st.st_mode);
        ::close(fd);
        return errorIn(name, "is " + kind + "; only regular files are read");
    }
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    return fd;
}

Result<std::vector<char>> readWholeFile(const std::string& path) {
    const std::string name = fileNameOf(path);
    auto fd = openRegularFile(path);
    if (!fd) return fd.status();
    std::unique_ptr<FILE, int (*)(FILE*)> file(::fdopen(*fd, "rb"), &std::fclose);
    if (!file) {
        ::close(*fd);
        return errorIn(name, std::string("cannot open: ") + std::strerror(errno));
    }
    if (std::fseek(file.get(), 0, SEEK_END) != 0) return errorIn(name, "cannot seek");
    const long size = std::ftell(file.get());
    if (size < 0) return errorIn(name, "cannot determine the file size");
    std::rewind(file.get());
    std::vector<char> bytes(static_cast<size_t>(size));
    if (size > 0 && std::fread(bytes.data(), 1, bytes.size(), file.get()) != bytes.size())
        return errorIn(name, "read error");
    return bytes;
}

bool isSafeRelativeUri(const std::string& uri, std::string& why) {
    if (uri.empty()) return why = "is empty", false;
    if (uri[0] == '/' || uri[0] == '\\') return why = "is an absolute path", false;
    const size_t colon = uri.find(':');
    if (colon != std::string::npos && uri.find_first_of("/\\") > colon)
        return why = "has a scheme ('" + uri.substr(0, colon) + ":'); only relative paths and data: URIs are allowed",
               false;
    size_t start = 0;
    while (start <= uri.size()) {
        const size_t end = std::min(uri.find_first_of("/\\", start), uri.size());
        if (uri.compare(start, end - start, "..") == 0) return why = "escapes the model folder ('..')", false;
        start = end + 1;
    }
    return true;
}

bool insideFolder(const std::filesystem::path& folder, const std::filesystem::path& file) {
    std::error_code ec1, ec2;
    const std::filesystem::path root = std::filesystem::canonical(folder, ec1);
    const std::filesystem::path target = std::filesystem::weakly_canonical(file, ec2);
    if (ec1 || ec2) return false;
    const auto mismatch = std::mismatch(root.begin(), root.end(), target.begin(), target.end());
    return mismatch.first == root.end();
}

}  // namespace vastray::import
