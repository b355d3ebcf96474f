// Issue 13 ("Real assets"): a package's emitter section (format version 12): the emissive
// triangles next-event estimation samples, at the positions the chunks decode. A forged section
// (a forger who recomputes its checksum) is refused by emitter and field; so are a changed record
// whose checksum was not recomputed, a count beyond the limit and a nonzero reserved word. A
// scene with more emitters than the build's limit stores none and says so.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <set>

#include "../../VolumePackageForge.h"
#include "PackageTestUtil.h"
#include "HeaderOffsets.h"
#include "package/PackageFormat.h"
#include "vastray/core/Checksum.h"

namespace vastray::test {
namespace {


// A generated soup (material 0, grey) with every seventh triangle given material 1, a lamp, and
// every eleventh material 2, grey too.
TriangleMesh soupWithLamps() {
    TriangleMesh mesh = generatedMesh(GeneratorKind::Soup, 700, 3);
    Material lamp{"lamp"};
    lamp.emissive = {4, 3, 2};
    mesh.materials = {Material{"grey"}, lamp, Material{"grey too"}};
    mesh.materialIds.assign(mesh.triangleCount(), 0);
    for (size_t t = 0; t < mesh.triangleCount(); ++t) mesh.materialIds[t] = t % 7 == 0 ? 1 : t % 11 == 0 ? 2 : 0;
    return mesh;
}

class EmitterPackage : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        auto reader = buildAndOpen(soupWithLamps(), tempPath("emitters.vast"), PackageBuildOptions{});
        ASSERT_TRUE(reader);
        count_ = uint32_t(reader->info().emitters.size());
        bytes_ = new std::vector<uint8_t>(readFile(tempPath("emitters.vast")));
        uint64_t volumesAt = 0;
        std::memcpy(&volumesAt, bytes_->data() + kVolumesOffsetAt, 8);
        emittersAt_ = volumesAt + 8;  // no volumes, no lights: the lights' checksum, then the emitters
    }
    static void TearDownTestSuite() { delete bytes_; }

    static size_t recordAt(uint32_t index) {
        return size_t(emittersAt_ + format::kEmittersHeadBytes) + size_t(index) * format::emitterBytes(format::kVersion);
    }
    static void reseal(std::vector<uint8_t>& bytes, bool emitters) {
        const uint64_t covered = format::kEmittersHeadBytes + uint64_t(count_) * format::emitterBytes(format::kVersion);
        if (emitters) putAt(bytes, size_t(emittersAt_ + covered), checksum64(bytes.data() + emittersAt_, covered));
        putAt(bytes, kHeaderChecksumAt, checksum64(bytes.data(), kHeaderChecksumAt));
    }
    static void expectRefused(std::vector<uint8_t> bytes, bool resealEmitters, const std::string& expected) {
        reseal(bytes, resealEmitters);
        expectOpenRefused(bytes, tempPath("forged-emitters.vast"), expected);
    }

    static std::vector<uint8_t>* bytes_;
    static uint64_t emittersAt_;
    static uint32_t count_;
};
std::vector<uint8_t>* EmitterPackage::bytes_ = nullptr;
uint64_t EmitterPackage::emittersAt_ = 0;
uint32_t EmitterPackage::count_ = 0;

TEST_F(EmitterPackage, EmittersAreTheLampTrianglesAsTheChunksDecodeThem) {
    auto reader = PackageReader::open(tempPath("emitters.vast"));
    ASSERT_TRUE(reader.isOk()) << reader.message();
    EXPECT_EQ((*reader)->info().formatVersion, format::kVersion);
    const std::vector<EmissiveTriangle>& emitters = (*reader)->info().emitters;
    ASSERT_EQ(emitters.size(), 100u) << "every seventh of 700 triangles";
    // The lamp triangles of the decoded chunks (once each), corners as decoded (quantized).
    std::set<std::array<float, 9>> decoded, stored;
    auto key = [](Vec3f a, Vec3f b, Vec3f c) {
        const std::array<Vec3f, 3> v = canonicalCorners(a, b, c);
        return std::array<float, 9>{v[0].x, v[0].y, v[0].z, v[1].x, v[1].y, v[1].z, v[2].x, v[2].y, v[2].z};
    };
    for (const ChunkInfo& info : (*reader)->info().chunks) {
        auto chunk = (*reader)->readChunk(info.id);
        ASSERT_TRUE(chunk) << chunk.message();
        for (size_t t = 0; t < chunk->primitiveIds.size(); ++t)
            if (chunk->materialIds[t] == 1)
                decoded.insert(key(chunk->positions[chunk->indices[3 * t]], chunk->positions[chunk->indices[3 * t + 1]],
                                   chunk->positions[chunk->indices[3 * t + 2]]));
    }
    for (const EmissiveTriangle& e : emitters) {
        EXPECT_EQ(e.material, 1u);
        stored.insert(key(e.v0, e.v1, e.v2));
    }
    EXPECT_EQ(stored, decoded);
}

