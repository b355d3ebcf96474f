// The pager of the device wavefront against a recording backend: which chunks it loads for a
// set of demand counters, which slots it takes, and how it counts loads and reloads.
#include <gtest/gtest.h>

#include <vector>

#include "../package/PackageTestUtil.h"
#include "render/ChunkCache.h"
#include "render/DemandPager.h"

namespace vastray::test {
namespace {

// Slots that remember which chunk was loaded into them, in order.
class RecordingBackend final : public ChunkBackend {
public:
    explicit RecordingBackend(uint32_t slots) : slots_(slots) {}
    std::string name() const override { return "recording"; }
    uint32_t slotCount() const override { return slots_; }
    Status load(uint32_t slot, const DecodedChunk& chunk, std::span<const uint8_t>) override {
        if (slot >= slots_) return Status::error("no slot " + std::to_string(slot));
        loads.push_back({slot, chunk.id});
        return Status::ok();
    }
    Status renderOnDevice(const DeviceRenderJob&, ChunkPager&, RenderImage&, StreamingStats&) override {
        return Status::error("not a renderer");
    }
    uint64_t bytesUploaded() const override { return 0; }
    uint64_t peakDeviceBytes() const override { return 0; }
    double uploadSeconds() const override { return 0; }
    double deviceSeconds() const override { return 0; }

    struct Load {
        uint32_t slot, chunk;
    };
    std::vector<Load> loads;

private:
    uint32_t slots_;
};

class DemandPagerTest : public ::testing::Test {
protected:
    void SetUp() override {
        PackageBuildOptions options;
        options.chunkSizeBytes = 64 << 10;
        reader_ = buildAndOpen(generatedMesh(GeneratorKind::Terrain, 20000), tempPath("pager.vast"), options);
        ASSERT_TRUE(reader_);
        ASSERT_GE(reader_->info().chunks.size(), 6u) << "the tests need several chunks";
        cache_ = std::make_unique<ChunkCache>(*reader_, 1ull << 30, 1);
    }
    std::unique_ptr<DemandPager> pager(RecordingBackend& backend) {
        return std::make_unique<DemandPager>(reader_->info(), ChunkAttributes{}, backend, *cache_, stats_);
    }
    std::vector<uint32_t> demand(std::initializer_list<std::pair<uint32_t, uint32_t>> waiting) const {
        std::vector<uint32_t> d(reader_->info().chunks.size(), 0);
        for (auto [chunk, rays] : waiting) d[chunk] = rays;
        return d;
    }

