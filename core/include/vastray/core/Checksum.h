#pragma once
#include <cstddef>
#include <cstdint>

namespace vastray {

// 64-bit XXH64 (seed 0) of a byte range: the checksum of every section and chunk of a package.
uint64_t checksum64(const void* data, size_t size);

}  // namespace vastray
