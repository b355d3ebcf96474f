// Format 16's chunk index layout (the directory entry's last word): every chunk's indices in 8
// bytes a triangle on the device, its long triangles (offsets beyond 16 bits) counted in the
// directory, found and checked when the chunk is read, refused where a forger miscounts them;
// unknown bits and a set word before 16 are refused when the package opens.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "BowlMesh.h"
#include "PackageTestUtil.h"
#include "VolumePackageForge.h"
#include "HeaderOffsets.h"
#include "package/PackageFormat.h"
#include "vastray/core/Checksum.h"

namespace vastray::test {
namespace {

constexpr uint64_t kFlagsInEntry = 44;  // in a directory entry

// The package's bytes with chunk `chunk`'s layout word set to `word` and the directory's and the
// header's checksums recomputed: a forger's package that opens as far as its fields allow.
std::vector<uint8_t> withLayoutWord(std::vector<uint8_t> bytes, uint32_t chunk, uint32_t word) {
    uint32_t chunks = 0;
    std::memcpy(&chunks, bytes.data() + 88, 4);
    const uint64_t directory = word64(bytes, kDirectoryOffsetAt);
    putAt(bytes, directory + 72ull * chunk + kFlagsInEntry, word);
    setWord64(bytes, kDirectoryChecksumAt, checksum64(bytes.data() + directory, 72ull * chunks));
    setWord64(bytes, 248, checksum64(bytes.data(), 248));
    return bytes;
}

TEST(ChunkFlags, EveryChunkCountsItsLongTriangles) {
    for (GeometryCodec codec : {GeometryCodec::Draco, GeometryCodec::Meshopt}) {
        const std::string name = geometryCodecName(codec);
        auto city = smallCity(codec, "flags-city");
        ASSERT_TRUE(city);
        ASSERT_GT(city->info().chunks.size(), 2u);
        for (const ChunkInfo& c : city->info().chunks) {
            EXPECT_EQ(c.flags, kChunkIndexDeltas16) << name << " chunk " << c.id;
            EXPECT_EQ(c.longTriangles, 0u) << name << " chunk " << c.id << ": a small chunk has no long triangle";
            auto chunk = city->readChunk(c.id);
            ASSERT_TRUE(chunk) << chunk.message();
            EXPECT_TRUE(chunk->indexDeltas16);
            EXPECT_TRUE(chunk->longTriangles.empty());
        }
        PackageBuildOptions options;
        options.codec = codec;
        options.chunkSizeBytes = 64 << 20;
        auto bowl = buildAndOpen(bowlUnderLongTriangles(), tempPath("flags-bowl-" + name + ".vast"), options);
        ASSERT_TRUE(bowl);
        ASSERT_EQ(bowl->info().chunks.size(), 1u);
        const ChunkInfo& c = bowl->info().chunks[0];
        EXPECT_EQ(c.flags, kChunkIndexDeltas16);
        EXPECT_GT(c.longTriangles, 0u) << name << ": the bowl must have a triangle beyond 16-bit offsets";
        auto chunk = bowl->readChunk(0);
        ASSERT_TRUE(chunk) << chunk.message();
        EXPECT_EQ(chunk->longTriangles, longTriangles(chunk->indices));
        EXPECT_EQ(chunk->longTriangles.size(), c.longTriangles);
        for (uint32_t t : chunk->longTriangles) {
            const int64_t first = chunk->indices[3 * t];
            EXPECT_GT(std::max(std::abs(int64_t(chunk->indices[3 * t + 1]) - first),
                               std::abs(int64_t(chunk->indices[3 * t + 2]) - first)),
                      kMaxIndexDelta16);
        }
    }
}

TEST(ChunkFlags, AMiscountIsRefusedWhenTheChunkIsRead) {
    PackageBuildOptions options;
    options.chunkSizeBytes = 64 << 20;
    const std::string pristine = tempPath("flags-bowl-claim.vast");
    auto built = buildAndOpen(bowlUnderLongTriangles(), pristine, options);
    ASSERT_TRUE(built);
    const uint32_t count = built->info().chunks[0].longTriangles;
    ASSERT_GT(count, 0u);
    for (uint32_t claimed : {0u, count - 1, count + 1}) {
        const std::string path = tempPath("flags-bowl-forged.vast");
        writeFile(path, withLayoutWord(readFile(pristine), 0, format::kDirectoryIndexDeltas16 | claimed));
        auto reader = PackageReader::open(path);
        ASSERT_TRUE(reader) << reader.message();
        EXPECT_EQ((*reader)->info().chunks[0].longTriangles, claimed);
        auto chunk = (*reader)->readChunk(0);
        ASSERT_FALSE(chunk);
        EXPECT_NE(chunk.message().find("chunk 0: " + std::to_string(count) +
                                       " triangles have vertex indices beyond 16-bit offsets, its directory entry says " +
                                       std::to_string(claimed)),
                  std::string::npos)
            << chunk.message();
        EXPECT_EQ((*reader)->verify().size(), 1u);
    }
    // Twelve bytes a triangle (no flag) is a layout format 16 never writes but reads.
    const std::string twelve = tempPath("flags-bowl-twelve.vast");
    writeFile(twelve, withLayoutWord(readFile(pristine), 0, 0));
    auto reader = PackageReader::open(twelve);
    ASSERT_TRUE(reader) << reader.message();
    EXPECT_EQ((*reader)->info().chunks[0].flags, 0u);
    auto chunk = (*reader)->readChunk(0);
    ASSERT_TRUE(chunk) << chunk.message();
    EXPECT_FALSE(chunk->indexDeltas16);
}

TEST(ChunkFlags, UnknownBitsAndAWordBeforeVersion16AreRefusedOnOpen) {
    PackageBuildOptions options;
    options.chunkSizeBytes = 64 << 10;
    const std::string pristine = tempPath("flags-city-open.vast");
    auto built = buildAndOpen(generatedMesh(GeneratorKind::City, 6000), pristine, options);
    ASSERT_TRUE(built);
    const std::vector<uint8_t> bytes = readFile(pristine);
    expectOpenRefused(withLayoutWord(bytes, 1, format::kDirectoryIndexDeltas16 | (1u << 27)), tempPath("flags-unknown.vast"),
                      "chunk 1: unknown index layout 0x88000000 in its directory entry");
    expectOpenRefused(withLayoutWord(bytes, 1, 5u), tempPath("flags-count-alone.vast"),
                      "chunk 1: unknown index layout 0x00000005 in its directory entry");
    const uint32_t triangles = built->info().chunks[1].triangleCount;
    expectOpenRefused(withLayoutWord(bytes, 1, format::kDirectoryIndexDeltas16 | (triangles + 1)),
                      tempPath("flags-too-many.vast"),
                      "chunk 1: " + std::to_string(triangles + 1) + " long triangles of " + std::to_string(triangles));

    // Format 15 reserved the word: the same package as 15 opens with 12-byte indices, and
    // refuses the word set.
    const std::vector<uint8_t> fifteen = withoutChunkFlags(bytes);
    const std::string old = tempPath("flags-version15.vast");
    writeFile(old, fifteen);
    auto reader = PackageReader::open(old);
    ASSERT_TRUE(reader) << reader.message();
    EXPECT_EQ((*reader)->info().formatVersion, 15u);
    for (const ChunkInfo& c : (*reader)->info().chunks) EXPECT_EQ(c.flags, 0u);
    EXPECT_TRUE((*reader)->verify().empty());
    expectOpenRefused(withLayoutWord(fifteen, 0, format::kDirectoryIndexDeltas16), tempPath("flags-version15-set.vast"),
                      "chunk 0: reserved directory field is not 0");
}

}  // namespace
}  // namespace vastray::test
