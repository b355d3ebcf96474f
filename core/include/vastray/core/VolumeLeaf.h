#pragma once
// A volume brick as a NanoVDB leaf node (docs/PACKAGE_FORMAT.md "Volumes", docs/RENDERING.md
// "Volumes"): how version 14 packages store bricks and how the device's brick pool holds them (the
// kernels read them with PNanoVDB.h, common/Volume.glsl). A brick's 8^3 voxels are one
// nanovdb::NanoLeaf of the volume's codec: float (exact), Fp16 or Fp8 (NanoVDB's quantized leaves:
// per leaf a minimum and a quantum, a 16- or 8-bit code per voxel). Above the leaves vastray keeps
// its own flat brick table rather than NanoVDB's root and internal nodes: those address their
// children by byte offsets inside one contiguous grid, which a pool of pages cannot be.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "vastray/core/Volume.h"

namespace vastray {

// The codec's name as the CLI and the docs spell it ("float", "fp16", "fp8"), and back.
const char* volumeCodecName(VolumeCodec codec);
std::optional<VolumeCodec> parseVolumeCodec(std::string_view name);
// Bytes of one leaf of the codec: sizeof(nanovdb::NanoLeaf<float | Fp16 | Fp8>) (2,144, 1,120, 608).
uint32_t volumeLeafBytes(VolumeCodec codec);
constexpr uint32_t kMaxVolumeLeafBytes = 2144;
// What the device keeps of a leaf: its bytes from the minimum on (the quantization header and the
// value table; 2,064, 1,040, 528 bytes), the first byte a read touches (PNanoVDB reads a quantized
// leaf's minimum and quantum 16 and 12 bytes before its table). The bounding box, flags and value
// mask before it (80 bytes) are checked when the leaf is read and not uploaded.
constexpr uint32_t kVolumeLeafDeviceOffset = 80;
inline uint32_t volumeDeviceLeafBytes(VolumeCodec codec) { return volumeLeafBytes(codec) - kVolumeLeafDeviceOffset; }

// Encodes kVolumeBrickVoxels values (x fastest, each finite and >= 0) as a leaf of `codec` whose
// first voxel has index `origin` into `leaf` (volumeLeafBytes(codec) bytes), and replaces each
// value by the one the leaf decodes to: a quantized value lies within the brick's [min, max] and
// within half a quantum (max - min) / (2^bits - 1) / 2 of the value given (one quantum where that
// would leave [min, max]). Float leaves keep the values exactly.
void encodeVolumeLeaf(VolumeCodec codec, std::array<int32_t, 3> origin, float* values, uint8_t* leaf);
// Decodes a leaf of `codec` (NanoVDB's C++ access) into kVolumeBrickVoxels values, x fastest.
// Returns an empty string, or what is wrong with it: a minimum or quantum that is not finite, a
// negative quantum, flags or a value mask other than the ones encodeVolumeLeaf writes.
std::string decodeVolumeLeaf(VolumeCodec codec, const uint8_t* leaf, float* values);

}  // namespace vastray
