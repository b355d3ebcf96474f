// KTX2 images of glTF textures (GltfTextures.cpp): KHR_texture_basisu's source and plain KTX2
// images are read like PNGs (data URIs of any media type included), a format not read here is
// warned by name and its map left out (or KHR_texture_basisu's fallback PNG used), a transfer
// function the map disagrees with is warned, a broken container fails the import naming the
// image and the field, and an imported KTX2 texture ends in the package page for page.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

#include "ImportTestFiles.h"
#include "Ktx2Writer.h"
#include "GltfTextureRead.h"
#include "import/GltfLoader.h"
#include "import/GltfTextures.h"
#include "package/TexturePages.h"
#include "streamer/package/PackageTestUtil.h"
#include "vastray/core/ImageFile.h"
#include "vastray/streamer/Import.h"

namespace vastray::test {
namespace {

using import::GltfTextures;

// A 3 x 2 RGBA8 KTX2 with every byte distinct; `transfer` 2 = sRGB, 1 = linear.
std::vector<uint8_t> rgbaKtx2(uint8_t transfer = 2, uint32_t vkFormat = 43) {
    Ktx2Spec s;
    s.vkFormat = vkFormat;
    s.width = 3;
    s.height = 2;
    s.transfer = transfer;
    for (int i = 0; i < 24; ++i) s.level.push_back(uint8_t(11 + 41 * i));
    return writeKtx2(s);
}

std::vector<uint8_t> bc1Ktx2() {
    Ktx2Spec s;
    s.vkFormat = 131;  // BC1_RGB_UNORM_BLOCK
    s.width = s.height = 4;
    s.level.assign(8, 0x55);
    return writeKtx2(s);
}

std::string dataUri(const std::string& mediaType, const std::vector<uint8_t>& bytes) {
    return "data:" + mediaType + ";base64," + base64(std::string(bytes.begin(), bytes.end()));
}

// A triangle with UVs whose materials, textures and images are the caller's.
std::string uvTexturedGltf(const std::string& materials, const std::string& rest) {
    GltfBuilder b;
    const int pos = b.addPositions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    std::string uv;
    for (float f : {0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 1.0f}) appendRaw(uv, f);
    const int uvs = b.addAccessor(uv, 5126, "VEC2", 3);
    return b.json(R"("meshes":[{"primitives":[{"attributes":{"POSITION":)" + std::to_string(pos) +
                  R"(,"TEXCOORD_0":)" + std::to_string(uvs) +
                  R"(},"material":0}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"materials":)" + materials + "," +
                  rest);
}

const char* kBaseColour = R"([{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}])";

TEST(GltfKtx2, BasisuExtensionAndPlainKtx2ImagesAreReadWithoutWarnings) {
    const std::vector<uint8_t> ktx2 = rgbaKtx2();
    const std::string images[] = {
        // KHR_texture_basisu without a fallback, the KTX2 in a data URI of its own media type
        R"("textures":[{"extensions":{"KHR_texture_basisu":{"source":0}}}],"extensionsUsed":["KHR_texture_basisu"],
           "images":[{"uri":")" + dataUri("image/ktx2", ktx2) + R"(","name":"albedo"}])",
        // a plain texture source that is a KTX2 (octet-stream, as tinygltf decodes it itself)
        R"("textures":[{"source":0}],"images":[{"uri":")" + dataUri("application/octet-stream", ktx2) +
            R"(","name":"albedo"}])"};
    for (const std::string& rest : images) {
        ImportReport report;
        auto textures = readTextures("ktx2.gltf", uvTexturedGltf(kBaseColour, rest), report);
        ASSERT_TRUE(textures) << textures.message();
        ASSERT_EQ(textures->textures.size(), 1u) << rest;
        const TextureSource& t = textures->textures[0];
        EXPECT_EQ(t.extension, ".ktx2");
        EXPECT_EQ(t.name, "image 0 ('albedo') of ktx2.gltf");
        EXPECT_EQ(t.encoding, TextureEncoding::Srgb);
        EXPECT_EQ(textures->materials[0].slots[uint32_t(TextureSlot::BaseColor)].texture, 0u);
        EXPECT_TRUE(report.warnings.empty()) << report.warnings[0];
        auto image = decodeRgba8Image(t.name, t.extension, t.bytes, 1000);
        ASSERT_TRUE(image) << image.message();
        EXPECT_EQ(image->texels[23], uint8_t(11 + 41 * 23));
    }
}

TEST(GltfKtx2, FormatsNotReadAreWarnedByNameOrGiveWayToTheFallback) {
    // KHR_texture_basisu's image is BC1 (not read); its texture's own source, a PNG, is used instead.
    const std::string fallback =
        R"("textures":[{"source":1,"extensions":{"KHR_texture_basisu":{"source":0}}}],"extensionsUsed":["KHR_texture_basisu"],
           "images":[{"uri":")" + dataUri("image/ktx2", bc1Ktx2()) + R"("},{"uri":"data:image/png;base64,)" +
        base64(tinyPng()) + R"("}])";
    ImportReport report;
    auto textures = readTextures("fallback.gltf", uvTexturedGltf(kBaseColour, fallback), report);
    ASSERT_TRUE(textures) << textures.message();
    ASSERT_EQ(textures->textures.size(), 1u);
    EXPECT_EQ(textures->textures[0].extension, ".png");
    EXPECT_EQ(textures->textures[0].name, "image 1 of fallback.gltf");
    EXPECT_TRUE(report.warnings.empty()) << report.warnings[0];

    // Without a fallback the map is left out, warned once with the format's name.
    const std::string alone = R"("textures":[{"extensions":{"KHR_texture_basisu":{"source":0}}}],
           "images":[{"uri":")" + dataUri("image/ktx2", bc1Ktx2()) + R"("}])";
    report = {};
    textures = readTextures("bc1.gltf", uvTexturedGltf(kBaseColour, alone), report);
    ASSERT_TRUE(textures) << textures.message();
    EXPECT_TRUE(textures->textures.empty());
    EXPECT_FALSE(textures->materials[0].any());
    ASSERT_EQ(report.warnings.size(), 1u);
    EXPECT_NE(report.warnings[0].find("1 texture maps with a KTX2 image in vkFormat 131 (a BC1-BC7 block format)"),
              std::string::npos)
        << report.warnings[0];
}

