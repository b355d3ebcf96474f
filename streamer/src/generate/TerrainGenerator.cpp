// Height field over x, z in [-1, 1]^2 (y up): fBm of seeded 2-D gradient noise on a regular
// grid of cx * cz cells, two triangles per cell.
#include <algorithm>
#include <climits>
#include <cmath>

#include "generate/BatchPipeline.h"
#include "generate/Generators.h"
#include "generate/Random.h"

namespace vastray::gen {
namespace {

constexpr int kOctaves = 5;
constexpr float kBaseFrequency = 2.0f;  // noise cells per unit of x or z at octave 0
constexpr float kMaxHeight = 0.4f;
constexpr uint64_t kBatchVertices = 1 << 16;  // heights per parallel batch (two in flight)

struct Grid {
    uint64_t cellsX, cellsZ;
};

Grid gridFor(uint64_t triangles) {
    double cells = static_cast<double>(triangles) / 2.0;
    auto cx = static_cast<uint64_t>(std::llround(std::sqrt(cells)));
    cx = std::max<uint64_t>(cx, 1);
    auto cz = static_cast<uint64_t>(std::llround(cells / static_cast<double>(cx)));
    return {cx, std::max<uint64_t>(cz, 1)};
}

float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }

// fBm of Perlin-style gradient noise. Neighbouring grid vertices mostly fall in the same
// noise cell, so each octave keeps the 4 gradients of the last cell it visited: hashing
// drops from 4 per octave per vertex to about 4 per cell. One instance per thread.
class TerrainNoise {
public:
    explicit TerrainNoise(uint64_t seed) {
        for (int octave = 0; octave < kOctaves; ++octave) {
            octaves_[octave].seed = hashCombine(seed, static_cast<uint64_t>(octave));
        }
    }

    // Height in [0, kMaxHeight] at (x, z) in [-1, 1]^2.
    float height(float x, float z) {
        float sum = 0.0f, amplitude = 1.0f, frequency = kBaseFrequency, norm = 0.0f;
        for (Octave& octave : octaves_) {
            sum += amplitude * noise(octave, x * frequency, z * frequency);
            norm += amplitude;
            amplitude *= 0.5f;
            frequency *= 2.0f;
        }
        // sum / norm stays mostly within +-0.45 (measured over seeds): stretch to use most of
        // [0, kMaxHeight], and clamp the rare peaks (flat tops are still valid triangles).
        float n = std::clamp(2.2f * sum / norm, -1.0f, 1.0f);
        return 0.5f * kMaxHeight * (n + 1.0f);
    }

private:
    struct Octave {
        uint64_t seed = 0;
        int64_t ix = INT64_MIN, iz = INT64_MIN;  // cell whose gradients are cached
        float gx[2][2] = {}, gz[2][2] = {};      // [dz][dx]
    };

    // Gradient with random components in [-1, 1]; no trig (libm sin/cos differ between
    // machines). Distinct odd multipliers keep (ix, iz) pairs apart before the avalanche.
    static void gradient(uint64_t seed, int64_t ix, int64_t iz, float& gx, float& gz) {
        uint64_t h = mix64(seed ^ (static_cast<uint64_t>(ix) * 0x9E3779B97F4A7C15ull) ^
                           (static_cast<uint64_t>(iz) * 0xC2B2AE3D27D4EB4Full));
        gx = static_cast<float>(h >> 40) * 0x1p-23f - 1.0f;
        gz = static_cast<float>((h >> 16) & 0xFFFFFF) * 0x1p-23f - 1.0f;
    }

