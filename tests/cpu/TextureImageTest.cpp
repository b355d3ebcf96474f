// readRgba8Image / decodeRgba8Image (core/ImageFile.h): texture images from files and from
// memory (a glTF buffer), as 8-bit RGBA, with their limits.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "TestScenes.h"
#include "vastray/core/ImageFile.h"

namespace vastray {
namespace {

std::vector<uint8_t> fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<uint8_t> pattern(uint32_t w, uint32_t h) {
    std::vector<uint8_t> rgba(size_t(w) * h * 4);
    for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = uint8_t((i * 37 + i / 4) & 0xFF);
    return rgba;
}

TEST(TextureImage, PngTexelsComeBackExactlyFromTheFileAndFromMemory) {
    const std::string path = test::tmpPath("texture.png");
    const std::vector<uint8_t> rgba = pattern(5, 3);
    ASSERT_TRUE(writeRgba8Png(path, 5, 3, rgba));
    auto fromFile = readRgba8Image(path, 1000);
    ASSERT_TRUE(fromFile) << fromFile.message();
    EXPECT_EQ(fromFile->width, 5u);
    EXPECT_EQ(fromFile->height, 3u);
    EXPECT_EQ(fromFile->texels, rgba);  // unassociated alpha: the stored colours, exactly
    auto fromMemory = decodeRgba8Image("image 0 of scene.glb", ".png", fileBytes(path), 1000);
    ASSERT_TRUE(fromMemory) << fromMemory.message();
    EXPECT_EQ(fromMemory->texels, rgba);
}

TEST(TextureImage, GreyAndRgbImagesBecomeRgbaWithOpaqueAlpha) {
    const std::string path = test::tmpPath("grey.png");
    OIIO::ImageSpec spec(3, 2, 1, OIIO::TypeDesc::UINT8);
    const uint8_t grey[6] = {0, 50, 100, 150, 200, 250};
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, spec) && out->write_image(OIIO::TypeDesc::UINT8, grey) && out->close());
    auto image = readRgba8Image(path, 100);
    ASSERT_TRUE(image) << image.message();
    for (size_t i = 0; i < 6; ++i) {
        EXPECT_EQ(image->texels[i * 4], grey[i]);
        EXPECT_EQ(image->texels[i * 4 + 1], grey[i]);
        EXPECT_EQ(image->texels[i * 4 + 2], grey[i]);
        EXPECT_EQ(image->texels[i * 4 + 3], 255);
    }
}

TEST(TextureImage, JpegDecodesFromMemoryAsFromItsFile) {
    const std::string path = "/usr/share/assimp/models/OBJ/SpiderTex.jpg";  // Debian's assimp-testmodels
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent (assimp-testmodels not installed)";
    auto fromFile = readRgba8Image(path, uint64_t(1) << 26);
    ASSERT_TRUE(fromFile) << fromFile.message();
    auto fromMemory = decodeRgba8Image("SpiderTex.jpg in memory", ".jpg", fileBytes(path), uint64_t(1) << 26);
    ASSERT_TRUE(fromMemory) << fromMemory.message();
    EXPECT_GT(fromFile->width, 0u);
    EXPECT_EQ(fromMemory->width, fromFile->width);
    EXPECT_EQ(fromMemory->texels, fromFile->texels);
}

TEST(TextureImage, OversizedGarbageAndUnknownImagesAreRefusedByName) {
    const std::string path = test::tmpPath("big.png");
    ASSERT_TRUE(writeRgba8Png(path, 40, 30, pattern(40, 30)));
    auto big = readRgba8Image(path, 1000);
    ASSERT_FALSE(big);
    EXPECT_NE(big.message().find("40x30"), std::string::npos) << big.message();
    EXPECT_NE(big.message().find("1000"), std::string::npos) << big.message();
    auto bigInMemory = decodeRgba8Image("image 2 of a.glb", ".png", fileBytes(path), 1000);
    ASSERT_FALSE(bigInMemory);
    EXPECT_NE(bigInMemory.message().find("image 2 of a.glb"), std::string::npos) << bigInMemory.message();

    std::vector<uint8_t> garbage(200, 0x5A);
    auto bad = decodeRgba8Image("image 1 of a.glb", ".png", garbage, 1000);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.message().find("image 1 of a.glb"), std::string::npos) << bad.message();
    std::vector<uint8_t> truncated = fileBytes(path);
    truncated.resize(truncated.size() / 2);
    EXPECT_FALSE(decodeRgba8Image("cut.png", ".png", truncated, 1u << 20));
    EXPECT_FALSE(decodeRgba8Image("x.qqq", ".qqq", garbage, 1000));
    EXPECT_FALSE(decodeRgba8Image("empty.png", ".png", {}, 1000));
    EXPECT_FALSE(readRgba8Image(test::tmpPath("missing.png"), 1000));
}

}  // namespace
}  // namespace vastray
