// KTX2 texture images (core/src/image/Ktx2*.cpp through decodeRgba8Image(".ktx2") and
// describeKtx2Image, vastray/core/ImageFile.h): uncompressed 8-bit formats stored as they are or
// Zstandard-supercompressed, Basis Universal UASTC, the swizzle and orientation keys, and hostile
// containers refused naming the image and the field.
#include <gtest/gtest.h>

#include <array>
#include <functional>

#include "Ktx2Writer.h"
#include "vastray/core/ImageFile.h"
#include "vastray/core/Texture.h"

namespace vastray::test {
namespace {

constexpr const char* kName = "image 2 ('x.ktx2') of model.gltf";
constexpr uint64_t kMaxPixels = uint64_t(kMaxTextureSide) * kMaxTextureSide;

// A 3 x 2 image whose every byte differs, `channels` bytes a texel.
std::vector<uint8_t> distinctTexels(uint32_t channels) {
    std::vector<uint8_t> t(3 * 2 * channels);
    for (size_t i = 0; i < t.size(); ++i) t[i] = uint8_t(17 + 37 * i);
    return t;
}

Ktx2Spec spec(uint32_t vkFormat, uint32_t channels) {
    Ktx2Spec s;
    s.vkFormat = vkFormat;
    s.width = 3;
    s.height = 2;
    s.level = distinctTexels(channels);
    return s;
}

Result<Rgba8Image> decode(const std::vector<uint8_t>& bytes) { return decodeRgba8Image(kName, ".ktx2", bytes, kMaxPixels); }

// The RGBA texel (x, y) of an image.
std::array<uint8_t, 4> texel(const Rgba8Image& image, uint32_t x, uint32_t y) {
    const uint8_t* t = image.texels.data() + (size_t(y) * image.width + x) * 4;
    return {t[0], t[1], t[2], t[3]};
}

TEST(Ktx2Image, Rgba8IsReadTexelForTexelStoredOrZstandardSupercompressed) {
    const std::vector<uint8_t> expected = distinctTexels(4);
    Ktx2Spec stored = spec(43, 4);
    Ktx2Spec zstd = stored;
    zstd.supercompression = 2;
    zstd.level = zstdFrame(expected);
    zstd.uncompressedLength = expected.size();
    for (const Ktx2Spec& s : {stored, zstd}) {
        auto image = decode(writeKtx2(s));
        ASSERT_TRUE(image) << image.message();
        EXPECT_EQ(image->width, 3u);
        EXPECT_EQ(image->height, 2u);
        EXPECT_EQ(image->texels, expected) << "supercompression " << s.supercompression;
    }
}

TEST(Ktx2Image, FewerChannelsReadAsVulkanSamplesThem) {
    // R8: (r, 0, 0, 255); R8G8: (r, g, 0, 255); R8G8B8: (r, g, b, 255), as a Vulkan image view
    // with the identity swizzle returns them.
    const struct {
        uint32_t vkFormat, channels;
    } formats[] = {{9, 1}, {15, 1}, {16, 2}, {23, 3}, {29, 3}};
    for (const auto& f : formats) {
        const std::vector<uint8_t> stored = distinctTexels(f.channels);
        auto image = decode(writeKtx2(spec(f.vkFormat, f.channels)));
        ASSERT_TRUE(image) << image.message();
        for (uint32_t i = 0; i < 6; ++i) {
            const auto t = texel(*image, i % 3, i / 3);
            const uint8_t* s = stored.data() + i * f.channels;
            EXPECT_EQ(t[0], s[0]) << "vkFormat " << f.vkFormat;
            EXPECT_EQ(t[1], f.channels > 1 ? s[1] : 0) << "vkFormat " << f.vkFormat;
            EXPECT_EQ(t[2], f.channels > 2 ? s[2] : 0) << "vkFormat " << f.vkFormat;
            EXPECT_EQ(t[3], 255) << "vkFormat " << f.vkFormat;
        }
    }
}

TEST(Ktx2Image, SwizzleAndOrientationKeysAreApplied) {
    // A grey image stored as R8 carries KTXswizzle "rrr1"; "ru" stores the bottom row first.
    Ktx2Spec s = spec(9, 1);
    s.keyValues = {{"KTXorientation", "ru"}, {"KTXswizzle", "rrr1"}};
    auto image = decode(writeKtx2(s));
    ASSERT_TRUE(image) << image.message();
    const std::vector<uint8_t> stored = distinctTexels(1);
    for (uint32_t y = 0; y < 2; ++y)
        for (uint32_t x = 0; x < 3; ++x) {
            const uint8_t grey = stored[(1 - y) * 3 + x];
            EXPECT_EQ(texel(*image, x, y), (std::array<uint8_t, 4>{grey, grey, grey, 255})) << x << "," << y;
        }
    s.keyValues = {{"KTXswizzle", "bgra"}};
    s.vkFormat = 37;
    s.level = distinctTexels(4);
    image = decode(writeKtx2(s));
    ASSERT_TRUE(image) << image.message();
    EXPECT_EQ(texel(*image, 0, 0), (std::array<uint8_t, 4>{s.level[2], s.level[1], s.level[0], s.level[3]}));
}

TEST(Ktx2Image, TexelsAreKeptWhateverTheTransferFunctionAndDescribedWithIt) {
    // sRGB or linear, the bytes come back as stored: the map's slot decides how they are read.
    Ktx2Spec srgb = spec(43, 4), linear = spec(37, 4);
    linear.transfer = 1;
    auto a = decode(writeKtx2(srgb)), b = decode(writeKtx2(linear));
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->texels, b->texels);
    auto d = describeKtx2Image(kName, writeKtx2(srgb));
    ASSERT_TRUE(d) << d.message();
    EXPECT_TRUE(d->readable);
    EXPECT_TRUE(d->srgb);
    EXPECT_EQ(d->format, "R8G8B8A8_SRGB");
    d = describeKtx2Image(kName, writeKtx2(linear));
    ASSERT_TRUE(d) << d.message();
    EXPECT_FALSE(d->srgb);
    EXPECT_EQ(d->format, "R8G8B8A8_UNORM");
}

TEST(Ktx2Image, FormatsNotReadAreDescribedByNameAndRefusedWhenDecoded) {
    Ktx2Spec bc1 = spec(131, 0);  // BC1_RGB_UNORM_BLOCK: one 8-byte block
    bc1.width = bc1.height = 4;
    bc1.level.assign(8, 0x55);
    auto d = describeKtx2Image(kName, writeKtx2(bc1));
    ASSERT_TRUE(d) << d.message();
    EXPECT_FALSE(d->readable);
    EXPECT_EQ(d->format, "vkFormat 131 (a BC1-BC7 block format)");
    auto image = decode(writeKtx2(bc1));
    ASSERT_FALSE(image);
    EXPECT_NE(image.message().find(std::string(kName) + ": KTX2 vkFormat 131"), std::string::npos) << image.message();
    Ktx2Spec zlib = spec(43, 4);
    zlib.supercompression = 3;
    d = describeKtx2Image(kName, writeKtx2(zlib));
    ASSERT_TRUE(d) << d.message();
    EXPECT_FALSE(d->readable);
    EXPECT_NE(decode(writeKtx2(zlib)).message().find("supercompressionScheme 3 (ZLIB)"), std::string::npos);
}

// A UASTC 4x4 block of one colour (mode 8: its 5-bit code 0x17, then R, G, B, A, bits LSB first).
std::array<uint8_t, 16> uastcSolidBlock(uint8_t r, uint8_t g, uint8_t b, uint8_t a) {
    const uint64_t bits = 0x17u | uint64_t(r) << 5 | uint64_t(g) << 13 | uint64_t(b) << 21 | uint64_t(a) << 29;
    std::array<uint8_t, 16> block{};
    std::memcpy(block.data(), &bits, 8);
    return block;
}

TEST(Ktx2Image, UastcIsTranscodedCroppedToTheImageStoredOrZstandardSupercompressed) {
    // A 6 x 5 image is 2 x 2 blocks, each of its own colour; the texels past the sides are cut.
    const std::array<std::array<uint8_t, 4>, 4> colours = {
        {{200, 10, 20, 255}, {30, 220, 40, 128}, {50, 60, 230, 0}, {7, 77, 177, 255}}};
    std::vector<uint8_t> blocks;
    for (const auto& c : colours) {
        const auto block = uastcSolidBlock(c[0], c[1], c[2], c[3]);
        blocks.insert(blocks.end(), block.begin(), block.end());
    }
    Ktx2Spec stored;
    stored.vkFormat = 0;
    stored.width = 6;
    stored.height = 5;
    stored.colorModel = 166;  // KHR_DF_MODEL_UASTC
    stored.channelId = 3;     // RGBA
    stored.level = blocks;
    Ktx2Spec zstd = stored;
    zstd.supercompression = 2;
    zstd.level = zstdFrame(blocks);
    zstd.uncompressedLength = blocks.size();
    for (const Ktx2Spec& s : {stored, zstd}) {
        const std::vector<uint8_t> bytes = writeKtx2(s);
        auto d = describeKtx2Image(kName, bytes);
        ASSERT_TRUE(d) << d.message();
        EXPECT_EQ(d->format, "UASTC");
        EXPECT_TRUE(d->readable);
        auto image = decode(bytes);
        ASSERT_TRUE(image) << image.message();
        ASSERT_EQ(image->width, 6u);
        ASSERT_EQ(image->height, 5u);
        for (uint32_t y = 0; y < 5; ++y)
            for (uint32_t x = 0; x < 6; ++x)
                ASSERT_EQ(texel(*image, x, y), colours[(y / 4) * 2 + x / 4])
                    << x << "," << y << " supercompression " << s.supercompression;
    }
    // Lengths other than its blocks' are refused before the transcoder allocates them.
    Ktx2Spec forged = zstd;
    forged.uncompressedLength = uint64_t(1) << 30;
    auto refused = decode(writeKtx2(forged));
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.message().find("level 0 uncompressed byte length 1073741824 is not the 64 of 4 UASTC blocks"),
              std::string::npos)
        << refused.message();
    // A UASTC block of an unknown mode (code 0x45: "future expansion") does not transcode.
    Ktx2Spec bad = stored;
    bad.level[16] = 0x45;
    auto image = decode(writeKtx2(bad));
    ASSERT_FALSE(image);
    EXPECT_NE(image.message().find(std::string(kName) + ": KTX2 Basis Universal"), std::string::npos) << image.message();
}