    static float noise(Octave& o, float x, float z) {
        float fx = std::floor(x), fz = std::floor(z);
        auto ix = static_cast<int64_t>(fx), iz = static_cast<int64_t>(fz);
        if (ix != o.ix || iz != o.iz) {
            o.ix = ix;
            o.iz = iz;
            for (int dz = 0; dz < 2; ++dz) {
                for (int dx = 0; dx < 2; ++dx) gradient(o.seed, ix + dx, iz + dz, o.gx[dz][dx], o.gz[dz][dx]);
            }
        }
        float tx = x - fx, tz = z - fz;
        float dot[2][2];
        for (int dz = 0; dz < 2; ++dz) {
            for (int dx = 0; dx < 2; ++dx) {
                dot[dz][dx] = o.gx[dz][dx] * (tx - static_cast<float>(dx)) +
                              o.gz[dz][dx] * (tz - static_cast<float>(dz));
            }
        }
        float u = fade(tx), v = fade(tz);
        float front = dot[0][0] + (dot[0][1] - dot[0][0]) * u;
        float back = dot[1][0] + (dot[1][1] - dot[1][0]) * u;
        return front + (back - front) * v;
    }

    Octave octaves_[kOctaves];
};

// In double so that the last vertex lands exactly on +1 and no two columns collide.
float gridCoordinate(uint64_t index, uint64_t cells) {
    return static_cast<float>(-1.0 + 2.0 * static_cast<double>(index) / static_cast<double>(cells));
}

// Walks grid vertices in row-major order from a flat index, without a division per vertex.
class GridCursor {
public:
    GridCursor(const Grid& grid, uint64_t vertex)
        : grid_(grid), i_(vertex % (grid.cellsX + 1)), k_(vertex / (grid.cellsX + 1)) {}
    float x() const { return gridCoordinate(i_, grid_.cellsX); }
    float z() const { return gridCoordinate(k_, grid_.cellsZ); }
    void advance() {
        if (++i_ > grid_.cellsX) {
            i_ = 0;
            ++k_;
        }
    }

private:
    const Grid& grid_;
    uint64_t i_, k_;
};

// Heights are computed in parallel batches of kBatchVertices (row-major vertex order) and
// streamed in order; each depends only on its grid position.
Status emitVertices(const Grid& grid, uint64_t seed, MeshSink& sink) {
    auto fill = [&grid, seed](uint64_t first, uint64_t count, float* out) {
        TerrainNoise noise(seed);
        GridCursor at(grid, first);
        for (uint64_t v = 0; v < count; ++v, at.advance()) out[v] = noise.height(at.x(), at.z());
    };
    auto emit = [&sink, at = GridCursor(grid, 0)](const float* heights, uint64_t count) mutable {
        for (uint64_t v = 0; v < count; ++v, at.advance())
            VASTRAY_TRY(sink.vertex({at.x(), heights[v], at.z()}));
        return Status::ok();
    };
    return runBatchPipeline<float>((grid.cellsX + 1) * (grid.cellsZ + 1), kBatchVertices, fill, emit);
}

// (vertex, its +z neighbour, its +x neighbour) is counter-clockwise seen from +y, so every
// normal points up whatever the heights.
Status emitFaces(const Grid& grid, MeshSink& sink) {
    const uint64_t rowLength = grid.cellsX + 1;
    for (uint64_t k = 0; k < grid.cellsZ; ++k) {
        for (uint64_t i = 0; i < grid.cellsX; ++i) {
            auto v00 = static_cast<uint32_t>(k * rowLength + i);
            uint32_t v10 = v00 + 1;
            auto v01 = static_cast<uint32_t>(v00 + rowLength);
            uint32_t v11 = v01 + 1;
            VASTRAY_TRY(sink.face(v00, v01, v10));
            VASTRAY_TRY(sink.face(v10, v01, v11));
        }
    }
    return Status::ok();
}

}  // namespace

GeneratedCounts terrainCounts(uint64_t triangles) {
    Grid grid = gridFor(triangles);
    return {(grid.cellsX + 1) * (grid.cellsZ + 1), 2 * grid.cellsX * grid.cellsZ};
}

Status generateTerrain(const GenerateOptions& options, MeshSink& sink) {
    Grid grid = gridFor(options.triangles);
    GeneratedCounts counts = terrainCounts(options.triangles);
    VASTRAY_TRY(sink.begin(counts.vertices, counts.triangles));
    VASTRAY_TRY(emitVertices(grid, options.seed, sink));
    VASTRAY_TRY(emitFaces(grid, sink));
    return sink.end();
}

}  // namespace vastray::gen
