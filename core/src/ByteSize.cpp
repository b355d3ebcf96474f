#include "vastray/core/ByteSize.h"

#include <cctype>
#include <cstdio>
#include <limits>

namespace vastray {
namespace {

struct Unit {
    std::string_view name;
    uint64_t factor;
};
constexpr Unit kUnits[] = {{"", 1},          {"b", 1},           {"k", 1ull << 10},  {"kb", 1ull << 10},
                           {"kib", 1ull << 10}, {"m", 1ull << 20},  {"mb", 1ull << 20}, {"mib", 1ull << 20},
                           {"g", 1ull << 30},  {"gb", 1ull << 30}, {"gib", 1ull << 30}, {"t", 1ull << 40},
                           {"tb", 1ull << 40}, {"tib", 1ull << 40}};

}  // namespace

Result<uint64_t> parseByteSize(std::string_view text) {
    const std::string original(text);
    size_t pos = 0;
    while (pos < text.size() && std::isspace((unsigned char)text[pos])) ++pos;
    uint64_t whole = 0;
    size_t digits = 0;
    while (pos < text.size() && std::isdigit((unsigned char)text[pos])) {
        const uint64_t d = uint64_t(text[pos] - '0');
        if (whole > (std::numeric_limits<uint64_t>::max() - d) / 10)
            return Status::error("size '" + original + "' is too large");
        whole = whole * 10 + d;
        ++pos;
        ++digits;
    }
    // An optional fraction, e.g. "1.5GiB".
    uint64_t fracNum = 0, fracDen = 1;
    if (pos < text.size() && text[pos] == '.') {
        ++pos;
        while (pos < text.size() && std::isdigit((unsigned char)text[pos]) && fracDen < 1000000ull) {
            fracNum = fracNum * 10 + uint64_t(text[pos] - '0');
            fracDen *= 10;
            ++pos;
            ++digits;
        }
    }
    if (digits == 0) return Status::error("size '" + original + "' is not a number with an optional KiB/MiB/GiB suffix");
    while (pos < text.size() && std::isspace((unsigned char)text[pos])) ++pos;
    std::string suffix;
    for (; pos < text.size(); ++pos) suffix.push_back(char(std::tolower((unsigned char)text[pos])));
    for (const Unit& unit : kUnits) {
        if (suffix != unit.name) continue;
        if (whole > std::numeric_limits<uint64_t>::max() / unit.factor)
            return Status::error("size '" + original + "' is too large");
        const uint64_t fracBytes = fracNum * unit.factor / fracDen;
        if (fracNum * unit.factor % fracDen != 0)
            return Status::error("size '" + original + "' is not a whole number of bytes");
        return whole * unit.factor + fracBytes;
    }
    return Status::error("size '" + original + "' has unknown unit '" + suffix + "' (use B, KiB, MiB, GiB or TiB)");
}

std::string formatBytes(uint64_t bytes) {
    char buffer[64];
    if (bytes < 1024) {
        std::snprintf(buffer, sizeof buffer, "%llu B", (unsigned long long)bytes);
        return buffer;
    }
    const char* units[] = {"KiB", "MiB", "GiB", "TiB"};
    double value = double(bytes) / 1024.0;
    int unit = 0;
    while (value >= 1024.0 && unit < 3) {
        value /= 1024.0;
        ++unit;
    }
    std::snprintf(buffer, sizeof buffer, "%.1f %s", value, units[unit]);
    return buffer;
}

}  // namespace vastray
