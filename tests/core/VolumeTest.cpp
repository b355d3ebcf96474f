// Density volumes (core/Volume.h): trilinear lookups over bricks, delta tracking and ratio
// tracking against Beer-Lambert's law, the Henyey-Greenstein phase function's sampling, and the
// checks that refuse a volume a file could forge.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "../VolumeTestSupport.h"
#include "vastray/core/Sampling.h"
#include "vastray/core/VecMath.h"

namespace vastray {
namespace {

// Voxels [0, 31]^3 of density 1, half a world unit each, moved by (-3, 2, 5): a ray along x through
// the middle crosses 31 voxel steps of density 1 and two one-voxel ramps (trilinear): 32 voxels of
// optical length, 16 world units.
Volume box(float densityScale) {
    VolumeMaterial m;
    m.densityScale = densityScale;
    return test::makeVolume({0, 0, 0}, {31, 31, 31}, [](int32_t, int32_t, int32_t) { return 1.0f; }, 0.5f,
                            {-3, 2, 5}, m);
}

TEST(Volume, TrilinearDensityOverBricks) {
    const Volume v = test::makeVolume({-5, 0, 0}, {20, 3, 3}, [](int32_t i, int32_t j, int32_t k) {
        return float(i + 5) + 0.25f * float(j) + 0.5f * float(k);
    });
    EXPECT_EQ(v.origin[0], -8);
    EXPECT_EQ(volumeVoxel(v, -5, 1, 2), 0.25f + 1.0f);
    EXPECT_EQ(volumeVoxel(v, 20, 3, 3), 25.0f + 0.75f + 1.5f);
    EXPECT_EQ(volumeVoxel(v, 21, 0, 0), 0.0f);  // outside the voxels given
    // Between voxels (across the brick boundary at i = 0): linear in each axis.
    EXPECT_NEAR(volumeDensity(v, {-0.5f, 1.5f, 2.0f}), 4.5f + 0.375f + 1.0f, 1e-5);
    EXPECT_NEAR(volumeDensity(v, {7.25f, 0.0f, 0.0f}), 12.25f, 1e-5);
    // Half a voxel outside: half the edge voxel.
    EXPECT_NEAR(volumeDensity(v, {-5.5f, 0.0f, 0.0f}), 0.0f * 0.5f, 1e-6);
    EXPECT_NEAR(volumeDensity(v, {20.5f, 0.0f, 0.0f}), 25.0f * 0.5f, 1e-5);
    // Every point's density is below its cell's majorant.
    for (float x = -9.0f; x < 24.0f; x += 0.37f) {
        const Vec3f p{x, 1.3f, 2.9f};
        const int64_t cell = int64_t(std::floor((x - v.origin[0]) / 8.0f));
        if (cell < 0 || cell >= int64_t(v.brickCells[0])) continue;
        EXPECT_LE(volumeDensity(v, p), v.majorant[uint64_t(cell)]) << x;
    }
}

// Transmittance through a homogeneous slab is exp(-sigma * length): ratio tracking's mean, and the
// share of free flights that pass, over 20,000 paths.
// An emission grid in the density's bricks: trilinear like the density, times the material's
// emission, at world points; none without a grid.
TEST(Volume, EmissionIsTrilinearInTheDensitysBricks) {
    VolumeMaterial m;
    m.emission = {2.0f, 1.0f, 0.5f};
    Volume v = test::makeVolume({0, 0, 0}, {15, 7, 7}, [](int32_t, int32_t, int32_t) { return 1.0f; }, 0.5f, {1, 0, 0}, m);
    EXPECT_EQ(volumeEmission(v, {3, 1, 1}).x, 0.0f);
    v.emissionVoxels.assign(v.voxels.size(), 0.0f);
    for (int32_t i = 0; i <= 15; ++i) {  // the emission grid rises along x: voxel i has i
        const uint32_t brick = v.brickOf[uint64_t((i - v.origin[0]) / 8) + v.brickCells[0] * (uint64_t(-v.origin[1] / 8) + v.brickCells[1] * uint64_t(-v.origin[2] / 8))];
        v.emissionVoxels[uint64_t(brick) * kVolumeBrickVoxels + uint64_t(i % 8) + 8 * (2 + 8 * 3)] = float(i);
    }
    EXPECT_EQ(checkVolume(v), "");
    // Index (7.5, 2, 3) is world (1 + 3.75, 1, 1.5): halfway between voxels 7 and 8.
    const Vec3f e = volumeEmission(v, {4.75f, 1.0f, 1.5f});
    EXPECT_NEAR(e.x, 2.0f * 7.5f, 1e-4);
    EXPECT_NEAR(e.y, 1.0f * 7.5f, 1e-4);
    EXPECT_NEAR(e.z, 0.5f * 7.5f, 1e-4);
    v.emissionVoxels[5] = std::nanf("");
    EXPECT_NE(checkVolume(v).find("emission voxel 5"), std::string::npos);
    v.emissionVoxels.pop_back();
    EXPECT_NE(checkVolume(v).find("one voxel per density voxel"), std::string::npos);
}

TEST(Volume, HomogeneousSlabFollowsBeerLambert) {
    const float sigma = 1.5f / 16.0f;  // optical depth 1.5 across the box
    const std::vector<Volume> volumes{box(sigma)};
    const Vec3f origin{-20.0f, 2.0f + 8.0f, 5.0f + 8.0f}, direction{1, 0, 0};
    const double expected = std::exp(-1.5);
    const int n = 20000;
    double sum = 0;
    int passed = 0;
    for (int i = 0; i < n; ++i) {
        uint32_t counter = 0;
        const RandomKey key{uint32_t(i), 0, 0};
        sum += volumeTransmittance(volumes, origin, direction, 1e30f, key, 7, &counter);
        counter = 0;
        VolumeCollision c;
        if (!sampleVolumeCollision(volumes, origin, direction, 1e30f, key, 8, &counter, &c)) ++passed;
    }
    const double sigmaOfMean = std::sqrt(expected * (1 - expected) / n);
    std::printf("transmittance %.5f, passed %.5f, expected %.5f (+-%.5f)\n", sum / n, double(passed) / n, expected,
                sigmaOfMean);
    EXPECT_NEAR(sum / n, expected, 4 * sigmaOfMean);
    EXPECT_NEAR(double(passed) / n, expected, 4 * sigmaOfMean);
    // A ray that stops inside the box: half the optical depth to the box's middle.
    sum = 0;
    for (int i = 0; i < n; ++i) {
        uint32_t counter = 0;
        sum += volumeTransmittance(volumes, origin, direction, 20.0f - 3.0f + 7.75f, {uint32_t(i), 1, 0}, 7, &counter);
    }
    EXPECT_NEAR(sum / n, std::exp(-0.75), 4 * sigmaOfMean);
    // Beyond tMax nothing collides, and a ray that misses the box sees nothing.
    uint32_t counter = 0;
    VolumeCollision c;
    EXPECT_FALSE(sampleVolumeCollision(volumes, origin, direction, 16.0f, {1, 0, 0}, 1, &counter, &c));
    EXPECT_EQ(volumeTransmittance(volumes, {-20, 40, 13}, direction, 1e30f, {1, 0, 0}, 1, &counter), 1.0f);
}

// A density rising linearly along x (voxel i has i / 31): optical length 16 voxels (trapezoids,
// and the half voxel of the ramp past the last); both estimators agree with exp(-tau).
TEST(Volume, HeterogeneousDensityFollowsItsOpticalDepth) {
    VolumeMaterial m;
    m.densityScale = 0.125f;  // tau = 0.125 * 16 voxels * 1 world unit = 2
    const std::vector<Volume> volumes{test::makeVolume(
        {0, 0, 0}, {31, 15, 15}, [](int32_t i, int32_t, int32_t) { return float(i) / 31.0f; }, 1.0f, {0, 0, 0}, m)};
    const double expected = std::exp(-2.0);
    const int n = 20000;
    double ratio = 0;
    int passed = 0;
    for (int i = 0; i < n; ++i) {
        uint32_t counter = 0;
        const RandomKey key{uint32_t(i), 3, 1};
        ratio += volumeTransmittance(volumes, {-5, 7.5f, 7.5f}, {1, 0, 0}, 1e30f, key, 11, &counter);
        counter = 0;
        VolumeCollision c;
        if (!sampleVolumeCollision(volumes, {-5, 7.5f, 7.5f}, {1, 0, 0}, 1e30f, key, 12, &counter, &c)) ++passed;
    }
    const double sigmaOfMean = std::sqrt(expected * (1 - expected) / n);
    std::printf("heterogeneous: ratio %.5f, passed %.5f, expected %.5f\n", ratio / n, double(passed) / n, expected);
    EXPECT_NEAR(ratio / n, expected, 4 * sigmaOfMean);
    EXPECT_NEAR(double(passed) / n, expected, 4 * sigmaOfMean);
}

// Two volumes overlap: the nearest of their free flights samples the summed extinction, and the
// share of collisions in each follows its share of it.
TEST(Volume, OverlappingVolumesAddTheirExtinction) {
    std::vector<Volume> volumes{box(0.5f / 16.0f), box(1.0f / 16.0f)};
    const int n = 20000;
    int passed = 0, inSecond = 0;
    for (int i = 0; i < n; ++i) {
        uint32_t counter = 0;
        VolumeCollision c;
        if (!sampleVolumeCollision(volumes, {-20.0f, 10.0f, 13.0f}, {1, 0, 0}, 1e30f, {uint32_t(i), 0, 0}, 5, &counter, &c))
            ++passed;
        else
            inSecond += c.volume == 1;
    }
    const double expected = std::exp(-1.5);
    EXPECT_NEAR(double(passed) / n, expected, 4 * std::sqrt(expected * (1 - expected) / n));
    const double collided = n - passed;
    EXPECT_NEAR(inSecond / collided, 2.0 / 3.0, 4 * std::sqrt(2.0 / 9.0 / collided));
}

TEST(Volume, HenyeyGreensteinSamplesItsDensity) {
    const Vec3f travel = normalize(Vec3f{0.3f, -0.5f, 0.8f});
    for (float g : {-0.4f, 0.0f, 0.7f}) {
        // The density integrates to 1 over the sphere (in cos theta, times 2 pi).
        double integral = 0;
        const int steps = 20000;
        const Frame frame = frameAround(travel);
        for (int i = 0; i < steps; ++i) {
            const float c = -1.0f + 2.0f * (float(i) + 0.5f) / steps;
            integral += henyeyGreenstein(g, travel, frame.toWorld({std::sqrt(1 - c * c), 0, c})) * 2.0 * kPi * 2.0 / steps;
        }
        EXPECT_NEAR(integral, 1.0, 2e-3) << g;
        // The mean cosine of the sampled directions is g; in bins of cos theta, the counts follow the density.
        const int n = 40000, bins = 10;
        std::vector<int> counts(bins, 0);
        double cosines = 0;
        for (int i = 0; i < n; ++i) {
            const Vec3f d = sampleHenyeyGreenstein(g, travel, randomFloat({uint32_t(i), 0, 0}, 2, 3),
                                                   randomFloat({uint32_t(i), 0, 0}, 3, 3));
            ASSERT_NEAR(length(d), 1.0f, 1e-5f);
            const float c = dot(travel, d);
            cosines += c;
            counts[std::min(bins - 1, int((c + 1.0f) * 0.5f * bins))]++;
        }
        EXPECT_NEAR(cosines / n, g, 0.01) << g;
        double chi2 = 0;
        for (int b = 0; b < bins; ++b) {
            double p = 0;  // the bin's probability: the density over its cosines, times 2 pi
            for (int s = 0; s < 200; ++s) {
                const float c = -1.0f + 2.0f * (b + (s + 0.5f) / 200.0f) / bins;
                p += henyeyGreenstein(g, travel, frame.toWorld({std::sqrt(1 - c * c), 0, c})) * 2.0 * kPi * (2.0 / bins) / 200;
            }
            chi2 += (counts[b] - n * p) * (counts[b] - n * p) / (n * p);
        }
        EXPECT_LT(chi2, 30.0) << g;  // 9 degrees of freedom: 30 is far in the tail
    }
}

TEST(Volume, ChecksRefuseWhatAFileCouldForge) {
    const Volume good = box(1.0f);
    EXPECT_EQ(checkVolume(good), "");
    auto refused = [&](const std::function<void(Volume&)>& change, const char* words) {
        Volume v = good;
        change(v);
        const std::string problem = checkVolume(v);
        EXPECT_NE(problem.find(words), std::string::npos) << "'" << problem << "' lacks '" << words << "'";
    };
    refused([](Volume& v) { v.brickOf[3] = uint32_t(v.brickCount()); }, "names brick");
    refused([](Volume& v) { v.voxels[7] = std::nanf(""); }, "voxel 7");
    refused([](Volume& v) { v.voxels[9] = -1.0f; }, "not in [0, 1e18]");
    refused([](Volume& v) { v.material.albedo[1] = 1.5f; }, "albedo");
    refused([](Volume& v) { v.material.anisotropy = 1.0f; }, "anisotropy");
    refused([](Volume& v) { v.material.densityScale = std::numeric_limits<float>::infinity(); }, "density scale");
    refused([](Volume& v) { v.origin[1] = 3; }, "multiple of 8");
    refused([](Volume& v) { v.origin[2] = std::numeric_limits<int32_t>::max() - 7; }, "32-bit");
    refused([](Volume& v) { v.brickCells[0] = 0; }, "no cells");
    refused([](Volume& v) { v.brickCells = {1u << 9, 1u << 9, 1u << 9}; }, "more than the limit");
    refused([](Volume& v) { v.brickOf.pop_back(); }, "one entry per cell");
    refused([](Volume& v) { v.voxels.pop_back(); }, "whole bricks");
    Volume singular = good;
    singular.indexToWorld = {1, 0, 0, 0, 2, 0, 0, 0, 0, 0, 0, 0};
    EXPECT_FALSE(finishVolumeTransform(singular));
    singular.indexToWorld = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, std::nanf("")};
    EXPECT_FALSE(finishVolumeTransform(singular));
}

// A hostile density (1e18 per voxel, scale 1e18) cannot hang tracking: it stops after
// kMaxVolumeSteps tentative collisions.
TEST(Volume, HostileDensityEndsTracking) {
    VolumeMaterial m;
    m.densityScale = 1e18f;
    const std::vector<Volume> volumes{
        test::makeVolume({0, 0, 0}, {7, 7, 7}, [](int32_t i, int32_t, int32_t) { return i == 3 ? 1e18f : 1e-3f; }, 1.0f,
                         {0, 0, 0}, m)};
    uint32_t counter = 0;
    EXPECT_EQ(volumeTransmittance(volumes, {-1, 3.5f, 3.5f}, {1, 0, 0}, 1e30f, {0, 0, 0}, 1, &counter), 0.0f);
    EXPECT_LE(counter, 2 * kMaxVolumeSteps + 2);
    counter = 0;
    VolumeCollision c;
    EXPECT_TRUE(sampleVolumeCollision(volumes, {-1, 3.5f, 3.5f}, {1, 0, 0}, 1e30f, {0, 0, 0}, 1, &counter, &c));
    EXPECT_LE(counter, 2 * kMaxVolumeSteps + 2);
}

}  // namespace
}  // namespace vastray

namespace vastray {
namespace {

// A brick table names stored bricks or none, each brick for one cell only: checkVolume and the
// package reader refuse a table where two cells share a brick (the paged pool keeps a brick where
// its one cell is, so a second cell would stay absent) or a cell names a brick beyond the stored ones.
TEST(Volume, BrickTableNamesEachBrickForOneCellOnly) {
    const std::vector<uint32_t> sound = {kNoBrick, 1, 0, kNoBrick, 2};
    EXPECT_EQ(checkBrickTable(sound, 3), "");
    EXPECT_EQ(checkBrickTable(sound, 2), "cell 4 names brick 2 of 2");
    const std::vector<uint32_t> shared = {kNoBrick, 1, 0, 1, 2};
    EXPECT_EQ(checkBrickTable(shared, 3), "cells 1 and 3 both name brick 1 (a brick belongs to one cell)");
    EXPECT_EQ(checkBrickTable({}, 0), "");
}

}  // namespace
}  // namespace vastray
