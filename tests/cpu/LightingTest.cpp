// Sun (next-event estimation), shadow rays and ambient occlusion against closed forms.
#include <gtest/gtest.h>

#include <cmath>

#include "TestScenes.h"
#include "vastray/core/Sampling.h"
#include "vastray/cpu/EmbreeRenderer.h"

namespace vastray {
namespace {

// The square [-s, s]^2 at height y; facing +y when `up`, else -y.
void addHorizontalQuad(TriangleMesh& mesh, float y, float s, bool up, uint32_t material) {
    const auto base = uint32_t(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), {{-s, y, -s}, {s, y, -s}, {s, y, s}, {-s, y, s}});
    // (-s,-s) -> (-s,+s) -> (+s,+s) is counter-clockwise seen from +y.
    const std::vector<uint32_t> upward{0, 3, 2, 0, 2, 1}, downward{0, 1, 2, 0, 2, 3};
    for (uint32_t i : up ? upward : downward) mesh.indices.push_back(base + i);
    mesh.materialIds.insert(mesh.materialIds.end(), {material, material});
}

RenderOptions lookDown() {
    RenderOptions o;
    o.width = o.height = 24;
    o.samplesPerPixel = 2;
    o.frameScene = false;
    o.camera = {{0, 5, 0.01f}, {0, 0, 0}, {0, 1, 0}, 30};
    o.environment.zenith = o.environment.horizon = o.environment.ground = {0, 0, 0};
    o.environment.sunDirection = {0.3f, 0.8f, 0.2f};
    o.environment.sunIrradiance = {2, 2, 2};
    return o;
}

TEST(Lighting, SunOnALambertianPlaneIsAlbedoOverPiTimesIrradianceTimesCosine) {
    RenderScene scene;
    Material ground;
    ground.baseColor = {0.5f, 0.5f, 0.5f, 1};
    scene.mesh.materials = {ground};
    addHorizontalQuad(scene.mesh, 0, 100, true, 0);
    const RenderOptions o = lookDown();
    auto image = renderWithEmbree(scene, o);
    ASSERT_TRUE(image) << image.message();
    // Black sky, nothing else in the scene: only the sun's direct term, the same at every
    // pixel. Float rounding of a few products: 1e-6 relative.
    const Vec3f sun = normalize(o.environment.sunDirection);
    const float expected = 0.5f / kPi * 2.0f * sun.y;
    for (size_t p = 0; p < image->pixelCount(); ++p)
        ASSERT_NEAR(image->rgb[3 * p], expected, 1e-6f * expected);
}

TEST(Lighting, SingleSidedRoofSeenFromBehindStillCastsItsShadow) {
    // The roof faces down: the camera above sees through its back, but shadow rays going
    // up meet its front. Sun blocked, sky black, roof underside unlit: exactly zero.
    RenderScene scene;
    Material ground, roof;
    roof.doubleSided = false;
    scene.mesh.materials = {ground, roof};
    addHorizontalQuad(scene.mesh, 0, 100, true, 0);
    addHorizontalQuad(scene.mesh, 1, 1000, false, 1);
    auto image = renderWithEmbree(scene, lookDown());
    ASSERT_TRUE(image) << image.message();
    for (size_t p = 0; p < image->pixelCount(); ++p) {
        ASSERT_EQ(image->alpha[p], 1.0f);
        ASSERT_EQ(image->rgb[3 * p], 0.0f) << "pixel " << p;
    }
}

TEST(Lighting, AmbientOcclusionIsOneOnAnOpenConvexShapeAndZeroInsideAClosedOne) {
    const RenderScene sphere = test::unitSphere(5000);
    RenderOptions o;
    o.width = o.height = 24;
    o.samplesPerPixel = 4;
    o.integrator = IntegratorKind::AmbientOcclusion;
    o.frameScene = false;
    o.camera = {{0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 40};
    auto outside = renderWithEmbree(sphere, o);
    ASSERT_TRUE(outside) << outside.message();
    o.camera = {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90};
    auto inside = renderWithEmbree(sphere, o);
    ASSERT_TRUE(inside) << inside.message();
    // Exact: a cosine ray from a convex surface always escapes, one from inside a closed
    // surface never does (robust offsets, watertight mesh).
    for (size_t p = 0; p < outside->pixelCount(); ++p) {
        ASSERT_EQ(outside->rgb[3 * p], 1.0f);
        ASSERT_EQ(inside->rgb[3 * p], 0.0f);
    }
}

}  // namespace
}  // namespace vastray
