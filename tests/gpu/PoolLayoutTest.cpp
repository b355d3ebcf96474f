#include <gtest/gtest.h>

#include <algorithm>
#include <utility>
#include <vector>

#include "PoolLayout.h"

namespace vastray::gpu {
namespace {

// The wavefront's state arrays (shared/WavefrontTypes.h's WavefrontParams) for any count of
// paths: each aligned for its element (vec4 16 bytes, uvec2 8, uint 4), none overlapping another,
// all inside the buffer; and the per-path figure the planner sizes waves with is what they take.
TEST(PoolLayout, StateArraysAreAlignedAndDisjointForAnyPathCount) {
    for (const uint64_t paths : {1ull, 2ull, 3ull, 7ull, 64ull, 1001ull, 160001ull, 1ull << 20}) {
        const StateLayout s = stateLayout(paths);
        const uint64_t groups = groupCapacity(paths);
        struct Array {
            const char* name;
            uint64_t at, bytes, align;
        };
        std::vector<Array> arrays = {
            {"rayOrigin", s.rayOrigin, 16 * paths, 16},        {"rayDirection", s.rayDirection, 32 * paths, 16},
            {"hitPosition", s.hitPosition, 16 * paths, 16},    {"hitNormal", s.hitNormal, 16 * paths, 16},
            {"hitIds", s.hitIds, 16 * paths, 16},              {"throughput", s.throughput, 16 * paths, 16},
            {"radiance", s.radiance, 16 * paths, 16},          {"pendingSun", s.pendingSun, 16 * paths, 16},
            {"accum", s.accum, 16 * paths, 16},                {"rayState", s.rayState, 16 * paths, 8},
            {"pathInfo", s.pathInfo, 8 * paths, 8},            {"groupState", s.groupState, 8 * groups, 8},
        };
        for (uint32_t q = 0; q < kQueueCount; ++q) {
            const uint64_t entries = q < kShadeQueue ? 2 * paths : q < kGroupQueue ? paths : groups;
            arrays.push_back({"queue", s.queues + queueOffset(q, paths), 4 * entries, 4});
        }
        std::sort(arrays.begin(), arrays.end(), [](const Array& a, const Array& b) { return a.at < b.at; });
        uint64_t end = 0, sum = 0;
        for (const Array& a : arrays) {
            EXPECT_EQ(a.at % a.align, 0u) << a.name << " with " << paths << " paths";
            EXPECT_GE(a.at, end) << a.name << " overlaps the array before it with " << paths << " paths";
            end = a.at + a.bytes, sum += a.bytes;
        }
        EXPECT_LE(end, s.totalBytes) << paths << " paths";
        EXPECT_EQ(sum, s.totalBytes) << "no gaps with " << paths << " paths";
        // kBytesPerPath leaves out the accumulator (a tile pixel's, kBytesPerTilePixel) and counts
        // the per-group arrays at half a group per path.
        EXPECT_EQ(s.totalBytes - 16 * paths, kBytesPerPath * paths + (paths % 2 ? 8 : 0)) << paths << " paths";
    }
}

// The hits' UVs (a render that reads the scene's texture coordinates): one vec2 per path after
// everything else, 8-byte aligned; without them the layout is the same as before and has none.
TEST(PoolLayout, HitUvsAreAppendedOnlyWhenTheRenderReadsThem) {
    for (const uint64_t paths : {1ull, 3ull, 1001ull, 1ull << 20}) {
        const StateLayout plain = stateLayout(paths), uvs = stateLayout(paths, true);
        EXPECT_EQ(plain.hitUv, 0u);
        EXPECT_EQ(uvs.queues, plain.queues);
        EXPECT_GE(uvs.hitUv, plain.totalBytes) << paths;
        EXPECT_EQ(uvs.hitUv % 8, 0u) << paths;
        EXPECT_EQ(uvs.totalBytes, uvs.hitUv + kBytesPerPathUv * paths) << paths;  // UV and footprint
        EXPECT_LT(uvs.hitUv - plain.totalBytes, 16u) << paths;
    }
}

// The punctual lights' section of the table buffer (counted, as the whole table buffer is,
// against --memory-budget): one WavefrontLight per package light after the stream window, none
// without lights.
TEST(PoolLayout, LightSectionHoldsThePackagesLightsAndCostsNothingWithoutThem) {
    PackageInfo package;
    package.materials.resize(1);
    const TableLayout none = tableLayout(4, package);
    EXPECT_EQ(none.lightCapacity, 0u);
    EXPECT_EQ(none.totalBytes, none.lights);
    package.lights.resize(3);
    const TableLayout three = tableLayout(4, package);
    EXPECT_EQ(three.lightCapacity, 3u);
    EXPECT_EQ(three.lights % 16, 0u);
    EXPECT_GE(three.lights, three.stream + sizeof(StreamWindow));
    EXPECT_EQ(three.totalBytes, three.lights + 3 * sizeof(WavefrontLight));
    EXPECT_EQ(three.totalBytes - none.totalBytes, 3 * sizeof(WavefrontLight));
}

}  // namespace
}  // namespace vastray::gpu
