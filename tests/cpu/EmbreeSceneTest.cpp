// Geometry semantics of docs/GEOMETRY.md, checked on the Embree reference.
#include <gtest/gtest.h>

#include <cmath>

#include "TestScenes.h"
#include "vastray/core/Random.h"
#include "vastray/core/RayOffset.h"
#include "vastray/core/Sampling.h"
#include "vastray/cpu/EmbreeScene.h"

namespace vastray {
namespace {

constexpr float kInf = 1e30f;

std::unique_ptr<EmbreeScene> build(const TriangleMesh& mesh) {
    auto scene = EmbreeScene::build(mesh);
    EXPECT_TRUE(scene) << scene.message();
    return scene ? std::move(*scene) : nullptr;
}

TEST(EmbreeScene, SingleSidedQuadIsInvisibleFromBehind) {
    auto scene = build(test::quadFacingPlusZ(false));
    SceneHit hit;
    ASSERT_TRUE(scene->intersect({{0.2f, 0.3f, 2}, {0, 0, -1}}, kInf, &hit));
    EXPECT_TRUE(hit.frontFacing);
    EXPECT_FLOAT_EQ(hit.t, 2.0f);
    EXPECT_FALSE(scene->intersect({{0.2f, 0.3f, -2}, {0, 0, 1}}, kInf, &hit));
    EXPECT_FALSE(scene->occluded({{0.2f, 0.3f, -2}, {0, 0, 1}}, kInf));
    EXPECT_TRUE(scene->occluded({{0.2f, 0.3f, 2}, {0, 0, -1}}, kInf));
}

TEST(EmbreeScene, DoubleSidedQuadIsHitFromBothSides) {
    auto scene = build(test::quadFacingPlusZ(true));
    SceneHit hit;
    ASSERT_TRUE(scene->intersect({{0.2f, 0.3f, -2}, {0, 0, 1}}, kInf, &hit));
    EXPECT_FALSE(hit.frontFacing);
    EXPECT_FLOAT_EQ(hit.t, 2.0f);
    EXPECT_TRUE(scene->occluded({{0.2f, 0.3f, -2}, {0, 0, 1}}, kInf));
}

TEST(EmbreeScene, RespectsTheRayRange) {
    auto scene = build(test::quadFacingPlusZ(true));
    SceneHit hit;
    EXPECT_FALSE(scene->intersect({{0, 0, 2}, {0, 0, -1}}, 1.5f, &hit));
    EXPECT_FALSE(scene->occluded({{0, 0, 2}, {0, 0, -1}}, 1.5f));
}

// Two coincident triangles of opposite winding: whichever side the ray comes from, the
// one facing it wins, whatever their order in the mesh (so no traversal order decides).
TEST(EmbreeScene, CoincidentOppositeTrianglesFacingTheRayWins) {
    for (bool frontFirst : {true, false}) {
        TriangleMesh mesh;
        mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
        const std::vector<uint32_t> ccw{0, 1, 2}, cw{0, 2, 1};  // ccw faces +z
        mesh.indices = frontFirst ? ccw : cw;
        mesh.indices.insert(mesh.indices.end(), (frontFirst ? cw : ccw).begin(),
                            (frontFirst ? cw : ccw).end());
        mesh.materials = {Material{}};
        auto scene = build(mesh);
        const uint32_t facesPlusZ = frontFirst ? 0 : 1;
        SceneHit hit;
        ASSERT_TRUE(scene->intersect({{0, 0, 3}, {0, 0, -1}}, kInf, &hit));
        EXPECT_TRUE(hit.frontFacing);
        EXPECT_EQ(hit.triangle, facesPlusZ);
        ASSERT_TRUE(scene->intersect({{0, 0, -3}, {0, 0, 1}}, kInf, &hit));
        EXPECT_TRUE(hit.frontFacing);
        EXPECT_EQ(hit.triangle, 1 - facesPlusZ);
    }
}

TEST(EmbreeScene, NoCracksAlongSharedEdgesOfAClosedMesh) {
    // Rays from inside the sphere through the midpoint of every edge must all hit: in
    // robust mode a ray never slips between two triangles that share an edge.
    // (Rays aimed exactly at a vertex are not covered: Embree 3.13 lets about 0.1% of
    // them through, see docs/GEOMETRY.md.)
    const RenderScene sphere = test::unitSphere(5000);
    ASSERT_GT(sphere.mesh.triangleCount(), 0u);
    auto scene = build(sphere.mesh);
    SceneHit hit;
    uint64_t missed = 0;
    for (uint64_t t = 0; t < sphere.mesh.triangleCount(); ++t) {
        for (int corner = 0; corner < 3; ++corner) {
            const Vec3f a = sphere.mesh.positions[sphere.mesh.indices[3 * t + corner]];
            const Vec3f b = sphere.mesh.positions[sphere.mesh.indices[3 * t + (corner + 1) % 3]];
            missed += !scene->intersect({{0, 0, 0}, (a + b) * 0.5f}, kInf, &hit);
            missed += !scene->intersect(
                {{0.01f, -0.02f, 0.015f}, (a + b) * 0.5f - Vec3f{0.01f, -0.02f, 0.015f}}, kInf, &hit);
        }
    }
    EXPECT_EQ(missed, 0u);
}

TEST(EmbreeScene, OffsetSecondaryRaysNeverHitTheirOwnSurfaceFarFromTheOrigin) {
    // A tilted plane at ~1e5 units: a fixed epsilon sized for unit scenes would be far
    // below the float spacing here (~0.008) and rays would re-hit their own triangle.
    TriangleMesh mesh;
    const Vec3f c{1e5f, -7e4f, 3e4f};
    mesh.positions = {c + Vec3f{-500, -100, -500}, c + Vec3f{500, 100, -500}, c + Vec3f{0, 50, 500}};
    mesh.indices = {0, 1, 2};
    Material m;
    mesh.materials = {m};
    auto scene = build(mesh);
    const Vec3f v0 = mesh.positions[0], v1 = mesh.positions[1], v2 = mesh.positions[2];
    const Vec3f n = normalize(cross(v1 - v0, v2 - v0));
    uint64_t selfHits = 0;
    for (uint32_t i = 0; i < 10000; ++i) {
        const float u = 0.5f * randomFloat({i, 0, 0}, 0, 3), v = 0.5f * randomFloat({i, 0, 0}, 1, 3);
        const Vec3f p = v0 + (v1 - v0) * u + (v2 - v0) * v;
        const Vec3f d = frameAround(n).toWorld(
            cosineHemisphere(randomFloat({i, 0, 0}, 2, 3), randomFloat({i, 0, 0}, 3, 3)));
        selfHits += scene->occluded({offsetRayOrigin(p, n), d}, kInf);
    }
    EXPECT_EQ(selfHits, 0u);
}

}  // namespace
}  // namespace vastray
