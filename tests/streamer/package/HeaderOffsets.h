#pragma once
// Byte offsets of the package header's fields, as serializeHeader writes them
// (docs/PACKAGE_FORMAT.md): magic, version, header size, 7 u64, 6 u32, bounds (6 f32), the grid's
// origin (3 f64) and range, the section offsets and checksums, then the cameras', lights' and
// volumes' fields; the header's own XXH64 in its last 8 bytes. The forging tests rewrite them.
#include <cstddef>

#include "package/PackageFormat.h"

namespace vastray::test {

constexpr size_t kGridBitsAt = 8 + 4 + 4 + 7 * 8 + 4;  // the second u32: the grid's bits
constexpr size_t kBoundsLoAt = 8 + 4 + 4 + 7 * 8 + 6 * 4;
constexpr size_t kBoundsHiAt = kBoundsLoAt + 12;
constexpr size_t kOriginAt = kBoundsHiAt + 12;
constexpr size_t kRangeAt = kOriginAt + 24;
constexpr size_t kMaterialsChecksumAt = kRangeAt + 8 + 4 * 8;
constexpr size_t kDirectoryOffsetAt = kRangeAt + 8 + 2 * 8;
constexpr size_t kDirectoryChecksumAt = kRangeAt + 8 + 6 * 8;
constexpr size_t kCamerasOffsetAt = kRangeAt + 8 + 7 * 8;
constexpr size_t kCamerasChecksumAt = kCamerasOffsetAt + 8;
constexpr size_t kCameraCountAt = kCamerasChecksumAt + 8;
constexpr size_t kLightCountAt = kCameraCountAt + 4;
constexpr size_t kVolumesOffsetAt = kLightCountAt + 4;
constexpr size_t kHeaderChecksumAt = format::kHeaderBytes - 8;
static_assert(kDirectoryChecksumAt == 200 && kCamerasOffsetAt == 208 && kCameraCountAt == 224);

}  // namespace vastray::test
