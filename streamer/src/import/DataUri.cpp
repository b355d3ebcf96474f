#include "import/DataUri.h"

namespace vastray::import {

std::vector<uint8_t> base64DataUriBytes(const std::string& uri) {
    const size_t comma = uri.find(',');
    if (uri.rfind("data:", 0) != 0 || comma == std::string::npos || comma < 7 ||
        uri.compare(comma - 7, 7, ";base64") != 0)
        return {};
    auto value = [](char c) -> int {
        if (c >= 'A' && c <= 'Z') return c - 'A';
        if (c >= 'a' && c <= 'z') return c - 'a' + 26;
        if (c >= '0' && c <= '9') return c - '0' + 52;
        return c == '+' ? 62 : c == '/' ? 63 : -1;
    };
    std::vector<uint8_t> out;
    out.reserve((uri.size() - comma) / 4 * 3);
    uint32_t bits = 0;
    int count = 0;
    for (size_t i = comma + 1; i < uri.size(); ++i) {
        const int v = value(uri[i]);
        if (v < 0) continue;
        bits = (bits << 6) | uint32_t(v);
        if ((count += 6) >= 8) out.push_back(uint8_t((bits >> (count -= 8)) & 0xff));
    }
    return out;
}

}  // namespace vastray::import
