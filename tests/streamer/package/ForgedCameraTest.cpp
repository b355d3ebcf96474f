// Issue 13 ("Real assets"): a package's camera section, forged. The checksum proves only that
// the bytes are the ones written: a forger who recomputes it can store a NaN eye, an eye on its
// target or a camera count no reader should allocate for. Each is refused with the file, the
// camera and the limit named; so is a camera section whose checksum was not recomputed.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>

#include "PackageTestUtil.h"
#include "HeaderOffsets.h"
#include "package/PackageFormat.h"
#include "vastray/core/Checksum.h"

namespace vastray::test {
namespace {

// In a camera: name, then eye, target, up (3 f32 each), fov.
constexpr size_t kEyeAt = format::kCameraNameBytes;
constexpr size_t kTargetAt = kEyeAt + 12;

class ForgedCameras : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        TriangleMesh mesh = generatedMesh(GeneratorKind::Soup, 500, 5);
        mesh.cameras = {{"Front", {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 40}},
                        {"Side", {{5, 0.5f, 0}, {0, 0.5f, 0}, {0, 1, 0}, 30}}};
        PackageBuildOptions options;
        auto reader = buildAndOpen(std::move(mesh), tempPath("cameras.vast"), options);
        ASSERT_TRUE(reader);
        ASSERT_EQ(reader->info().cameras.size(), 2u);
        bytes_ = new std::vector<uint8_t>(readFile(tempPath("cameras.vast")));
        std::memcpy(&camerasAt_, bytes_->data() + kCamerasOffsetAt, 8);
    }
    static void TearDownTestSuite() { delete bytes_; }

    template <typename T>
    static void put(std::vector<uint8_t>& bytes, size_t at, T value) {
        putAt(bytes, at, value);
    }
    static size_t cameraAt(uint32_t index) { return size_t(camerasAt_) + size_t(index) * format::kCameraBytes; }

    // Recomputes the cameras' checksum (when asked) and the header's, as a forger would.
    static void reseal(std::vector<uint8_t>& bytes, bool cameras) {
        if (cameras) put(bytes, kCamerasChecksumAt, checksum64(bytes.data() + camerasAt_, 2 * format::kCameraBytes));
        put(bytes, kHeaderChecksumAt, checksum64(bytes.data(), kHeaderChecksumAt));
    }

    static void expectRefused(std::vector<uint8_t> bytes, bool resealCameras, const std::string& expected) {
        reseal(bytes, resealCameras);
        expectOpenRefused(bytes, tempPath("forged-cameras.vast"), expected);
    }

    static std::vector<uint8_t>* bytes_;
    static uint64_t camerasAt_;
};
std::vector<uint8_t>* ForgedCameras::bytes_ = nullptr;
uint64_t ForgedCameras::camerasAt_ = 0;

TEST_F(ForgedCameras, ResealedPristinePackageStillOpens) {
    std::vector<uint8_t> bytes = *bytes_;
    reseal(bytes, true);
    const std::string path = tempPath("forged-cameras.vast");
    writeFile(path, bytes);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader.isOk()) << reader.message();
    ASSERT_EQ((*reader)->info().cameras.size(), 2u);
    EXPECT_EQ((*reader)->info().cameras[1].name, "Side");
    EXPECT_EQ((*reader)->info().cameras[1].camera.eye, (Vec3f{5, 0.5f, 0}));
}

TEST_F(ForgedCameras, NanEyeIsRefusedWithTheCamera) {
    std::vector<uint8_t> bytes = *bytes_;
    put(bytes, cameraAt(1) + kEyeAt + 4, std::numeric_limits<float>::quiet_NaN());
    expectRefused(bytes, true, "camera 1 'Side': camera eye is not finite");
}

TEST_F(ForgedCameras, EyeOnTheTargetIsRefusedWithTheCamera) {
    std::vector<uint8_t> bytes = *bytes_;
    std::memcpy(&bytes[cameraAt(0) + kTargetAt], &bytes[cameraAt(0) + kEyeAt], 12);
    expectRefused(bytes, true, "camera 0 'Front': camera eye equals target");
}

TEST_F(ForgedCameras, CountBeyondTheLimitIsRefusedBeforeAnyRead) {
    std::vector<uint8_t> bytes = *bytes_;
    put(bytes, kCameraCountAt, format::kMaxCameras + 1);
    expectRefused(bytes, true, "header: camera count 65537 exceeds the limit of 65536");
    put(bytes, kCameraCountAt, std::numeric_limits<uint32_t>::max());
    expectRefused(bytes, true, "header: camera count 4294967295 exceeds the limit of 65536");
}

TEST_F(ForgedCameras, CountThatDisagreesWithTheSectionsIsRefused) {
    std::vector<uint8_t> bytes = *bytes_;
    put(bytes, kCameraCountAt, uint32_t(3));
    expectRefused(bytes, true, "section offsets are inconsistent");
}

TEST_F(ForgedCameras, ChangedCameraWithoutItsChecksumIsRefused) {
    std::vector<uint8_t> bytes = *bytes_;
    bytes[cameraAt(1)] = 'T';  // "Side" -> "Tide"; the header still holds the old checksum
    expectRefused(bytes, false, "cameras checksum mismatch (stored 0x");  // then the value computed
}

// A forged name that is not UTF-8 (half a character, a lone continuation byte) opens with '?'
// for each bad byte: names go out as JSON and protobuf strings, which must be valid UTF-8.
TEST_F(ForgedCameras, NameThatIsNotUtf8OpensWithQuestionMarks) {
    std::vector<uint8_t> bytes = *bytes_;
    const char forged[] = "S\xE2\x82" "de\x80";  // "S", a 3-byte character cut short, "de", a continuation byte
    std::memcpy(&bytes[cameraAt(1)], forged, sizeof forged);  // with its NUL
    reseal(bytes, true);
    const std::string path = tempPath("forged-cameras.vast");
    writeFile(path, bytes);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader.isOk()) << reader.message();
    EXPECT_EQ((*reader)->info().cameras[1].name, "S??de?");
}

// A caller that bypasses the importers (which cut names and say so) still gets a name cut at a
// character boundary, never half a UTF-8 character: "€" is 3 bytes, 21 of them fill 63.
TEST(PackageCameras, WriterKeepsAtMost64BytesOfWholeCharacters) {
    TriangleMesh mesh = generatedMesh(GeneratorKind::Soup, 200, 7);
    std::string euros;
    for (int i = 0; i < 30; ++i) euros += "\xE2\x82\xAC";
    mesh.cameras = {{euros, {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 40}}, {std::string(64, 'a'), {{0, 0, 6}, {0, 0, 0}, {0, 1, 0}, 40}}};
    auto reader = buildAndOpen(std::move(mesh), tempPath("euro-cameras.vast"), PackageBuildOptions{});
    ASSERT_TRUE(reader);
    ASSERT_EQ(reader->info().cameras.size(), 2u);
    EXPECT_EQ(reader->info().cameras[0].name, euros.substr(0, 63));
    EXPECT_EQ(reader->info().cameras[1].name, std::string(64, 'a')) << "a name of exactly 64 bytes is kept whole";
}

}  // namespace
}  // namespace vastray::test
