#pragma once
// A mesh whose package chunk has long triangles (vertex indices further apart than the 16-bit
// offsets of 8-byte device indices reach, kChunkIndexDeltas16): a bowl z = x^2 + y^2 over a
// 256 x 256 grid of quads on [-1, 1]^2 (66,049 vertices, one chunk at the default size) under two
// large triangles: the lid, flat at z = 2 between three of the rim's corners, and the slant from
// the bowl's centre to the other two corners. The codecs order vertices by locality, so the large
// triangles' corners lie tens of thousands of vertices apart.
#include <cstdint>

#include "vastray/core/Mesh.h"

namespace vastray::test {

inline constexpr uint32_t kBowlQuads = 256;
inline constexpr uint32_t kBowlLid = 2 * kBowlQuads * kBowlQuads;  // the lid's primitive id
inline constexpr uint32_t kBowlSlant = kBowlLid + 1;                // the slant's

inline TriangleMesh bowlUnderLongTriangles() {
    constexpr uint32_t n = kBowlQuads;
    TriangleMesh mesh;
    for (uint32_t j = 0; j <= n; ++j)
        for (uint32_t i = 0; i <= n; ++i) {
            const float x = 2.0f * float(i) / n - 1.0f, y = 2.0f * float(j) / n - 1.0f;
            mesh.positions.push_back({x, y, x * x + y * y});
        }
    auto at = [](uint32_t i, uint32_t j) { return j * (n + 1) + i; };
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i)
            mesh.indices.insert(mesh.indices.end(),
                                {at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
    mesh.indices.insert(mesh.indices.end(), {at(0, 0), at(n, 0), at(0, n), at(n / 2, n / 2), at(n, 0), at(n, n)});
    mesh.materials = {Material{}};
    return mesh;
}

}  // namespace vastray::test
