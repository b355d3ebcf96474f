#pragma once
// Minimal whitespace/number scanning over an in-memory text buffer, shared by the OBJ
// and ASCII PLY readers. std::from_chars: no locale, no allocation, no iostreams.
#include <charconv>
#include <cstdint>
#include <string_view>
#include <type_traits>

namespace vastray::import {

inline bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

inline const char* skipBlanks(const char* p, const char* end) {
    while (p < end && isBlank(*p)) ++p;
    return p;
}

// The next blank-separated token; advances p past it.
inline std::string_view nextToken(const char*& p, const char* end) {
    p = skipBlanks(p, end);
    const char* start = p;
    while (p < end && !isBlank(*p)) ++p;
    return {start, static_cast<size_t>(p - start)};
}

// Signed decimal integers dominate OBJ face lines; this is about twice as fast as
// std::from_chars<int64_t> there. Refuses values beyond +-2^62 rather than wrapping.
inline bool parseInteger(const char*& p, const char* end, int64_t& out) {
    const char* q = p;
    const bool negative = q < end && *q == '-';
    if (q < end && (*q == '-' || *q == '+')) ++q;
    const char* digits = q;
    uint64_t value = 0;
    while (q < end && unsigned(*q - '0') < 10u && q - digits < 19) value = value * 10 + unsigned(*q++ - '0');
    if (q == digits || (q < end && unsigned(*q - '0') < 10u) || value > (uint64_t(1) << 62)) return false;
    out = negative ? -int64_t(value) : int64_t(value);
    p = q;
    return true;
}

// from_chars rejects a leading '+', which some exporters write.
template <typename T>
inline bool parseNumber(const char*& p, const char* end, T& out) {
    p = skipBlanks(p, end);
    if constexpr (std::is_same_v<T, int64_t>) return parseInteger(p, end, out);
    const char* start = (p < end && *p == '+') ? p + 1 : p;
    const auto [next, ec] = std::from_chars(start, end, out);
    if (ec != std::errc() || next == start) return false;
    p = next;
    return true;
}

// A whole field: the number must end at a blank or the line end ("3.1+e2" is refused).
template <typename T>
inline bool parseField(const char*& p, const char* end, T& out) {
    return parseNumber(p, end, out) && (p == end || isBlank(*p));
}

inline std::string_view trimmed(const char* p, const char* end) {
    p = skipBlanks(p, end);
    while (end > p && isBlank(end[-1])) --end;
    return {p, static_cast<size_t>(end - p)};
}

}  // namespace vastray::import
