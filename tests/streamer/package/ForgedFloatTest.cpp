// Issue 16: a package whose checksums were recomputed after its floats were forged (NaN or
// Inf grid origin, grid range 1e300, inverted or NaN bounds, a NaN cell or chunk BVH box)
// passed `info --verify` and rendered sky. The reader must refuse each by name.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <tuple>

#include "PackageTestUtil.h"
#include "HeaderOffsets.h"
#include "package/PackageFormat.h"
#include "vastray/core/Checksum.h"

namespace vastray::test {
namespace {

// In a directory entry: offset, size, checksum, resident bytes, four counts, then the cell.
constexpr size_t kEntryChecksumAt = 2 * 8;
constexpr size_t kEntryCellAt = 4 * 8 + 4 * 4;
// In a chunk blob: magic, version, five counts, flags, then the BVH's box.
constexpr size_t kBlobBvhBoundsAt = 4 + 4 + 5 * 4 + 4;

const float kNan = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

class ForgedFloats : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        PackageBuildOptions options;
        options.chunkSizeBytes = 32 << 10;
        auto reader = buildAndOpen(generatedMesh(GeneratorKind::Soup, 2000, 3), tempPath("floats.vast"), options);
        ASSERT_TRUE(reader);
        info_ = new PackageInfo(reader->info());
        bytes_ = new std::vector<uint8_t>(readFile(tempPath("floats.vast")));
    }
    static void TearDownTestSuite() {
        delete info_;
        delete bytes_;
    }

    template <typename T>
    static void put(std::vector<uint8_t>& bytes, size_t at, T value) {
        std::memcpy(&bytes[at], &value, sizeof value);
    }

    // Recomputes the directory's and the header's checksums, as a forger would.
    static void reseal(std::vector<uint8_t>& bytes) {
        const uint64_t directoryAt = format::kHeaderBytes + info_->materials.size() * format::kMaterialBytes +
                                     info_->topTree.size() * sizeof(KdNode);
        const uint64_t directoryBytes = info_->chunks.size() * format::kDirectoryEntryBytes;
        put(bytes, kDirectoryChecksumAt, checksum64(bytes.data() + directoryAt, directoryBytes));
        put(bytes, kHeaderChecksumAt, checksum64(bytes.data(), kHeaderChecksumAt));
    }

    static uint64_t entryAt(uint32_t chunk) {
        return format::kHeaderBytes + info_->materials.size() * format::kMaterialBytes +
               info_->topTree.size() * sizeof(KdNode) + uint64_t(chunk) * format::kDirectoryEntryBytes;
    }

    static std::string write(const std::vector<uint8_t>& bytes) {
        const std::string path = tempPath("forged-floats.vast");
        writeFile(path, bytes);
        return path;
    }

    static void expectRefused(std::vector<uint8_t> bytes, const std::string& expected) {
        reseal(bytes);
        auto reader = PackageReader::open(write(bytes));
        ASSERT_FALSE(reader.isOk()) << "accepted; expected '" << expected << "'";
        EXPECT_NE(reader.message().find(expected), std::string::npos) << reader.message();
        EXPECT_NE(reader.message().find("forged-floats.vast"), std::string::npos) << reader.message();
    }

    // A forged blob with its own, the directory's and the header's checksums recomputed: the
    // package opens, and verify names the chunk.
    static void expectChunkRefused(std::vector<uint8_t> bytes, uint32_t id, const std::string& expected) {
        const ChunkInfo& chunk = info_->chunks[id];
        put(bytes, entryAt(id) + kEntryChecksumAt, checksum64(bytes.data() + chunk.offset, chunk.size));
        reseal(bytes);
        auto reader = PackageReader::open(write(bytes));
        ASSERT_TRUE(reader.isOk()) << reader.message();
        const std::vector<std::string> problems = (*reader)->verify();
        ASSERT_EQ(problems.size(), 1u);
        EXPECT_NE(problems[0].find(expected), std::string::npos) << problems[0];
    }

