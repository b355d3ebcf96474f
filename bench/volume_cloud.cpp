// A cloud-sized density grid for the volume figures (docs/PERFORMANCE.md, "Volumes"): fractal
// value noise (fBm, 5 octaves) inside a sphere that fades to 0 before the grid's faces, N^3
// voxels, written as an OpenVDB float grid `density` (for `vastray import --volume`) and as the
// same voxels in Mitsuba 3's .vol format (for its `gridvolume`), so both renderers trace one grid.
//
//   usage: volume_cloud N OUT.vdb OUT.vol [cloud|box]
// box: density 1 at the voxels whose centre lies within |x|, |y|, |z| < 0.8, else 0 (a homogeneous
// cube whose trilinear edge ramps integrate as a step midway between the last voxel centre inside
// and the first outside: bench/mitsuba_volume.py's `homogeneous` medium fills that cube).
// The .vdb maps voxel ijk to the world point (ijk - N/2) * 2/N (the cloud spans [-1, 1]^3); the
// .vol is dense, x fastest, and Mitsuba places it with a `to_world` (bench/mitsuba_volume.py).
#include <openvdb/openvdb.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "BenchFlags.h"

namespace {

uint32_t hash(int32_t x, int32_t y, int32_t z, uint32_t octave) {
    uint32_t h = uint32_t(x) * 73856093u ^ uint32_t(y) * 19349663u ^ uint32_t(z) * 83492791u ^ octave * 2654435761u;
    h ^= h >> 16, h *= 0x7feb352du, h ^= h >> 15, h *= 0x846ca68bu, h ^= h >> 16;
    return h;
}

// Value noise in [0, 1]: lattice values blended with smoothstep weights.
float noise(float x, float y, float z, uint32_t octave) {
    const float fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
    const int32_t ix = int32_t(fx), iy = int32_t(fy), iz = int32_t(fz);
    auto smooth = [](float t) { return t * t * (3.0f - 2.0f * t); };
    const float u = smooth(x - fx), v = smooth(y - fy), w = smooth(z - fz);
    auto at = [&](int dx, int dy, int dz) { return float(hash(ix + dx, iy + dy, iz + dz, octave) >> 8) / 16777216.0f; };
    auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
    return lerp(lerp(lerp(at(0, 0, 0), at(1, 0, 0), u), lerp(at(0, 1, 0), at(1, 1, 0), u), v),
                lerp(lerp(at(0, 0, 1), at(1, 0, 1), u), lerp(at(0, 1, 1), at(1, 1, 1), u), v), w);
}

// The density at a point of [-1, 1]^3: fBm, thresholded, inside a sphere of radius 0.9 that fades out.
float density(float x, float y, float z) {
    const float r = std::sqrt(x * x + y * y + z * z);
    if (r >= 0.9f) return 0.0f;
    float sum = 0.0f, amplitude = 0.5f, frequency = 4.0f;
    for (uint32_t octave = 0; octave < 5; ++octave) {
        sum += amplitude * noise(x * frequency + 17.0f, y * frequency + 31.0f, z * frequency + 5.0f, octave);
        amplitude *= 0.5f, frequency *= 2.0f;
    }
    const float fade = std::fmin(1.0f, (0.9f - r) / 0.3f);
    return std::fmax(0.0f, (sum - 0.35f) * 2.5f) * fade;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string kind = argc == 5 ? argv[4] : "cloud";
    if ((argc != 4 && argc != 5) || (kind != "cloud" && kind != "box")) {
        std::fprintf(stderr, "usage: %s N OUT.vdb OUT.vol [cloud|box]\n", argv[0]);
        return 2;
    }
    const bool box = kind == "box";
    const int n = vastray::bench::FlagNumbers("volume_cloud", 2).get<int>("N", argv[1], 8, 2048);
    std::vector<float> voxels(size_t(n) * n * n);
    const float scale = 2.0f / float(n);
    tbb::parallel_for(0, n, [&](int k) {
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
            {
                const float x = (i - n / 2) * scale, y = (j - n / 2) * scale, z = (k - n / 2) * scale;
                voxels[(size_t(k) * n + j) * n + i] =
                    box ? (std::fabs(x) < 0.8f && std::fabs(y) < 0.8f && std::fabs(z) < 0.8f ? 1.0f : 0.0f) : density(x, y, z);
            }
    });
    openvdb::initialize();
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    {
        openvdb::FloatGrid::Accessor access = grid->getAccessor();
        for (int k = 0; k < n; ++k)
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i)
                    if (const float d = voxels[(size_t(k) * n + j) * n + i]; d > 0.0f) access.setValue({i, j, k}, d);
    }
    auto transform = openvdb::math::Transform::createLinearTransform(scale);
    transform->postTranslate({-1.0, -1.0, -1.0});
    grid->setTransform(transform);
    openvdb::io::File vdb(argv[2]);
    vdb.write({grid});
    vdb.close();
    // Mitsuba's .vol: "VOL", version 3, encoding 1 (float32), resolution, 1 channel, bounding box.
    std::ofstream vol(argv[3], std::ios::binary);
    const char header[4] = {'V', 'O', 'L', 3};
    vol.write(header, 4);
    const int32_t fields[5] = {1, n, n, n, 1};
    vol.write(reinterpret_cast<const char*>(fields), sizeof fields);
    const float bounds[6] = {-1, -1, -1, 1, 1, 1};
    vol.write(reinterpret_cast<const char*>(bounds), sizeof bounds);
    vol.write(reinterpret_cast<const char*>(voxels.data()), std::streamsize(voxels.size() * 4));
    uint64_t active = 0;
    double sum = 0;
    for (float d : voxels) active += d > 0.0f, sum += d;
    std::printf("{\"voxels\": %d, \"active\": %llu, \"mean_density\": %.6f}\n", n, (unsigned long long)active,
                sum / double(voxels.size()));
    return vol ? 0 : 1;
}
