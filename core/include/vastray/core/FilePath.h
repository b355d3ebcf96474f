#pragma once

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

namespace vastray {

// A path's extension as std::filesystem::path::extension gives it (with its dot; "" for none or
// for a name that is only a dot file), in lower case: the one way a file's kind is read from its
// name (".PNG", ".Png" and ".png" are one kind).
inline std::string lowerExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

}  // namespace vastray
