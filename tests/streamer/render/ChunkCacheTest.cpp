// The host cache's speculative queue: a render's order replaces the order chunks were queued in
// as the scene opened, and no queued chunk is lost or decoded twice on the way.
#include <gtest/gtest.h>

#include <numeric>
#include <vector>

#include "../package/PackageTestUtil.h"
#include "render/ChunkCache.h"

namespace vastray::test {
namespace {

TEST(ChunkCache, SpeculativeOrderPutsTheAskedFirstInTheirOrder) {
    const std::vector<uint32_t> waiting{0, 1, 2, 3, 4, 5, 6, 7};
    // 9 is not waiting; 2 asked twice keeps its first place.
    EXPECT_EQ(speculativeOrder(waiting, std::vector<uint32_t>{5, 2, 9, 2}),
              (std::vector<uint32_t>{5, 2, 0, 1, 3, 4, 6, 7}));
    EXPECT_EQ(speculativeOrder(waiting, std::vector<uint32_t>{}), waiting);
    EXPECT_EQ(speculativeOrder(std::vector<uint32_t>{}, std::vector<uint32_t>{1, 2}), std::vector<uint32_t>{});
    EXPECT_EQ(speculativeOrder(std::vector<uint32_t>{3, 1, 2}, std::vector<uint32_t>{2, 1, 3}),
              (std::vector<uint32_t>{2, 1, 3}));
}

TEST(ChunkCache, ReorderedQueueDecodesEveryChunkOnce) {
    PackageBuildOptions options;
    options.chunkSizeBytes = 64 << 10;
    auto reader = buildAndOpen(generatedMesh(GeneratorKind::Terrain, 20000), tempPath("cache-order.vast"), options);
    ASSERT_TRUE(reader);
    const uint32_t chunks = uint32_t(reader->info().chunks.size());
    ASSERT_GE(chunks, 6u) << "the test needs several chunks";
    ChunkCache cache(*reader, 1ull << 30, 1);
    for (uint32_t id = 0; id < chunks; ++id) cache.prefetchBackground(id);  // as a scene opens
    std::vector<uint32_t> reversed(chunks + 2);
    std::iota(reversed.rbegin(), reversed.rend(), 0u);  // chunks + 1 .. 0: two ids past the last
    cache.prefetchBackground(reversed);
    for (uint32_t id = 0; id < chunks; ++id) {
        auto chunk = cache.get(id);
        ASSERT_TRUE(chunk.isOk()) << chunk.message();
        EXPECT_EQ((*chunk)->id, id);
    }
    EXPECT_EQ(cache.decodes(), chunks);
}

}  // namespace
}  // namespace vastray::test
