#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "vastray/core/ImageFile.h"
#include "vastray/core/Result.h"

namespace vastray {

// decodeRgba8Image's reader for ".ktx2" (ImageFile.h says what it reads); errors name `name` and
// the field. A format describeKtx2Image calls unreadable is an error here.
Result<Rgba8Image> decodeKtx2Image(const std::string& name, const std::vector<uint8_t>& bytes, uint64_t maxPixels);
// The same from a file (readRgba8Image's reader for ".ktx2"); errors name the path.
Result<Rgba8Image> readKtx2Image(const std::string& path, uint64_t maxPixels);

}  // namespace vastray
