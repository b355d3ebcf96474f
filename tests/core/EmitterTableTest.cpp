// Issue 13 ("Real assets"): the emissive triangles' table (core/Emitters.h) and next-event
// estimation's emitter steps (core/PathShading.h). The alias method realises each triangle's
// probability (area x largest emission component / total) exactly up to float rounding, and its
// draws pass a chi-square test; points are uniform on a triangle; the solid-angle density is
// the area density times d^2 / cos; single-sided emitters are dark from behind; the hit weight
// and next-event estimation's weight of one direction sum to 1.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "vastray/core/EnvironmentMap.h"
#include "vastray/core/PathShading.h"
#include "vastray/core/Random.h"
#include "vastray/core/VecMath.h"

namespace vastray {
namespace {

Material emitter(const char* name, std::array<float, 3> emission, bool doubleSided = true) {
    Material m{name};
    m.baseColor = {0, 0, 0, 1};
    m.emissive = emission;
    m.doubleSided = doubleSided;
    return m;
}

// Right triangles in the plane y = 0 with legs a (area a^2 / 2), front (counter-clockwise seen
// from +y: cross(v1 - v0, v2 - v0) along +y).
EmissiveTriangle rightTriangle(float x, float a, uint32_t material) {
    return {{x, 0, 0}, {x, 0, a}, {x + a, 0, 0}, material};
}

TEST(EmitterTable, AliasColumnsRealiseAreaTimesEmission) {
    const std::vector<Material> materials = {emitter("dim", {0.5f, 0.2f, 0.1f}), emitter("bright", {1, 4, 2}),
                                             Material{"grey"}};
    std::vector<EmissiveTriangle> triangles;
    const float legs[] = {1.0f, 0.3f, 2.0f, 0.05f, 1.7f, 0.9f, 0.4f};
    for (size_t i = 0; i < std::size(legs); ++i) triangles.push_back(rightTriangle(3.0f * i, legs[i], uint32_t(i % 2)));
    const EmitterTable table = makeEmitterTable(triangles, materials);
    ASSERT_EQ(table.entries.size(), triangles.size());
    double power = 0;
    for (size_t i = 0; i < triangles.size(); ++i) power += 0.5 * legs[i] * legs[i] * (i % 2 ? 4.0 : 0.5);
    // Each column's own share plus what the others' aliases give it, over n columns.
    std::vector<double> realised(triangles.size(), 0.0);
    for (const EmitterEntry& e : table.entries) {
        const size_t self = size_t(&e - table.entries.data());
        realised[self] += e.keep;
        realised[e.alias] += 1.0 - e.keep;
    }
    for (size_t i = 0; i < triangles.size(); ++i) {
        const double expected = 0.5 * legs[i] * legs[i] * (i % 2 ? 4.0 : 0.5) / power;
        EXPECT_NEAR(realised[i] / double(triangles.size()), expected, 1e-6) << "triangle " << i;
    }
    EXPECT_FLOAT_EQ(table.areaDensity[0], float(0.5 / power));
    EXPECT_FLOAT_EQ(table.areaDensity[1], float(4.0 / power));
    EXPECT_EQ(table.areaDensity[2], 0.0f) << "a material no entry has";

    // Draws: chi-square over the 7 triangles, 200,000 draws (6 degrees of freedom; 22.5 is the
    // 0.999 quantile).
    std::vector<double> counts(triangles.size(), 0.0);
    const uint32_t draws = 200000;
    for (uint32_t k = 0; k < draws; ++k) {
        const RandomKey key{k, 0, 0};
        counts[pickEmitter(table, randomBits(key, kDimEmitterPick, 5), randomFloat(key, kDimEmitterKeep, 5))] += 1;
    }
    double chiSquare = 0;
    for (size_t i = 0; i < triangles.size(); ++i) {
        const double expected = draws * (0.5 * legs[i] * legs[i] * (i % 2 ? 4.0 : 0.5) / power);
        chiSquare += (counts[i] - expected) * (counts[i] - expected) / expected;
    }
    std::printf("emitter picks: chi-square %.2f over %zu triangles (bound 22.5)\n", chiSquare, triangles.size());
    EXPECT_LT(chiSquare, 22.5);
}

TEST(EmitterTable, ZeroWeightTrianglesAndNonEmittersAreLeftOut) {
    const std::vector<Material> materials = {emitter("lamp", {1, 1, 1})};
    const std::vector<EmissiveTriangle> flat = {{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, 0}};
    EXPECT_TRUE(makeEmitterTable(flat, materials).entries.empty()) << "a triangle of zero area";

    TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}};
    mesh.indices = {0, 1, 2, 0, 1, 3, 0, 2, 1};
    Material plain{"plain"}, mapped = emitter("screen", {1, 1, 1}), cut = emitter("leaf", {1, 1, 1});
    mapped.textures.slots[uint32_t(TextureSlot::Emissive)].texture = 0;
    cut.textures.slots[uint32_t(TextureSlot::BaseColor)].texture = 0;
    cut.alphaCutoff = 0.5f;
    mesh.materials = {emitter("lamp", {0, 2, 0}), plain, mapped, cut};
    EXPECT_TRUE(isSampledEmitter(mesh.materials[0], 1));
    EXPECT_FALSE(isSampledEmitter(plain, 1));
    EXPECT_TRUE(isSampledEmitter(mapped, 1)) << "an emissive map is read where the drawn point falls";
    EXPECT_TRUE(isSampledEmitter(mapped, 0));
    EXPECT_FALSE(isSampledEmitter(cut, 1)) << "a cut-out's holes would shine";
    Material blend = emitter("veil", {1, 1, 1});
    blend.alphaBlend = true;
    EXPECT_TRUE(isSampledEmitter(blend, 1)) << "a blend of alpha 1 without a map is opaque";
    blend.baseColor[3] = 0.5f;
    EXPECT_FALSE(isSampledEmitter(blend, 1)) << "rays meet a blend with its alpha only";
    mesh.materialIds = {0, 0, 0};
    const std::vector<EmissiveTriangle> all = collectEmitters(mesh, 1);
    ASSERT_EQ(all.size(), 2u) << "the degenerate second triangle is left out";
    EXPECT_EQ(all[1].v1, (Vec3f{0, 1, 0})) << "corners as the mesh orders them";
    EXPECT_EQ(all[1].t1, (std::array<float, 2>{0, 0})) << "no UVs: (0, 0)";
    mesh.uvs = {{0.1f, 0.2f}, {0.3f, 0.4f}, {0.5f, 0.6f}, {0.7f, 0.8f}};
    const std::vector<EmissiveTriangle> withUvs = collectEmitters(mesh, 1);
    ASSERT_EQ(withUvs.size(), 2u);
    EXPECT_EQ(withUvs[1].t0, (std::array<float, 2>{0.1f, 0.2f})) << "the corners' UVs, in the corners' order";
    EXPECT_EQ(withUvs[1].t1, (std::array<float, 2>{0.5f, 0.6f}));
    EXPECT_EQ(withUvs[1].t2, (std::array<float, 2>{0.3f, 0.4f}));
    mesh.uvs.clear();
    const std::vector<uint32_t> kept = {2};
    EXPECT_EQ(collectEmitters(mesh, 1, kept).size(), 1u);
    mesh.materialIds = {1, 3, 3};
    EXPECT_TRUE(collectEmitters(mesh, 1).empty());
    mesh.materialIds = {2, 1, 1};
    EXPECT_EQ(collectEmitters(mesh, 1).size(), 1u) << "a mapped emitter is collected";
}

