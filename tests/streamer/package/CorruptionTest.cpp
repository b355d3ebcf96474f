// A damaged package is an error that names what is damaged, never a crash or a wrong scene.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

#include "PackageTestUtil.h"
#include "package/PackageFormat.h"
#include "vastray/core/Checksum.h"

namespace vastray::test {
namespace {

class Corruption : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        PackageBuildOptions options;
        options.chunkSizeBytes = 32 << 10;
        auto reader = buildAndOpen(generatedMesh(GeneratorKind::Soup, 3000, 5), pristinePath(), options);
        ASSERT_TRUE(reader);
        info_ = new PackageInfo(reader->info());
        bytes_ = new std::vector<uint8_t>(readFile(pristinePath()));
    }
    static void TearDownTestSuite() {
        delete info_;
        delete bytes_;
    }
    static std::string pristinePath() { return tempPath("pristine.vast"); }

    // Writes the package with one byte changed and returns the path.
    static std::string withFlippedByte(uint64_t offset) {
        std::vector<uint8_t> bytes = *bytes_;
        bytes[offset] ^= 0x5A;
        const std::string path = tempPath("damaged.vast");
        writeFile(path, bytes);
        return path;
    }

    // Recomputes the header's checksum (its last 8 of 256 bytes) over the forged header.
    static void resealHeader(std::vector<uint8_t>& bytes) {
        const uint64_t sum = checksum64(bytes.data(), 248);
        std::memcpy(&bytes[248], &sum, 8);
    }

    static PackageInfo* info_;
    static std::vector<uint8_t>* bytes_;
};
PackageInfo* Corruption::info_ = nullptr;
std::vector<uint8_t>* Corruption::bytes_ = nullptr;

TEST_F(Corruption, PristinePackageVerifies) {
    auto reader = PackageReader::open(pristinePath());
    ASSERT_TRUE(reader.isOk()) << reader.message();
    EXPECT_GT(info_->chunks.size(), 3u);
    EXPECT_TRUE((*reader)->verify().empty());
}

TEST_F(Corruption, AnyChunkByteIsReportedWithTheChunkName) {
    for (const ChunkInfo& chunk : info_->chunks) {
        // Several places in every chunk: header, Draco stream, ids, KD nodes, last byte.
        for (uint64_t at : {uint64_t(0), uint64_t(40), chunk.size / 3, chunk.size / 2, chunk.size * 3 / 4, chunk.size - 1}) {
            auto reader = PackageReader::open(withFlippedByte(chunk.offset + at));
            ASSERT_TRUE(reader.isOk()) << reader.message();
            const std::vector<std::string> problems = (*reader)->verify();
            ASSERT_EQ(problems.size(), 1u) << "chunk " << chunk.id << " byte " << at;
            char values[64];
            std::snprintf(values, sizeof values, " (stored 0x%016llx, computed 0x", (unsigned long long)chunk.checksum);
            EXPECT_NE(problems[0].find("chunk " + std::to_string(chunk.id) + ": checksum mismatch" + values),
                      std::string::npos)
                << problems[0];
        }
    }
}

TEST_F(Corruption, EveryByteOfOneChunkIsCaught) {
    const ChunkInfo& chunk = info_->chunks.front();
    std::vector<uint8_t> blob(bytes_->begin() + chunk.offset, bytes_->begin() + chunk.offset + chunk.size);
    // XXH64 over the blob, as the reader computes it: every single-byte change must alter it.
    for (uint64_t at = 0; at < blob.size(); ++at) {
        blob[at] ^= 0x01;
        ASSERT_NE(checksum64(blob.data(), blob.size()), chunk.checksum) << "byte " << at;
        blob[at] ^= 0x01;
    }
}

TEST_F(Corruption, HeaderAndSectionDamageFailsToOpenWithTheSectionNamed) {
    const uint64_t materials = 256, tree = materials + info_->materials.size() * format::kMaterialBytes;
    const uint64_t directory = tree + info_->topTree.size() * 8;
    const struct {
        uint64_t offset;
        const char* expected;
    } cases[] = {{0, "bad magic"},           {20, "header checksum"},  {255, "header checksum"},
                 {materials + 3, "materials"}, {tree + 1, "top-level tree"}, {directory + 5, "chunk directory"}};
    for (const auto& c : cases) {
        auto reader = PackageReader::open(withFlippedByte(c.offset));
        ASSERT_FALSE(reader.isOk()) << "offset " << c.offset;
        EXPECT_NE(reader.message().find(c.expected), std::string::npos) << reader.message();
        EXPECT_NE(reader.message().find("damaged.vast"), std::string::npos) << reader.message();
    }
}

