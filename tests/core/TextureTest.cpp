// core/Texture.h: the layout of levels and pages, where a bilinear footprint lies for each wrap
// mode, and the ray-cone level of detail. Sampling against an independent bilinear filter is in
// tests/streamer/package/TexturePagesTest.cpp (it needs pages built from an image).
#include <gtest/gtest.h>

#include <cmath>

#include "vastray/core/Texture.h"

namespace vastray {
namespace {

TEST(Texture, LayoutHalvesEachSideDownToOneTexelAndCountsPagesPerLevel) {
    auto square = makeTextureLayout(1024, 1024);
    ASSERT_TRUE(square) << square.message();
    EXPECT_EQ(square->levelCount, 11u);
    // 1024: 8x8 pages, 512: 4x4, 256: 2x2, 128 and below: one page each (seven levels).
    EXPECT_EQ(square->pageCount, 64u + 16u + 4u + 1u + 7u);
    EXPECT_EQ(square->levels[1].firstPage, 64u);
    EXPECT_EQ(square->levels[10].width, 1u);

    auto strip = makeTextureLayout(300, 5);
    ASSERT_TRUE(strip) << strip.message();
    const uint32_t widths[] = {300, 150, 75, 37, 18, 9, 4, 2, 1};
    const uint32_t heights[] = {5, 2, 1, 1, 1, 1, 1, 1, 1};
    ASSERT_EQ(strip->levelCount, 9u);
    for (uint32_t l = 0; l < 9; ++l) {
        EXPECT_EQ(strip->levels[l].width, widths[l]) << l;
        EXPECT_EQ(strip->levels[l].height, heights[l]) << l;
    }
    EXPECT_EQ(strip->levels[0].pagesX, 3u);
    EXPECT_EQ(strip->levels[1].pagesX, 2u);
    EXPECT_EQ(strip->pageCount, 3u + 2u + 7u);

    auto largest = makeTextureLayout(kMaxTextureSide, 1);
    ASSERT_TRUE(largest) << largest.message();
    EXPECT_EQ(largest->levelCount, kMaxTextureLevels);
}

TEST(Texture, LayoutRefusesEmptyAndOversizedTexturesNamingTheLimit) {
    EXPECT_FALSE(makeTextureLayout(0, 4));
    auto big = makeTextureLayout(16, kMaxTextureSide + 1);
    ASSERT_FALSE(big);
    EXPECT_NE(big.message().find("16x16385"), std::string::npos) << big.message();
    EXPECT_NE(big.message().find("16384"), std::string::npos) << big.message();
}

TextureFootprint at(const TextureLayout& layout, TextureWrap wrap, float u, float v, uint32_t level = 0) {
    return textureFootprint(layout, level, wrap, wrap, u, v);
}

TEST(Texture, TexelCentresLandOnTheirTexelsWithNoWeightOnTheNeighbours) {
    const TextureLayout layout = *makeTextureLayout(300, 200);
    for (TextureWrap wrap : {TextureWrap::Repeat, TextureWrap::Clamp, TextureWrap::Mirror})
        for (uint32_t x : {0u, 1u, 127u, 128u, 255u, 299u})
            for (uint32_t y : {0u, 127u, 128u, 199u}) {
                const TextureFootprint f = at(layout, wrap, (x + 0.5f) / 300.0f, (y + 0.5f) / 200.0f);
                EXPECT_EQ(f.page, (y / 128) * 3 + x / 128) << textureWrapName(wrap) << " " << x << "," << y;
                EXPECT_EQ(f.localX, x % 128);
                EXPECT_EQ(f.localY, y % 128);
                EXPECT_NEAR(f.fx, 0.0f, 1e-3f);
                EXPECT_NEAR(f.fy, 0.0f, 1e-3f);
            }
}

TEST(Texture, WrapModesPlaceTheFootprintAsGltfSamplersDo) {
    const TextureLayout layout = *makeTextureLayout(256, 256);
    // Repeat: u = 0 lies between the last texel and the first (the last texel's page, the
    // stored column beyond it is the first texel's copy).
    TextureFootprint f = at(layout, TextureWrap::Repeat, 0.0f, 0.5f);
    EXPECT_EQ(f.page, 1u);  // x: texel 255 (page column 1); y: texel 127 (page row 0)
    EXPECT_EQ(f.localX, 127u);
    EXPECT_FLOAT_EQ(f.fx, 0.5f);
    TextureFootprint a = at(layout, TextureWrap::Repeat, 1.3f, -0.6f), b = at(layout, TextureWrap::Repeat, 0.3f, 0.4f);
    EXPECT_EQ(a.page, b.page);
    EXPECT_EQ(a.localX, b.localX);
    EXPECT_EQ(a.localY, b.localY);
    EXPECT_NEAR(a.fx, b.fx, 1e-3f);
    EXPECT_NEAR(a.fy, b.fy, 1e-3f);
    // Clamp: anything outside [0, 1] is the edge texel, whole.
    f = at(layout, TextureWrap::Clamp, -3.0f, 7.0f);
    EXPECT_EQ(f.page, 2u);
    EXPECT_EQ(f.localX, 0u);
    EXPECT_EQ(f.localY, 127u);
    EXPECT_EQ(f.fx, 0.0f);
    EXPECT_EQ(f.fy, 0.0f);
    // Mirror: -0.3 is 0.3 and 1.3 is 0.7.
    a = at(layout, TextureWrap::Mirror, -0.3f, 1.3f);
    b = at(layout, TextureWrap::Mirror, 0.3f, 0.7f);
    EXPECT_EQ(a.page, b.page);
    EXPECT_EQ(a.localX, b.localX);
    EXPECT_EQ(a.localY, b.localY);
    EXPECT_NEAR(a.fx, b.fx, 1e-3f);
    EXPECT_NEAR(a.fy, b.fy, 1e-3f);
    // Non-finite coordinates are u = 0, not undefined behaviour.
    f = at(layout, TextureWrap::Clamp, std::nanf(""), INFINITY);
    EXPECT_EQ(f.localX, 0u);
    EXPECT_EQ(f.localY, 0u);
}

TEST(Texture, StoredIndexBeyondTheEdgeIsTheWrapModesTexel) {
    EXPECT_EQ(storedTexelIndex(5, 10, TextureWrap::Repeat), 5u);
    EXPECT_EQ(storedTexelIndex(10, 10, TextureWrap::Repeat), 0u);
    EXPECT_EQ(storedTexelIndex(10, 10, TextureWrap::Clamp), 9u);
    EXPECT_EQ(storedTexelIndex(10, 10, TextureWrap::Mirror), 9u);
}

TEST(Texture, SrgbDecodeIsTheTransferFunction) {
    EXPECT_EQ(srgb8ToLinear(0), 0.0f);
    EXPECT_EQ(srgb8ToLinear(255), 1.0f);
    EXPECT_NEAR(srgb8ToLinear(188), 0.5029f, 1e-4f);
    EXPECT_NEAR(srgb8ToLinear(10), 10.0f / 255.0f / 12.92f, 1e-7f);
}

TEST(Texture, RayConeLevelOfDetailIsOneLevelPerDoublingOfTheFootprint) {
    // A unit square (twice its area: 2) mapped onto a 256 x 256 texture (uv cross 2 -> texel area 2 * 65536).
    const float texelArea = 2.0f * 256.0f * 256.0f, worldArea = 2.0f;
    EXPECT_NEAR(textureLod(texelArea, worldArea, 1.0f / 256.0f, 1.0f), 0.0f, 1e-5f);
    EXPECT_NEAR(textureLod(texelArea, worldArea, 2.0f / 256.0f, 1.0f), 1.0f, 1e-5f);
    EXPECT_NEAR(textureLod(texelArea, worldArea, 2.0f / 256.0f, -0.5f), 2.0f, 1e-5f);
    EXPECT_EQ(textureLod(0.0f, worldArea, 1.0f, 1.0f), 0.0f);
    EXPECT_EQ(textureLod(texelArea, 0.0f, 1.0f, 1.0f), 0.0f);
    EXPECT_EQ(textureLod(texelArea, worldArea, 1.0f, 0.0f), 0.0f);
    EXPECT_EQ(textureLod(texelArea, worldArea, std::nanf(""), 1.0f), 0.0f);
}

}  // namespace
}  // namespace vastray
