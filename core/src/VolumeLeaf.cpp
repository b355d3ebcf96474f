#include "vastray/core/VolumeLeaf.h"

#include <nanovdb/NanoVDB.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace vastray {
namespace {

using FloatLeaf = nanovdb::NanoLeaf<float>;
using Fp16Leaf = nanovdb::NanoLeaf<nanovdb::Fp16>;
using Fp8Leaf = nanovdb::NanoLeaf<nanovdb::Fp8>;
static_assert(sizeof(FloatLeaf) == kMaxVolumeLeafBytes && sizeof(Fp16Leaf) == 1120 && sizeof(Fp8Leaf) == 608,
              "the package format fixes the leaves' sizes (docs/PACKAGE_FORMAT.md)");
static_assert(FloatLeaf::DIM == kVolumeBrickSize, "a brick is one leaf");

// NanoVDB's flags for a leaf vastray writes: bit 1, its bounding box is set (the brick's 8^3).
constexpr uint8_t kLeafFlags = 2;

// A leaf's bytes at NanoVDB's 32-byte alignment (packages and pools hold them at any offset).
struct alignas(32) LeafBytes {
    uint8_t bytes[kMaxVolumeLeafBytes];
};

// Our voxel order (x fastest) from NanoVDB's (z fastest): the same index with x and z swapped.
uint32_t nanoOffset(uint32_t ourIndex) {
    const uint32_t x = ourIndex % 8, y = ourIndex / 8 % 8, z = ourIndex / 64;
    return (x << 6) | (y << 3) | z;
}

template <typename Data>
void writeHeader(Data& d, std::array<int32_t, 3> origin) {
    d.mBBoxMin = nanovdb::Coord(origin[0], origin[1], origin[2]);
    d.mBBoxDif[0] = d.mBBoxDif[1] = d.mBBoxDif[2] = uint8_t(kVolumeBrickSize - 1);
    d.mFlags = kLeafFlags;
    d.mValueMask.setOn();
}

template <typename Data>
std::string checkHeader(const Data& d) {
    if (d.mFlags != kLeafFlags) return "its flags are " + std::to_string(d.mFlags) + ", not " + std::to_string(kLeafFlags);
    if (!d.mValueMask.isOn()) return "not every voxel of its value mask is on";
    for (int a = 0; a < 3; ++a)
        if (d.mBBoxDif[a] != kVolumeBrickSize - 1 || d.mBBoxMin[a] % int32_t(kVolumeBrickSize) != 0)
            return "its bounding box is not one brick's";
    return {};
}

// Fp16 and Fp8: NanoVDB's quantization (its CreateNanoGrid: code = (v - min) / quantum + 1/2),
// then each code lowered while its value would pass the brick's largest (rounding in the decode).
template <typename Leaf, uint32_t kBits>
void encodeQuantized(std::array<int32_t, 3> origin, float* values, uint8_t* out) {
    LeafBytes storage{};
    auto& d = *reinterpret_cast<typename Leaf::DataType*>(storage.bytes);
    writeHeader(d, origin);
    const auto [lo, hi] = std::minmax_element(values, values + kVolumeBrickVoxels);
    const float min = *lo, max = *hi;
    d.init(min, max, uint8_t(kBits));
    const float levels = float((1u << kBits) - 1);
    const float encode = max > min ? levels / (max - min) : 0.0f;
    uint32_t minCode = ~0u, maxCode = 0;
    for (uint32_t i = 0; i < kVolumeBrickVoxels; ++i) {
        uint32_t code = uint32_t(std::min(levels, encode * (values[i] - min) + 0.5f));
        while (code > 0 && float(code) * d.mQuantum + d.mMinimum > max) --code;
        const uint32_t at = nanoOffset(i);
        if constexpr (kBits == 16)
            d.mCode[at] = uint16_t(code);
        else
            d.mCode[at] = uint8_t(code);
        minCode = std::min(minCode, code), maxCode = std::max(maxCode, code);
    }
    // Statistics as NanoVDB keeps them (16-bit codes of the same quantum; not read by vastray).
    d.mMin = uint16_t(minCode), d.mMax = uint16_t(maxCode), d.mAvg = 0, d.mDev = 0;
    const auto* leaf = reinterpret_cast<const Leaf*>(storage.bytes);
    for (uint32_t i = 0; i < kVolumeBrickVoxels; ++i) values[i] = leaf->getValue(nanoOffset(i));
    std::memcpy(out, storage.bytes, sizeof(Leaf));
}

void encodeFloat(std::array<int32_t, 3> origin, float* values, uint8_t* out) {
    LeafBytes storage{};
    auto& d = *reinterpret_cast<FloatLeaf::DataType*>(storage.bytes);
    writeHeader(d, origin);
    const auto [lo, hi] = std::minmax_element(values, values + kVolumeBrickVoxels);
    d.mMinimum = *lo, d.mMaximum = *hi;
    double sum = 0.0, squares = 0.0;
    for (uint32_t i = 0; i < kVolumeBrickVoxels; ++i) {
        d.mValues[nanoOffset(i)] = values[i];
        sum += values[i], squares += double(values[i]) * values[i];
    }
    const double mean = sum / kVolumeBrickVoxels;
    d.mAverage = float(mean);
    d.mStdDevi = float(std::sqrt(std::max(0.0, squares / kVolumeBrickVoxels - mean * mean)));
    std::memcpy(out, storage.bytes, sizeof(FloatLeaf));
}

template <typename Leaf>
std::string decode(const uint8_t* bytes, float* values) {
    LeafBytes storage;
    std::memcpy(storage.bytes, bytes, sizeof(Leaf));
    const auto* leaf = reinterpret_cast<const Leaf*>(storage.bytes);
    if (std::string problem = checkHeader(*leaf->data()); !problem.empty()) return problem;
    if constexpr (!std::is_same_v<Leaf, FloatLeaf>) {
        const auto& d = *leaf->data();
        if (!std::isfinite(d.mMinimum)) return "its minimum " + std::to_string(d.mMinimum) + " is not finite";
        if (!(d.mQuantum >= 0.0f && std::isfinite(d.mQuantum)))
            return "its quantum " + std::to_string(d.mQuantum) + " is not finite and >= 0";
    }
    for (uint32_t i = 0; i < kVolumeBrickVoxels; ++i) values[i] = leaf->getValue(nanoOffset(i));
    return {};
}

}  // namespace