TEST_F(Corruption, TruncatedOrExtendedFileFailsToOpen) {
    std::vector<uint8_t> bytes = *bytes_;
    const std::string path = tempPath("truncated.vast");
    for (size_t keep : {size_t(0), size_t(100), size_t(256), bytes.size() / 2, bytes.size() - 1}) {
        writeFile(path, std::vector<uint8_t>(bytes.begin(), bytes.begin() + keep));
        auto reader = PackageReader::open(path);
        EXPECT_FALSE(reader.isOk()) << "kept " << keep;
    }
    bytes.push_back(0);
    writeFile(path, bytes);
    auto reader = PackageReader::open(path);
    ASSERT_FALSE(reader.isOk());
    EXPECT_NE(reader.message().find("truncated or appended"), std::string::npos) << reader.message();
}

TEST_F(Corruption, ForgedCountsWithAValidChecksumAreRejectedBeforeAllocating) {
    std::vector<uint8_t> bytes = *bytes_;
    const size_t chunkCountAt = 8 + 4 + 4 + 7 * 8 + 4 + 4 + 4 + 4;  // see serializeHeader
    for (uint32_t forged : {0xFFFFFFFFu, 1u << 23, 0u}) {
        std::memcpy(&bytes[chunkCountAt], &forged, 4);
        resealHeader(bytes);
        const std::string path = tempPath("forged.vast");
        writeFile(path, bytes);
        auto reader = PackageReader::open(path);
        EXPECT_FALSE(reader.isOk()) << forged;
    }
}

// The header records its own size; any other size (a different writer's layout) is refused by
// name, with the stored size, whether or not the header's checksum was recomputed over it.
TEST_F(Corruption, ForgedHeaderSizeIsRefusedWithTheSizeNamed) {
    const size_t headerSizeAt = 8 + 4;  // see serializeHeader: magic, version, header size
    for (const uint32_t forged : {0u, 255u, 257u, 512u, 0xFFFFFFFFu}) {
        for (const bool resealed : {false, true}) {
            std::vector<uint8_t> bytes = *bytes_;
            std::memcpy(&bytes[headerSizeAt], &forged, 4);
            if (resealed) resealHeader(bytes);
            const std::string path = tempPath("header-size.vast");
            writeFile(path, bytes);
            auto reader = PackageReader::open(path);
            ASSERT_FALSE(reader.isOk()) << forged;
            EXPECT_NE(reader.message().find("header size " + std::to_string(forged) + " is not 256"), std::string::npos)
                << reader.message();
            EXPECT_NE(reader.message().find("header-size.vast"), std::string::npos) << reader.message();
        }
    }
}

// Flag bits this reader does not know (a newer writer's feature) are refused by name, in the
// header and in a chunk, even when every checksum matches.
TEST_F(Corruption, UnknownFlagBitsAreRefused) {
    std::vector<uint8_t> bytes = *bytes_;
    const size_t flagsAt = 8 + 4 + 4 + 7 * 8;  // see serializeHeader
    bytes[flagsAt] |= 0x80;
    resealHeader(bytes);
    const std::string path = tempPath("unknown-flags.vast");
    writeFile(path, bytes);
    auto forged = PackageReader::open(path);
    ASSERT_FALSE(forged.isOk());
    EXPECT_NE(forged.message().find("unknown flags"), std::string::npos) << forged.message();

    auto reader = PackageReader::open(pristinePath());
    ASSERT_TRUE(reader.isOk()) << reader.message();
    const ChunkInfo& chunk = info_->chunks[0];
    auto blob = (*reader)->readChunkBlob(chunk.id);
    ASSERT_TRUE(blob.isOk()) << blob.message();
    const size_t chunkFlagsAt = 4 + 4 + 5 * 4;  // magic, version, four counts, geometry bytes
    (*blob)[chunkFlagsAt] |= 0x40;
    auto decoded = decodeChunkBlob(*blob, chunk, info_->grid, uint32_t(info_->materials.size()),
                                   info_->triangleCount + info_->collapsedDropped);
    ASSERT_FALSE(decoded.isOk());
    EXPECT_NE(decoded.message().find("unknown flags"), std::string::npos) << decoded.message();
}

TEST(PackageReaderErrors, NonPackagesAreRejected) {
    const std::string path = tempPath("garbage.vast");
    writeFile(path, std::vector<uint8_t>(4096, 0xAB));
    auto reader = PackageReader::open(path);
    ASSERT_FALSE(reader.isOk());
    EXPECT_NE(reader.message().find("not a vastray package"), std::string::npos) << reader.message();
    reader = PackageReader::open(tempPath("does-not-exist.vast"));
    ASSERT_FALSE(reader.isOk());
    EXPECT_NE(reader.message().find("cannot open"), std::string::npos) << reader.message();
}

}  // namespace
}  // namespace vastray::test
