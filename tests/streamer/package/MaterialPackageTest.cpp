// Issue 13 ("Real assets"): a package's material records (format version 8 adds
// KHR_materials_specular's colour factor and KHR_materials_clearcoat's factors, 11 the alpha
// cut-out's cutoff). Materials round-trip exactly; a forged record (a
// forger who recomputes the materials' checksum) is refused naming the material and the field;
// packages of older versions still read, their specular colour glTF's default, white.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <tuple>

#include "PackageTestUtil.h"
#include "VolumePackageForge.h"
#include "HeaderOffsets.h"
#include "package/PackageFormat.h"
#include "vastray/core/Checksum.h"

namespace vastray::test {
namespace {

// In a version 8 record: the specular colour after the name, the coat and its roughness, then
// three reserved words.
constexpr size_t kSpecularColorAt = format::kMaterialBytesBefore8;
constexpr size_t kClearcoatAt = kSpecularColorAt + 12;
constexpr size_t kReservedAt = kClearcoatAt + 8;
// The cutoff (version 11): after the colours, the double-sided word and the three factors.
constexpr size_t kAlphaCutoffAt = 4 * 4 + 3 * 4 + 4 + 3 * 4;

std::vector<Material> threeMaterials() {
    Material plastic{"Plastic", {0.2f, 0.4f, 0.8f, 1}, {0, 0, 0}, 0.0f, 0.3f, 1.0f, {0.5f, 1.0f, 2.0f}, 0.0f, 0.0f, true};
    Material colourless{"Colourless", {0.8f, 0.8f, 0.8f, 1}, {0, 0, 0}, 0.0f, 0.6f, 0.5f, {0, 0, 0}, 1.0f, 0.125f, false};
    Material saturated{"Saturated", {1, 1, 1, 1}, {1, 2, 3}, 0.25f, 1.0f, 1.0f, {25, 1000, 0.125f}, 0.5f, 1.0f, true};
    saturated.alphaCutoff = 0.375f;
    plastic.alphaBlend = true;
    colourless.ior = 2.25f, saturated.ior = 0.0f;  // KHR_materials_ior (version 13)
    return {plastic, colourless, saturated};
}

class MaterialPackage : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        TriangleMesh mesh = generatedMesh(GeneratorKind::Soup, 500, 5);
        mesh.materials = threeMaterials();
        mesh.materialIds.resize(mesh.triangleCount());
        for (size_t t = 0; t < mesh.materialIds.size(); ++t) mesh.materialIds[t] = uint32_t(t % 3);
        auto reader = buildAndOpen(std::move(mesh), tempPath("materials.vast"), PackageBuildOptions{});
        ASSERT_TRUE(reader);
        bytes_ = new std::vector<uint8_t>(readFile(tempPath("materials.vast")));
    }
    static void TearDownTestSuite() { delete bytes_; }

    static size_t recordAt(uint32_t index) { return format::kHeaderBytes + size_t(index) * format::kMaterialBytes; }

    // Recomputes the materials' and the header's checksums, as a forger would.
    static void reseal(std::vector<uint8_t>& bytes) {
        putAt(bytes, kMaterialsChecksumAt, checksum64(bytes.data() + format::kHeaderBytes, 3 * format::kMaterialBytes));
        putAt(bytes, kHeaderChecksumAt, checksum64(bytes.data(), kHeaderChecksumAt));
    }
    static void expectRefused(std::vector<uint8_t> bytes, const std::string& expected) {
        reseal(bytes);
        expectOpenRefused(bytes, tempPath("forged-materials.vast"), expected);
    }

    static std::vector<uint8_t>* bytes_;
};
std::vector<uint8_t>* MaterialPackage::bytes_ = nullptr;

