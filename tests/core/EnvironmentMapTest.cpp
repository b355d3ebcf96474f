// The environment map's lookup and importance sampling (core/EnvironmentMap.h): samples follow
// the stated density (a chi-square test over the texels, as Mitsuba's test suite checks its
// samplers), the density integrates to one over the sphere and is the one the lookup reports,
// and hostile maps are refused by name.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "vastray/core/EnvironmentMap.h"
#include "vastray/core/Random.h"
#include "vastray/core/Sampling.h"
#include "vastray/core/VecMath.h"

namespace vastray {
namespace {

constexpr uint32_t kW = 16, kH = 8;

// A map with every kind of texel: black rows and columns, a bright spot, a gradient.
std::shared_ptr<const EnvironmentMap> variedMap() {
    std::vector<float> r(kW * kH), g(kW * kH), b(kW * kH);
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            const uint32_t i = y * kW + x;
            const float v = (x == 3) ? 0.0f : 0.1f + 0.05f * float(x) + 0.2f * float(y % 3);
            r[i] = v, g[i] = 0.5f * v, b[i] = (y == 6) ? 0.0f : 2.0f * v;
            if (y == 2) r[i] = g[i] = b[i] = 0.0f;  // a black row
            if (x == 11 && y == 1) r[i] = g[i] = b[i] = 50.0f;
        }
    auto map = makeEnvironmentMap("varied", kW, kH, r, g, b);
    EXPECT_TRUE(map) << map.message();
    return *map;
}

float envU01(uint32_t i, uint32_t d) { return randomFloat({i, 0, 0}, d, 1234); }

TEST(EnvironmentMap, SamplesFollowTheTexelWeights) {
    const auto map = variedMap();
    const Frame frame = environmentFrame({0, 1, 0}, 30.0f);  // a turned map: the frame is all that counts
    const Vec3f up = frame.normal;
    const uint32_t n = 400000;
    std::vector<double> counts(kW * kH, 0.0);
    // A direction drawn within float rounding of a texel's edge may look up its neighbour.
    uint32_t elsewhere = 0;
    for (uint32_t i = 0; i < n; ++i) {
        const EnvironmentSample s = sampleEnvironment(*map, frame, envU01(i, 0), envU01(i, 1));
        ASSERT_GT(s.pdf, 0.0f);
        // The lookup and the density at the drawn direction are the sample's.
        const Vec3f looked = environmentRadiance(*map, frame, s.direction);
        const float pdf = environmentPdf(*map, frame, s.direction);
        if (looked.x != s.radiance.x || looked.z != s.radiance.z || std::fabs(pdf - s.pdf) > 1e-3f * s.pdf) ++elsewhere;
        const Frame& f = frame;
        float phi = std::atan2(dot(s.direction, f.bitangent), dot(s.direction, f.tangent));
        if (phi < 0) phi += 2 * kPi;
        const uint32_t x = std::min(uint32_t(phi / (2 * kPi) * kW), kW - 1);
        const uint32_t y = std::min(uint32_t(std::acos(std::clamp(dot(s.direction, up), -1.0f, 1.0f)) / kPi * kH), kH - 1);
        counts[y * kW + x] += 1;
    }
    // Expected probability of each texel: mean RGB times sin(theta) at its centre, normalized.
    std::vector<double> expected(kW * kH);
    double total = 0;
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            const uint32_t i = y * kW + x;
            const double mean = (double(map->rgb[3 * i]) + map->rgb[3 * i + 1] + map->rgb[3 * i + 2]) / 3.0;
            expected[i] = mean * std::sin(kPi * (y + 0.5) / kH);
            total += expected[i];
        }
    double chi2 = 0;
    uint32_t dof = 0;
    for (uint32_t i = 0; i < kW * kH; ++i) {
        const double e = expected[i] / total * n;
        if (e == 0.0) {
            EXPECT_LE(counts[i], double(elsewhere)) << "texel " << i << " has no light and must never be drawn";
            continue;
        }
        chi2 += (counts[i] - e) * (counts[i] - e) / e;
        ++dof;
    }
    // dof - 1 degrees of freedom (~100): the 1e-6 quantile is below 190.
    std::printf("chi-square %.1f over %u texels; %u of %u samples looked up elsewhere\n", chi2, dof, elsewhere, n);
    EXPECT_LE(elsewhere, n / 10000);
    EXPECT_LT(chi2, 190.0);
    EXPECT_GT(dof, 80u);
}

TEST(EnvironmentMap, DensityIntegratesToOneOverTheSphere) {
    for (const Vec3f up : {Vec3f{0, 1, 0}, Vec3f{0, 0, 1}, normalize(Vec3f{1, -2, 0.5f})}) {
        const auto map = variedMap();
        const Frame frame = environmentFrame(up, up.z == 1.0f ? -100.0f : 0.0f);
        // Uniform directions on the sphere: E[pdf / (1 / 4 pi)] = 1.
        const uint32_t n = 400000;
        double sum = 0, squares = 0;
        for (uint32_t i = 0; i < n; ++i) {
            const float z = 1.0f - 2.0f * envU01(i, 2), phi = 2 * kPi * envU01(i, 3);
            const float r = std::sqrt(std::fmax(0.0f, 1 - z * z));
            const double value = double(environmentPdf(*map, frame, {r * std::cos(phi), r * std::sin(phi), z})) * 4 * kPi;
            sum += value, squares += value * value;
        }
        const double mean = sum / n, standardError = std::sqrt((squares / n - mean * mean) / n);
        std::printf("integral %.4f, standard error %.4f\n", mean, standardError);
        EXPECT_LT(standardError, 0.02);
        EXPECT_NEAR(mean, 1.0, 5 * standardError) << up.x << "," << up.y << "," << up.z;
    }
}

