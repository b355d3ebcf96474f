// A cut-out whose mask is another image than its base colour map's (an OBJ map_d beside map_Kd,
// baked into map_Kd's alpha at import: docs/RENDERING.md, "Cut-outs") lets the scene behind it
// through on the Embree reference, from the OBJ and from its package alike. The device reads
// the same material and texture (TextureDeviceRenderTest compares the backends on cut-outs).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "TestRenders.h"
#include "TestScenes.h"
#include "vastray/core/ImageFile.h"
#include "vastray/cpu/EmbreeRenderer.h"
#include "vastray/cpu/RenderScene.h"
#include "vastray/streamer/Import.h"
#include "vastray/streamer/PackageBuilder.h"

namespace vastray {
namespace {

constexpr uint32_t kPixels = 8;

void writeText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// The unit quad at z = 0 (red map_Kd, map_d a 2 x 1 grey mask: black left, white right, both
// clamped) in front of a larger green quad at z = -1. The mask is resampled to the 8 x 8 base:
// column alphas 0, 0, 32, 96, 159, 223, 255, 255 (x = (i + 0.5) / 4 - 0.5 over 0 and 255).
std::string writeMaskedQuadObj() {
    std::vector<uint8_t> red;
    for (uint32_t i = 0; i < kPixels * kPixels; ++i) red.insert(red.end(), {255, 0, 0, 255});
    EXPECT_TRUE(writeRgba8Png(test::tmpPath("cut-red.png"), kPixels, kPixels, red));
    // A grey mask with no alpha: writeRgba8Png writes RGBA, so its alpha is given as the mask too
    // (the default channel then reads the alpha: the same values).
    EXPECT_TRUE(writeRgba8Png(test::tmpPath("cut-mask.png"), 2, 1, {0, 0, 0, 0, 255, 255, 255, 255}));
    writeText(test::tmpPath("cut.mtl"), "newmtl front\nKd 1 1 1\nmap_Kd -clamp on cut-red.png\n"
                                        "map_d -clamp on cut-mask.png\nnewmtl back\nKd 0 1 0\n");
    const std::string obj = test::tmpPath("cut.obj");
    writeText(obj, "mtllib cut.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                   "v -1 -1 -1\nv 2 -1 -1\nv 2 2 -1\nv -1 2 -1\n"
                   "usemtl front\nf 1/1 2/2 3/3 4/4\nusemtl back\nf 5 6 7 8\n");
    return obj;
}

// Columns 0-3 (mask alpha below 0.5) show the green quad behind, 4-7 the red map; the albedo is
// exact (1 and 0 in linear) but for float noise, tolerance 1e-6.
void expectCutLeftHalf(const RenderScene& scene, const char* what) {
    auto rendered = renderWithEmbree(scene, test::headOnAlbedo(kPixels), nullptr, {});
    ASSERT_TRUE(rendered) << rendered.message();
    for (uint32_t y = 0; y < kPixels; ++y)
        for (uint32_t x = 0; x < kPixels; ++x) {
            const float* a = &rendered->albedo[3 * (size_t(y) * kPixels + x)];
            const bool cut = x < kPixels / 2;
            EXPECT_NEAR(a[0], cut ? 0.0f : 1.0f, 1e-6f) << what << " pixel " << x << "," << y;
            EXPECT_NEAR(a[1], cut ? 1.0f : 0.0f, 1e-6f) << what << " pixel " << x << "," << y;
        }
}

TEST(CutoutImportRender, AMaskOnAnotherImageLetsTheBackgroundThroughItsCutRegion) {
    const std::string obj = writeMaskedQuadObj();
    auto fromFile = loadRenderScene(obj);
    ASSERT_TRUE(fromFile) << fromFile.message();
    ASSERT_EQ(fromFile->textures.size(), 1u);
    EXPECT_EQ(fromFile->mesh.materials[0].alphaCutoff, 0.5f);
    expectCutLeftHalf(*fromFile, "from the OBJ");

    auto imported = importMesh(obj);
    ASSERT_TRUE(imported) << imported.message();
    const std::string package = test::tmpPath("cut.vast");
    PackageBuildOptions build;
    build.quantizeBits = 0;
    build.progress = Progress::Mode::None;
    ASSERT_TRUE(buildPackage(imported->mesh, package, build));
    auto fromPackage = loadRenderScene(package);
    ASSERT_TRUE(fromPackage) << fromPackage.message();
    expectCutLeftHalf(*fromPackage, "from its package");
}

}  // namespace
}  // namespace vastray