const char* volumeCodecName(VolumeCodec codec) {
    switch (codec) {
    case VolumeCodec::Float: return "float";
    case VolumeCodec::Fp16: return "fp16";
    case VolumeCodec::Fp8: return "fp8";
    }
    return "?";
}

std::optional<VolumeCodec> parseVolumeCodec(std::string_view name) {
    for (uint32_t c = 0; c < kVolumeCodecCount; ++c)
        if (name == volumeCodecName(VolumeCodec(c))) return VolumeCodec(c);
    return std::nullopt;
}

uint32_t volumeLeafBytes(VolumeCodec codec) {
    switch (codec) {
    case VolumeCodec::Float: return sizeof(FloatLeaf);
    case VolumeCodec::Fp16: return sizeof(Fp16Leaf);
    case VolumeCodec::Fp8: return sizeof(Fp8Leaf);
    }
    return 0;
}

void encodeVolumeLeaf(VolumeCodec codec, std::array<int32_t, 3> origin, float* values, uint8_t* leaf) {
    switch (codec) {
    case VolumeCodec::Float: return encodeFloat(origin, values, leaf);
    case VolumeCodec::Fp16: return encodeQuantized<Fp16Leaf, 16>(origin, values, leaf);
    case VolumeCodec::Fp8: return encodeQuantized<Fp8Leaf, 8>(origin, values, leaf);
    }
}

std::string decodeVolumeLeaf(VolumeCodec codec, const uint8_t* leaf, float* values) {
    switch (codec) {
    case VolumeCodec::Float: return decode<FloatLeaf>(leaf, values);
    case VolumeCodec::Fp16: return decode<Fp16Leaf>(leaf, values);
    case VolumeCodec::Fp8: return decode<Fp8Leaf>(leaf, values);
    }
    return "its codec " + std::to_string(uint32_t(codec)) + " is not one vastray reads";
}

}  // namespace vastray