    std::unique_ptr<PackageReader> reader_;
    std::unique_ptr<ChunkCache> cache_;
    StreamingStats stats_;
};

TEST_F(DemandPagerTest, LoadsTheMostWantedChunksIntoFreeSlots) {
    RecordingBackend backend(2);
    auto p = pager(backend);
    p->beginStream();
    auto loaded = p->page(demand({{0, 5}, {1, 9}, {2, 1}, {3, 5}}));
    ASSERT_TRUE(loaded) << loaded.message();
    EXPECT_EQ(*loaded, (std::vector<uint32_t>{1, 0})) << "most waiting rays first; chunk id breaks ties";
    EXPECT_EQ(p->chunkSlots()[1], backend.loads[0].slot);
    EXPECT_EQ(p->chunkSlots()[0], backend.loads[1].slot);
    EXPECT_EQ(p->chunkSlots()[3], kEmptyCell);
    EXPECT_EQ(stats_.chunkLoads, 2u);
    EXPECT_FALSE(p->allResident());
}

TEST_F(DemandPagerTest, NeverEvictsAChunkRaysWaitFor) {
    RecordingBackend backend(2);
    auto p = pager(backend);
    p->beginStream();
    ASSERT_TRUE(p->page(demand({{0, 1}, {1, 1}})));
    // Chunk 0 is resident and (as far as the pager knows) still wanted; chunk 1 is not: the new
    // chunk takes chunk 1's slot.
    auto loaded = p->page(demand({{0, 4}, {2, 3}, {3, 2}}));
    ASSERT_TRUE(loaded) << loaded.message();
    EXPECT_EQ(*loaded, (std::vector<uint32_t>{2}));
    EXPECT_NE(p->chunkSlots()[0], kEmptyCell);
    EXPECT_EQ(p->chunkSlots()[1], kEmptyCell);
    EXPECT_EQ(p->chunkSlots()[3], kEmptyCell) << "no slot was free for it";
}

TEST_F(DemandPagerTest, EvictsTheLeastRecentlyUsedIdleChunk) {
    RecordingBackend backend(2);
    auto p = pager(backend);
    p->beginStream();
    ASSERT_TRUE(p->page(demand({{0, 2}, {1, 1}})));  // chunk 0 loaded first, then chunk 1
    std::vector<uint32_t> touched(reader_->info().chunks.size(), 0);
    touched[0] = 1;  // a ray traced chunk 0 after both were loaded
    p->streamTouched(touched);
    ASSERT_TRUE(p->page(demand({{4, 1}})));
    EXPECT_NE(p->chunkSlots()[0], kEmptyCell) << "the recently traced chunk stays";
    EXPECT_EQ(p->chunkSlots()[1], kEmptyCell);
    EXPECT_NE(p->chunkSlots()[4], kEmptyCell);
}

TEST_F(DemandPagerTest, CountsReloadsWithinAStreamOnly) {
    RecordingBackend backend(1);
    auto p = pager(backend);
    p->beginStream();
    ASSERT_TRUE(p->page(demand({{0, 1}})));
    ASSERT_TRUE(p->page(demand({{1, 1}})));
    ASSERT_TRUE(p->page(demand({{0, 1}})));  // chunk 0 again in the same stream
    EXPECT_EQ(stats_.streamReloads, 1u);
    p->beginStream();
    ASSERT_TRUE(p->page(demand({{1, 1}})));  // not seen in this stream: a load, not a reload
    EXPECT_EQ(stats_.streamReloads, 1u);
    EXPECT_EQ(stats_.chunkLoads, 4u);
    EXPECT_EQ(cache_->decodes(), 2u) << "the host cache decodes each chunk once";
}

TEST_F(DemandPagerTest, AllResidentOnceEveryChunkHasASlot) {
    const uint32_t chunks = uint32_t(reader_->info().chunks.size());
    RecordingBackend backend(chunks);
    auto p = pager(backend);
    p->beginStream();
    std::vector<uint32_t> everything(chunks, 1);
    auto loaded = p->page(everything);
    ASSERT_TRUE(loaded) << loaded.message();
    EXPECT_EQ(loaded->size(), chunks);
    EXPECT_TRUE(p->allResident());
}

TEST_F(DemandPagerTest, FillsFreeSlotsWithChunksRaysReachLater) {
    RecordingBackend backend(3);
    auto p = pager(backend);
    p->beginStream();
    // Rays wait for chunk 0; behind it they reach chunk 2 (3 rays) and chunk 5 (7 rays).
    auto loaded = p->page(demand({{0, 4}}), demand({{2, 3}, {5, 7}}));
    ASSERT_TRUE(loaded) << loaded.message();
    EXPECT_EQ(*loaded, (std::vector<uint32_t>{0, 5, 2})) << "waited for first, then most reached later";
    // All slots are taken now: a chunk only reached later evicts nothing.
    loaded = p->page(demand({}), demand({{4, 9}}));
    ASSERT_TRUE(loaded) << loaded.message();
    EXPECT_TRUE(loaded->empty());
    EXPECT_EQ(p->chunkSlots()[4], kEmptyCell);
}

TEST_F(DemandPagerTest, EvictsChunksNoRayReachesLaterFirst) {
    RecordingBackend backend(2);
    auto p = pager(backend);
    p->beginStream();
    ASSERT_TRUE(p->page(demand({{0, 2}, {1, 1}})));
    std::vector<uint32_t> touched(reader_->info().chunks.size(), 0);
    touched[1] = 1;  // chunk 1 is the more recently used
    p->markUsed(touched);
    // Rays wait for chunk 3 and will reach chunk 0 after it: chunk 1 goes, although more recent.
    ASSERT_TRUE(p->page(demand({{3, 5}}), demand({{0, 5}})));
    EXPECT_NE(p->chunkSlots()[0], kEmptyCell);
    EXPECT_EQ(p->chunkSlots()[1], kEmptyCell);
    EXPECT_NE(p->chunkSlots()[3], kEmptyCell);
}

// Chunks queued in the background decode once each, a get() of one still queued is served (it
// moves to the front), and each decoded chunk is the one asked for.
TEST_F(DemandPagerTest, BackgroundPrefetchDecodesEachChunkOnceAndGetStillServes) {
    const uint32_t chunks = uint32_t(reader_->info().chunks.size());
    ChunkCache cache(*reader_, 1ull << 30, 1);
    for (uint32_t c = 0; c < chunks; ++c) cache.prefetchBackground(c);
    EXPECT_GT(cache.unusedBytes(), 0u);
    auto last = cache.get(chunks - 1);
    ASSERT_TRUE(last) << last.message();
    EXPECT_EQ((*last)->id, chunks - 1);
    for (uint32_t c = 0; c < chunks; ++c) {
        auto got = cache.get(c);
        ASSERT_TRUE(got) << got.message();
        EXPECT_EQ((*got)->id, c);
    }
    EXPECT_EQ(cache.decodes(), chunks) << "a chunk queued twice (background, then wanted) decodes once";
    EXPECT_EQ(cache.unusedBytes(), 0u);
    cache.prefetchBackground(0);  // cached already: nothing to do
    EXPECT_EQ(cache.decodes(), chunks);
}

// The time get() waits for a decode is counted (a render's decode_wait_seconds); a chunk already
// decoded costs none.
TEST_F(DemandPagerTest, CacheCountsTheTimeGetWaitsForADecode) {
    ChunkCache cache(*reader_, 1ull << 30, 1);
    EXPECT_EQ(cache.waitSeconds(), 0.0);
    ASSERT_TRUE(cache.get(0));  // nobody asked before: decoded now, waited for
    const double waited = cache.waitSeconds();
    EXPECT_GT(waited, 0.0);
    EXPECT_LE(waited, cache.decodeSeconds() + 1.0);
    ASSERT_TRUE(cache.get(0));  // cached
    EXPECT_EQ(cache.waitSeconds(), waited);
}

}  // namespace
}  // namespace vastray::test