TEST(EmitterTable, PointsAreUniformOverTheTriangle) {
    // UVs that follow x and z: a point's UV is where it lies.
    const EmitterEntry e{{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 0, 1.0f, 0, {0, 0}, {1, 0}, {0, 1}};
    // The four triangles of the midpoint subdivision each get a quarter.
    uint32_t counts[4] = {};
    const uint32_t draws = 100000;
    Vec3f sum{0, 0, 0};
    for (uint32_t k = 0; k < draws; ++k) {
        const RandomKey key{k, 1, 2};
        const float u1 = randomFloat(key, kDimEmitterU, 9), u2 = randomFloat(key, kDimEmitterV, 9);
        const Vec3f p = emitterPoint(e, u1, u2);
        const std::array<float, 2> uv = emitterUv(e, u1, u2);
        ASSERT_NEAR(uv[0], p.x, 1e-6f);
        ASSERT_NEAR(uv[1], p.z, 1e-6f);
        ASSERT_GE(p.x, 0.0f);
        ASSERT_GE(p.z, 0.0f);
        ASSERT_LE(p.x + p.z, 1.0f + 1e-6f);
        sum = sum + p;
        counts[p.x > 0.5f ? 1 : p.z > 0.5f ? 2 : p.x + p.z < 0.5f ? 0 : 3]++;
    }
    double chiSquare = 0;
    for (uint32_t c : counts) chiSquare += (c - draws / 4.0) * (c - draws / 4.0) / (draws / 4.0);
    EXPECT_LT(chiSquare, 16.3) << "3 degrees of freedom, 0.999 quantile";
    EXPECT_NEAR(sum.x / draws, 1.0 / 3.0, 0.004);
    EXPECT_NEAR(sum.z / draws, 1.0 / 3.0, 0.004);
}

TEST(EmitterTable, SampleDensityIsAreaDensityTimesDistanceSquaredOverCosine) {
    // One square lamp, two triangles, facing down (front along -y) at height 2 over the origin.
    const std::vector<Material> materials = {emitter("lamp", {3, 2, 1}, false)};
    const std::vector<EmissiveTriangle> square = {{{-1, 2, -1}, {1, 2, -1}, {1, 2, 1}, 0},
                                                  {{-1, 2, -1}, {1, 2, 1}, {-1, 2, 1}, 0}};
    ASSERT_LT(normalize(geometricNormal(square[0].v0, square[0].v1, square[0].v2)).y, 0.0f);
    const EmitterTable table = makeEmitterTable(square, materials);
    EXPECT_FLOAT_EQ(table.areaDensity[0], 0.25f) << "1 / the area, whatever the emission";
    const Vec3f origin{0.3f, 0, -0.2f};
    uint32_t drawn = 0;
    for (uint32_t k = 0; k < 1000; ++k) {
        EmitterSample s;
        ASSERT_TRUE(sampleEmitter(table, materials, {}, 0.5f, origin, {k, 0, 1}, 3, &s));
        const Vec3f y = origin + s.direction * s.distance;
        EXPECT_NEAR(y.y, 2.0f, 1e-4f) << "the point lies on the lamp (moved off it by 256 ULPs)";
        EXPECT_LT(y.y, 2.0f) << "moved towards the origin";
        const float cosine = s.direction.y;
        EXPECT_NEAR(s.pdf, 0.5f * 0.25f * s.distance * s.distance / cosine, 1e-5f * s.pdf);
        EXPECT_EQ(s.radiance, (Vec3f{3, 2, 1}));
        ++drawn;
    }
    // From above, the single-sided lamp shows its back: nothing.
    EmitterSample s;
    for (uint32_t k = 0; k < 100; ++k) EXPECT_FALSE(sampleEmitter(table, materials, {}, 0.5f, {0, 5, 0}, {k, 0, 1}, 3, &s));
    // Double-sided, it lights both sides.
    const std::vector<Material> twoSided = {emitter("lamp", {3, 2, 1}, true)};
    EXPECT_TRUE(sampleEmitter(makeEmitterTable(square, twoSided), twoSided, {}, 0.5f, {0, 5, 0}, {0, 0, 1}, 3, &s));
    EXPECT_LT(s.direction.y, 0.0f) << "down to the lamp";
    EXPECT_GT(s.distance, 2.9f);
}

TEST(EmitterTable, HitWeightAndSampleWeightOfOneDirectionSumToOne) {
    for (float bouncePdf : {0.01f, 0.3f, 1.0f, 7.0f}) {
        const float pick = 0.5f, density = 0.04f, t = 2.5f, cosine = 0.6f;
        const float lightPdf = pick * density * (t * t / cosine);
        const float hit = emitterHitWeight(pick, density, t, cosine, bouncePdf);
        EXPECT_NEAR(hit + powerHeuristic(lightPdf, bouncePdf), 1.0f, 1e-6f);
    }
    EXPECT_EQ(emitterHitWeight(0.5f, 0.04f, 1.0f, 1.0f, 0.0f), 1.0f) << "a camera ray";
    EXPECT_EQ(emitterHitWeight(0.5f, 0.0f, 1.0f, 1.0f, 0.3f), 1.0f) << "a material the table does not sample";
}

TEST(EmitterTable, PickProbabilityShareWithOtherLights) {
    Environment env;
    EmitterTable table;
    EXPECT_EQ(emitterPickProbability(env, {}, nullptr), 0.0f);
    EXPECT_EQ(emitterPickProbability(env, {}, &table), 0.0f) << "an empty table";
    table.entries.push_back({});
    EXPECT_EQ(emitterPickProbability(env, {}, &table), 0.5f) << "the default sun shines";
    env.sunIrradiance = {0, 0, 0};
    EXPECT_EQ(emitterPickProbability(env, {}, &table), 1.0f) << "nothing else brings light";
    const LightEntry light;
    EXPECT_EQ(emitterPickProbability(env, std::span<const LightEntry>(&light, 1), &table), 0.5f);
}

}  // namespace
}  // namespace vastray