TEST_F(EmitterPackage, ResealedPristinePackageStillOpens) {
    std::vector<uint8_t> bytes = *bytes_;
    reseal(bytes, true);
    const std::string path = tempPath("forged-emitters.vast");
    writeFile(path, bytes);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader.isOk()) << reader.message();
    EXPECT_EQ((*reader)->info().emitters.size(), count_);
}

TEST_F(EmitterPackage, ForgedRecordsAreRefusedByEmitterAndField) {
    std::vector<uint8_t> bytes = *bytes_;
    putAt(bytes, recordAt(3) + 4, std::numeric_limits<float>::quiet_NaN());  // v0.y
    expectRefused(bytes, true, "emitter 3: corner coordinate nan is not within +-");
    bytes = *bytes_;
    putAt(bytes, recordAt(5) + 36, uint32_t(9));
    expectRefused(bytes, true, "emitter 5: material 9 of 3");
    bytes = *bytes_;
    putAt(bytes, recordAt(2) + 40 + 12, std::numeric_limits<float>::infinity());  // t1.v (format 15)
    expectRefused(bytes, true, "emitter 2: corner UV inf is not within +-");
    bytes = *bytes_;
    putAt(bytes, recordAt(0) + 36, uint32_t(2));
    expectRefused(bytes, true, "emitter 0: material 2 ('grey too') is not an emitter next-event estimation samples");
    bytes = *bytes_;
    putAt(bytes, size_t(emittersAt_ + 4), uint32_t(1));
    expectRefused(bytes, true, "emitters: the word after the count is not 0");
}

TEST_F(EmitterPackage, ChangedRecordWithoutItsChecksumIsRefused) {
    std::vector<uint8_t> bytes = *bytes_;
    putAt(bytes, recordAt(1), 1.5f);
    expectRefused(bytes, false, "emitters checksum mismatch (stored 0x");
}

TEST_F(EmitterPackage, CountBeyondTheLimitOrTheSectionsIsRefused) {
    std::vector<uint8_t> bytes = *bytes_;
    putAt(bytes, size_t(emittersAt_), kMaxEmitters + 1);
    expectRefused(bytes, false, "section offsets are inconsistent");
    putAt(bytes, size_t(emittersAt_), count_ + 1);
    expectRefused(bytes, false, "section offsets are inconsistent");
}

// A version 11 package (no emitter section) still opens: its emitters are found by chance only.
TEST(EmitterPackageBuild, VersionElevenPackageOpensWithoutEmitters) {
    TriangleMesh mesh = soupWithLamps();
    const std::string path = tempPath("no-section.vast");
    PackageBuildOptions options;
    options.maxEmitters = 0;  // an empty section, which a version 11 package lacks
    ASSERT_TRUE(buildAndOpen(std::move(mesh), path, options));
    writeFile(tempPath("version11.vast"), withoutEmitterSection(withoutCoatMaps(readFile(path))));
    auto reader = PackageReader::open(tempPath("version11.vast"));
    ASSERT_TRUE(reader) << reader.message();
    EXPECT_EQ((*reader)->info().formatVersion, 11u);
    EXPECT_TRUE((*reader)->info().emitters.empty());
    EXPECT_TRUE((*reader)->verify().empty());
}

TEST(EmitterPackageBuild, MoreEmittersThanTheLimitStoresNoneAndWarns) {
    PackageBuildOptions options;
    options.maxEmitters = 99;
    options.progress = Progress::Mode::None;
    auto report = buildPackage(soupWithLamps(), tempPath("too-many-emitters.vast"), options);
    ASSERT_TRUE(report) << report.message();
    EXPECT_EQ(report->emitters, 0u);
    EXPECT_EQ(report->emittersLeftOut, 100u);
    ASSERT_EQ(report->warnings.size(), 1u);
    EXPECT_NE(report->warnings[0].find("100 emissive triangles are more than the 99"), std::string::npos)
        << report->warnings[0];
    auto reader = PackageReader::open(tempPath("too-many-emitters.vast"));
    ASSERT_TRUE(reader) << reader.message();
    EXPECT_TRUE((*reader)->info().emitters.empty());
    options.maxEmitters = 100;
    report = buildPackage(soupWithLamps(), tempPath("enough-emitters.vast"), options);
    ASSERT_TRUE(report) << report.message();
    EXPECT_EQ(report->emitters, 100u);
    EXPECT_TRUE(report->warnings.empty());
}

}  // namespace
}  // namespace vastray::test
