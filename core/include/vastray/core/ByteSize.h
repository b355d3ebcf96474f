#pragma once
#include <cstdint>
#include <string>
#include <string_view>

#include "vastray/core/Result.h"

namespace vastray {

// Parses "16MiB", "512 KiB", "2GiB", "1048576", "64B" (binary units; KB/MB/GB are
// accepted as the same binary multiples). Rejects negatives, fractions of a byte and overflow.
Result<uint64_t> parseByteSize(std::string_view text);

// "16.0 MiB", "512 B": for messages and reports.
std::string formatBytes(uint64_t bytes);

}  // namespace vastray
