// An OBJ cut-out whose map_d is another image than its map_Kd (baked into the base colour map's
// alpha at import: docs/RENDERING.md, "Cut-outs") renders on the device as on the Embree
// reference: the mask's cut half shows the quad behind (CutoutImportRenderTest checks the
// reference's pixels exactly).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "StreamTestSupport.h"
#include "TestTmp.h"
#include "vastray/core/ImageFile.h"
#include "vastray/streamer/Import.h"
#include "vastray/streamer/PackageBuilder.h"

namespace vastray {
namespace {

// The package of a red unit quad at z = 0 whose map_d (a 2 x 1 mask, 0 then 255) cuts its left
// half, in front of a green quad at z = -1.
std::string maskedQuadPackage() {
    const std::filesystem::path dir = test::testTmpDir("cutout-import");
    std::filesystem::create_directories(dir);
    std::vector<uint8_t> red;
    for (int i = 0; i < 64; ++i) red.insert(red.end(), {255, 0, 0, 255});
    EXPECT_TRUE(writeRgba8Png((dir / "red.png").string(), 8, 8, red));
    EXPECT_TRUE(writeRgba8Png((dir / "mask.png").string(), 2, 1, {0, 0, 0, 0, 255, 255, 255, 255}));
    std::ofstream(dir / "cut.mtl") << "newmtl front\nKd 1 1 1\nmap_Kd -clamp on red.png\nmap_d -clamp on mask.png\n"
                                      "newmtl back\nKd 0 1 0\n";
    std::ofstream(dir / "cut.obj") << "mtllib cut.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                                      "vt 0 1\nv -1 -1 -1\nv 2 -1 -1\nv 2 2 -1\nv -1 2 -1\n"
                                      "usemtl front\nf 1/1 2/2 3/3 4/4\nusemtl back\nf 5 6 7 8\n";
    auto imported = importMesh((dir / "cut.obj").string());
    EXPECT_TRUE(imported) << imported.message();
    const std::string package = (dir / "cut.vast").string();
    PackageBuildOptions build;
    build.quantizeBits = 0;
    build.progress = Progress::Mode::None;
    if (imported) {
        EXPECT_TRUE(buildPackage(imported->mesh, package, build));
    }
    return package;
}

// The albedo AOV, head on at the front quad (pixel centres at texel centres): equal on both
// backends within 2e-5 (TextureDeviceRenderTest's tolerance for cut-outs), the left four columns
// green, the right four red.
TEST(CutoutImportDevice, AMaskOnAnotherImageCutsOnTheDeviceAsOnTheReference) {
    const std::string package = maskedQuadPackage();
    RenderOptions o;
    o.width = o.height = 8;
    o.samplesPerPixel = 1;
    o.frameScene = false;
    const float fov = 40.0f;
    o.camera = {{0.5f, 0.5f, 0.5f / std::tan(fov * 0.5f * float(M_PI) / 180.0f)}, {0.5f, 0.5f, 0}, {0, 1, 0}, fov};
    o.aovs = kAovAlbedo;
    auto device = test::renderVulkan(package, o, 256ull << 20);
    ASSERT_TRUE(device) << device.message();
    auto reference = test::renderEmbree(package, o);
    ASSERT_TRUE(reference) << reference.message();
    for (uint32_t p = 0; p < 64; ++p) {
        const bool cut = p % 8 < 4;
        EXPECT_NEAR(reference->albedo[3 * p + 1], cut ? 1.0f : 0.0f, 1e-6f) << "pixel " << p;
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(device->albedo[3 * p + c], reference->albedo[3 * p + c], 2e-5f) << "pixel " << p << " channel " << c;
    }
}

}  // namespace
}  // namespace vastray
