// streamer/src/package/TexturePages: mip levels (an area-weighted box filter in linear space),
// pages with the column and row beyond (core/Texture.h), and their compression. Sampling the
// pages is checked against an independent bilinear filter that wraps each texel index itself.
#include <gtest/gtest.h>

#include "TestTextures.h"

#include <cmath>
#include <cstring>
#include <random>

#include <zstd.h>

#include "package/TexturePages.h"

namespace vastray {
namespace {

Rgba8Image solid(uint32_t w, uint32_t h, uint8_t r, uint8_t g, uint8_t b, uint8_t a) {
    Rgba8Image image{w, h, {}};
    for (uint32_t i = 0; i < w * h; ++i) image.texels.insert(image.texels.end(), {r, g, b, a});
    return image;
}

Rgba8Image noise(uint32_t w, uint32_t h, uint32_t seed) { return vastray::test::noiseImage(w, h, seed); }

TEST(TexturePages, ConstantImagesStayConstantAtEveryLevel) {
    for (TextureEncoding encoding : {TextureEncoding::Srgb, TextureEncoding::Linear}) {
        auto pyramid = buildTexturePyramid(solid(300, 77, 77, 130, 201, 200), TextureWrap::Repeat,
                                           TextureWrap::Clamp, encoding);
        ASSERT_TRUE(pyramid) << pyramid.message();
        ASSERT_EQ(pyramid->pages.size(), size_t(pyramid->layout.pageCount) * kTexturePageBytes);
        for (size_t i = 0; i < pyramid->pages.size(); i += 4) {
            ASSERT_EQ(pyramid->pages[i], 77) << i;
            ASSERT_EQ(pyramid->pages[i + 1], 130) << i;
            ASSERT_EQ(pyramid->pages[i + 2], 201) << i;
            ASSERT_EQ(pyramid->pages[i + 3], 200) << i;
        }
    }
}

TEST(TexturePages, DownsamplingAveragesInLinearSpaceWeightedByArea) {
    // Black and white side by side: half linear intensity is sRGB 188, not 128; alpha is linear.
    Rgba8Image pair{2, 1, {0, 0, 0, 0, 255, 255, 255, 255}};
    Rgba8Image half = downsampleLevel(pair, TextureEncoding::Srgb);
    ASSERT_EQ(half.width, 1u);
    EXPECT_EQ(half.texels[0], 188);
    EXPECT_EQ(half.texels[3], 128);
    half = downsampleLevel(pair, TextureEncoding::Linear);
    EXPECT_EQ(half.texels[0], 128);
    // An odd side: three texels become one, each weighted a third.
    Rgba8Image three{3, 1, {0, 0, 0, 0, 90, 90, 90, 90, 180, 180, 180, 180}};
    Rgba8Image one = downsampleLevel(three, TextureEncoding::Linear);
    ASSERT_EQ(one.width, 1u);
    EXPECT_EQ(one.texels[0], 90);
    // Five texels become two, covering 2.5 texels each: (0 + 100 + 0.5 * 200) / 2.5 = 80.
    Rgba8Image five{5, 1, {}};
    for (uint8_t v : {0, 100, 200, 100, 0}) five.texels.insert(five.texels.end(), {v, v, v, v});
    Rgba8Image two = downsampleLevel(five, TextureEncoding::Linear);
    ASSERT_EQ(two.width, 2u);
    EXPECT_EQ(two.texels[0], 80);
    EXPECT_EQ(two.texels[4], 80);
}

// Bilinear filtering as a texture unit does it, texel by texel: wrap each of the four texel
// indices on its own (repeat: modulo; clamp: to the edge; mirror: reflected).
int64_t wrapIndex(int64_t i, int64_t n, TextureWrap wrap) {
    switch (wrap) {
        case TextureWrap::Repeat: return ((i % n) + n) % n;
        case TextureWrap::Clamp: return std::clamp<int64_t>(i, 0, n - 1);
        case TextureWrap::Mirror: {
            const int64_t period = ((i % (2 * n)) + 2 * n) % (2 * n);
            return period < n ? period : 2 * n - 1 - period;
        }
    }
    return 0;
}

TextureSample referenceBilinear(const Rgba8Image& image, TextureWrap wrapS, TextureWrap wrapT, float u, float v) {
    const double x = double(u) * image.width - 0.5, y = double(v) * image.height - 0.5;
    const int64_t x0 = int64_t(std::floor(x)), y0 = int64_t(std::floor(y));
    const double fx = x - double(x0), fy = y - double(y0);
    double sum[4] = {0, 0, 0, 0};
    for (int corner = 0; corner < 4; ++corner) {
        const int64_t tx = wrapIndex(x0 + (corner & 1), image.width, wrapS);
        const int64_t ty = wrapIndex(y0 + (corner >> 1), image.height, wrapT);
        const double w = ((corner & 1) ? fx : 1 - fx) * ((corner >> 1) ? fy : 1 - fy);
        const uint8_t* t = image.texels.data() + (size_t(ty) * image.width + size_t(tx)) * 4;
        for (int c = 0; c < 4; ++c) sum[c] += w * (c < 3 ? srgb8ToLinear(t[c]) : t[c] / 255.0);
    }
    return {float(sum[0]), float(sum[1]), float(sum[2]), float(sum[3])};
}

TEST(TexturePages, SamplingThePagesEqualsBilinearFilteringOfTheImageForEveryWrapMode) {
    const Rgba8Image image = noise(300, 140, 7);  // three pages across, two down; partial pages
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> coordinate(-2.5f, 2.5f);
    for (TextureWrap wrapS : {TextureWrap::Repeat, TextureWrap::Clamp, TextureWrap::Mirror})
        for (TextureWrap wrapT : {TextureWrap::Repeat, TextureWrap::Clamp, TextureWrap::Mirror}) {
            auto pyramid = buildTexturePyramid(image, wrapS, wrapT, TextureEncoding::Srgb);
            ASSERT_TRUE(pyramid) << pyramid.message();
            const TexturePageFetch fetch = [&](uint32_t page) {
                return pyramid->pages.data() + size_t(page) * kTexturePageBytes;
            };
            for (int i = 0; i < 4000; ++i) {
                // Every fourth sample at a page seam or an image edge, where the stored column and
                // row beyond are read.
                float u = coordinate(rng), v = coordinate(rng);
                if (i % 4 == 0) u = (128.0f + (i % 8 ? 0.0f : 172.0f)) / 300.0f + 1e-4f;
                if (i % 4 == 1) v = (i % 8 == 1 ? 128.0f : 140.0f) / 140.0f - 1e-4f;
                const TextureSample got = sampleTexture(pyramid->layout, wrapS, wrapT, TextureEncoding::Srgb,
                                                        fetch, u, v, 0.0f);
                const TextureSample want = referenceBilinear(image, wrapS, wrapT, u, v);
                ASSERT_NEAR(got.r, want.r, 2e-4f) << textureWrapName(wrapS) << "/" << textureWrapName(wrapT)
                                                 << " u " << u << " v " << v;
                ASSERT_NEAR(got.g, want.g, 2e-4f);
                ASSERT_NEAR(got.b, want.b, 2e-4f);
                ASSERT_NEAR(got.a, want.a, 2e-4f);
            }
        }
}

TEST(TexturePages, TrilinearBlendsTheTwoLevelsAroundTheLevelOfDetail) {
    const Rgba8Image image = noise(64, 64, 3);
    auto pyramid = buildTexturePyramid(image, TextureWrap::Repeat, TextureWrap::Repeat, TextureEncoding::Linear);
    ASSERT_TRUE(pyramid);
    const TexturePageFetch fetch = [&](uint32_t page) {
        return pyramid->pages.data() + size_t(page) * kTexturePageBytes;
    };
    auto sample = [&](float lod) {
        return sampleTexture(pyramid->layout, TextureWrap::Repeat, TextureWrap::Repeat, TextureEncoding::Linear,
                             fetch, 0.37f, 0.61f, lod);
    };
    const TextureSample l1 = sample(1.0f), l2 = sample(2.0f), mid = sample(1.25f);
    EXPECT_NEAR(mid.r, 0.75f * l1.r + 0.25f * l2.r, 1e-6f);
    EXPECT_NEAR(mid.a, 0.75f * l1.a + 0.25f * l2.a, 1e-6f);
    // Beyond the last level: the 1 x 1 level, the image's average.
    const TextureSample top = sample(100.0f), last = sample(6.0f);
    EXPECT_EQ(top.g, last.g);
    EXPECT_NE(l1.r, l2.r);
}

TEST(TexturePages, PagesRoundTripThroughTheirCompressionAndGarbageIsRefused) {
    auto pyramid = buildTexturePyramid(noise(130, 129, 5), TextureWrap::Repeat, TextureWrap::Repeat,
                                       TextureEncoding::Srgb);
    ASSERT_TRUE(pyramid);
    std::vector<uint8_t> page(kTexturePageBytes);
    for (uint32_t p = 0; p < pyramid->layout.pageCount; ++p) {
        const uint8_t* original = pyramid->pages.data() + size_t(p) * kTexturePageBytes;
        const std::vector<uint8_t> packed = encodeTexturePage(original);
        ASSERT_FALSE(packed.empty());
        ASSERT_TRUE(decodeTexturePage(packed.data(), packed.size(), page.data()));
        ASSERT_EQ(0, std::memcmp(page.data(), original, kTexturePageBytes)) << p;
    }
    const std::vector<uint8_t> flat(kTexturePageBytes, 9);
    std::vector<uint8_t> packed = encodeTexturePage(flat.data());
    EXPECT_LT(packed.size(), kTexturePageBytes / 100);  // a flat page costs next to nothing
    // Cut short, bit-flipped header, not zstd at all, a frame of another size.
    Status cut = decodeTexturePage(packed.data(), packed.size() - 3, page.data());
    EXPECT_FALSE(cut);
    std::vector<uint8_t> garbage(64, 0xAB);
    Status notZstd = decodeTexturePage(garbage.data(), garbage.size(), page.data());
    ASSERT_FALSE(notZstd);
    EXPECT_NE(notZstd.message().find("not a zstd frame"), std::string::npos) << notZstd.message();
    const std::vector<uint8_t> small(1000, 1);
    std::vector<uint8_t> other(ZSTD_COMPRESSBOUND(1000));
    other.resize(ZSTD_compress(other.data(), other.size(), small.data(), small.size(), 1));
    Status wrongSize = decodeTexturePage(other.data(), other.size(), page.data());
    ASSERT_FALSE(wrongSize);
    EXPECT_NE(wrongSize.message().find("1000 bytes"), std::string::npos) << wrongSize.message();
}

TEST(TexturePages, ImagesOfTheWrongSizeAreRefused) {
    Rgba8Image bad{4, 4, std::vector<uint8_t>(10)};
    auto pyramid = buildTexturePyramid(bad, TextureWrap::Repeat, TextureWrap::Repeat, TextureEncoding::Srgb);
    ASSERT_FALSE(pyramid);
    EXPECT_NE(pyramid.message().find("10 bytes"), std::string::npos) << pyramid.message();
    EXPECT_FALSE(buildTexturePyramid(Rgba8Image{0, 4, {}}, TextureWrap::Repeat, TextureWrap::Repeat,
                                     TextureEncoding::Srgb));
}

}  // namespace
}  // namespace vastray