TEST_F(MaterialPackage, MaterialsRoundTripExactly) {
    auto reader = PackageReader::open(tempPath("materials.vast"));
    ASSERT_TRUE(reader.isOk()) << reader.message();
    EXPECT_EQ((*reader)->info().formatVersion, format::kVersion);
    const std::vector<Material> expected = threeMaterials();
    const std::vector<Material>& read = (*reader)->info().materials;
    ASSERT_EQ(read.size(), expected.size());
    for (size_t i = 0; i < read.size(); ++i) {
        EXPECT_EQ(read[i].name, expected[i].name);
        EXPECT_EQ(read[i].baseColor, expected[i].baseColor);
        EXPECT_EQ(read[i].emissive, expected[i].emissive);
        EXPECT_EQ(read[i].metallic, expected[i].metallic);
        EXPECT_EQ(read[i].roughness, expected[i].roughness);
        EXPECT_EQ(read[i].specular, expected[i].specular);
        EXPECT_EQ(read[i].specularColor, expected[i].specularColor);
        EXPECT_EQ(read[i].clearcoat, expected[i].clearcoat);
        EXPECT_EQ(read[i].clearcoatRoughness, expected[i].clearcoatRoughness);
        EXPECT_EQ(read[i].doubleSided, expected[i].doubleSided);
        EXPECT_EQ(read[i].alphaCutoff, expected[i].alphaCutoff);
        EXPECT_EQ(read[i].alphaBlend, expected[i].alphaBlend);
        EXPECT_EQ(read[i].ior, expected[i].ior);
    }
}

TEST_F(MaterialPackage, ForgedFactorsAreRefusedByMaterial) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (const auto& [material, channel, value, expected] :
         {std::tuple{1u, 0u, nan, "material 1 ('Colourless'): specular colour (nan, 0, 0) is outside [0, 1000]"},
          std::tuple{0u, 2u, -1.0f, "material 0 ('Plastic'): specular colour (0.5, 1, -1) is outside [0, 1000]"},
          std::tuple{2u, 1u, 1001.0f, "material 2 ('Saturated'): specular colour (25, 1001, 0.125) is outside [0, 1000]"},
          std::tuple{2u, 0u, std::numeric_limits<float>::infinity(),
                     "material 2 ('Saturated'): specular colour (inf, 1000, 0.125) is outside [0, 1000]"}}) {
        std::vector<uint8_t> bytes = *bytes_;
        putAt(bytes, recordAt(material) + kSpecularColorAt + 4 * channel, value);
        expectRefused(bytes, expected);
    }
    for (const auto& [material, field, value, expected] :
         {std::tuple{0u, 0u, 1.5f, "material 0 ('Plastic'): clearcoat 1.5 is outside [0, 1]"},
          std::tuple{1u, 1u, nan, "material 1 ('Colourless'): clearcoat roughness nan is outside [0, 1]"},
          std::tuple{2u, 0u, -0.25f, "material 2 ('Saturated'): clearcoat -0.25 is outside [0, 1]"}}) {
        std::vector<uint8_t> bytes = *bytes_;
        putAt(bytes, recordAt(material) + kClearcoatAt + 4 * field, value);
        expectRefused(bytes, expected);
    }
    for (const auto& [material, value, expected] :
         {std::tuple{0u, 1.5f, "material 0 ('Plastic'): alpha cutoff 1.5 is outside [0, 1]"},
          std::tuple{2u, nan, "material 2 ('Saturated'): alpha cutoff nan is outside [0, 1]"}}) {
        std::vector<uint8_t> bytes = *bytes_;
        putAt(bytes, recordAt(material) + kAlphaCutoffAt, value);
        expectRefused(bytes, expected);
    }
    // Version 12: the first word after the coat holds flags (bit 0: alpha blending); 13: the
    // second the ior; the third stays reserved.
    for (const auto& [value, expected] :
         {std::pair{0.5f, "material 1 ('Colourless'): ior 0.5 is neither 0 nor in [1, 1000]"},
          std::pair{nan, "material 1 ('Colourless'): ior nan is neither 0 nor in [1, 1000]"},
          std::pair{1001.0f, "material 1 ('Colourless'): ior 1001 is neither 0 nor in [1, 1000]"}}) {
        std::vector<uint8_t> bytes = *bytes_;
        putAt(bytes, recordAt(1) + kReservedAt + 4, value);
        expectRefused(bytes, expected);
    }
    {
        std::vector<uint8_t> bytes = *bytes_;
        putAt(bytes, recordAt(1) + kReservedAt + 8, uint32_t(1));
        expectRefused(bytes, "material 1 ('Colourless') has a non-zero reserved field");
    }
    std::vector<uint8_t> bytes = *bytes_;
    putAt(bytes, recordAt(1) + kReservedAt, uint32_t(2));
    expectRefused(bytes, "material 1 ('Colourless') has unknown flags 2");
}