    static PackageInfo* info_;
    static std::vector<uint8_t>* bytes_;
};
PackageInfo* ForgedFloats::info_ = nullptr;
std::vector<uint8_t>* ForgedFloats::bytes_ = nullptr;

TEST_F(ForgedFloats, ResealedPristinePackageStillOpens) {
    std::vector<uint8_t> bytes = *bytes_;
    reseal(bytes);
    auto reader = PackageReader::open(write(bytes));
    ASSERT_TRUE(reader.isOk()) << reader.message();
    EXPECT_TRUE((*reader)->verify().empty());
}

TEST_F(ForgedFloats, NanGridOriginIsRefused) {
    std::vector<uint8_t> bytes = *bytes_;
    put(bytes, kOriginAt + 8, std::numeric_limits<double>::quiet_NaN());
    expectRefused(bytes, "grid origin y nan is not a finite coordinate");
}

TEST_F(ForgedFloats, InfiniteGridOriginIsRefused) {
    std::vector<uint8_t> bytes = *bytes_;
    put(bytes, kOriginAt, -std::numeric_limits<double>::infinity());
    expectRefused(bytes, "grid origin x -inf is not a finite coordinate");
}

TEST_F(ForgedFloats, HugeGridRangeIsRefused) {
    std::vector<uint8_t> bytes = *bytes_;
    put(bytes, kRangeAt, 1e300);
    expectRefused(bytes, "grid range 1e+300 is outside (0, 2e18]");
}

TEST_F(ForgedFloats, InvertedSceneBoundsAreRefused) {
    std::vector<uint8_t> bytes = *bytes_;
    put(bytes, kBoundsLoAt + 4, info_->bounds.hi.y + 1.0f);
    expectRefused(bytes, "scene bounds are inverted on y");
}

TEST_F(ForgedFloats, NanAndInfiniteSceneBoundsAreRefused) {
    std::vector<uint8_t> bytes = *bytes_;
    put(bytes, kBoundsHiAt + 8, kNan);
    expectRefused(bytes, "scene bounds z nan is not finite");
    bytes = *bytes_;
    put(bytes, kBoundsLoAt, -kInf);
    expectRefused(bytes, "scene bounds x -inf is not finite");
}

TEST_F(ForgedFloats, NanCellBoundsAreRefusedWithTheChunk) {
    std::vector<uint8_t> bytes = *bytes_;
    put(bytes, entryAt(1) + kEntryCellAt + 4, kNan);
    expectRefused(bytes, "chunk 1: cell bounds y nan is not finite");
}

// The blob's own checksum, then the directory's and the header's, all recomputed: only the
// value check can tell.
TEST_F(ForgedFloats, NanChunkBvhBoundsFailVerifyWithTheChunk) {
    std::vector<uint8_t> bytes = *bytes_;
    put(bytes, info_->chunks[2].offset + kBlobBvhBoundsAt + 12, kNan);
    expectChunkRefused(bytes, 2, "chunk 2: BVH bounds x nan is not finite");
}

// Not floats, but the same forgery: a blob whose tree or leaf order is wrong, with every checksum
// recomputed, would make the kernel read outside the chunk or loop.
TEST_F(ForgedFloats, BvhChildPointingBackFailsVerifyWithTheNode) {
    std::vector<uint8_t> bytes = *bytes_;
    const ChunkInfo& chunk = info_->chunks[1];
    const uint64_t nodesAt = chunk.offset + chunk.size - uint64_t(chunk.triangleCount) * 4 -
                             uint64_t(chunk.bvhNodeCount) * sizeof(Bvh4Node);
    put(bytes, nodesAt + offsetof(Bvh4Node, child), uint32_t(0));  // the root's first child: the root
    expectChunkRefused(bytes, 1, "chunk 1: BVH node 0: child 0 is not a later node");
}

TEST_F(ForgedFloats, LeafOrderThatIsNotAPermutationFailsVerify) {
    std::vector<uint8_t> bytes = *bytes_;
    const ChunkInfo& chunk = info_->chunks[1];
    const uint64_t orderAt = chunk.offset + chunk.size - uint64_t(chunk.triangleCount) * 4;
    uint32_t first = 0;
    std::memcpy(&first, &bytes[orderAt], 4);
    put(bytes, orderAt + 4, first);  // entry 1 repeats entry 0
    expectChunkRefused(bytes, 1, "chunk 1: leaf order entry 1 is not a permutation");
}

