#pragma once
// data: URIs (RFC 2397) the glTF loader leaves undecoded: tinygltf decodes a data URI only for
// a few media types (octet-stream, PNG, JPEG, ...), not "data:image/ktx2;base64,...".
#include <cstdint>
#include <string>
#include <vector>

namespace vastray::import {

// The bytes of a base64 data URI; empty when `uri` is not one (no ";base64," before its comma).
// Characters outside the base64 alphabet (padding, line breaks) are skipped.
std::vector<uint8_t> base64DataUriBytes(const std::string& uri);

}  // namespace vastray::import
