// streamer/src/package/TextureSection: the package's texture table and page frames round trip,
// and a forged or cut table or page is refused naming the file, the texture or entry and the
// field (each forgery re-checksummed, so that the check of the field itself is what refuses it).
#include <gtest/gtest.h>

#include "TestTextures.h"

#include <cstring>

#include "package/TextureSection.h"
#include "vastray/core/Checksum.h"

namespace vastray {
namespace {

Rgba8Image noise(uint32_t w, uint32_t h, uint32_t seed) { return vastray::test::noiseImage(w, h, seed, 0x3F); }

struct Written {
    std::vector<TexturePyramid> pyramids;
    std::vector<uint8_t> table, data;
};

Written writeTwo() {
    Written w;
    w.pyramids.push_back(*buildTexturePyramid(noise(200, 130, 1), TextureWrap::Clamp, TextureWrap::Mirror,
                                              TextureEncoding::Srgb));
    w.pyramids.push_back(*buildTexturePyramid(noise(16, 8, 2), TextureWrap::Repeat, TextureWrap::Repeat,
                                              TextureEncoding::Linear));
    TextureSectionWriter writer;
    EXPECT_TRUE(writer.add("bricks.png", w.pyramids[0]));
    w.data = writer.data();  // a writer may also write out and clear its data after each texture
    writer.data().clear();
    EXPECT_TRUE(writer.add("image 1 of scene.glb", w.pyramids[1]));
    w.data.insert(w.data.end(), writer.data().begin(), writer.data().end());
    w.table = writer.tableBytes();
    return w;
}

TEST(TextureSection, TableAndPagesRoundTrip) {
    const Written w = writeTwo();
    auto table = parseTextureTable(w.table.data(), w.table.size(), 2, w.data.size(), "scene.vast");
    ASSERT_TRUE(table) << table.message();
    ASSERT_EQ(table->textures.size(), 2u);
    EXPECT_EQ(table->textures[0].name, "bricks.png");
    EXPECT_EQ(table->textures[0].wrapS, TextureWrap::Clamp);
    EXPECT_EQ(table->textures[0].wrapT, TextureWrap::Mirror);
    EXPECT_EQ(table->textures[1].encoding, TextureEncoding::Linear);
    EXPECT_EQ(table->textures[1].firstEntry, w.pyramids[0].layout.pageCount);
    EXPECT_EQ(table->entries.size(), size_t(w.pyramids[0].layout.pageCount + w.pyramids[1].layout.pageCount));
    std::vector<uint8_t> page(kTexturePageBytes);
    for (uint32_t t = 0; t < 2; ++t)
        for (uint32_t p = 0; p < w.pyramids[t].layout.pageCount; ++p) {
            const TexturePageEntry& e = table->entries[table->textures[t].firstEntry + p];
            ASSERT_TRUE(readTexturePage(table->textures, table->entries, t, p, w.data.data() + e.offset, e.size,
                                        page.data(), "scene.vast"));
            ASSERT_EQ(0, std::memcmp(page.data(), w.pyramids[t].pages.data() + size_t(p) * kTexturePageBytes,
                                     kTexturePageBytes))
                << t << " " << p;
        }
    // A package without textures: no table.
    TextureSectionWriter none;
    EXPECT_TRUE(none.tableBytes().empty());
    auto nothing = parseTextureTable(nullptr, 0, 0, 0, "plain.vast");
    ASSERT_TRUE(nothing) << nothing.message();
    EXPECT_TRUE(nothing->textures.empty());
}

TEST(TextureSection, TheHeadRoundTripsAndAForgedOneIsRefused) {
    const std::vector<uint8_t> bytes = serializeTextureHead({3, 123456789, 3 * kTextureRecordBytes + 8 + 48});
    ASSERT_EQ(bytes.size(), kTextureHeadBytes);
    auto head = parseTextureHead(bytes.data(), bytes.size());
    ASSERT_TRUE(head) << head.message();
    EXPECT_EQ(head->count, 3u);
    EXPECT_EQ(head->tableOffset, 123456789u);
    auto refused = [](const TextureHead& h, const char* says) {
        const std::vector<uint8_t> b = serializeTextureHead(h);
        auto parsed = parseTextureHead(b.data(), b.size());
        ASSERT_FALSE(parsed) << says;
        EXPECT_NE(parsed.message().find(says), std::string::npos) << parsed.message();
    };
    refused({kMaxPackageTextures + 1, 0, 1u << 30}, "4097 textures is more than the 4096");
    refused({2, 0, 2 * kTextureRecordBytes}, "a table of 192 bytes for 2 textures");
    refused({0, 0, 8}, "a table of 8 bytes for 0 textures");
    std::vector<uint8_t> flipped = bytes;
    flipped[9] ^= 1;
    auto parsed = parseTextureHead(flipped.data(), flipped.size());
    ASSERT_FALSE(parsed);
    EXPECT_NE(parsed.message().find("checksum"), std::string::npos) << parsed.message();
    EXPECT_FALSE(parseTextureHead(bytes.data(), bytes.size() - 1));
}

// The table with one u32 or u64 at `at` replaced, and its checksum made right again.
template <typename T>
std::vector<uint8_t> forged(std::vector<uint8_t> table, size_t at, T value) {
    std::memcpy(table.data() + at, &value, sizeof(T));
    const uint64_t sum = checksum64(table.data(), table.size() - 8);
    std::memcpy(table.data() + table.size() - 8, &sum, 8);
    return table;
}

TEST(TextureSection, ForgedFieldsAreRefusedByName) {
    const Written w = writeTwo();
    const size_t record0 = 0, record1 = kTextureRecordBytes, field = 64;
    const size_t entries = 2 * kTextureRecordBytes;
    const size_t entry1 = entries + kTexturePageEntryBytes;
    struct Case {
        std::vector<uint8_t> table;
        const char* says;
    } cases[] = {
        {forged(w.table, record0 + field, uint32_t(0)), "texture 0 ('bricks.png'): a texture of 0x130 texels"},
        {forged(w.table, record0 + field + 4, uint32_t(kMaxTextureSide + 1)), "outside 1..16384"},
        {forged(w.table, record0 + field + 8, uint32_t(3)), "wrap modes 3, 2"},
        {forged(w.table, record1 + field + 16, uint32_t(2)), "texture 1 ('image 1 of scene.glb'): encoding 2"},
        {forged(w.table, record0 + field + 20, uint32_t(9)), "9 levels and"},
        {forged(w.table, record1 + field + 28, uint32_t(0)), "first page entry 0, not"},
        {forged(w.table, entry1, uint64_t(1)), "page entry 1: offset 1, where the previous frame ends at"},
        {forged(w.table, entry1 + 16, uint32_t(0)), "page entry 1: a frame of 0 bytes"},
        {forged(w.table, entry1 + 20, uint32_t(5)), "page entry 1: reserved word 5"},
    };
    for (const Case& c : cases) {
        auto table = parseTextureTable(c.table.data(), c.table.size(), 2, w.data.size(), "forged.vast");
        ASSERT_FALSE(table) << c.says;
        EXPECT_NE(table.message().find("forged.vast: textures: "), std::string::npos) << table.message();
        EXPECT_NE(table.message().find(c.says), std::string::npos) << table.message();
    }
    // A flipped bit anywhere the fields do not catch: the checksum does.
    std::vector<uint8_t> flipped = w.table;
    flipped[record0 + 3] ^= 0x20;  // inside the first name
    auto table = parseTextureTable(flipped.data(), flipped.size(), 2, w.data.size(), "flip.vast");
    ASSERT_FALSE(table);
    EXPECT_NE(table.message().find("checksum does not match"), std::string::npos) << table.message();
    // Page data shorter or longer than the frames.
    table = parseTextureTable(w.table.data(), w.table.size(), 2, w.data.size() - 1, "short.vast");
    ASSERT_FALSE(table);
    EXPECT_NE(table.message().find("beyond the"), std::string::npos) << table.message();
    table = parseTextureTable(w.table.data(), w.table.size(), 2, w.data.size() + 1, "long.vast");
    ASSERT_FALSE(table);
    EXPECT_NE(table.message().find("the page data at"), std::string::npos) << table.message();
    // A table longer than its textures' records and entries, or a count that disagrees.
    std::vector<uint8_t> longer = w.table;
    longer.insert(longer.end(), 8, 0);
    table = parseTextureTable(longer.data(), longer.size(), 2, w.data.size(), "long.vast");
    ASSERT_FALSE(table);
    table = parseTextureTable(w.table.data(), w.table.size(), 1, w.data.size(), "count.vast");
    ASSERT_FALSE(table);
}

TEST(TextureSection, EveryCutOfTheTableIsRefusedAndAForgedPageToo) {
    const Written w = writeTwo();
    for (size_t cut = 0; cut < w.table.size(); ++cut)
        ASSERT_FALSE(parseTextureTable(w.table.data(), cut, 2, w.data.size(), "cut.vast")) << cut;
    auto table = parseTextureTable(w.table.data(), w.table.size(), 2, w.data.size(), "scene.vast");
    ASSERT_TRUE(table);
    const TexturePageEntry& e = table->entries[3];
    std::vector<uint8_t> frame(w.data.begin() + long(e.offset), w.data.begin() + long(e.offset + e.size));
    std::vector<uint8_t> page(kTexturePageBytes);
    frame[frame.size() / 2] ^= 1;
    Status bad = readTexturePage(table->textures, table->entries, 0, 3, frame.data(), frame.size(), page.data(),
                                 "scene.vast");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.message().find("scene.vast: texture 0 ('bricks.png') page 3: checksum"), std::string::npos)
        << bad.message();
    bad = readTexturePage(table->textures, table->entries, 0, 3, frame.data(), frame.size() - 1, page.data(),
                          "scene.vast");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.message().find("bytes read, the entry says"), std::string::npos) << bad.message();
}

}  // namespace
}  // namespace vastray