TEST(GltfKtx2, ATransferFunctionTheMapDisagreesWithIsWarnedAndTheMapsEncodingKept) {
    // A linear KTX2 as base colour (sRGB by glTF's rules) and an sRGB one as a normal map (linear).
    const std::string rest = R"("textures":[{"source":0},{"source":1}],"images":[{"uri":")" +
                             dataUri("image/ktx2", rgbaKtx2(1, 37)) + R"("},{"uri":")" +
                             dataUri("image/ktx2", rgbaKtx2(2, 43)) + R"("}])";
    ImportReport report;
    auto textures = readTextures(
        "mismatch.gltf",
        uvTexturedGltf(R"([{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}},"normalTexture":{"index":1}}])", rest),
        report);
    ASSERT_TRUE(textures) << textures.message();
    ASSERT_EQ(textures->textures.size(), 2u);
    EXPECT_EQ(textures->textures[0].encoding, TextureEncoding::Srgb);
    EXPECT_EQ(textures->textures[1].encoding, TextureEncoding::Linear);
    ASSERT_EQ(report.warnings.size(), 1u);
    EXPECT_NE(report.warnings[0].find("2 texture maps whose KTX2 image's transfer function is not the map's"),
              std::string::npos)
        << report.warnings[0];
}

TEST(GltfKtx2, ABrokenContainerFailsTheImportNamingTheImageAndTheField) {
    std::vector<uint8_t> ktx2 = rgbaKtx2();
    putU64(ktx2, ktx2at::kLevelLength, 99);
    const std::string rest =
        R"("textures":[{"source":0}],"images":[{"uri":")" + dataUri("image/ktx2", ktx2) + R"(","name":"x.ktx2"}])";
    ImportReport report;
    auto textures = readTextures("model.gltf", uvTexturedGltf(kBaseColour, rest), report);
    ASSERT_FALSE(textures);
    EXPECT_NE(textures.message().find("image 0 ('x.ktx2') of model.gltf: KTX2 level 0 byte length 99 at offset"),
              std::string::npos)
        << textures.message();
    // A KHR_texture_basisu source that names no image is refused by texture.
    const std::string noSource = R"("textures":[{"extensions":{"KHR_texture_basisu":{"source":"a"}}}],"images":[])";
    textures = readTextures("model.gltf", uvTexturedGltf(kBaseColour, noSource), report);
    ASSERT_FALSE(textures);
    EXPECT_NE(textures.message().find("texture 0 KHR_texture_basisu source is not an image index"), std::string::npos)
        << textures.message();
}

TEST(GltfKtx2, AnImportedKtx2TextureIsStoredPageForPageAsItsDecodedImage) {
    const std::vector<uint8_t> ktx2 = rgbaKtx2();
    const std::string rest = R"("textures":[{"extensions":{"KHR_texture_basisu":{"source":0}}}],
        "extensionsUsed":["KHR_texture_basisu"],"images":[{"uri":")" +
                             dataUri("image/ktx2", ktx2) + R"(","name":"albedo"}])";
    const std::string path = writeFile("ktx2-scene.gltf", uvTexturedGltf(kBaseColour, rest));
    auto imported = importMesh(path);
    ASSERT_TRUE(imported) << imported.message();
    EXPECT_TRUE(imported->report.warnings.empty()) << imported->report.warnings[0];
    ASSERT_EQ(imported->mesh.textures.size(), 1u);
    auto reader = buildAndOpen(std::move(imported->mesh), tempPath("ktx2-scene.vast"), {});
    ASSERT_TRUE(reader);
    const PackageInfo& info = reader->info();
    ASSERT_EQ(info.textures.size(), 1u);
    EXPECT_EQ(info.textures[0].name, "image 0 ('albedo') of ktx2-scene.gltf");
    EXPECT_EQ(info.textures[0].layout.width, 3u);
    EXPECT_EQ(info.textures[0].layout.height, 2u);
    EXPECT_EQ(info.materials[0].textures.slots[uint32_t(TextureSlot::BaseColor)].texture, 0u);
    auto image = decodeRgba8Image("ktx2", ".ktx2", ktx2, 1000);
    ASSERT_TRUE(image);
    auto pyramid = buildTexturePyramid(*image, TextureWrap::Repeat, TextureWrap::Repeat, TextureEncoding::Srgb);
    ASSERT_TRUE(pyramid);
    ASSERT_EQ(info.textures[0].layout.pageCount, pyramid->layout.pageCount);
    std::vector<uint8_t> page(kTexturePageBytes);
    for (uint32_t p = 0; p < pyramid->layout.pageCount; ++p) {
        ASSERT_TRUE(reader->readTexturePage(0, p, page.data()));
        EXPECT_EQ(0, std::memcmp(page.data(), pyramid->pages.data() + size_t(p) * kTexturePageBytes, kTexturePageBytes))
            << "page " << p;
    }
}

}  // namespace
}  // namespace vastray::test