TEST(EnvironmentMap, TopRowIsTheZenithAndAzimuthStartsAtTheTangent) {
    std::vector<float> r(4 * 2, 0.0f), g(8, 0.0f), b(8, 0.0f);
    r[0] = 1;           // row 0 (zenith side), column 0: phi in [0, 90) degrees
    g[4 + 2] = 1;       // row 1 (nadir side), column 2: phi in [180, 270)
    auto map = makeEnvironmentMap("tiny", 4, 2, r, g, b);
    ASSERT_TRUE(map) << map.message();
    for (const Vec3f up : {Vec3f{0, 1, 0}, Vec3f{0, 0, 1}}) {
        const Frame f = frameAround(up), same = environmentFrame(up, 0.0f);
        EXPECT_EQ(same.tangent, f.tangent);
        EXPECT_EQ(same.bitangent, f.bitangent);
        const Vec3f northEast = normalize(up + f.tangent + f.bitangent * 0.5f);
        EXPECT_EQ(environmentRadiance(**map, f, northEast).x, 1.0f);
        const Vec3f southWest = normalize(up * -1.0f - f.tangent - f.bitangent * 0.5f);
        EXPECT_EQ(environmentRadiance(**map, f, southWest).y, 1.0f);
        EXPECT_EQ(environmentRadiance(**map, f, up * -1.0f).x, 0.0f);
        // --environment-rotate 90 turns the map by one of its four columns: what lay at azimuth
        // phi + 90 degrees of the unturned frame now reads column 0.
        const Frame turned = environmentFrame(up, 90.0f);
        const float phi = 30.0f * kPi / 180.0f + kPi / 2;
        const Vec3f d = normalize(up + f.tangent * std::cos(phi) + f.bitangent * std::sin(phi));
        EXPECT_EQ(environmentRadiance(**map, turned, d).x, 1.0f);
        EXPECT_EQ(environmentRadiance(**map, f, d).x, 0.0f);
    }
}

TEST(EnvironmentMap, BlackMapIsNotSampled) {
    std::vector<float> zero(6, 0.0f);
    auto map = makeEnvironmentMap("black", 3, 2, zero, zero, zero);
    ASSERT_TRUE(map) << map.message();
    EXPECT_FALSE((*map)->sampleable);
    const Frame frame = frameAround({0, 1, 0});
    EXPECT_EQ(sampleEnvironment(**map, frame, 0.3f, 0.7f).pdf, 0.0f);
    EXPECT_EQ(environmentPdf(**map, frame, {1, 0, 0}), 0.0f);
}

TEST(EnvironmentMap, HostileMapsAreRefusedByName) {
    std::vector<float> one(4, 1.0f);
    auto expectError = [](const Result<std::shared_ptr<const EnvironmentMap>>& r, const std::string& part) {
        ASSERT_FALSE(r);
        EXPECT_NE(r.message().find(part), std::string::npos) << r.message();
        EXPECT_NE(r.message().find("sky.exr"), std::string::npos) << r.message();
    };
    std::vector<float> bad = one;
    bad[3] = std::nanf("");
    expectError(makeEnvironmentMap("sky.exr", 2, 2, one, bad, one), "texel (1, 1) channel G");
    bad[3] = -1.0f;
    expectError(makeEnvironmentMap("sky.exr", 2, 2, one, one, bad), "texel (1, 1) channel B");
    bad[3] = INFINITY;
    expectError(makeEnvironmentMap("sky.exr", 2, 2, bad, one, one), "channel R");
    expectError(makeEnvironmentMap("sky.exr", 2, 2, one, one, one, 1e18f * 10), "scale");
    expectError(makeEnvironmentMap("sky.exr", 2, 2, one, one, one, -1.0f), "scale");
    std::vector<float> big(4, 1e17f);
    expectError(makeEnvironmentMap("sky.exr", 2, 2, big, big, big, 100.0f), "scaled by");
    expectError(makeEnvironmentMap("sky.exr", 0, 2, {}, {}, {}), "outside the limits");
    expectError(makeEnvironmentMap("sky.exr", kMaxEnvironmentSide + 1, 1, one, one, one), "outside the limits");
    expectError(makeEnvironmentMap("sky.exr", 16384, 8192, one, one, one), "outside the limits");
    expectError(makeEnvironmentMap("sky.exr", 2, 3, one, one, one), "R, G and B channels of 2x3");
}

TEST(EnvironmentMap, PowerHeuristic) {
    EXPECT_EQ(powerHeuristic(0.0f, 1.0f), 0.0f);
    EXPECT_EQ(powerHeuristic(1.0f, 0.0f), 1.0f);
    EXPECT_FLOAT_EQ(powerHeuristic(1.0f, 1.0f), 0.5f);
    EXPECT_FLOAT_EQ(powerHeuristic(3.0f, 1.0f) + powerHeuristic(1.0f, 3.0f), 1.0f);
    EXPECT_EQ(powerHeuristic(1e-30f, 1e30f), 0.0f);  // no overflow into NaN
    EXPECT_EQ(powerHeuristic(1e30f, 1e-30f), 1.0f);
}

}  // namespace
}  // namespace vastray
