// The paged volume pool's host side (gpu/src/DeviceVolumes.h) with bricks that stay in their
// source: each step reads only the bricks walks ask for, empty slots fill before a brick is
// evicted, a brick a parked walk keeps is not evicted (the least recently used of the others
// goes), the host cache keeps what it read (a brick paged in again is read again only once the
// cache lost it), and every resident slot holds its brick's voxels, whatever the cache evicted.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <tuple>

#include "DeviceVolumes.h"
#include "GpuTestSupport.h"
#include "PoolLayout.h"
#include "vastray/core/VolumeLeaf.h"

namespace vastray::gpu {
namespace {

// Brick b's voxel i is b + i / 1024: every brick different, every voxel known.
float voxelOf(uint32_t brick, uint32_t i) { return float(brick) + float(i) / 1024.0f; }

class CountingBricks final : public VolumeBrickSource {
public:
    Status readBrick(uint32_t, uint32_t brick, float* density, float*, uint8_t*) const override {
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

constexpr uint64_t kPaths = 64;

// The volume's cell table as the kernels see it: per cell its slot, or kBrickAbsent | brick.
std::vector<uint32_t> cellTable(const DeviceVolumes& pool, const Volume& v) {
    const std::vector<VolumeShape> shapes = volumeShapes(std::span(&v, 1));
    const PagedVolumeLayout layout = pagedVolumeLayout(shapes, pool.slotCount(), kPaths);
    std::vector<uint32_t> table(v.cellCount());
    EXPECT_TRUE(pool.buffer()->download(table.data(), table.size() * 4, layout.brickOf[0]));
    return table;
}

// A pool of kMinVolumeSlots slots over sourcedVolume, its bricks counted as they are read.
struct SourcedPool {
    explicit SourcedPool(VulkanDevice& device, uint64_t hostCacheBytes = kVolumeHostCacheBytes)
        : source(std::make_shared<const CountingBricks>()),
          volumes(sourcedVolume(source)),
          pool(device, hostCacheBytes, kMinVolumeSlots) {  // (the budget's last granule would hold more)
        const Status prepared = pool.prepare(
            volumes, pagedVolumeBytes(volumeShapes(*volumes), kMinVolumeSlots, kPaths), kPaths, stats);
        EXPECT_TRUE(prepared) << prepared.message();
        EXPECT_EQ(pool.slotCount(), kMinVolumeSlots);
        ready = prepared && pool.slotCount() == kMinVolumeSlots;
    }
    const Volume& volume() const { return (*volumes)[0]; }
    std::shared_ptr<const CountingBricks> source;
    std::shared_ptr<const std::vector<Volume>> volumes;
    DeviceVolumes pool;
    StreamingStats stats;
    bool ready = false;
};

// Walks wait for the bricks of columns x0 to x0 + 3 (64 bricks, a pool's worth; a column of 16 a
// step, since more than a third of the free slots would load a region), then of 12 to 15, then of
// 0 to 3 again, and every resident slot's voxels are checked.
Steps pageBricksBackAndForth(VulkanDevice& device, uint64_t hostCacheBytes) {
    SourcedPool sourced(device, hostCacheBytes);
    auto& [source, volumes, pool, stats, ready] = sourced;
    Steps steps;
    if (!ready) return steps;
    EXPECT_GE(pool.hostCacheBricks(), kMinVolumeSlots);
    EXPECT_EQ(source->reads.load(), 0u) << "nothing is read before a walk asks";
    const Volume& v = sourced.volume();
    for (const uint32_t x0 : {0u, 12u, 0u}) {
        const uint64_t before = source->reads.load();
        for (uint32_t x = x0; x < x0 + 4; ++x) {
            std::vector<uint32_t> demand(pool.demandCount(), 0);
            for (uint32_t c = 0; c < v.cellCount(); ++c)
                if (c % 16 == x) demand[v.brickOf[c]] = 1;
            auto loads = pool.page(demand, stats);
            EXPECT_TRUE(loads) << loads.message();
            EXPECT_EQ(loads ? *loads : 0, kMinVolumeSlots / 4);
        }
        steps.reads.push_back(source->reads.load() - before);
    }
    EXPECT_EQ(stats.volumeBricksRead, source->reads.load());
    // Every cell with a slot: that slot holds the cell's brick.
    const std::vector<uint32_t> table = cellTable(pool, v);
    const PagedVolumeLayout layout = pagedVolumeLayout(volumeShapes(*volumes), pool.slotCount(), kPaths);
    uint64_t resident = 0;
    std::vector<float> voxels(kVolumeBrickVoxels);
    for (uint32_t c = 0; c < table.size(); ++c) {
        if (table[c] & kBrickAbsent) continue;
        ++resident;
        EXPECT_LT(c % 16, 4u) << "cell " << c << " is resident, but no walk waits for it";
        // Each slot holds the brick's NanoVDB float leaf from its minimum on (core/VolumeLeaf.h):
        // the values from byte 16, z fastest.
        std::vector<float> kept(volumeDeviceLeafBytes(VolumeCodec::Float) / 4);
        EXPECT_TRUE(pool.buffer()->download(kept.data(), kept.size() * 4, layout.density + uint64_t(table[c]) * kept.size() * 4));
        for (uint32_t i = 0; i < kVolumeBrickVoxels; ++i) voxels[i] = kept[4 + (i % 8) * 64 + (i / 8 % 8) * 8 + i / 64];
        for (uint32_t i = 0; i < kVolumeBrickVoxels; i += 37) EXPECT_EQ(voxels[i], voxelOf(c, i)) << "cell " << c;
    }
    EXPECT_EQ(resident, kMinVolumeSlots);
    return steps;
}

TEST(DeviceVolumes, HostCacheKeepsTheBricksItReadAndSlotsHoldTheirBricks) {
    VASTRAY_REQUIRE_DEVICE(device);
    // A cache of the default size holds all 256 bricks: the third step reads none.
    const Steps roomy = pageBricksBackAndForth(device, kVolumeHostCacheBytes);
    ASSERT_EQ(roomy.reads.size(), 3u);
    EXPECT_EQ(roomy.reads[0], kMinVolumeSlots);
    EXPECT_EQ(roomy.reads[1], kMinVolumeSlots);
    EXPECT_EQ(roomy.reads[2], 0u) << "a brick still in the host cache is read again";
    // A cache of one pool's worth loses the first step's bricks to the second: the third step
    // reads them again, and the slots still hold the right voxels.
    const Steps tight = pageBricksBackAndForth(device, 1);
    ASSERT_EQ(tight.reads.size(), 3u);
    EXPECT_EQ(tight.reads[0], kMinVolumeSlots);
    EXPECT_EQ(tight.reads[1], kMinVolumeSlots);
    EXPECT_EQ(tight.reads[2], kMinVolumeSlots);
}

// Which slots a step fills: the empty ones before any brick is evicted; then the least recently
// used brick no parked walk keeps; never a kept one while another slot is free of them; and when
// the bricks walks wait for outnumber the slots not kept, a region still loads (no stall).
TEST(DeviceVolumes, EmptySlotsFillFirstAndKeptBricksStay) {
    VASTRAY_REQUIRE_DEVICE(device);
    SourcedPool sourced(device);
    ASSERT_TRUE(sourced.ready);
    auto& [source, volumes, pool, stats, ready] = sourced;
    const Volume& v = sourced.volume();
    const uint32_t bricks = uint32_t(v.brickCount()), slots = pool.slotCount();
    // One step: walks wait for `waited`; parked walks keep the slots of `kept` (cells).
    auto step = [&](const std::vector<uint32_t>& waited, const std::vector<uint32_t>& kept) -> uint64_t {
        std::vector<uint32_t> demand(pool.demandCount(), 0);
        for (const uint32_t c : waited) demand[v.brickOf[c]] = 1;
        const std::vector<uint32_t> table = cellTable(pool, v);
        for (const uint32_t c : kept) {
            EXPECT_EQ(table[c] & kBrickAbsent, 0u) << "cell " << c << " is kept but not resident";
            demand[2 * bricks + table[c]] = 1;
        }
        auto loads = pool.page(demand, stats);
        EXPECT_TRUE(loads) << loads.message();
        return loads ? *loads : 0;
    };
    auto resident = [&](uint32_t cell) { return (cellTable(pool, v)[cell] & kBrickAbsent) == 0; };
    const uint32_t a = 0, b = 255;
    EXPECT_EQ(step({a}, {}), 1u) << "only the brick a walk waits for is loaded";
    EXPECT_EQ(step({b}, {}), 1u);
    EXPECT_TRUE(resident(a)) << "a brick was evicted while slots were empty";
    // Fills the pool: a and b, then cells 1 to 62, at most a third of the free slots a step (more
    // would load a region).
    for (uint32_t c = 1; c + 2 <= slots;) {
        std::vector<uint32_t> some;
        for (; c + 2 <= slots && 3 * (some.size() + 1) <= slots; ++c) some.push_back(c);
        EXPECT_EQ(step(some, {}), some.size());
    }
    EXPECT_TRUE(resident(a) && resident(b)) << "a brick was evicted while slots were empty";
    for (uint32_t c = 1; c + 2 <= slots; ++c) EXPECT_TRUE(resident(c)) << "cell " << c;
    // Full: the least recently used goes (a, loaded first), unless a parked walk keeps it.
    EXPECT_EQ(step({100}, {}), 1u);
    EXPECT_FALSE(resident(a)) << "not the least recently used brick was evicted";
    std::vector<uint32_t> keptAllBut3 = {b, 100};  // every resident brick but cells 1 to 3's
    for (uint32_t c = 4; c <= 62; ++c) keptAllBut3.push_back(c);
    EXPECT_EQ(step({101}, keptAllBut3), 1u);
    EXPECT_FALSE(resident(1) && resident(2) && resident(3)) << "a brick a parked walk keeps was evicted";
    for (const uint32_t c : keptAllBut3) EXPECT_TRUE(resident(c)) << "cell " << c << " was kept, but evicted";
    // Every slot kept and more bricks waited for than the pool holds: a region loads anyway.
    std::vector<uint32_t> all(bricks), keptAll = keptAllBut3;
    for (uint32_t c = 0; c < bricks; ++c) all[c] = c;
    keptAll.push_back(101);
    for (const uint32_t c : {1u, 2u, 3u})
        if (resident(c)) keptAll.push_back(c);
    const uint64_t loads = step(all, keptAll);
    EXPECT_GT(loads, 0u) << "a step loaded nothing while walks wait";
    EXPECT_LE(loads, slots);
    EXPECT_EQ(stats.volumeBrickLoads, slots + 2 + loads);
}

// A step loads the waited bricks while they take at most a third of the slots free of kept bricks
// (21 of 64: exactly those), and a region beyond (22: the region of 48 bricks they lie in).
TEST(DeviceVolumes, RegionStepWhenTheWaitedBricksTakeMoreThanAThirdOfTheFreeSlots) {
    VASTRAY_REQUIRE_DEVICE(device);
    for (const uint64_t waitedCount : {21u, 22u}) {
        SourcedPool sourced(device);
        ASSERT_TRUE(sourced.ready);
        const Volume& v = sourced.volume();
        ASSERT_EQ(sourced.pool.slotCount(), 64u);
        std::vector<uint32_t> waited;  // columns x = 0 and 1: the home of one region
        for (uint32_t c = 0; waited.size() < waitedCount; ++c)
            if (c % 16 < 2) waited.push_back(c);
        std::vector<uint32_t> demand(sourced.pool.demandCount(), 0);
        for (const uint32_t c : waited) demand[v.brickOf[c]] = 1;
        const uint64_t loads = sourced.pool.page(demand, sourced.stats).value();
        const std::vector<uint32_t> table = cellTable(sourced.pool, v);
        for (const uint32_t c : waited) EXPECT_EQ(table[c] & kBrickAbsent, 0u) << "cell " << c << " is absent";
        if (waitedCount == 21) EXPECT_EQ(loads, 21u) << "a step loaded more than the waited bricks";
        else EXPECT_EQ(loads, 48u) << "no region loaded (cells x < 3: the region of columns 0 and 1)";
    }
}

// A region step (the waited bricks take more than a third of the slots not kept) fills the empty
// slots before it evicts a brick, kept or not.
TEST(DeviceVolumes, RegionStepFillsEmptySlotsFirst) {
    VASTRAY_REQUIRE_DEVICE(device);
    SourcedPool sourced(device);
    ASSERT_TRUE(sourced.ready);
    auto& [source, volumes, pool, stats, ready] = sourced;
    const Volume& v = sourced.volume();
    const uint32_t bricks = uint32_t(v.brickCount());
    std::vector<uint32_t> column;  // the 16 cells at x = 15, into the first 16 slots
    for (uint32_t c = 15; c < bricks; c += 16) column.push_back(c);
    std::vector<uint32_t> demand(pool.demandCount(), 0);
    for (const uint32_t c : column) demand[v.brickOf[c]] = 1;
    ASSERT_EQ(pool.page(demand, stats).value(), column.size());
    // Walks wait for every brick; the column's are kept, 48 slots are empty.
    std::vector<uint32_t> table = cellTable(pool, v);
    std::fill(demand.begin(), demand.end(), 0);
    for (uint32_t c = 0; c < bricks; ++c) demand[v.brickOf[c]] = 1;
    for (const uint32_t c : column) demand[2 * bricks + table[c]] = 1;
    const uint64_t empty = pool.slotCount() - column.size();
    const uint64_t loads = pool.page(demand, stats).value();
    EXPECT_GT(loads, 0u);
    table = cellTable(pool, v);
    uint64_t evicted = 0;
    for (const uint32_t c : column) evicted += (table[c] & kBrickAbsent) != 0;
    EXPECT_EQ(evicted, loads > empty ? loads - empty : 0) << "a region evicted bricks while slots were empty";
}

// A volume of nx x 4 x 4 cells, each with its own brick (in the source: no voxels in memory).
Volume denseVolume(uint32_t nx) {
    Volume v;
    v.brickCells = {nx, 4, 4};
    v.brickOf.resize(v.cellCount());
    for (uint32_t c = 0; c < v.cellCount(); ++c) v.brickOf[c] = c;
    v.bricks = {std::make_shared<const CountingBricks>(), 0, v.cellCount(), false};
    return v;
}

// The paging regions: every brick has its home in one, whose bricks (its box grown by a cell)
// hold it and fit the pool; and the volume is cut into the fewest regions of the two ways tried.
// Halves: 16 x 4 x 4 cells at 100 slots become 4 regions (cutting off a third first gives 5);
// 24 x 4 x 4 at 160 slots become 3 regions cut by thirds (halves give 4).
TEST(DeviceVolumes, RegionsFitThePoolAndAreTheFewestOfTwoCuts) {
    for (const auto& [nx, slots, fewest] : {std::tuple{16u, 100u, 4u}, std::tuple{24u, 160u, 3u}}) {
        const Volume v = denseVolume(nx);
        const VolumeRegions regions = volumeRegions(v, slots);
        EXPECT_EQ(regions.bricks.size(), fewest) << nx << " x 4 x 4 cells, " << slots << " slots";
        ASSERT_EQ(regions.home.size(), v.brickCount());
        for (const std::vector<uint32_t>& r : regions.bricks) EXPECT_LE(r.size(), slots);
        for (uint32_t b = 0; b < regions.home.size(); ++b) {
            ASSERT_LT(regions.home[b], regions.bricks.size()) << "brick " << b << " has no home";
            const std::vector<uint32_t>& r = regions.bricks[regions.home[b]];
            EXPECT_NE(std::find(r.begin(), r.end(), b), r.end()) << "brick " << b << " is not in its home";
        }
    }
}

}  // namespace
}  // namespace vastray::gpu
