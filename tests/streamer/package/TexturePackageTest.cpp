// Textures in the package (format 10, issue 13): a mesh's textures are decoded, mip-mapped and
// paged at import, and every page reads back equal to the pyramid built from the same image;
// materials keep their maps; a package without textures stores no table; a forged material, a
// forged head, a cut table or a flipped page is refused by name.
#include <cstring>
#include <filesystem>

#include "PackageTestUtil.h"
#include "package/PackageFormat.h"
#include "package/TextureSection.h"
#include "vastray/core/Checksum.h"
#include "vastray/core/ImageFile.h"

namespace vastray::test {
namespace {

std::vector<uint8_t> pattern(uint32_t w, uint32_t h) {
    std::vector<uint8_t> rgba(size_t(w) * h * 4);
    for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = uint8_t((i * 29 + (i / 4) % 7 * 40) & 0xFF);
    return rgba;
}

// A quad with UVs whose material reads `png` as its base colour (clamped, offset by a quarter)
// and as its metallic-roughness map (linear).
TriangleMesh texturedQuad(const std::string& png) {
    TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    Material m;
    m.name = "painted";
    m.textures.slots[uint32_t(TextureSlot::BaseColor)] = {0, khrTextureTransform(0.25f, 0, 0, 1, 1)};
    m.textures.slots[uint32_t(TextureSlot::MetallicRoughness)] = {1, kIdentityUvTransform};
    m.textures.slots[uint32_t(TextureSlot::ClearcoatRoughness)] = {1, khrTextureTransform(0, 0.5f, 0, 2, 2)};
    m.clearcoat = 1.0f;
    m.textures.occlusionStrength = 0.5f;
    mesh.materials = {m};
    const std::vector<uint8_t> bytes = readFile(png);
    mesh.textures.push_back({"albedo.png", ".png", bytes, TextureWrap::Clamp, TextureWrap::Mirror, TextureEncoding::Srgb});
    mesh.textures.push_back({"albedo.png as data", ".png", bytes, TextureWrap::Repeat, TextureWrap::Repeat,
                             TextureEncoding::Linear});
    return mesh;
}

class TexturePackage : public ::testing::Test {
protected:
    void SetUp() override {
        png_ = tempPath("albedo.png");
        ASSERT_TRUE(writeRgba8Png(png_, 300, 170, pattern(300, 170)));
    }
    std::string png_;
};

TEST_F(TexturePackage, EveryPageReadsBackAsTheImagesPyramidAndMaterialsKeepTheirMaps) {
    const std::string path = tempPath("textured.vast");
    auto reader = buildAndOpen(texturedQuad(png_), path, {});
    ASSERT_TRUE(reader);
    const PackageInfo& info = reader->info();
    EXPECT_EQ(info.formatVersion, format::kVersion);
    ASSERT_EQ(info.textures.size(), 2u);
    const Rgba8Image image{300, 170, pattern(300, 170)};
    std::vector<uint8_t> page(kTexturePageBytes);
    for (uint32_t t = 0; t < 2; ++t) {
        const PackageTexture& x = info.textures[t];
        auto pyramid = buildTexturePyramid(image, x.wrapS, x.wrapT, x.encoding);
        ASSERT_TRUE(pyramid);
        EXPECT_EQ(x.layout.width, 300u);
        EXPECT_EQ(x.layout.pageCount, pyramid->layout.pageCount);
        for (uint32_t p = 0; p < x.layout.pageCount; ++p) {
            ASSERT_TRUE(reader->readTexturePage(t, p, page.data()));
            ASSERT_EQ(0, std::memcmp(page.data(), pyramid->pages.data() + size_t(p) * kTexturePageBytes,
                                     kTexturePageBytes))
                << t << " " << p;
        }
    }
    EXPECT_EQ(info.textures[0].wrapS, TextureWrap::Clamp);
    EXPECT_EQ(info.textures[0].wrapT, TextureWrap::Mirror);
    EXPECT_EQ(info.textures[1].encoding, TextureEncoding::Linear);
    EXPECT_EQ(info.textures[0].name, "albedo.png");
    const Material& m = info.materials[0];
    EXPECT_EQ(m.textures.slots[uint32_t(TextureSlot::BaseColor)].texture, 0u);
    EXPECT_EQ(m.textures.slots[uint32_t(TextureSlot::BaseColor)].transform[2], 0.25f);
    EXPECT_EQ(m.textures.slots[uint32_t(TextureSlot::MetallicRoughness)].texture, 1u);
    EXPECT_EQ(m.textures.slots[uint32_t(TextureSlot::Normal)].texture, kNoTexture);
    EXPECT_EQ(m.textures.slots[uint32_t(TextureSlot::Clearcoat)].texture, kNoTexture);
    EXPECT_EQ(m.textures.slots[uint32_t(TextureSlot::ClearcoatRoughness)].texture, 1u);  // format 13
    EXPECT_EQ(m.textures.slots[uint32_t(TextureSlot::ClearcoatRoughness)].transform, khrTextureTransform(0, 0.5f, 0, 2, 2));
    EXPECT_EQ(m.textures.occlusionStrength, 0.5f);
    EXPECT_FALSE(reader->readTexturePage(2, 0, page.data()));
    EXPECT_FALSE(reader->readTexturePage(0, info.textures[0].layout.pageCount, page.data()));

    // The same import gives the same bytes.
    const std::string again = tempPath("textured-again.vast");
    ASSERT_TRUE(buildAndOpen(texturedQuad(png_), again, {}));
    EXPECT_EQ(readFile(path), readFile(again));
}

// The largest transform an importer accepts (an MTL -s 1e6 1e6 -o 1e6 1e6: v's offset becomes
// 1 - 1e6 - 1e6 in the stored v-down space) is one a reader accepts too.
TEST_F(TexturePackage, TheLargestImportableTransformRoundTrips) {
    TriangleMesh mesh = texturedQuad(png_);
    const float big = kMaxUvTransformValue;
    const UvTransform largest{big, 0, big, 0, big, 1.0f - big - big};
    mesh.materials[0].textures.slots[uint32_t(TextureSlot::BaseColor)].transform = largest;
    auto reader = buildAndOpen(std::move(mesh), tempPath("largest.vast"), {});
    ASSERT_TRUE(reader);
    EXPECT_EQ(reader->info().materials[0].textures.slots[uint32_t(TextureSlot::BaseColor)].transform, largest);
}

TEST_F(TexturePackage, APackageWithoutTexturesHasAnEmptyHeadAndNoTable) {
    TriangleMesh mesh = texturedQuad(png_);
    mesh.textures.clear();
    mesh.materials[0].textures = MaterialTextures{};
    auto reader = buildAndOpen(std::move(mesh), tempPath("plain.vast"), {});
    ASSERT_TRUE(reader);
    EXPECT_TRUE(reader->info().textures.empty());
    EXPECT_EQ(reader->info().textureDataBytes, 0u);
    EXPECT_EQ(reader->info().textureDataOffset, reader->info().fileBytes);
}

TEST_F(TexturePackage, AnUndecodableImageFailsTheImportNamingIt) {
    TriangleMesh mesh = texturedQuad(png_);
    mesh.textures[1].bytes.resize(mesh.textures[1].bytes.size() / 3);
    const std::string path = tempPath("broken.vast");
    auto report = buildPackage(std::move(mesh), path, {});
    ASSERT_FALSE(report);
    EXPECT_NE(report.message().find("albedo.png as data"), std::string::npos) << report.message();
    EXPECT_FALSE(std::filesystem::exists(path));
    EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
}

// Where the texture head lies: after the lights section, right before the first blob.
uint64_t textureHeadAt(const PackageInfo& info) { return info.chunks[0].offset - kTextureHeadBytes; }

TEST_F(TexturePackage, ForgedMaterialsHeadsTablesAndPagesAreRefusedByName) {
    const std::string path = tempPath("forge-source.vast");
    auto reader = buildAndOpen(texturedQuad(png_), path, {});
    ASSERT_TRUE(reader);
    const PackageInfo info = reader->info();
    const std::vector<uint8_t> good = readFile(path);
    auto refusedWith = [&](const std::vector<uint8_t>& bytes, const std::string& says) {
        const std::string forged = tempPath("forged.vast");
        writeFile(forged, bytes);
        auto opened = PackageReader::open(forged);
        ASSERT_FALSE(opened) << says;
        EXPECT_NE(opened.message().find(says), std::string::npos) << opened.message();
    };
    // A material naming a texture the package lacks (its checksum made right again).
    {
        std::vector<uint8_t> bytes = good;
        const size_t mapAt = format::kHeaderBytes + format::kMaterialBytesBefore10 + format::kMaterialMapBytes;
        const uint32_t nine = 9;
        std::memcpy(bytes.data() + mapAt, &nine, 4);
        const uint64_t sum = checksum64(bytes.data() + format::kHeaderBytes, format::kMaterialBytes);
        // The materials' checksum is the header's field after the four offsets (PACKAGE_FORMAT.md).
        const size_t checksumAt = 8 + 8 + 7 * 8 + 8 + 16 + 24 + 32 + 32;
        std::memcpy(bytes.data() + checksumAt, &sum, 8);
        const uint64_t headerSum = checksum64(bytes.data(), format::kHeaderBytes - 8);
        std::memcpy(bytes.data() + format::kHeaderBytes - 8, &headerSum, 8);
        refusedWith(bytes, "material 0 ('painted'): metallicRoughnessTexture names texture 9 of 2");
    }
    // A head whose count disagrees with the table (re-checksummed).
    {
        std::vector<uint8_t> bytes = good;
        const size_t at = textureHeadAt(info);
        auto head = parseTextureHead(bytes.data() + at, kTextureHeadBytes);
        ASSERT_TRUE(head) << head.message();
        TextureHead forged = *head;
        forged.count = 3;
        const std::vector<uint8_t> h = serializeTextureHead(forged);
        std::memcpy(bytes.data() + at, h.data(), h.size());
        refusedWith(bytes, "textures:");
    }
    // A flipped bit in the head, in the table.
    {
        std::vector<uint8_t> bytes = good;
        bytes[textureHeadAt(info) + 10] ^= 4;
        refusedWith(bytes, "the head's checksum does not match");
        bytes = good;
        bytes[bytes.size() - 20] ^= 4;
        refusedWith(bytes, "textures:");
    }
    // A page whose frame is flipped opens (pages are checked when read) and is refused when read.
    {
        std::vector<uint8_t> bytes = good;
        const TexturePageEntry& e = info.texturePages[2];
        bytes[info.textureDataOffset + e.offset + e.size / 2] ^= 1;
        const std::string forged = tempPath("flipped-page.vast");
        writeFile(forged, bytes);
        auto opened = PackageReader::open(forged);
        ASSERT_TRUE(opened) << opened.message();
        std::vector<uint8_t> page(kTexturePageBytes);
        Status s = (*opened)->readTexturePage(0, 2, page.data());
        ASSERT_FALSE(s);
        EXPECT_NE(s.message().find("texture 0 ('albedo.png') page 2: checksum does not match"), std::string::npos)
            << s.message();
        const std::vector<std::string> problems = (*opened)->verify();
        ASSERT_EQ(problems.size(), 1u);
        EXPECT_EQ(problems[0], s.message());
    }
}

}  // namespace
}  // namespace vastray::test
