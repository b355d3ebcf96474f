// Volume bricks as NanoVDB leaf nodes (core/VolumeLeaf.h): the bytes are NanoVDB's leaf layout
// (read back through NanoVDB's own coordinate API and through PNanoVDB.h, the access the GPU
// kernels compile), float leaves are exact, quantized ones stay within their stated error, and
// hostile leaf headers are refused by what is wrong.
#include <gtest/gtest.h>

#define PNANOVDB_C
#include <nanovdb/NanoVDB.h>
#include <nanovdb/PNanoVDB.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "vastray/core/VolumeLeaf.h"

namespace vastray {
namespace {

// A brick of values x fastest: a smooth ramp with a few zeros and one spike.
std::vector<float> brickValues(float scale) {
    std::vector<float> v(kVolumeBrickVoxels);
    for (uint32_t i = 0; i < kVolumeBrickVoxels; ++i)
        v[i] = i % 37 == 0 ? 0.0f : scale * (0.1f + 0.8f * float((i * 2654435761u) % 1000) / 1000.0f);
    v[300] = 3.0f * scale;
    return v;
}

struct alignas(32) Leaf {
    uint8_t bytes[kMaxVolumeLeafBytes];
};

constexpr VolumeCodec kCodecs[] = {VolumeCodec::Float, VolumeCodec::Fp16, VolumeCodec::Fp8};

TEST(VolumeLeaf, NamesAndSizesAreNanoVdbs) {
    for (VolumeCodec c : kCodecs) EXPECT_EQ(parseVolumeCodec(volumeCodecName(c)), c);
    EXPECT_FALSE(parseVolumeCodec("fp4"));
    EXPECT_FALSE(parseVolumeCodec(""));
    EXPECT_EQ(volumeLeafBytes(VolumeCodec::Float), sizeof(nanovdb::NanoLeaf<float>));
    EXPECT_EQ(volumeLeafBytes(VolumeCodec::Fp16), sizeof(nanovdb::NanoLeaf<nanovdb::Fp16>));
    EXPECT_EQ(volumeLeafBytes(VolumeCodec::Fp8), sizeof(nanovdb::NanoLeaf<nanovdb::Fp8>));
}

// A float leaf holds the values exactly, where NanoVDB's coordinate lookup finds them (index
// space: the brick's origin plus x, y, z), its bounding box the brick's.
TEST(VolumeLeaf, FloatLeavesAreExactAndNanoVdbFindsEachVoxel) {
    const std::vector<float> given = brickValues(2.0f);
    std::vector<float> values = given;
    Leaf leaf{};
    encodeVolumeLeaf(VolumeCodec::Float, {16, -8, 40}, values.data(), leaf.bytes);
    EXPECT_EQ(values, given);
    const auto* nano = reinterpret_cast<const nanovdb::NanoLeaf<float>*>(leaf.bytes);
    EXPECT_EQ(nano->origin(), nanovdb::Coord(16, -8, 40));
    EXPECT_EQ(nano->bbox(), nanovdb::CoordBBox(nanovdb::Coord(16, -8, 40), nanovdb::Coord(23, -1, 47)));
    EXPECT_EQ(nano->minimum(), 0.0f);
    EXPECT_EQ(nano->maximum(), 6.0f);
    for (uint32_t i = 0; i < kVolumeBrickVoxels; ++i) {
        const nanovdb::Coord ijk(16 + int32_t(i % 8), -8 + int32_t(i / 8 % 8), 40 + int32_t(i / 64));
        ASSERT_EQ(nano->getValue(ijk), given[i]) << i;
        ASSERT_TRUE(nano->isActive(ijk));
    }
    std::vector<float> decoded(kVolumeBrickVoxels);
    EXPECT_EQ(decodeVolumeLeaf(VolumeCodec::Float, leaf.bytes, decoded.data()), "");
    EXPECT_EQ(decoded, given);
}

// Fp16 and Fp8: every voxel within half a quantum ((max - min) / (2^bits - 1)) of its value, in
// [min, max]; what encode hands back is what decode reads; a constant brick is exact.
TEST(VolumeLeaf, QuantizedLeavesStayWithinHalfAQuantum) {
    for (VolumeCodec codec : {VolumeCodec::Fp16, VolumeCodec::Fp8}) {
        SCOPED_TRACE(volumeCodecName(codec));
        const float levels = codec == VolumeCodec::Fp16 ? 65535.0f : 255.0f;
        for (float scale : {1e-6f, 1.0f, 7.5f, 3e17f}) {
            const std::vector<float> given = brickValues(scale);
            const float lo = *std::min_element(given.begin(), given.end());
            const float hi = *std::max_element(given.begin(), given.end());
            std::vector<float> values = given;
            Leaf leaf{};
            encodeVolumeLeaf(codec, {0, 0, 0}, values.data(), leaf.bytes);
            std::vector<float> decoded(kVolumeBrickVoxels);
            ASSERT_EQ(decodeVolumeLeaf(codec, leaf.bytes, decoded.data()), "");
            EXPECT_EQ(decoded, values);
            const float half = 0.5f * (hi - lo) / levels;
            for (uint32_t i = 0; i < kVolumeBrickVoxels; ++i) {
                ASSERT_GE(values[i], lo) << i;
                ASSERT_LE(values[i], hi) << i;
                ASSERT_LE(std::fabs(values[i] - given[i]), half * 1.001f + hi * 1e-6f) << i << " at scale " << scale;
            }
            EXPECT_EQ(values[300], hi) << "the largest value is a code of its own";
        }
        std::vector<float> constant(kVolumeBrickVoxels, 0.3f);
        Leaf leaf{};
        encodeVolumeLeaf(codec, {8, 8, 8}, constant.data(), leaf.bytes);
        EXPECT_TRUE(std::all_of(constant.begin(), constant.end(), [](float x) { return x == 0.3f; }));
    }
}

// The kernels' reads (common/Volume.glsl's leafValue, here through PNanoVDB.h's C form): the
// value table at NanoVDB's leaf_off_table of each grid type (96, which the kernels take as a
// constant), a float at 4 per voxel in pnanovdb_leaf_coord_to_offset's order, Fp16 and Fp8
// through pnanovdb_leaf_fp16/fp8_read_float; and PNanoVDB's own leaf value address agrees.
TEST(VolumeLeaf, PNanoVdbReadsWhatNanoVdbDecodes) {
    constexpr uint32_t kLeafTableOffset = 96;  // in the whole leaf (common/Volume.glsl: 16, from its minimum on)
    for (VolumeCodec codec : kCodecs) {
        SCOPED_TRACE(volumeCodecName(codec));
        const uint32_t type = codec == VolumeCodec::Float  ? PNANOVDB_GRID_TYPE_FLOAT
                              : codec == VolumeCodec::Fp16 ? PNANOVDB_GRID_TYPE_FP16
                                                           : PNANOVDB_GRID_TYPE_FP8;
        EXPECT_EQ(pnanovdb_grid_type_constants[type].leaf_off_table, kLeafTableOffset);
        // The device keeps the leaf from its minimum on: the first byte PNanoVDB's reads touch.
        EXPECT_EQ(kLeafTableOffset - PNANOVDB_LEAF_TABLE_NEG_OFF_MINIMUM, kVolumeLeafDeviceOffset);
        EXPECT_EQ(volumeDeviceLeafBytes(codec), volumeLeafBytes(codec) - 80);
        EXPECT_EQ(pnanovdb_grid_type_constants[type].leaf_size, volumeLeafBytes(codec));
        std::vector<float> values = brickValues(4.0f);
        Leaf leaf{};
        encodeVolumeLeaf(codec, {-64, 128, 8}, values.data(), leaf.bytes);
        pnanovdb_buf_t buf = pnanovdb_make_buf(reinterpret_cast<uint32_t*>(leaf.bytes), kMaxVolumeLeafBytes / 4);
        pnanovdb_leaf_handle_t handle{};
        handle.address.byte_offset = 0;
        pnanovdb_address_t table{};
        table.byte_offset = kLeafTableOffset;
        for (uint32_t i = 0; i < kVolumeBrickVoxels; ++i) {
            const pnanovdb_coord_t ijk{int32_t(i % 8), int32_t(i / 8 % 8), int32_t(i / 64)};
            const pnanovdb_address_t value = pnanovdb_leaf_get_value_address(type, buf, handle, &ijk);
            float read = 0.0f, reference = 0.0f;
            if (codec == VolumeCodec::Float) {
                read = pnanovdb_read_float(buf, pnanovdb_address_offset(table, 4 * pnanovdb_leaf_coord_to_offset(&ijk)));
                reference = pnanovdb_read_float(buf, value);
            } else if (codec == VolumeCodec::Fp16) {
                read = pnanovdb_leaf_fp16_read_float(buf, table, &ijk);
                reference = pnanovdb_leaf_fp16_read_float(buf, value, &ijk);
            } else {
                read = pnanovdb_leaf_fp8_read_float(buf, table, &ijk);
                reference = pnanovdb_leaf_fp8_read_float(buf, value, &ijk);
            }
            ASSERT_EQ(read, values[i]) << i;
            ASSERT_EQ(reference, values[i]) << i;
        }
    }
}

// What a forged leaf in a package could hold: each refused by what is wrong.
TEST(VolumeLeaf, HostileLeafHeadersAreRefusedByWhatIsWrong) {
    std::vector<float> values = brickValues(1.0f), out(kVolumeBrickVoxels);
    auto forged = [&](VolumeCodec codec, auto change) {
        Leaf leaf{};
        std::vector<float> v = values;
        encodeVolumeLeaf(codec, {0, 0, 0}, v.data(), leaf.bytes);
        change(leaf.bytes);
        return decodeVolumeLeaf(codec, leaf.bytes, out.data());
    };
    auto setFloat = [](uint8_t* at, float x) { std::memcpy(at, &x, 4); };
    // Byte 15: NanoVDB's flags; 16..79 the value mask; 80 and 84 a quantized leaf's minimum and quantum.
    EXPECT_EQ(forged(VolumeCodec::Float, [](uint8_t* b) { b[15] = 3; }), "its flags are 3, not 2");
    EXPECT_EQ(forged(VolumeCodec::Fp8, [](uint8_t* b) { b[20] = 0; }), "not every voxel of its value mask is on");
    EXPECT_EQ(forged(VolumeCodec::Fp16, [](uint8_t* b) { b[12] = 3; }), "its bounding box is not one brick's");
    EXPECT_EQ(forged(VolumeCodec::Fp16, [](uint8_t* b) { b[0] = 5; }), "its bounding box is not one brick's");
    EXPECT_EQ(forged(VolumeCodec::Fp16, [&](uint8_t* b) { setFloat(b + 80, std::nanf("")); }),
              "its minimum nan is not finite");
    EXPECT_EQ(forged(VolumeCodec::Fp8, [&](uint8_t* b) { setFloat(b + 84, -1.0f); }),
              "its quantum -1.000000 is not finite and >= 0");
    EXPECT_EQ(forged(VolumeCodec::Fp8, [&](uint8_t* b) { setFloat(b + 84, INFINITY); }),
              "its quantum inf is not finite and >= 0");
    EXPECT_EQ(decodeVolumeLeaf(VolumeCodec(7), Leaf{}.bytes, out.data()), "its codec 7 is not one vastray reads");
}

}  // namespace
}  // namespace vastray