// The blend flag round-trips (and a forger's flag on an opaque material is read as set).
TEST_F(MaterialPackage, AlphaBlendFlagIsReadFromTheFlagsWord) {
    std::vector<uint8_t> bytes = *bytes_;
    putAt(bytes, recordAt(1) + kReservedAt, uint32_t(format::kMaterialAlphaBlend));
    reseal(bytes);
    const std::string path = tempPath("forged-materials.vast");
    writeFile(path, bytes);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    EXPECT_TRUE((*reader)->info().materials[1].alphaBlend);
    EXPECT_FALSE((*reader)->info().materials[2].alphaBlend);
}

// A changed record without a recomputed checksum is refused before its fields are read.
TEST_F(MaterialPackage, ChangedRecordWithoutItsChecksumIsRefused) {
    std::vector<uint8_t> bytes = *bytes_;
    putAt(bytes, recordAt(0) + kSpecularColorAt, 0.75f);
    expectOpenRefused(bytes, tempPath("forged-materials.vast"), "materials checksum mismatch");
}

// A version 12 package (five maps a material, no coat maps, no ior) still reads, its coats
// unmapped and its ior glTF's default.
TEST_F(MaterialPackage, VersionTwelvePackageReadsWithItsCoatsUnmapped) {
    writeFile(tempPath("version12.vast"), withoutCoatMaps(*bytes_));
    auto reader = PackageReader::open(tempPath("version12.vast"));
    ASSERT_TRUE(reader) << reader.message();
    EXPECT_EQ((*reader)->info().formatVersion, 12u);
    EXPECT_TRUE((*reader)->verify().empty());
    const std::vector<Material> expected = threeMaterials();
    ASSERT_EQ((*reader)->info().materials.size(), expected.size());
    for (size_t i = 0; i < expected.size(); ++i) {
        const Material& m = (*reader)->info().materials[i];
        EXPECT_EQ(m.clearcoat, expected[i].clearcoat) << m.name;
        EXPECT_EQ(m.clearcoatRoughness, expected[i].clearcoatRoughness) << m.name;
        EXPECT_EQ(m.alphaBlend, expected[i].alphaBlend) << m.name;
        EXPECT_EQ(m.ior, 1.5f) << m.name;  // the word was reserved (zero) before version 13
        EXPECT_FALSE(m.textures.any()) << m.name;
    }
}

// The seed corpus keeps packages of versions 5 (glossy: metallic-roughness materials) and 7
// (lights): they still read, with glTF's default specular colour and no coat.
TEST(MaterialPackageVersions, OlderPackagesReadWithAWhiteSpecularColour) {
    for (const auto& [seed, version] : {std::pair{"glossy.vast", 5u}, std::pair{"lights.vast", 7u}, std::pair{"small.vast", 3u}}) {
        auto reader = PackageReader::open(std::string(VASTRAY_FUZZ_CORPUS) + "/vast/" + seed);
        ASSERT_TRUE(reader.isOk()) << seed << ": " << reader.message();
        EXPECT_EQ((*reader)->info().formatVersion, version) << seed;
        EXPECT_TRUE((*reader)->verify().empty()) << seed;
        for (const Material& m : (*reader)->info().materials)
            EXPECT_EQ(m.specularColor, (std::array<float, 3>{1, 1, 1})) << seed << " " << m.name;
        for (const Material& m : (*reader)->info().materials) EXPECT_EQ(m.clearcoat, 0.0f) << seed << " " << m.name;
        for (const Material& m : (*reader)->info().materials) EXPECT_EQ(m.alphaCutoff, 0.0f) << seed << " " << m.name;
    }
}

}  // namespace
}  // namespace vastray::test