TEST_F(ForgedFloats, OlderFormatVersionsAskForAReimport) {
    for (uint32_t version : {1u, 2u}) {
        std::vector<uint8_t> bytes = *bytes_;
        put(bytes, 8, version);
        expectRefused(bytes, "package format version " + std::to_string(version) +
                                 " is not supported (this vastray reads 3 to " + std::to_string(format::kVersion) + "): re-import the mesh");
    }
}

// Version 3 is version 4 without volumes: its header has zeros where version 4 keeps the volume
// records' offset and checksum (and the volume count), and versions 3 and 4 have no
// metallic-roughness factors in their materials. The seed corpus keeps version 3 packages (and a
// version 4 one): they still read, Lambertian; version 3 bytes that claim volumes do not.
TEST_F(ForgedFloats, VersionThreeWithoutVolumesStillReads) {
    constexpr size_t kVolumeCountAt = 8 + 4 + 4 + 7 * 8 + 4 + 4 + 3 * 4;
    std::vector<uint8_t> bytes = readFile(std::string(VASTRAY_FUZZ_CORPUS) + "/vast/small.vast");
    auto reader = PackageReader::open(write(bytes));
    ASSERT_TRUE(reader) << reader.message();
    EXPECT_EQ(reader.value()->info().formatVersion, 3u);
    EXPECT_TRUE(reader.value()->info().volumes.empty());
    EXPECT_TRUE(reader.value()->verify().empty());
    for (const Material& m : reader.value()->info().materials) {
        EXPECT_EQ(m.metallic, 0.0f);
        EXPECT_EQ(m.specular, 0.0f);
        EXPECT_EQ(m.roughness, 1.0f);
    }
    put(bytes, kVolumeCountAt, uint32_t(1));
    put(bytes, kHeaderChecksumAt, checksum64(bytes.data(), kHeaderChecksumAt));
    reader = PackageReader::open(write(bytes));
    ASSERT_FALSE(reader);
    EXPECT_NE(reader.message().find("a version 3 package with volume fields"), std::string::npos) << reader.message();
    bytes = *bytes_;
    put(bytes, kVolumeCountAt, uint32_t(65));
    expectRefused(bytes, "volume count 65 exceeds the limit of 64");
}

// A version 5 material's metallic-roughness factors are fractions; a forger who recomputes the
// materials' checksum still meets the range check.
TEST_F(ForgedFloats, MaterialFactorsOutsideTheUnitIntervalAreRefused) {
    constexpr size_t kMetallicAt = format::kHeaderBytes + 4 * 4 + 3 * 4 + 4;
    for (const auto& [at, value, expected] :
         {std::tuple{kMetallicAt, 2.0f, "material 0 (''): metallic 2 is outside [0, 1]"},
          std::tuple{kMetallicAt + 4, kNan, "material 0 (''): roughness nan is outside [0, 1]"},
          std::tuple{kMetallicAt + 8, -0.5f, "material 0 (''): specular -0.5 is outside [0, 1]"}}) {
        std::vector<uint8_t> bytes = *bytes_;
        put(bytes, at, value);
        const uint64_t materialsBytes = info_->materials.size() * format::kMaterialBytes;
        put(bytes, kMaterialsChecksumAt, checksum64(bytes.data() + format::kHeaderBytes, materialsBytes));
        expectRefused(bytes, expected);
    }
}

TEST(PackageReaderInputs, FifoIsRefusedWithoutBlocking) {
    const std::string path = tempPath("fifo.vast");
    std::filesystem::remove(path);
    ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
    auto reader = PackageReader::open(path);
    ASSERT_FALSE(reader.isOk());
    EXPECT_NE(reader.message().find("fifo.vast: is not a regular file"), std::string::npos) << reader.message();
    std::filesystem::remove(path);
}

}  // namespace
}  // namespace vastray::test
