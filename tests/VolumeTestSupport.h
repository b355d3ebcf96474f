#pragma once
// Volumes built in code for tests (core/Volume.h): voxels from a function over an index box,
// in bricks as the importer stores them, with majorants and the world map finished.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "vastray/core/RenderOptions.h"
#include "vastray/core/Volume.h"

namespace vastray::test {

// A narrow view straight down (-y) at the origin over a black world without sun, 16 x 16 pixels
// at 128 spp: what a glowing slab alone gives (the glowing-slab tests).
inline RenderOptions glowingSlabView() {
    RenderOptions o;
    o.width = o.height = 16;
    o.samplesPerPixel = 128;
    o.frameScene = false;
    o.camera.eye = {0.01f, 5, 0.02f};
    o.camera.target = {0.01f, -5, 0.02f};
    o.camera.up = {0, 0, 1};
    o.camera.fovYDegrees = 1.0f;
    o.environment.zenith = o.environment.horizon = o.environment.ground = {0, 0, 0};
    o.environment.sunIrradiance = {0, 0, 0};
    return o;
}

// Voxels ijk in [lo, hi] (inclusive) take density(i, j, k); index space maps to the world by
// scale * ijk + translation.
inline Volume makeVolume(std::array<int32_t, 3> lo, std::array<int32_t, 3> hi,
                         const std::function<float(int32_t, int32_t, int32_t)>& density, float scale = 1.0f,
                         Vec3f translation = {0, 0, 0}, VolumeMaterial material = {}) {
    Volume v;
    v.name = "test";
    v.material = material;
    const int32_t b = int32_t(kVolumeBrickSize);
    for (int a = 0; a < 3; ++a) {
        // Points in (lo - 1, hi + 1) can have density: the grid covers them.
        v.origin[a] = int32_t(std::floor(double(lo[a] - 1) / b)) * b;
        v.brickCells[a] = uint32_t((hi[a] + 1 - v.origin[a]) / b + 1);
    }
    v.brickOf.assign(v.cellCount(), kNoBrick);
    for (uint32_t cz = 0; cz < v.brickCells[2]; ++cz)
        for (uint32_t cy = 0; cy < v.brickCells[1]; ++cy)
            for (uint32_t cx = 0; cx < v.brickCells[0]; ++cx) {
                std::vector<float> brick(kVolumeBrickVoxels, 0.0f);
                bool any = false;
                for (int32_t z = 0; z < b; ++z)
                    for (int32_t y = 0; y < b; ++y)
                        for (int32_t x = 0; x < b; ++x) {
                            const int32_t i = v.origin[0] + int32_t(cx) * b + x, j = v.origin[1] + int32_t(cy) * b + y,
                                          k = v.origin[2] + int32_t(cz) * b + z;
                            if (i < lo[0] || j < lo[1] || k < lo[2] || i > hi[0] || j > hi[1] || k > hi[2]) continue;
                            const float d = density(i, j, k);
                            brick[x + b * (y + b * z)] = d;
                            any = any || d != 0.0f;
                        }
                if (!any) continue;
                v.brickOf[cx + v.brickCells[0] * (cy + v.brickCells[1] * cz)] = uint32_t(v.brickCount());
                v.voxels.insert(v.voxels.end(), brick.begin(), brick.end());
            }
    v.indexToWorld = {scale, 0, 0, translation.x, 0, scale, 0, translation.y, 0, 0, scale, translation.z};
    EXPECT_TRUE(finishVolumeTransform(v));
    computeVolumeMajorants(v);
    EXPECT_EQ(checkVolume(v), "");
    return v;
}

}  // namespace vastray::test
