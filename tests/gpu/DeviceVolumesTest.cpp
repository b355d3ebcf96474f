// The paged volume pool's host side (gpu/src/DeviceVolumes.h) with bricks that stay in their
// source: each step reads only the bricks of the region it loads, the host cache keeps what it
// read (a brick paged in again is read again only once the cache lost it), and every resident
// slot holds its brick's voxels, whatever the cache evicted.
#include <gtest/gtest.h>

#include <atomic>

#include "DeviceVolumes.h"
#include "GpuTestSupport.h"
#include "PoolLayout.h"

namespace vastray::gpu {
namespace {

// Brick b's voxel i is b + i / 1024: every brick different, every voxel known.
float voxelOf(uint32_t brick, uint32_t i) { return float(brick) + float(i) / 1024.0f; }

class CountingBricks final : public VolumeBrickSource {
public:
    Status readBrick(uint32_t, uint32_t brick, float* density, float*) const override {
        reads.fetch_add(1);
        for (uint32_t i = 0; i < kVolumeBrickVoxels; ++i) density[i] = voxelOf(brick, i);
        return Status::ok();
    }
    mutable std::atomic<uint64_t> reads{0};
};

// 16 x 4 x 4 cells, every one with its own brick (brick = cell), the voxels left in `source`.
std::shared_ptr<const std::vector<Volume>> sourcedVolume(const std::shared_ptr<const CountingBricks>& source) {
    Volume v;
    v.name = "counted";
    v.brickCells = {16, 4, 4};
    v.brickOf.resize(v.cellCount());
    std::vector<float> maximum(v.cellCount());
    for (uint32_t c = 0; c < v.cellCount(); ++c) v.brickOf[c] = c, maximum[c] = voxelOf(c, kVolumeBrickVoxels - 1);
    v.bricks = {source, 0, v.cellCount(), false};
    EXPECT_TRUE(finishVolumeTransform(v));
    computeVolumeMajorants(v, maximum);
    return std::make_shared<const std::vector<Volume>>(std::vector<Volume>{std::move(v)});
}

struct Steps {
    std::vector<uint64_t> reads;  // bricks read by each step
};

// Pages in the region of the brick at x = 0, then at x = 15, then at x = 0 again (a pool of 64
// slots holds one region of 3 or 4 columns of 16 bricks), and checks every resident slot's voxels.
Steps pageBackAndForth(VulkanDevice& device, uint64_t hostCacheBytes) {
    auto source = std::make_shared<const CountingBricks>();
    const auto volumes = sourcedVolume(source);
    const std::vector<VolumeShape> shapes = volumeShapes(*volumes);
    constexpr uint64_t kPaths = 64;
    DeviceVolumes pool(device, hostCacheBytes);
    StreamingStats stats;
    Steps steps;
    const Status prepared = pool.prepare(volumes, pagedVolumeBytes(shapes, kMinVolumeSlots, kPaths), kPaths, stats);
    EXPECT_TRUE(prepared) << prepared.message();
    if (!prepared) return steps;
    EXPECT_EQ(pool.slotCount(), kMinVolumeSlots);
    EXPECT_GE(pool.hostCacheBricks(), kMinVolumeSlots);
    EXPECT_EQ(source->reads.load(), 0u) << "nothing is read before a walk asks";
    const Volume& v = (*volumes)[0];
    for (const uint32_t x : {0u, 15u, 0u}) {
        std::vector<uint32_t> demand(2 * v.brickCount(), 0);
        demand[v.brickOf[x + 16 * (1 + 4 * 1)]] = 1;  // a walk waits for the brick at (x, 1, 1)
        const uint64_t before = source->reads.load();
        auto loads = pool.page(demand, stats);
        EXPECT_TRUE(loads) << loads.message();
        EXPECT_GT(loads ? *loads : 0, 0u);
        steps.reads.push_back(source->reads.load() - before);
    }
    EXPECT_EQ(stats.volumeBricksRead, source->reads.load());
    // Every cell with a slot: that slot holds the cell's brick.
    const PagedVolumeLayout layout = pagedVolumeLayout(shapes, pool.slotCount(), kPaths);
    std::vector<uint32_t> table(v.cellCount());
    EXPECT_TRUE(pool.buffer()->download(table.data(), table.size() * 4, layout.brickOf[0]));
    uint64_t resident = 0;
    std::vector<float> voxels(kVolumeBrickVoxels);
    for (uint32_t c = 0; c < table.size(); ++c) {
        if (table[c] & kBrickAbsent) continue;
        ++resident;
        EXPECT_TRUE(pool.buffer()->download(voxels.data(), voxels.size() * 4,
                                            layout.density + uint64_t(table[c]) * 4 * kVolumeBrickVoxels));
        for (uint32_t i = 0; i < kVolumeBrickVoxels; i += 37) EXPECT_EQ(voxels[i], voxelOf(c, i)) << "cell " << c;
    }
    EXPECT_GT(resident, 0u);
    return steps;
}

TEST(DeviceVolumes, HostCacheKeepsTheBricksItReadAndSlotsHoldTheirBricks) {
    VASTRAY_REQUIRE_DEVICE(device);
    // A cache of the default size holds all 256 bricks: the third step reads none.
    const Steps roomy = pageBackAndForth(device, kVolumeHostCacheBytes);
    ASSERT_EQ(roomy.reads.size(), 3u);
    EXPECT_GT(roomy.reads[0], 0u);
    EXPECT_LE(roomy.reads[0], kMinVolumeSlots);
    EXPECT_GT(roomy.reads[1], 0u);
    EXPECT_EQ(roomy.reads[2], 0u) << "a brick still in the host cache is read again";
    // A cache of one pool's worth loses the first region's bricks to the second: the third step
    // reads them again, and the slots still hold the right voxels.
    const Steps tight = pageBackAndForth(device, 1);
    ASSERT_EQ(tight.reads.size(), 3u);
    EXPECT_EQ(tight.reads[0], roomy.reads[0]);
    EXPECT_EQ(tight.reads[1], roomy.reads[1]);
    EXPECT_GT(tight.reads[2], 0u);
}

}  // namespace
}  // namespace vastray::gpu
