#pragma once
// Names a package stores in fixed fields (materials, cameras) are UTF-8 text that JSON and
// protobuf carry to users: these keep them whole characters and valid.
#include <cstddef>
#include <string>

namespace vastray {

// `text` cut before its first NUL byte, then to at most maxBytes without splitting a UTF-8
// character (the cut backs up over at most 3 continuation bytes; bytes that are not UTF-8 are
// cut at the limit). Unchanged if it fits.
std::string cutUtf8(const std::string& text, size_t maxBytes);

// `text` with every byte that does not belong to a well-formed UTF-8 character (RFC 3629: no
// overlong forms, no surrogates, nothing above U+10FFFF) replaced by '?'. Valid text is unchanged.
std::string validUtf8(const std::string& text);

}  // namespace vastray
