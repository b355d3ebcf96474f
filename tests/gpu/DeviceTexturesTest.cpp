// Paged textures on the device (gpu/src/DeviceTextures.h): pages come in as waiting paths ask for
// them, each slot holds the bytes of the page the page table names, and the host cache of
// inflated pages keeps a page read once from being read again, within its bound, never handing
// out bytes it dropped.
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <vector>

#include "DeviceTextures.h"
#include "GpuTestSupport.h"

namespace vastray::gpu {
namespace {

// One 1024^2 texture (92 pages with its levels) whose page p reads as bytes derived from p, the
// reads counted (atomically: DeviceTextures reads pages on worker threads; a plain counter lost
// increments, and the test failed ~1 run in 15).
struct FakeTextures {
    std::vector<PackageTexture> textures;
    std::atomic<uint64_t> reads{0};
    FakeTextures() {
        PackageTexture t;
        t.name = "fake";
        t.layout = makeTextureLayout(1024, 1024).value();
        textures.push_back(t);
    }
    static uint8_t byteOf(uint32_t page, uint64_t i) { return uint8_t(page * 31 + i * 7); }
    TexturePageReader reader() {
        return [this](uint32_t, uint32_t page, uint8_t* out) {
            ++reads;
            for (uint64_t i = 0; i < kTexturePageBytes; ++i) out[i] = byteOf(page, i);
            return Status::ok();
        };
    }
};

// Every resident page's slot holds that page's bytes.
void expectSlotsHoldTheirPages(const DeviceTextures& t) {
    const uint64_t base = t.buffer().address();
    std::vector<uint32_t> table(t.pageCount());
    ASSERT_TRUE(t.buffer().download(table.data(), table.size() * 4, t.pageTableAddress() - base));
    std::vector<uint8_t> slot(kTexturePageBytes);
    for (uint32_t p = 0; p < table.size(); ++p) {
        if (table[p] == kTexturePageAbsent) continue;
        ASSERT_TRUE(t.buffer().download(slot.data(), slot.size(),
                                        t.poolAddress() - base + uint64_t(table[p]) * kTexturePageBytes));
        for (uint64_t i = 0; i < kTexturePageBytes; i += 997)
            ASSERT_EQ(slot[i], FakeTextures::byteOf(p, i)) << "page " << p << " byte " << i;
    }
}

// Three steps asking for pages 0-15, 16-31, then 0-15 again through 16 slots; a host cache of
// `cachePages` pages. Returns the pages read at each step.
std::vector<uint64_t> pageTexturesBackAndForth(VulkanDevice& device, uint64_t cachePages) {
    FakeTextures fake;
    DeviceTextures t(device, cachePages * kTexturePageBytes);
    StreamingStats stats;
    EXPECT_TRUE(t.prepare(fake.textures, fake.reader(), pagedTextureBytes(fake.textures, kMinTexturePageSlots), stats));
    EXPECT_TRUE(t.paged());
    EXPECT_EQ(t.slotCount(), kMinTexturePageSlots);
    std::vector<uint64_t> reads;
    for (uint32_t first : {0u, 16u, 0u}) {
        std::vector<uint32_t> demand(t.pageCount(), 0);
        for (uint32_t p = first; p < first + 16; ++p) demand[p] = 1;
        const uint64_t before = fake.reads;
        auto loaded = t.page(demand, stats);
        EXPECT_TRUE(loaded) << loaded.message();
        EXPECT_EQ(loaded ? *loaded : 0, 16u);
        reads.push_back(fake.reads - before);
        expectSlotsHoldTheirPages(t);
    }
    EXPECT_EQ(stats.texturePagesRead, reads[0] + reads[1] + reads[2]);
    EXPECT_EQ(stats.texturePageLoads, 48u);
    return reads;
}

TEST(DeviceTextures, TheHostCacheKeepsPagesWithinItsBound) {
    VASTRAY_REQUIRE_DEVICE(device);
    // Room for every page: the third step reads none.
    EXPECT_EQ(pageTexturesBackAndForth(device, 1000), (std::vector<uint64_t>{16, 16, 0}));
    // Room for 20: the second step drops the first's 12 oldest, which the third reads again; the
    // 4 it kept come from the cache.
    EXPECT_EQ(pageTexturesBackAndForth(device, 20), (std::vector<uint64_t>{16, 16, 12}));
    // No room: every load reads.
    EXPECT_EQ(pageTexturesBackAndForth(device, 0), (std::vector<uint64_t>{16, 16, 16}));
}

TEST(DeviceTextures, TooFewBytesForTheFewestSlotsAreRefusedNamingBoth) {
    VASTRAY_REQUIRE_DEVICE(device);
    FakeTextures fake;
    DeviceTextures t(device);
    StreamingStats stats;
    const Status s =
        t.prepare(fake.textures, fake.reader(), pagedTextureBytes(fake.textures, kMinTexturePageSlots) - 1, stats);
    ASSERT_FALSE(s);
    EXPECT_NE(s.message().find("paged through the fewest page slots (16)"), std::string::npos) << s.message();
    EXPECT_FALSE(t.present());
}

}  // namespace
}  // namespace vastray::gpu
