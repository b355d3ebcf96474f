// Needle, sliver and near-degenerate triangles: closed planar sheets made of them must not let a
// ray through (rays aimed at random points, at shared edges and at shared vertices), in every
// backend; exactly degenerate triangles are never hit (docs/GEOMETRY.md, KdTree.h).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "StressSupport.h"

namespace vastray::stress {
namespace {

constexpr float kPi = 3.14159265358979f;

// A sheet in the plane z = 0 and the points a ray aimed at it must not pass: `covered` is a
// rectangle inside the sheet; vertices/edges are targets on shared features.
struct Sheet {
    Mesh mesh;
    Vec3f coveredLo, coveredHi;
    std::vector<Vec3f> vertexTargets;
    std::vector<std::pair<Vec3f, Vec3f>> edgeTargets;  // shared edges (both ends)
};

// n needles around the centre of the unit disk (each 360/n degrees wide).
Sheet needleFan(uint32_t n) {
    Sheet s;
    s.mesh.positions.push_back({0, 0, 0});
    for (uint32_t k = 0; k < n; ++k) {
        const float a = 2.0f * kPi * float(k) / float(n);
        s.mesh.positions.push_back({std::cos(a), std::sin(a), 0});
        s.mesh.indices.insert(s.mesh.indices.end(), {0, 1 + k, 1 + (k + 1) % n});
        s.edgeTargets.push_back({{0, 0, 0}, s.mesh.positions.back()});
    }
    s.vertexTargets = {{0, 0, 0}};  // shared by all n needles
    s.coveredLo = {-0.7f, -0.7f, 0}, s.coveredHi = {0.7f, 0.7f, 0};
    return s;
}

// Rows of slivers: each row is a strip between two lines of vertices, the upper line shifted by
// `shear` (alternately left and right), so each triangle has a long side about `shear` and a
// short one of 1/columns, and an angle close to 180 degrees.
Sheet sliverSheet(uint32_t columns, uint32_t rows, float shear) {
    Sheet s;
    const uint32_t perLine = columns + uint32_t(std::ceil(shear * float(columns))) + 1;
    for (uint32_t j = 0; j <= rows; ++j)
        for (uint32_t i = 0; i < perLine; ++i)
            s.mesh.positions.push_back(
                {float(i) / float(columns) - (j % 2 ? shear : 0.0f), float(j) / float(rows), 0});
    for (uint32_t j = 0; j < rows; ++j)
        for (uint32_t i = 0; i + 1 < perLine; ++i) {
            const uint32_t a = j * perLine + i, b = a + 1, c = a + perLine, d = c + 1;
            s.mesh.indices.insert(s.mesh.indices.end(), {a, b, c, b, d, c});
            if (j > 0 && j + 1 < rows) s.edgeTargets.push_back({s.mesh.positions[b], s.mesh.positions[c]});
            if (j > 0) s.vertexTargets.push_back(s.mesh.positions[b]);
        }
    s.coveredLo = {0.05f, 0.01f, 0}, s.coveredHi = {0.95f, 0.99f, 0};
    // Keep only interior features.
    std::erase_if(s.vertexTargets, [&](Vec3f p) { return p.x < 0.05f || p.x > 0.95f || p.y > 0.99f; });
    std::erase_if(s.edgeTargets, [&](const auto& e) {
        return std::min(e.first.x, e.second.x) < 0.05f || std::max(e.first.x, e.second.x) > 0.95f;
    });
    return s;
}

// The unit square split along its diagonal by a chain of points, each followed by a twin one ulp
// further along: fans from the two other corners to the chain make every second triangle one
// ulp wide (near-degenerate), and a few exactly degenerate triangles (repeated or collinear
// corners) lie on top, which must never be hit.
Sheet nearDegenerateSquare(uint32_t chain, Mesh* degenerate) {
    Sheet s;
    s.mesh.positions = {{1, 0, 0}, {0, 1, 0}};
    for (uint32_t k = 0; k <= chain; ++k) {
        const float t = float(k) / float(chain);
        s.mesh.positions.push_back({t, t, 0});
        if (k > 0 && k < chain)
            s.mesh.positions.push_back({std::nextafter(t, 2.0f), std::nextafter(t, 2.0f), 0});
    }
    const uint32_t points = uint32_t(s.mesh.positions.size());
    for (uint32_t k = 2; k + 1 < points; ++k) {
        s.mesh.indices.insert(s.mesh.indices.end(), {0, k + 1, k, 1, k, k + 1});
        s.vertexTargets.push_back(s.mesh.positions[k + 1]);
        s.edgeTargets.push_back({s.mesh.positions[k], s.mesh.positions[k + 1]});
        if (k + 2 < points) s.edgeTargets.push_back({s.mesh.positions[0], s.mesh.positions[k + 1]});
    }
    s.vertexTargets.pop_back();  // the far corner is on the boundary
    s.coveredLo = {0.02f, 0.02f, 0}, s.coveredHi = {0.98f, 0.98f, 0};
    // Above the square (z = 0.5): zero-area triangles only; they must never be hit.
    degenerate->positions = {{0, 0, 0.5f}, {1, 1, 0.5f}, {0.5f, 0.5f, 0.5f}, {1, 0, 0.5f}, {0, 1, 0.5f}};
    degenerate->indices = {0, 1, 2, 3, 4, 2, 0, 0, 1, 3, 3, 3};
    return s;
}

struct SheetRays {
    std::vector<Ray> rays;
    std::vector<uint8_t> kind;  // 0 random point, 1 edge, 2 vertex
};

// Rays from above (z in [0.5, 2]) in random slanted directions, aimed at points of the sheet.
SheetRays sheetRays(const Sheet& s, uint32_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    SheetRays out;
    for (uint32_t i = 0; i < count; ++i) {
        Vec3f target;
        const uint8_t kind = uint8_t(i % 3);
        if (kind == 0) {
            target = {s.coveredLo.x + (s.coveredHi.x - s.coveredLo.x) * unit(rng),
                      s.coveredLo.y + (s.coveredHi.y - s.coveredLo.y) * unit(rng), 0};
        } else if (kind == 1) {
            const auto& [a, b] = s.edgeTargets[rng() % s.edgeTargets.size()];
            target = a + (b - a) * (i % 4 == 1 ? 0.5f : 0.01f + 0.98f * unit(rng));  // off the ends
        } else {
            target = s.vertexTargets[rng() % s.vertexTargets.size()];
        }
        const Vec3f origin = target + Vec3f{unit(rng) - 0.5f, unit(rng) - 0.5f, 0.5f + 1.5f * unit(rng)};
        out.rays.push_back({i % 5 == 0 ? Vec3f{target.x, target.y, 1.0f} : origin,
                            i % 5 == 0 ? Vec3f{0, 0, -1} : target - origin});
        out.kind.push_back(kind);
    }
    return out;
}

void expectSheetHolds(const std::string& name, const Sheet& sheet, const Mesh& extra = {}) {
    Mesh mesh = sheet.mesh;
    const uint32_t sheetTriangles = mesh.count();
    for (const uint32_t i : extra.indices) mesh.indices.push_back(i + uint32_t(mesh.positions.size()));
    mesh.positions.insert(mesh.positions.end(), extra.positions.begin(), extra.positions.end());
    const SheetRays rays = sheetRays(sheet, 30000, 9);
    std::vector<RayHit> kdHits;
    for (BackendKind kind : kRayBackends) {
        const std::vector<RayHit> hits = makeBackend(kind, mesh)->trace(rays.rays);
        uint64_t leaks[3] = {0, 0, 0}, degenerateHits = 0;
        for (size_t i = 0; i < hits.size(); ++i) {
            leaks[rays.kind[i]] += !hits[i].found;
            degenerateHits += hits[i].found && hits[i].triangle >= sheetTriangles;
        }
        figure(name, backendName(kind),
               "rays=%zu point_leaks=%llu edge_leaks=%llu vertex_leaks=%llu degenerate_hits=%llu",
               hits.size(), (unsigned long long)leaks[0], (unsigned long long)leaks[1],
               (unsigned long long)leaks[2], (unsigned long long)degenerateHits);
        EXPECT_EQ(degenerateHits, 0u) << name << " " << backendName(kind);
        EXPECT_EQ(leaks[0], 0u) << name << " " << backendName(kind) << ": random points of a closed sheet";
        if (kind == BackendKind::Embree) {
            // Robust Embree: no edge leaks; vertex leaks documented (0.3% on the icosphere);
            // bounded at 2% of vertex rays (vertices here are shared by 6 to 1000 triangles).
            EXPECT_EQ(leaks[1], 0u) << name << " embree";
            EXPECT_LE(double(leaks[2]), 0.02 * double(hits.size()) / 3) << name << " embree";
        } else {
            EXPECT_EQ(leaks[1] + leaks[2], 0u) << name << " " << backendName(kind);
        }
        if (kind == BackendKind::Kd) kdHits = hits;
        if (kind == BackendKind::Gpu) {
            EXPECT_EQ(agreement(hits, kdHits), 1.0) << name;
        }
    }
}

TEST(Degenerate, NeedleFan) { expectSheetHolds("needles-fan-1000", needleFan(1000)); }

TEST(Degenerate, SliverSheet) { expectSheetHolds("slivers-sheet", sliverSheet(64, 256, 0.25f)); }

TEST(Degenerate, NearDegenerateSquareAndZeroAreaTriangles) {
    Mesh degenerate;
    const Sheet sheet = nearDegenerateSquare(400, &degenerate);
    expectSheetHolds("near-degenerate-square", sheet, degenerate);
}

// The same sheets through the streaming renderer: a camera above looking straight down whose
// pixel-centre rays all land inside the covered rectangle (the centre pixel, with an odd image,
// runs along -z exactly: onto the fan's 1000-needle centre vertex).
TEST(Degenerate, StreamingSheets) {
    Mesh degenerate;
    const std::pair<std::string, Sheet> sheets[] = {
        {"needles-fan-1000", needleFan(1000)},
        {"slivers-sheet", sliverSheet(64, 256, 0.25f)},
        {"near-degenerate-square", nearDegenerateSquare(400, &degenerate)}};
    for (const auto& [name, sheet] : sheets) {
        const Vec3f centre = (sheet.coveredLo + sheet.coveredHi) * 0.5f;
        const float half =
            0.5f * std::min(sheet.coveredHi.x - sheet.coveredLo.x, sheet.coveredHi.y - sheet.coveredLo.y);
        Camera camera;
        camera.eye = centre + Vec3f{0, 0, 1};
        camera.target = centre;
        // Corner rays land at half * 0.95 from the centre on both axes: inside the rectangle.
        camera.fovYDegrees = 2.0f * std::atan(0.95f * half) * 180.0f / kPi;
        // Four copies side by side (the one in view, three beside it) so that the package has
        // several chunks and the two-slot render streams; the fan's 1000 needles meet in one
        // point, so a chunk must hold a whole fan (~32 KB at the default 32 resident bytes per
        // triangle: 64 KiB chunks).
        Mesh scene = sheet.mesh;
        for (int copy = 1; copy < 4; ++copy) {
            const Vec3f shift{2.5f * float(copy % 2), 2.5f * float(copy / 2), 0};
            const uint32_t base = uint32_t(scene.positions.size());
            for (const Vec3f& p : sheet.mesh.positions) scene.positions.push_back(p + shift);
            for (uint32_t i : sheet.mesh.indices) scene.indices.push_back(base + i);
        }
        const std::string path = packageFromMesh("stream-" + name, scene, 64 << 10);
        const std::optional<StreamingTrio> trio = renderTrio(path, aimedRender(63, 63, camera));
        ASSERT_TRUE(trio);
        figure("stream-" + name, "embree", "rays=%u leaks=%llu", 63 * 63,
               (unsigned long long)missCount(trio->reference));
        figure("stream-" + name, "vulkan-ample", "rays=%u leaks=%llu primid_agreement=%.6f", 63 * 63,
               (unsigned long long)missCount(trio->ample), primIdAgreement(trio->ample, trio->reference));
        figure("stream-" + name, "vulkan-2slot", "rays=%u leaks=%llu loads=%llu", 63 * 63,
               (unsigned long long)missCount(trio->tight), (unsigned long long)trio->tightStats.chunkLoads);
        EXPECT_EQ(missCount(trio->ample), 0u) << name;
        EXPECT_EQ(missCount(trio->tight), 0u) << name;
        EXPECT_LE(missCount(trio->reference), 1u) << name << ": at most the centre vertex may leak in Embree";
        EXPECT_EQ(primIdAgreement(trio->ample, trio->tight), 1.0) << name;
    }
}

}  // namespace
}  // namespace vastray::stress
