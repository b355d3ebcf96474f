// common/Texture.glsl through GpuTextureSampler against core/Texture.h's sampleTexture: the same
// trilinear samples for every wrap pair and both encodings (within float rounding: the GPU
// decodes sRGB with pow, the CPU with a table), and a page the pool lacks is named, never
// replaced by other texels.
#include <gtest/gtest.h>

#include "TestTextures.h"

#include <random>
#include <set>

#include "GpuTestSupport.h"
#include "package/TexturePages.h"
#include "vastray/gpu/GpuTextureSampler.h"

namespace vastray::gpu::test {
namespace {

Rgba8Image noise(uint32_t w, uint32_t h, uint32_t seed) { return vastray::test::noiseImage(w, h, seed); }

struct Textures {
    std::vector<TexturePyramid> pyramids;
    std::vector<TextureUpload> uploads;
};

// Nine textures, one per wrap pair, alternating sRGB and linear; sizes not powers of two, with
// partial pages.
Textures nineTextures() {
    Textures t;
    const TextureWrap wraps[] = {TextureWrap::Repeat, TextureWrap::Clamp, TextureWrap::Mirror};
    for (uint32_t i = 0; i < 9; ++i) {
        const TextureEncoding encoding = i % 2 ? TextureEncoding::Linear : TextureEncoding::Srgb;
        t.pyramids.push_back(*buildTexturePyramid(noise(150 + 37 * i, 131 - 9 * i, i), wraps[i % 3], wraps[i / 3], encoding));
    }
    for (const TexturePyramid& p : t.pyramids)
        t.uploads.push_back({p.layout, p.wrapS, p.wrapT, p.encoding, p.pages.data()});
    return t;
}

std::vector<TextureQuery> randomQueries(uint32_t count, uint32_t textures, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> coordinate(-2.5f, 2.5f), lod(-1.0f, 9.0f);
    std::vector<TextureQuery> queries(count);
    for (uint32_t i = 0; i < count; ++i)
        queries[i] = {i % textures, coordinate(rng), coordinate(rng), i % 5 == 0 ? 0.0f : lod(rng)};
    return queries;
}

TEST(GpuTextureSampling, SamplesEqualTheCpuSamplingForEveryWrapPairAndEncoding) {
    VASTRAY_REQUIRE_DEVICE(device);
    auto sampler = GpuTextureSampler::create(device);
    ASSERT_TRUE(sampler) << sampler.message();
    const Textures t = nineTextures();
    ASSERT_TRUE((*sampler)->upload(t.uploads, [](uint32_t, uint32_t) { return true; }));
    const std::vector<TextureQuery> queries = randomQueries(20000, 9, 5);
    auto got = (*sampler)->sample(queries);
    ASSERT_TRUE(got) << got.message();
    for (size_t i = 0; i < queries.size(); ++i) {
        const TextureQuery& q = queries[i];
        const TexturePyramid& p = t.pyramids[q.texture];
        const TextureSample want = sampleTexture(
            p.layout, p.wrapS, p.wrapT, p.encoding,
            [&](uint32_t page) { return p.pages.data() + size_t(page) * kTexturePageBytes; }, q.u, q.v, q.lod);
        const TextureSampleResult& g = (*got)[i];
        ASSERT_EQ(g.missingEntry, kTexturePageAbsent) << i;
        ASSERT_NEAR(g.r, want.r, 2e-5f) << "query " << i << " texture " << q.texture << " uv " << q.u << ","
                                         << q.v << " lod " << q.lod;
        ASSERT_NEAR(g.g, want.g, 2e-5f) << i;
        ASSERT_NEAR(g.b, want.b, 2e-5f) << i;
        ASSERT_NEAR(g.a, want.a, 2e-5f) << i;
    }
}

TEST(GpuTextureSampling, AnAbsentPageIsNamedAndNeverStandsInForAnother) {
    VASTRAY_REQUIRE_DEVICE(device);
    auto sampler = GpuTextureSampler::create(device);
    ASSERT_TRUE(sampler) << sampler.message();
    const Textures t = nineTextures();
    // Every third page of every texture is left out of the pool.
    auto resident = [](uint32_t texture, uint32_t page) { return (texture + page) % 3 != 0; };
    ASSERT_TRUE((*sampler)->upload(t.uploads, resident));
    const std::vector<TextureQuery> queries = randomQueries(20000, 9, 9);
    auto got = (*sampler)->sample(queries);
    ASSERT_TRUE(got) << got.message();
    size_t absent = 0;
    for (size_t i = 0; i < queries.size(); ++i) {
        const TextureQuery& q = queries[i];
        const TexturePyramid& p = t.pyramids[q.texture];
        // The pages the CPU sampling reads for this query.
        std::set<uint32_t> read;
        const TextureSample want = sampleTexture(p.layout, p.wrapS, p.wrapT, p.encoding,
                                                 [&](uint32_t page) {
                                                     read.insert(page);
                                                     return p.pages.data() + size_t(page) * kTexturePageBytes;
                                                 },
                                                 q.u, q.v, q.lod);
        std::set<uint32_t> missing;
        for (uint32_t page : read)
            if (!resident(q.texture, page)) missing.insert((*sampler)->pageTableEntry(q.texture, page));
        const TextureSampleResult& g = (*got)[i];
        if (missing.empty()) {
            ASSERT_EQ(g.missingEntry, kTexturePageAbsent) << i;
            ASSERT_NEAR(g.r, want.r, 2e-5f) << i;
            ASSERT_NEAR(g.a, want.a, 2e-5f) << i;
        } else {
            ++absent;
            ASSERT_TRUE(missing.count(g.missingEntry)) << "query " << i << " names entry " << g.missingEntry;
        }
    }
    EXPECT_GT(absent, queries.size() / 10);  // the test exercised absent pages
    EXPECT_EQ((*sampler)->residentPages() > 0, true);
}

}  // namespace
}  // namespace vastray::gpu::test
