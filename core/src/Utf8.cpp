#include "vastray/core/Utf8.h"

#include <algorithm>
#include <cstdint>

namespace vastray {

std::string cutUtf8(const std::string& text, size_t maxBytes) {
    size_t end = std::min(text.find('\0'), text.size());
    if (end > maxBytes) {
        end = maxBytes;
        // Back up over continuation bytes (10xxxxxx) so the cut falls before a lead byte; a
        // character has at most 3 of them, more is not UTF-8 and is cut at the limit.
        size_t cut = end;
        while (cut > 0 && cut + 3 > end && (uint8_t(text[cut]) & 0xC0) == 0x80) --cut;
        if ((uint8_t(text[cut]) & 0xC0) != 0x80) end = cut;
    }
    return text.substr(0, end);
}

namespace {

// The length of the well-formed character at text[i], or 0 when none starts there.
size_t characterBytes(const std::string& text, size_t i) {
    const uint8_t b0 = uint8_t(text[i]);
    if (b0 < 0x80) return 1;
    size_t n = 0;
    uint8_t lo = 0x80, hi = 0xBF;  // the allowed range of the second byte
    if (b0 >= 0xC2 && b0 <= 0xDF) n = 2;
    else if (b0 == 0xE0) n = 3, lo = 0xA0;  // no overlong forms
    else if (b0 == 0xED) n = 3, hi = 0x9F;  // no surrogates
    else if (b0 >= 0xE1 && b0 <= 0xEF) n = 3;
    else if (b0 == 0xF0) n = 4, lo = 0x90;
    else if (b0 >= 0xF1 && b0 <= 0xF3) n = 4;
    else if (b0 == 0xF4) n = 4, hi = 0x8F;  // nothing above U+10FFFF
    else return 0;
    if (i + n > text.size()) return 0;
    const uint8_t b1 = uint8_t(text[i + 1]);
    if (b1 < lo || b1 > hi) return 0;
    for (size_t k = 2; k < n; ++k)
        if ((uint8_t(text[i + k]) & 0xC0) != 0x80) return 0;
    return n;
}

}  // namespace

std::string validUtf8(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (size_t i = 0; i < text.size();) {
        const size_t n = characterBytes(text, i);
        if (n == 0) {
            out.push_back('?');
            ++i;
        } else {
            out.append(text, i, n);
            i += n;
        }
    }
    return out;
}

}  // namespace vastray
