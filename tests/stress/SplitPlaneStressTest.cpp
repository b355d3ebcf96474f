// Triangles lying in split planes, rays parallel to an axis (zero direction components), rays
// starting on and running inside KD split planes and the package's cell faces, and rays grazing
// a silhouette; in every backend, against the Embree reference or an analytic answer.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "StressSupport.h"
#include "vastray/core/VecMath.h"

namespace vastray::stress {
namespace {

// Same distance: both miss, or both hit at t within 1e-5 relative. Triangle ids are not compared
// where coincident or crossing triangles meet at one point (the axis grid): any of them is right.
bool sameDistance(const RayHit& a, const RayHit& b) {
    return a.found == b.found && (!a.found || std::abs(a.t - b.t) <= 1e-5f * std::max(1.0f, std::abs(a.t)));
}

// Rays towards the axis grid (planes at the integers 0..n) from one unit outside it, along an
// axis or slanted in one other coordinate, that reach the first plane at t = 1 at a point
// strictly inside it: on grid vertices (integer coordinates), on edges (one integer) or anywhere.
// Axis-parallel ones run inside one or two planes of in-plane triangles, which never count.
std::vector<Ray> gridRays(int n, uint32_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::vector<Ray> rays;
    for (uint32_t i = 0; i < count; ++i) {
        const int axis = int(i % 3), a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
        const bool positive = (i / 3) % 2 == 0;
        Vec3f hit, d{0, 0, 0};
        const uint32_t category = (i / 6) % 3;  // 0 vertex, 1 edge, 2 anywhere
        auto coordinate = [&](bool onLine) {
            return onLine ? float(1 + int(rng() % uint32_t(n - 1))) : 0.01f + (float(n) - 0.02f) * unit(rng);
        };
        hit[a1] = coordinate(category <= 1);
        hit[a2] = coordinate(category == 0);
        hit[axis] = positive ? 0.0f : float(n);
        d[axis] = positive ? 1.0f : -1.0f;
        if (i % 4 == 3) d[a1] = 0.25f * (unit(rng) - 0.5f);  // slanted inside the plane a2 = hit[a2]
        rays.push_back({hit - d, d});
    }
    return rays;
}

TEST(SplitPlanes, AxisParallelRaysOnGridPlanes) {
    const int n = 4;
    const Mesh grid = test::makeAxisGrid(n);
    const std::vector<Ray> rays = gridRays(n, 30000, 3);
    std::vector<RayHit> kdHits;
    for (BackendKind kind : kRayBackends) {
        const std::vector<RayHit> hits = makeBackend(kind, grid)->trace(rays);
        uint64_t wrong = 0, misses = 0;
        for (const RayHit& h : hits) {
            misses += !h.found;
            // The first plane is one unit away along a unit axis: t = 1 up to the rounding of
            // the slanted origins (hit - d), a few ulps.
            wrong += !h.found || std::abs(h.t - 1.0f) > 1e-6f;
        }
        figure("axis-rays-grid", backendName(kind), "rays=%zu misses=%llu wrong_t_or_miss=%llu", hits.size(),
               (unsigned long long)misses, (unsigned long long)wrong);
        EXPECT_EQ(wrong, 0u) << backendName(kind);
        if (kind == BackendKind::Kd) kdHits = hits;
        if (kind == BackendKind::Gpu) {
            EXPECT_EQ(agreement(hits, kdHits), 1.0);
        }
    }
}

// Rays whose origin lies exactly on a split plane of the chunk tree (the one KdBackend builds),
// half of them running inside it (that direction component zero).
std::vector<Ray> splitPlaneRays(const Mesh& mesh, uint32_t count, uint32_t seed) {
    const KdTree tree = buildKdTree(mesh.positions.data(), mesh.indices.data(), mesh.count(),
                                    compactKdBuildOptions(mesh.count()));
    std::vector<KdNode> interior;
    for (const KdNode& node : tree.nodes)
        if (!node.isLeaf()) interior.push_back(node);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    const Vec3f lo = tree.bounds.lo, e = tree.bounds.hi - tree.bounds.lo;
    std::vector<Ray> rays;
    for (uint32_t i = 0; i < count && !interior.empty(); ++i) {
        const KdNode node = interior[rng() % interior.size()];
        Vec3f o{lo.x + e.x * unit(rng), lo.y + e.y * unit(rng), lo.z + e.z * unit(rng)};
        o[int(node.axis())] = node.split();
        Vec3f d{normal(rng), normal(rng), normal(rng)};
        if (i % 2 == 0) d[int(node.axis())] = 0.0f;
        if (i % 6 == 0) d[(int(node.axis()) + 1) % 3] = 0.0f;  // along an axis inside the plane
        rays.push_back({o, d});
    }
    return rays;
}

// A ray whose origin lies exactly on a triangle (the axis grid: on a split plane inside a grid
// square) and crosses it meets that triangle at t = 0 exactly. Embree returns that hit; the
// watertight test's t (a sum of sheared products) rounds to either side of 0 and rejects the
// negative ones. Such rays are counted separately (start_on_surface) and left out of the
// agreement: which answer is right at t = 0 is a convention, and offset secondary rays never
// start on a surface.
void expectSplitPlaneRaysAgree(const std::string& name, const Mesh& mesh, double minAgreement) {
    const std::vector<Ray> rays = splitPlaneRays(mesh, 30000, 5);
    ASSERT_FALSE(rays.empty());
    const std::vector<RayHit> reference = EmbreeBackend(mesh).trace(rays);
    std::vector<RayHit> kdHits;
    for (BackendKind kind : {BackendKind::Kd, BackendKind::Gpu}) {
        const std::vector<RayHit> hits = makeBackend(kind, mesh)->trace(rays);
        uint64_t onSurface = 0, onSurfaceHits = 0, compared = 0, same = 0;
        for (size_t i = 0; i < hits.size(); ++i) {
            if (reference[i].found && reference[i].t == 0.0f) {
                ++onSurface, onSurfaceHits += hits[i].found && hits[i].t == 0.0f;
                continue;
            }
            ++compared, same += sameDistance(hits[i], reference[i]);
        }
        const double rate = double(same) / double(std::max<uint64_t>(compared, 1));
        figure(name, backendName(kind),
               "rays=%zu start_on_surface=%llu t0_hits=%llu distance_agreement_with_reference=%.6f",
               hits.size(), (unsigned long long)onSurface, (unsigned long long)onSurfaceHits, rate);
        EXPECT_GE(rate, minAgreement)
            << name << " " << backendName(kind)
            << firstMismatches(rays, hits, reference, [](const RayHit& a, const RayHit& b) {
                   return (b.found && b.t == 0.0f) || sameDistance(a, b);
               });
        if (kind == BackendKind::Kd)
            kdHits = hits;
        else
            EXPECT_EQ(agreement(hits, kdHits), 1.0) << name << ": GPU kernel differs from the KD traversal";
    }
}

// Random origins and directions: an exact tie with an edge has probability ~0, so the only
// legitimate disagreements are rays starting exactly on a triangle (the grid: in-plane starts
// hit at t = 0 or not depending on the test's rounding); bounds chosen from that (comments below).
TEST(SplitPlanes, RaysStartingOnAndInsideSplitPlanes) {
    // Icosphere: no triangle lies in a split plane; all rays must agree.
    expectSplitPlaneRaysAgree("split-plane-rays-icosphere",
                              test::makeIcosphere(4, {0.25f, -0.5f, 0.125f}, 2.0f), 0.9999);
    // Axis grid: every triangle lies in a plane that is also a split plane, and half of the
    // rays run inside such a plane (in-plane triangles never count, GEOMETRY.md); apart from
    // the t = 0 starts all must agree too.
    expectSplitPlaneRaysAgree("split-plane-rays-axis-grid", test::makeAxisGrid(4), 0.9999);
}

// A camera whose eye lies exactly on an interior cell face of the package, looking along
// `forward` with that face's axis as `up`: with an odd image height the middle row's pixel-centre
// rays have a zero component along the face axis, i.e. they start on and run inside the face.
void expectCellFaceRendersAgree(const std::string& name, const Mesh& mesh, Vec3f eyeHint) {
    const std::string path = packageFromMesh(name, mesh, 16 << 10);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    const PackageInfo& info = (*reader)->info();
    const std::vector<Cell> cells = topLevelCells(info);
    uint32_t faces = 0;
    for (int axis = 0; axis < 3; ++axis) {
        // The interior face nearest to the hint on this axis.
        float face = NAN;
        for (const Cell& c : cells)
            if (c.box.hi[axis] < info.bounds.hi[axis] &&
                (std::isnan(face) ||
                 std::abs(c.box.hi[axis] - eyeHint[axis]) < std::abs(face - eyeHint[axis])))
                face = c.box.hi[axis];
        if (std::isnan(face)) continue;
        ++faces;
        Camera camera;
        camera.eye = eyeHint;
        camera.eye[axis] = face;
        Vec3f forward{0, 0, 0}, up{0, 0, 0};
        forward[(axis + 1) % 3] = 1.0f;
        up[axis] = 1.0f;
        camera.target = camera.eye + forward;
        camera.up = up;
        camera.fovYDegrees = 100.0f;
        const RenderOptions o = aimedRender(65, 49, camera);
        const std::optional<StreamingTrio> trio = renderTrio(path, o);
        ASSERT_TRUE(trio);
        uint64_t same = 0, sameTight = 0, onSurface = 0;
        std::string mismatches;
        for (size_t p = 0; p < trio->reference.primId.size(); ++p) {
            auto hitOf = [&](const RenderImage& image) {
                return RayHit{image.primId[p] != kMissPrimId, image.depth[p], image.primId[p], false};
            };
            if (trio->reference.primId[p] != kMissPrimId && trio->reference.depth[p] == 0.0f) {
                ++onSurface;  // the eye lies on a triangle: t = 0, see expectSplitPlaneRaysAgree
                continue;
            }
            const bool agree = sameDistance(hitOf(trio->ample), hitOf(trio->reference));
            same += agree;
            sameTight += sameDistance(hitOf(trio->tight), hitOf(trio->reference));
            if (!agree && mismatches.size() < 400)
                mismatches += "\n  pixel " + std::to_string(p) + ": depth " +
                              std::to_string(trio->ample.depth[p]) + " prim " +
                              std::to_string(trio->ample.primId[p]) + ", reference depth " +
                              std::to_string(trio->reference.depth[p]) + " prim " +
                              std::to_string(trio->reference.primId[p]);
        }
        const double pixels = double(trio->reference.primId.size() - onSurface);
        const std::string caseName = name + "-face-axis" + std::to_string(axis);
        figure(caseName, "vulkan-ample",
               "rays=%zu in_face_rays=%u start_on_surface=%llu distance_agreement_with_reference=%.6f",
               trio->reference.primId.size(), o.width, (unsigned long long)onSurface, double(same) / pixels);
        figure(caseName, "vulkan-2slot",
               "rays=%zu in_face_rays=%u start_on_surface=%llu distance_agreement_with_reference=%.6f "
               "loads=%llu",
               trio->reference.primId.size(), o.width, (unsigned long long)onSurface,
               double(sameTight) / pixels, (unsigned long long)trio->tightStats.chunkLoads);
        // At most 1 pixel may differ (an exact tie with an edge is possible on the grid).
        EXPECT_GE(double(same), pixels - 1) << caseName << mismatches;
        EXPECT_GE(double(sameTight), pixels - 1) << caseName;
        EXPECT_EQ(primIdAgreement(trio->ample, trio->tight), 1.0) << caseName;
    }
    EXPECT_GT(faces, 0u) << name << ": no interior cell face (one chunk?)";
}

TEST(SplitPlanes, StreamingRaysInsideCellFaces) {
    expectCellFaceRendersAgree("cell-face-icosphere", test::makeIcosphere(4, {0.25f, -0.5f, 0.125f}, 2.0f),
                               {0.3f, -0.4f, 0.2f});
    expectCellFaceRendersAgree("cell-face-axis-grid", test::makeAxisGrid(6), {2.5f, 3.25f, 2.75f});
}

// Outside origins; targets on the silhouette seen from there: points of edges whose two
// triangles face opposite ways (kind 0). For each edge point also two rays shifted by `shift`
// across the plane through the origin and the edge, a supporting plane of the convex mesh:
// the one shifted away from the mesh can touch nothing (kind 2, must miss), the one shifted
// towards it passes inside the wedge of the two faces (kind 1, must hit).
struct GrazingRays {
    std::vector<Ray> rays;
    std::vector<uint8_t> kind;
};

GrazingRays silhouetteRays(const Mesh& mesh, Vec3f centre, float radius, uint32_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> edgeTriangles;
    for (uint32_t t = 0; t < mesh.count(); ++t)
        for (int k = 0; k < 3; ++k)
            edgeTriangles[std::minmax(mesh.indices[3 * t + k], mesh.indices[3 * t + (k + 1) % 3])].push_back(
                t);
    const float shift = 1e-5f * radius;  // ~100 float spacings at these coordinates
    GrazingRays out;
    while (out.rays.size() < count) {
        const Vec3f d = test::normalized({normal(rng), normal(rng), normal(rng)});
        const Vec3f origin = centre + d * (3.0f * radius);
        auto facing = [&](uint32_t t) {
            const Vec3f* p = mesh.positions.data();
            const Vec3f a = p[mesh.indices[3 * t]], b = p[mesh.indices[3 * t + 1]],
                        c = p[mesh.indices[3 * t + 2]];
            return dot(cross(b - a, c - a), a - origin) < 0;
        };
        for (const auto& [edge, tris] : edgeTriangles) {
            if (tris.size() != 2 || facing(tris[0]) == facing(tris[1]) || out.rays.size() >= count) continue;
            const Vec3f a = mesh.positions[edge.first], b = mesh.positions[edge.second];
            const Vec3f target = a + (b - a) * (0.1f + 0.8f * unit(rng));
            Vec3f away = normalize(cross(a - origin, b - origin));
            if (dot(away, centre - origin) > 0) away = away * -1.0f;
            out.rays.push_back({origin, target - origin}), out.kind.push_back(0);
            out.rays.push_back({origin, target - away * shift - origin}), out.kind.push_back(1);
            out.rays.push_back({origin, target + away * shift - origin}), out.kind.push_back(2);
        }
    }
    return out;
}

TEST(Grazing, SilhouetteRays) {
    const Vec3f centre{0.25f, -0.5f, 0.125f};
    const Mesh sphere = test::makeIcosphere(4, centre, 2.0f);
    const GrazingRays grazing = silhouetteRays(sphere, centre, 2.0f, 30000, 13);
    const std::vector<RayHit> reference = EmbreeBackend(sphere).trace(grazing.rays);
    std::vector<RayHit> kdHits;
    for (BackendKind kind : kRayBackends) {
        const std::vector<RayHit> hits =
            kind == BackendKind::Embree ? reference : makeBackend(kind, sphere)->trace(grazing.rays);
        uint64_t touching = 0, touchingHits = 0, through = 0, insideMisses = 0, outsideHits = 0,
                 sameFound = 0;
        std::string throughRays;
        for (size_t i = 0; i < hits.size(); ++i) {
            // Convex: a first hit far beyond the silhouette point (t = 1) went through the surface.
            if (hits[i].found && hits[i].t > 1.001f) {
                ++through;
                throughRays +=
                    "\n  kind " + std::to_string(grazing.kind[i]) + ": " + describe(grazing.rays[i], hits[i]);
            }
            if (grazing.kind[i] == 0) {
                ++touching, touchingHits += hits[i].found;
                sameFound += hits[i].found == reference[i].found;
            }
            insideMisses += grazing.kind[i] == 1 && !hits[i].found;
            outsideHits += grazing.kind[i] == 2 && hits[i].found;
        }
        figure("grazing-silhouette-icosphere", backendName(kind),
               "rays=%zu touching=%llu touching_hit_rate=%.4f touching_agreement_with_reference=%.6f "
               "inside_1e-5_misses=%llu outside_1e-5_hits=%llu through=%llu",
               hits.size(), (unsigned long long)touching, double(touchingHits) / double(touching),
               double(sameFound) / double(touching), (unsigned long long)insideMisses,
               (unsigned long long)outsideHits, (unsigned long long)through);
        // Rays exactly touching the silhouette hit or miss by rounding (reported only); rays
        // 1e-5 radius inside or outside of it have one right answer in every backend.
        // Embree (robust mode) slips through the front face of a touching ray now and then and
        // reports the back face behind it (measured 1 in 10^4 touching rays, t = 1.007); the
        // reference is allowed 2, our watertight test none.
        EXPECT_LE(through, kind == BackendKind::Embree ? 2u : 0u) << backendName(kind) << throughRays;
        EXPECT_EQ(insideMisses, 0u) << backendName(kind);
        EXPECT_EQ(outsideHits, 0u) << backendName(kind);
        if (kind == BackendKind::Kd) kdHits = hits;
        if (kind == BackendKind::Gpu) {
            EXPECT_EQ(agreement(hits, kdHits), 1.0);
        }
    }
}

// The framed icosphere through the streaming renderer: pixels on the silhouette (a 4-neighbour
// differs in hit/miss in the reference) must agree with Embree.
TEST(Grazing, StreamingSilhouettePixels) {
    const Mesh sphere = test::makeIcosphere(4, {0.25f, -0.5f, 0.125f}, 2.0f);
    const std::string path = packageFromMesh("grazing-stream-icosphere", sphere, 16 << 10);
    Aabb box;
    for (const Vec3f& p : sphere.positions) box.extend(p);
    const RenderOptions o = aimedRender(160, 120, frameBounds(box, 40.0f, 160.0f / 120.0f), kAovPrimId);
    const std::optional<StreamingTrio> trio = renderTrio(path, o);
    ASSERT_TRUE(trio);
    const std::vector<uint32_t>& ref = trio->reference.primId;
    uint64_t silhouette = 0, sameAmple = 0, sameTight = 0;
    for (uint32_t y = 1; y + 1 < o.height; ++y)
        for (uint32_t x = 1; x + 1 < o.width; ++x) {
            const uint32_t p = y * o.width + x;
            const bool hit = ref[p] != kMissPrimId;
            bool edge = false;
            for (uint32_t q : {p - 1, p + 1, p - o.width, p + o.width})
                edge = edge || (ref[q] != kMissPrimId) != hit;
            if (!edge) continue;
            ++silhouette;
            sameAmple += trio->ample.primId[p] == ref[p];
            sameTight += trio->tight.primId[p] == ref[p];
        }
    figure("grazing-stream-icosphere", "vulkan-ample", "silhouette_pixels=%llu agreement_with_reference=%.6f",
           (unsigned long long)silhouette, double(sameAmple) / double(silhouette));
    figure("grazing-stream-icosphere", "vulkan-2slot", "silhouette_pixels=%llu agreement_with_reference=%.6f",
           (unsigned long long)silhouette, double(sameTight) / double(silhouette));
    EXPECT_GT(silhouette, 100u);
    // Pixel centres fall at arbitrary positions relative to the edges: no exact ties, so every
    // silhouette pixel must agree.
    EXPECT_EQ(sameAmple, silhouette);
    EXPECT_EQ(sameTight, silhouette);
}

}  // namespace
}  // namespace vastray::stress
