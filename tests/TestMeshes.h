#pragma once
// Test meshes shared by the CPU KD-tree tests and the GPU tracer tests, which must trace the
// very same triangles.
#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "vastray/core/KdTree.h"

namespace vastray::test {

struct Mesh {
    std::vector<Vec3f> positions;
    std::vector<uint32_t> indices;
    std::vector<uint8_t> singleSided;  // empty: all double-sided
    uint32_t count() const { return uint32_t(indices.size() / 3); }
    KdTree build(const KdBuildOptions& options = {}) const {
        return buildKdTree(positions.data(), indices.data(), count(), options);
    }
};

inline Vec3f normalized(Vec3f v) { return v * (1.0f / std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z)); }

inline Vec3f randomVec(std::mt19937& rng, float lo, float hi) {
    std::uniform_real_distribution<float> d(lo, hi);
    return {d(rng), d(rng), d(rng)};
}

// Closed sphere with shared vertices: each subdivision splits every edge once (midpoint cache).
inline Mesh makeIcosphere(int subdivisions, Vec3f center, float radius) {
    const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
    std::vector<Vec3f> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    std::vector<uint32_t> f = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4,
                               11, 10, 2, 10, 7, 6, 7, 1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8,
                               3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
    for (Vec3f& v : p) v = normalized(v);
    for (int s = 0; s < subdivisions; ++s) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
        auto midpoint = [&](uint32_t a, uint32_t b) {
            auto [it, inserted] = mid.try_emplace(std::minmax(a, b), uint32_t(p.size()));
            if (inserted) p.push_back(normalized((p[a] + p[b]) * 0.5f));
            return it->second;
        };
        std::vector<uint32_t> g;
        for (size_t i = 0; i < f.size(); i += 3) {
            const uint32_t a = f[i], b = f[i + 1], c = f[i + 2];
            const uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
            g.insert(g.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        f = std::move(g);
    }
    Mesh m;
    for (const Vec3f& v : p) m.positions.push_back(center + v * radius);
    m.indices = std::move(f);
    return m;
}

// Random triangles; with duplicates: every fourth triangle is repeated with reversed winding and
// every fifth exactly (same corners, same order), so rays meet ties in t: exact ones between
// copies (lower index wins), and often exact ones between opposite windings (front-facing wins).
inline Mesh makeSoup(uint32_t count, uint32_t seed, bool duplicates = false) {
    std::mt19937 rng(seed);
    Mesh m;
    for (uint32_t i = 0; i < count; ++i) {
        const Vec3f c = randomVec(rng, -10, 10);
        const uint32_t base = uint32_t(m.positions.size());
        for (int k = 0; k < 3; ++k) m.positions.push_back(c + randomVec(rng, -1.5f, 1.5f));
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
        if (duplicates && i % 4 == 0) m.indices.insert(m.indices.end(), {base, base + 2, base + 1});
        if (duplicates && i % 5 == 0) m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
    }
    return m;
}

// Unit squares on every integer plane of an n^3 lattice: triangles lie in the split planes.
inline Mesh makeAxisGrid(int n) {
    Mesh m;
    for (int axis = 0; axis < 3; ++axis)
        for (int i = 0; i <= n; ++i)
            for (int j = 0; j < n; ++j)
                for (int k = 0; k < n; ++k) {
                    const uint32_t base = uint32_t(m.positions.size());
                    for (int c = 0; c < 4; ++c) {
                        Vec3f v;
                        v[axis] = float(i);
                        v[(axis + 1) % 3] = float(j + (c & 1));
                        v[(axis + 2) % 3] = float(k + (c >> 1));
                        m.positions.push_back(v);
                    }
                    m.indices.insert(m.indices.end(), {base, base + 1, base + 3, base, base + 3, base + 2});
                }
    return m;
}

}  // namespace vastray::test
