#include "vastray/core/Checksum.h"

#include <xxhash.h>

namespace vastray {

uint64_t checksum64(const void* data, size_t size) { return XXH64(data, size, 0); }

}  // namespace vastray
