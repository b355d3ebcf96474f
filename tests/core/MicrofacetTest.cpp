// The metallic-roughness BSDF (core/Microfacet.h): its samples follow the density it reports
// (a chi-square test against the density integrated over bins, as Mitsuba's test suite checks
// its BSDFs), the density integrates to one, and a white surface reflects all it receives for
// every roughness and angle (the white furnace, within 1 %), while a coloured one reflects less.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "vastray/core/Microfacet.h"
#include "vastray/core/Random.h"
#include "vastray/core/Sampling.h"
#include "vastray/core/VecMath.h"

namespace vastray {
namespace {

float bsdfU01(uint32_t i, uint32_t d) { return randomFloat({i, 0, 0}, d, 99); }

Vec3f outgoing(float mu) { return {std::sqrt(1.0f - mu * mu), 0.0f, mu}; }

// The directional albedo towards wo, integral of f cos over the hemisphere, estimated with the
// BSDF's own sampling (n samples).
Vec3f albedoTowards(const Bsdf& b, Vec3f wo, uint32_t n) {
    const float* t = microfacetTables().data();
    double sum[3] = {0, 0, 0};
    for (uint32_t i = 0; i < n; ++i) {
        Vec3f wi, weight;
        float pdf;
        if (!sampleBsdf(b, wo, bsdfU01(i, 0), bsdfU01(i, 1), bsdfU01(i, 2), t, &wi, &weight, &pdf)) continue;
        for (int c = 0; c < 3; ++c) sum[c] += weight[c];
    }
    return {float(sum[0] / n), float(sum[1] / n), float(sum[2] / n)};
}
// The same at cos(theta_o) = mu.
Vec3f albedo(const Bsdf& b, float mu, uint32_t n) { return albedoTowards(b, outgoing(mu), n); }

// A coat whose normal leans away from the shading normal (a base normal map bent the latter).
Bsdf tiltedCoat(Bsdf b, Vec3f coatNormal) {
    b.coatNormal = normalize(coatNormal);
    return b;
}

TEST(Microfacet, WhiteFurnaceReflectsEverythingAtEveryRoughness) {
    for (const float metallic : {0.0f, 1.0f, 0.5f})
        for (const float roughness : {0.0f, 0.05f, 0.2f, 0.4f, 0.6f, 0.8f, 1.0f})
            for (const float mu : {0.05f, 0.2f, 0.5f, 0.8f, 1.0f}) {
                const Bsdf b{{1, 1, 1}, metallic, roughness, 1.0f};
                const Vec3f a = albedo(b, mu, 200000);
                EXPECT_NEAR(a.x, 1.0f, 0.01f) << "metallic " << metallic << " roughness " << roughness << " mu " << mu;
            }
}

TEST(Microfacet, ColouredAndLayerlessSurfacesReflectLess) {
    // No layer, not metallic: the Lambertian base exactly (albedo = base, f = base / pi).
    const Bsdf lambert{{0.5f, 0.25f, 1.0f}, 0.0f, 0.7f, 0.0f};
    const Vec3f wi = normalize(Vec3f{0.2f, 0.3f, 0.9f});
    const Vec3f f = evalBsdf(lambert, outgoing(0.6f), wi, microfacetTables().data()).f;
    EXPECT_NEAR(f.x, 0.5f / kPi, 1e-6f);
    EXPECT_NEAR(f.y, 0.25f / kPi, 1e-6f);
    EXPECT_NEAR(f.z, 1.0f / kPi, 1e-6f);
    // A black dielectric keeps its specular layer only (a few per cent, more at grazing).
    const Vec3f black = albedo({{0, 0, 0}, 0.0f, 0.3f, 1.0f}, 0.9f, 100000);
    EXPECT_GT(black.x, 0.02f);
    EXPECT_LT(black.x, 0.08f);
    EXPECT_GT(albedo({{0, 0, 0}, 0.0f, 0.3f, 1.0f}, 0.1f, 100000).x, black.x);
    // A gold-like metal reflects about its base colour (more at grazing by Fresnel).
    const Vec3f gold = albedo({{1.0f, 0.76f, 0.33f}, 1.0f, 0.5f, 1.0f}, 1.0f, 100000);
    EXPECT_NEAR(gold.x, 1.0f, 0.01f);
    EXPECT_NEAR(gold.y, 0.76f, 0.05f);
    EXPECT_NEAR(gold.z, 0.33f, 0.08f);
}

// KHR_materials_specular's specularColorFactor: a white base under a layer of any F0 (0 to 1,
// coloured) still reflects all it receives (the furnace, 1 % as above); per channel the layer
// reflects more with a larger colour.
TEST(Microfacet, WhiteFurnaceHoldsForEverySpecularColour) {
    for (const Vec3f colour : {Vec3f{0, 0, 0}, Vec3f{0.5f, 1.0f, 2.0f}, Vec3f{10, 0.2f, 25}, Vec3f{1000, 1000, 1000}})
        for (const float roughness : {0.0f, 0.3f, 0.7f, 1.0f})
            for (const float mu : {0.05f, 0.5f, 1.0f}) {
                Bsdf b{{1, 1, 1}, 0.0f, roughness, 1.0f};
                b.specularColor = colour;
                const Vec3f a = albedo(b, mu, 100000);
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(a[c], 1.0f, 0.01f) << "colour " << colour[c] << " roughness " << roughness << " mu " << mu;
            }
    Bsdf black{{0, 0, 0}, 0.0f, 0.3f, 1.0f};
    black.specularColor = {0.5f, 1.0f, 2.0f};
    const Vec3f a = albedo(black, 0.9f, 100000);
    EXPECT_LT(a.x, a.y);
    EXPECT_LT(a.y, a.z);
}

// KHR_materials_clearcoat: a white base (dielectric, metal) under a full coat of any roughness
// still reflects all it receives (1 %, never more: the coat takes its own albedo from the base);
// a black base under a coat reflects the coat alone, a few per cent, more at grazing.
TEST(Microfacet, WhiteFurnaceHoldsUnderAClearcoat) {
    for (const float metallic : {0.0f, 1.0f})
        for (const float coatRoughness : {0.0f, 0.1f, 0.3f, 0.6f, 1.0f})
            for (const float mu : {0.05f, 0.3f, 0.7f, 1.0f}) {
                Bsdf b{{1, 1, 1}, metallic, 0.5f, 1.0f};
                b.clearcoat = 1.0f, b.clearcoatRoughness = coatRoughness;
                const Vec3f a = albedo(b, mu, 100000);
                EXPECT_NEAR(a.x, 1.0f, 0.01f) << "metallic " << metallic << " coat roughness " << coatRoughness << " mu " << mu;
                EXPECT_LE(a.x, 1.0f + 0.01f);
            }
    Bsdf black{{0, 0, 0}, 0.0f, 0.5f, 0.0f};
    black.clearcoat = 1.0f, black.clearcoatRoughness = 0.2f;
    const float normal = albedo(black, 1.0f, 100000).x, grazing = albedo(black, 0.1f, 100000).x;
    EXPECT_NEAR(normal, 0.04f, 0.01f);
    EXPECT_GT(grazing, 2 * normal);
    // Without a coat the BSDF is the base's exactly, whatever the coat's roughness says.
    Bsdf uncoated{{0.6f, 0.3f, 0.2f}, 0.2f, 0.4f, 1.0f};
    uncoated.clearcoatRoughness = 0.7f;
    const Vec3f wo = outgoing(0.6f), wi = normalize(Vec3f{0.2f, 0.3f, 0.9f});
    const float* t = microfacetTables().data();
    const BsdfValue withRoughness = evalBsdf(uncoated, wo, wi, t);
    const BsdfValue plain = evalBsdf({{0.6f, 0.3f, 0.2f}, 0.2f, 0.4f, 1.0f}, wo, wi, t);
    EXPECT_EQ(withRoughness.f.x, plain.f.x);
    EXPECT_EQ(withRoughness.pdf, plain.pdf);
}

// A coat whose normal is not the shading normal's (a base normal map bent the latter; the coat
// keeps the unbent one): its lobe is taken about its own normal. A white base under it reflects
// no more than it receives (what the coat reflects below the base's horizon is lost, a little at
// these tilts), and a black base reflects the coat's highlight about the coat normal: the
// directional albedo of the tilted coat seen from along its normal equals the untilted coat's
// seen from along +z (the same lobe, turned), to the estimate's noise.
TEST(Microfacet, ATiltedCoatTakesItsLobeAboutItsOwnNormal) {
    for (const float coatRoughness : {0.05f, 0.3f, 0.8f})
        for (const float mu : {0.4f, 0.8f, 1.0f}) {
            const Bsdf b = tiltedCoat(Bsdf{{1, 1, 1}, 0.0f, 0.5f, 1.0f, {1, 1, 1}, 1.0f, coatRoughness}, {0.2f, 0.1f, 0.97f});
            const Vec3f a = albedo(b, mu, 100000);
            EXPECT_LE(a.x, 1.01f) << "coat roughness " << coatRoughness << " mu " << mu;
            EXPECT_GE(a.x, 0.9f) << "coat roughness " << coatRoughness << " mu " << mu;
        }
    // Black base: only the coat reflects. wo along the tilted coat normal, against the untilted
    // coat seen head-on; both estimates count only directions above the base's horizon, which
    // a smooth coat's reflection about a normal 14 degrees off +z leaves.
    Bsdf black{{0, 0, 0}, 0.0f, 0.5f, 0.0f};
    black.clearcoat = 1.0f, black.clearcoatRoughness = 0.1f;
    const float* t = microfacetTables().data();
    const Vec3f n = normalize(Vec3f{0.2f, 0.1f, 0.97f});
    const Bsdf tilted = tiltedCoat(black, n);
    const float alongTilted = albedoTowards(tilted, n, 200000).x, straight = albedoTowards(black, {0, 0, 1}, 200000).x;
    EXPECT_NEAR(alongTilted, straight, 1e-3) << "tilted " << alongTilted;
    EXPECT_NEAR(straight, 0.04, 0.01);
    // The highlight follows the coat normal: the mirror direction of wo = +z about the tilted
    // normal reflects far more than the mirror direction about +z (wo itself).
    const Vec3f mirror = n * (2.0f * n.z) - Vec3f{0, 0, 1};
    EXPECT_GT(evalBsdf(tilted, {0, 0, 1}, mirror, t).f.x, 10.0f * evalBsdf(tilted, {0, 0, 1}, {0, 0, 1}, t).f.x);
}

// specularColorFactor 0 is not specularFactor 0: glTF's layer keeps F90 = specularFactor, so
// F0 = 0 leaves Schlick's grazing term (1 - cos)^5 alone. Over a black base: next to nothing
// at normal incidence (where specularFactor 0 gives exactly nothing), a visible share at grazing.
// KHR_materials_ior's F0: exactly the constant at glTF's default 1.5 (the default material's
// steps stay what they were), ((ior - 1) / (ior + 1))^2 elsewhere, 1 at the extension's 0.
TEST(Microfacet, IorSetsTheLayersF0) {
    EXPECT_EQ(iorF0(1.5f), kDielectricF0);
    EXPECT_FLOAT_EQ(iorF0(2.0f), 1.0f / 9.0f);
    EXPECT_FLOAT_EQ(iorF0(1.0f), 0.0f);
    EXPECT_FLOAT_EQ(iorF0(0.0f), 1.0f);
    Material m;
    m.ior = 0.99f;
    EXPECT_EQ(materialFactorProblem(m), "ior 0.99 is neither 0 nor in [1, 1000]");
    m.ior = 1000.0f;
    EXPECT_EQ(materialFactorProblem(m), "");
}

TEST(Microfacet, ZeroSpecularColourKeepsOnlyTheGrazingFresnel) {
    Bsdf colourless{{0, 0, 0}, 0.0f, 0.3f, 1.0f};
    colourless.specularColor = {0, 0, 0};
    const Bsdf layerless{{0, 0, 0}, 0.0f, 0.3f, 0.0f};
    EXPECT_EQ(albedo(layerless, 1.0f, 10000).x, 0.0f);
    EXPECT_LT(albedo(colourless, 1.0f, 100000).x, 0.005f);
    EXPECT_GT(albedo(colourless, 0.05f, 100000).x, 0.1f);
    // At normal incidence on the mirror direction the layer's Fresnel term is exactly 0.
    const Bsdf smooth{{0, 0, 0}, 0.0f, 0.0f, 1.0f, {0, 0, 0}};
    EXPECT_EQ(evalBsdf(smooth, {0, 0, 1}, {0, 0, 1}, microfacetTables().data()).f.x, 0.0f);
}

// The 1e-6 upper quantile of chi-square with k degrees of freedom (Wilson and Hilferty).
double chiSquareBound(double k) {
    const double z = 4.753, c = 2.0 / (9.0 * k);
    return k * std::pow(1.0 - c + z * std::sqrt(c), 3.0);
}

TEST(Microfacet, SamplesFollowTheReportedDensity) {
    const float* t = microfacetTables().data();
    constexpr uint32_t kCos = 16, kPhi = 32, kSub = 12, n = 400000;
    for (const Bsdf b : {Bsdf{{0.8f, 0.8f, 0.8f}, 0.0f, 0.5f, 1.0f}, Bsdf{{0.9f, 0.6f, 0.3f}, 1.0f, 0.35f, 1.0f},
                         Bsdf{{0.2f, 0.2f, 0.2f}, 0.3f, 0.8f, 0.5f},
                         Bsdf{{0.7f, 0.1f, 0.1f}, 0.0f, 0.6f, 1.0f, {1, 1, 1}, 1.0f, 0.3f},
                         Bsdf{{0.9f, 0.6f, 0.3f}, 1.0f, 0.7f, 1.0f, {1, 1, 1}, 0.5f, 0.4f},
                         tiltedCoat(Bsdf{{0.7f, 0.1f, 0.1f}, 0.0f, 0.6f, 1.0f, {1, 1, 1}, 1.0f, 0.3f}, {0.35f, -0.2f, 0.9f}),
                         tiltedCoat(Bsdf{{0.2f, 0.2f, 0.2f}, 0.0f, 0.5f, 1.0f, {1, 1, 1}, 1.0f, 0.15f}, {-0.5f, 0.1f, 0.8f})})
        for (const float mu : {0.3f, 0.85f}) {
            const Vec3f wo = outgoing(mu);
            // Bins of equal solid angle: uniform in cos(theta) and phi.
            std::vector<double> counts(kCos * kPhi, 0.0), expected(kCos * kPhi, 0.0);
            uint32_t below = 0;  // drawn below the surface (a specular reflection of a steep normal)
            for (uint32_t i = 0; i < n; ++i) {
                Vec3f wi, weight;
                float pdf;
                if (!sampleBsdf(b, wo, bsdfU01(i, 0), bsdfU01(i, 1), bsdfU01(i, 2), t, &wi, &weight, &pdf)) {
                    ++below;
                    continue;
                }
                // The bounce reports what evalBsdf gives next-event estimation's MIS for this
                // direction (the same steps; 1e-4 relative leaves room for fp contraction).
                const BsdfValue v = evalBsdf(b, wo, wi, t);
                ASSERT_NEAR(pdf, v.pdf, 1e-4f * pdf);
                ASSERT_NEAR(weight.x, v.f.x * wi.z / v.pdf, 1e-4f * weight.x);
                float phi = std::atan2(wi.y, wi.x);
                if (phi < 0) phi += 2 * kPi;
                const uint32_t x = std::min(uint32_t(phi / (2 * kPi) * kPhi), kPhi - 1);
                const uint32_t y = std::min(uint32_t(wi.z * kCos), kCos - 1);
                counts[y * kPhi + x] += 1;
            }
            // The density integrated over each bin (midpoint rule on kSub x kSub points).
            double total = 0;
            for (uint32_t y = 0; y < kCos; ++y)
                for (uint32_t x = 0; x < kPhi; ++x) {
                    double sum = 0;
                    for (uint32_t sy = 0; sy < kSub; ++sy)
                        for (uint32_t sx = 0; sx < kSub; ++sx) {
                            const double z = (y + (sy + 0.5) / kSub) / kCos;
                            const double phi = 2 * kPi * (x + (sx + 0.5) / kSub) / kPhi;
                            const double s = std::sqrt(std::fmax(0.0, 1.0 - z * z));
                            const Vec3f wi{float(s * std::cos(phi)), float(s * std::sin(phi)), float(z)};
                            sum += evalBsdf(b, wo, wi, t).pdf;
                        }
                    const double binArea = 2 * kPi / (double(kCos) * kPhi);
                    expected[y * kPhi + x] = sum / (kSub * kSub) * binArea;
                    total += expected[y * kPhi + x];
                }
            // Over the hemisphere the density integrates to the share not drawn below it.
            EXPECT_NEAR(total + double(below) / n, 1.0, 0.01) << "the density integrates to " << total;
            // Chi-square over bins expecting at least 5 samples; the rest pooled.
            double chi2 = 0, pooledCount = 0, pooledExpected = 0;
            uint32_t dof = 0;
            for (uint32_t i = 0; i < kCos * kPhi; ++i) {
                const double e = expected[i] * n;
                if (e < 5) {
                    pooledCount += counts[i], pooledExpected += e;
                    continue;
                }
                chi2 += (counts[i] - e) * (counts[i] - e) / e;
                ++dof;
            }
            if (pooledExpected >= 5) chi2 += (pooledCount - pooledExpected) * (pooledCount - pooledExpected) / pooledExpected, ++dof;
            std::printf("metallic %.1f roughness %.2f clearcoat %.1f (normal z %.2f) mu %.2f: chi-square %.1f over %u bins (bound %.1f)\n",
                        b.metallic, b.roughness, b.clearcoat, b.coatNormal.z, mu, chi2, dof, chiSquareBound(dof - 1));
            EXPECT_GT(dof, 50u);
            EXPECT_LT(chi2, chiSquareBound(dof - 1));
        }
}

TEST(Microfacet, TablesAreSaneAndTheLookupIsExactAtTheNodes) {
    const std::vector<float>& t = microfacetTables();
    ASSERT_EQ(t.size(), kMicrofacetTableFloats);
    for (uint32_t i = 0; i < t.size(); ++i) {
        EXPECT_TRUE(std::isfinite(t[i]));
        EXPECT_GT(t[i], 0.0f);
        // Albedos and their averages are fractions; the mixed term E + W / E is below 2.
        EXPECT_LE(t[i], (i < kMicrofacetMixAverageTable ? 1.0f : 2.0f) + 1e-5f) << "entry " << i;
    }
    // A smooth lobe loses nothing to masking; the roughest loses over half, at normal incidence
    // too (half its visible normals reflect below the surface there).
    EXPECT_GT(microfacetTableLookup(t.data() + kMicrofacetMetalTable, 0.5f, 0.0f), 0.999f);
    EXPECT_LT(microfacetTableLookup(t.data() + kMicrofacetMetalTable, 1.0f, 1.0f), 0.5f);
    const uint32_t n = kMicrofacetTableSide;
    EXPECT_EQ(microfacetTableLookup(t.data() + kMicrofacetDielectricTable, 7.0f / (n - 1), 12.0f / (n - 1)),
              t[kMicrofacetDielectricTable + 12 * n + 7]);
}

}  // namespace
}  // namespace vastray