// One hostile change to a valid 3 x 2 RGBA8 file, and what the error must name.
struct Hostile {
    const char* what;
    std::function<std::vector<uint8_t>()> bytes;
    const char* field;
};

std::vector<uint8_t> valid() { return writeKtx2(spec(43, 4)); }

std::vector<uint8_t> withSpec(const std::function<void(Ktx2Spec&)>& change) {
    Ktx2Spec s = spec(43, 4);
    change(s);
    return writeKtx2(s);
}

std::vector<uint8_t> forged(size_t at, uint64_t value, bool wide = false) {
    std::vector<uint8_t> b = valid();
    if (wide) putU64(b, at, value);
    else putU32(b, at, uint32_t(value));
    return b;
}

TEST(Ktx2Image, HostileContainersAreRefusedNamingTheImageAndTheField) {
    const Hostile cases[] = {
        {"wrong identifier", [] { auto b = valid(); b[5] = '1'; return b; }, "KTX 2.0 identifier"},
        {"truncated header", [] { auto b = valid(); b.resize(50); return b; }, "header and index need 80 bytes; the file has 50 bytes"},
        {"level index past the end", [] { auto b = valid(); b.resize(90); return b; }, "level index of 1 levels"},
        {"level 0 offset past the end", [] { return forged(ktx2at::kLevelOffset, uint64_t(1) << 40, true); },
         "level 0 byte offset 1099511627776 is past the file's"},
        {"level 0 length past the end", [] { return forged(ktx2at::kLevelLength, 99999, true); },
         "level 0 byte length 99999 at offset"},
        {"level 0 length wrapping", [] { return forged(ktx2at::kLevelLength, ~uint64_t(0), true); }, "level 0 byte length 18446744073709551615"},
        {"width 0", [] { return forged(ktx2at::kWidth, 0); }, "pixelWidth 0 x pixelHeight 2"},
        {"1D (height 0)", [] { return forged(ktx2at::kHeight, 0); }, "pixelWidth 3 x pixelHeight 0"},
        {"beyond the limit", [] { return forged(ktx2at::kWidth, kMaxTextureSide + 1); }, "beyond the 16384 texels"},
        {"array", [] { return withSpec([](Ktx2Spec& s) { s.layers = 2; }); }, "layerCount 2: an array texture"},
        {"cube map", [] { return withSpec([](Ktx2Spec& s) { s.faces = 6; }); }, "faceCount 6: a cube map"},
        {"3D", [] { return withSpec([](Ktx2Spec& s) { s.depth = 4; }); }, "pixelDepth 4: a 3D texture"},
        {"too many levels", [] { return withSpec([](Ktx2Spec& s) { s.levels = 3; }); }, "levelCount 3 is more than the 2 levels"},
        {"unknown supercompression", [] { return withSpec([](Ktx2Spec& s) { s.supercompression = 7; }); },
         "supercompressionScheme 7 is not one of"},
        {"DFD past the end", [] { return forged(ktx2at::kDfdLength, 4000); }, "DFD (offset 104, 4000 bytes) ends past the file's"},
        {"DFD too short", [] { return forged(ktx2at::kDfdLength, 8); }, "DFD byte length 8 is less than the 28"},
        {"uncompressed length", [] { return forged(ktx2at::kLevelUncompressed, 23, true); },
         "level 0 uncompressed byte length 23 is not the 24 of 3x2 R8G8B8A8_SRGB texels"},
        {"stored length", [] { return withSpec([](Ktx2Spec& s) { s.level.push_back(0); s.uncompressedLength = 24; }); },
         "level 0 byte length 25 is not its uncompressed 24"},
        {"zstd frame of another size",
         [] { return withSpec([](Ktx2Spec& s) { s.supercompression = 2; s.level = zstdFrame(std::vector<uint8_t>(10, 1)); s.uncompressedLength = 24; }); },
         "Zstandard frame inflates to 10 bytes, not the 24"},
        {"not zstd", [] { return withSpec([](Ktx2Spec& s) { s.supercompression = 2; s.uncompressedLength = 24; }); },
         "level 0 is not a Zstandard frame"},
        {"truncated zstd",
         [] { return withSpec([](Ktx2Spec& s) { s.supercompression = 2; s.level = zstdFrame(distinctTexels(4), 1); s.level.resize(s.level.size() - 3); s.uncompressedLength = 24; }); },
         "Zstandard data does not inflate to its 24 bytes"},
        {"bad swizzle", [] { return withSpec([](Ktx2Spec& s) { s.keyValues = {{"KTXswizzle", "rgbx"}}; }); },
         "KTXswizzle 'rgbx' is not four of r, g, b, a, 0, 1"},
        {"bad orientation", [] { return withSpec([](Ktx2Spec& s) { s.keyValues = {{"KTXorientation", "up"}}; }); },
         "KTXorientation 'up'"},
        {"BasisLZ without global data", [] { return withSpec([](Ktx2Spec& s) { s.vkFormat = 0; s.supercompression = 1; }); },
         "supercompressionScheme 1 (BasisLZ) without supercompression global data"},
    };
    for (const Hostile& c : cases) {
        auto image = decode(c.bytes());
        ASSERT_FALSE(image) << c.what;
        EXPECT_EQ(image.message().rfind(kName, 0), 0u) << c.what << ": " << image.message();
        EXPECT_NE(image.message().find(c.field), std::string::npos) << c.what << ": " << image.message();
    }
}

