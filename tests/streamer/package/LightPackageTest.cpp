// Issue 13 ("Real assets"): a package's light section (format version 7). Lights round-trip
// exactly; a forged record (a forger who recomputes the section's checksum) is refused by light
// and field; so are a changed record whose checksum was not recomputed and a count beyond the
// limit.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>

#include "PackageTestUtil.h"
#include "HeaderOffsets.h"
#include "package/PackageFormat.h"
#include "vastray/core/Checksum.h"
#include "vastray/core/VecMath.h"

namespace vastray::test {
namespace {

// In a light record: name, type, colour (3 f32), intensity.
constexpr size_t kTypeAt = format::kLightNameBytes;
constexpr size_t kIntensityAt = kTypeAt + 4 + 12;

std::vector<PunctualLight> threeLights() {
    PunctualLight sun{"Sun", LightType::Directional, {1, 0.9f, 0.8f}, 2.5f};
    sun.direction = normalize(Vec3f{0.3f, -1, 0.2f});
    PunctualLight bulb{"Bulb", LightType::Point, {1, 1, 1}, 40.0f, 12.0f};
    bulb.position = {1, 2, 3};
    PunctualLight spot{"Spot", LightType::Spot, {0.5f, 1, 0.25f}, 100.0f, 0.0f, 0.2f, 0.6f, {0, 5, 0}, {0, -1, 0}};
    return {sun, bulb, spot};
}

class LightPackage : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        TriangleMesh mesh = generatedMesh(GeneratorKind::Soup, 500, 5);
        mesh.lights = threeLights();
        auto reader = buildAndOpen(std::move(mesh), tempPath("lights.vast"), PackageBuildOptions{});
        ASSERT_TRUE(reader);
        bytes_ = new std::vector<uint8_t>(readFile(tempPath("lights.vast")));
        std::memcpy(&lightsAt_, bytes_->data() + kVolumesOffsetAt, 8);  // no volumes: the lights follow
    }
    static void TearDownTestSuite() { delete bytes_; }

    static size_t lightAt(uint32_t index) { return size_t(lightsAt_) + size_t(index) * format::kLightBytes; }

    // Recomputes the lights' checksum (when asked) and the header's, as a forger would.
    static void reseal(std::vector<uint8_t>& bytes, bool lights) {
        if (lights) putAt(bytes, lightAt(3), checksum64(bytes.data() + lightsAt_, 3 * format::kLightBytes));
        putAt(bytes, kHeaderChecksumAt, checksum64(bytes.data(), kHeaderChecksumAt));
    }

    static void expectRefused(std::vector<uint8_t> bytes, bool resealLights, const std::string& expected) {
        reseal(bytes, resealLights);
        expectOpenRefused(bytes, tempPath("forged-lights.vast"), expected);
    }

    static std::vector<uint8_t>* bytes_;
    static uint64_t lightsAt_;
};
std::vector<uint8_t>* LightPackage::bytes_ = nullptr;
uint64_t LightPackage::lightsAt_ = 0;

TEST_F(LightPackage, LightsRoundTripExactly) {
    auto reader = PackageReader::open(tempPath("lights.vast"));
    ASSERT_TRUE(reader.isOk()) << reader.message();
    EXPECT_EQ((*reader)->info().formatVersion, format::kVersion);
    const std::vector<PunctualLight> expected = threeLights();
    const std::vector<PunctualLight>& read = (*reader)->info().lights;
    ASSERT_EQ(read.size(), expected.size());
    for (size_t i = 0; i < read.size(); ++i) {
        EXPECT_EQ(read[i].name, expected[i].name);
        EXPECT_EQ(read[i].type, expected[i].type);
        EXPECT_EQ(read[i].color, expected[i].color);
        EXPECT_EQ(read[i].intensity, expected[i].intensity);
        EXPECT_EQ(read[i].range, expected[i].range);
        EXPECT_EQ(read[i].innerConeAngle, expected[i].innerConeAngle);
        EXPECT_EQ(read[i].outerConeAngle, expected[i].outerConeAngle);
        EXPECT_EQ(read[i].position, expected[i].position);
        EXPECT_EQ(read[i].direction, expected[i].direction);
    }
}

TEST_F(LightPackage, ResealedPristinePackageStillOpens) {
    std::vector<uint8_t> bytes = *bytes_;
    reseal(bytes, true);
    const std::string path = tempPath("forged-lights.vast");
    writeFile(path, bytes);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader.isOk()) << reader.message();
    EXPECT_EQ((*reader)->info().lights.size(), 3u);
}

TEST_F(LightPackage, ForgedRecordsAreRefusedByLightAndField) {
    std::vector<uint8_t> bytes = *bytes_;
    putAt(bytes, lightAt(1) + kIntensityAt, std::numeric_limits<float>::quiet_NaN());
    expectRefused(bytes, true, "light 1 'Bulb': intensity nan is outside [0, 1e+09]");
    bytes = *bytes_;
    putAt(bytes, lightAt(2) + kTypeAt, uint32_t(7));
    expectRefused(bytes, true, "light 2 'Spot': type 7 is not directional, point or spot");
    bytes = *bytes_;
    putAt(bytes, lightAt(0) + kTypeAt + 4, 2.0f);  // the colour's red
    expectRefused(bytes, true, "light 0 'Sun': color component 2 is outside [0, 1]");
    bytes = *bytes_;
    putAt(bytes, lightAt(2) + format::kLightBytes - 4, uint32_t(1));  // a reserved word
    expectRefused(bytes, true, "light 2 'Spot': its reserved words are not 0");
}

TEST_F(LightPackage, ChangedLightWithoutItsChecksumIsRefused) {
    std::vector<uint8_t> bytes = *bytes_;
    bytes[lightAt(1)] = 'C';  // "Bulb" -> "Culb"
    expectRefused(bytes, false, "lights checksum mismatch (stored 0x");
}

TEST_F(LightPackage, CountBeyondTheLimitOrTheSectionsIsRefused) {
    std::vector<uint8_t> bytes = *bytes_;
    putAt(bytes, kLightCountAt, kMaxLights + 1);
    expectRefused(bytes, false, "header: light count 4097 exceeds the limit of 4096");
    putAt(bytes, kLightCountAt, uint32_t(4));
    expectRefused(bytes, false, "section offsets are inconsistent");
}

// Before version 7 the word after the camera count was reserved: an older package with it set
// is refused, not read as having lights.
TEST_F(LightPackage, OlderVersionWithALightCountIsRefused) {
    std::vector<uint8_t> bytes = *bytes_;
    putAt(bytes, 8, uint32_t(6));
    putAt(bytes, kLightCountAt, uint32_t(3));
    expectRefused(bytes, false, "header: the field after the camera count is not 0 (a version 6 package has no lights)");
}

}  // namespace
}  // namespace vastray::test
