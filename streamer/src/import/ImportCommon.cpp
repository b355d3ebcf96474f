#include "import/ImportCommon.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
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

Result<std::vector<char>> readWholeFile(const std::string& path) {
    const std::string name = fileNameOf(path);
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) return errorIn(name, "is a directory, not a mesh file");
    std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!file) return errorIn(name, std::string("cannot open: ") + std::strerror(errno));
    if (std::fseek(file.get(), 0, SEEK_END) != 0) return errorIn(name, "cannot seek");
    const long size = std::ftell(file.get());
    if (size < 0) return errorIn(name, "cannot determine the file size");
    std::rewind(file.get());
    std::vector<char> bytes(static_cast<size_t>(size));
    if (size > 0 && std::fread(bytes.data(), 1, bytes.size(), file.get()) != bytes.size())
        return errorIn(name, "read error");
    return bytes;
}

}  // namespace vastray::import