TEST(Ktx2Image, MalformedKeyValueDataIsRefusedByOffset) {
    std::vector<uint8_t> b = withSpec([](Ktx2Spec& s) { s.keyValues = {{"KTXswizzle", "rgba"}}; });
    const uint32_t kvdOffset = 80 + 24 + 44;
    putU32(b, kvdOffset, 1000);  // an entry longer than the data
    auto image = decode(b);
    ASSERT_FALSE(image);
    EXPECT_NE(image.message().find("key/value data: entry of 1000 bytes at offset 148"), std::string::npos)
        << image.message();
    b = withSpec([](Ktx2Spec& s) { s.keyValues = {{"KTXswizzle", "rgba"}}; });
    putU32(b, kvdOffset, 4);  // "KTXs": a key without its NUL
    image = decode(b);
    ASSERT_FALSE(image);
    EXPECT_NE(image.message().find("the key at offset 152 has no NUL"), std::string::npos) << image.message();
}

TEST(Ktx2Image, MorePixelsThanAllowedAreRefusedBeforeInflating) {
    auto image = decodeRgba8Image(kName, ".ktx2", valid(), 5);
    ASSERT_FALSE(image);
    EXPECT_NE(image.message().find("3x2 pixels is more than the 5"), std::string::npos) << image.message();
}

}  // namespace
}  // namespace vastray::test
