// The host cache's speculative queue: a render's order replaces the order chunks were queued in
// as the scene opened, and no queued chunk is lost or decoded twice on the way. Its decoded hook
// (ChunkBackend::stage) sees every chunk once, before get() returns it, including those decoded
// before the hook was set.
#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <mutex>
#include <numeric>
#include <thread>
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

// A terrain in chunks of 64 KiB: several chunks to queue and decode.
std::unique_ptr<PackageReader> terrainPackage(const std::string& name) {
    PackageBuildOptions options;
    options.chunkSizeBytes = 64 << 10;
    auto reader = buildAndOpen(generatedMesh(GeneratorKind::Terrain, 20000), tempPath(name + ".vast"), options);
    if (reader && reader->info().chunks.size() < 6) ADD_FAILURE() << "the test needs several chunks";
    return reader;
}

TEST(ChunkCache, ReorderedQueueDecodesEveryChunkOnce) {
    auto reader = terrainPackage("cache-order");
    ASSERT_TRUE(reader);
    const uint32_t chunks = uint32_t(reader->info().chunks.size());
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

TEST(ChunkCache, DecodedHookSeesEveryChunkOnceBeforeItsGet) {
    auto reader = terrainPackage("cache-hook");
    ASSERT_TRUE(reader);
    const uint32_t chunks = uint32_t(reader->info().chunks.size());
    ChunkCache cache(*reader, 1ull << 30, 3);
    // Half the chunks decoded before the hook exists (as while the backend is made).
    const uint32_t early = chunks / 2;
    for (uint32_t id = 0; id < early; ++id) ASSERT_TRUE(cache.get(id).isOk());
    std::mutex mutex;
    std::map<uint32_t, int> seen;  // chunk id -> hook calls
    cache.setDecodedHook([&](const DecodedChunk& chunk) {
        std::lock_guard<std::mutex> lock(mutex);
        ++seen[chunk.id];
    });
    for (uint32_t id = early; id < chunks; ++id) {
        auto chunk = cache.get(id);
        ASSERT_TRUE(chunk.isOk()) << chunk.message();
        std::lock_guard<std::mutex> lock(mutex);
        EXPECT_EQ(seen[id], 1) << "chunk " << id << " returned before its hook ran";
    }
    // The early chunks run through the hook on the workers: wait for them (bounded).
    for (int i = 0; i < 500; ++i) {
        {
            std::lock_guard<std::mutex> lock(mutex);
            if (seen.size() == chunks) break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    std::lock_guard<std::mutex> lock(mutex);
    ASSERT_EQ(seen.size(), chunks);
    for (const auto& [id, calls] : seen) EXPECT_EQ(calls, 1) << "chunk " << id;
    EXPECT_EQ(cache.decodes(), chunks) << "the hook must not decode again";
}

}  // namespace
}  // namespace vastray::test
