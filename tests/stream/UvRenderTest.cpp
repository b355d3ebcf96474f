// The uv AOV (issue 13): a package's texture coordinates interpolated at the pixel-centre hit by
// the device wavefront (lavapipe here) and by the Embree reference, against the analytic UV of a
// quad seen head-on; the two agree; streamed equals in core; a scene without UVs gives 0.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>

#include "StreamTestSupport.h"
#include "TestTmp.h"
#include "vastray/core/ImageFile.h"
#include "vastray/streamer/PackageBuilder.h"

namespace vastray {
namespace {

// The unit quad in z = 0 as a grid of `cells` x `cells` squares (several chunks at the smallest
// chunk size), its UVs affine in the position: u = 0.5 x + 0.25, v = 1 - y (a texture's v grows
// downwards). Without `uvs`, none.
TriangleMesh unitQuad(uint32_t cells, bool uvs) {
    TriangleMesh mesh;
    mesh.materials = {Material{}};
    for (uint32_t y = 0; y <= cells; ++y)
        for (uint32_t x = 0; x <= cells; ++x) {
            const float px = float(x) / float(cells), py = float(y) / float(cells);
            mesh.positions.push_back({px, py, 0.0f});
            if (uvs) mesh.uvs.push_back({0.5f * px + 0.25f, 1.0f - py});
        }
    for (uint32_t y = 0; y < cells; ++y)
        for (uint32_t x = 0; x < cells; ++x) {
            const uint32_t a = y * (cells + 1) + x, b = a + 1, c = a + cells + 1, d = c + 1;
            mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
        }
    return mesh;
}

std::string package(const std::string& name, TriangleMesh mesh) {
    const std::filesystem::path dir = test::testTmpDir("uv-render");
    std::filesystem::create_directories(dir);
    const std::string path = (dir / (name + ".vast")).string();
    PackageBuildOptions options;
    options.quantizeBits = 0;  // lossless: the quad's corners are exactly where the analytic UV assumes
    options.chunkSizeBytes = kMinChunkSizeBytes;
    options.progress = Progress::Mode::None;
    auto report = buildPackage(std::move(mesh), path, options);
    EXPECT_TRUE(report) << report.message();
    return path;
}

// Straight at the quad's centre from z = 2, the quad filling most of the frame.
RenderOptions headOn() {
    RenderOptions o;
    o.width = 40, o.height = 32;
    o.samplesPerPixel = 1;
    o.maxDepth = 1;
    o.frameScene = false;
    o.camera.eye = {0.5f, 0.5f, 2.0f};
    o.camera.target = {0.5f, 0.5f, 0.0f};
    o.camera.up = {0.0f, 1.0f, 0.0f};
    o.camera.fovYDegrees = 35.0f;
    o.aovs = kAovUv | kAovPrimId;
    return o;
}

// The pixel-centre ray of every pixel meets z = 0 where double arithmetic says; inside the quad
// (away from its border by 1e-4, where a pixel-centre ray could miss in float) the UV must be
// 0.5 x + 0.25, 1 - y within 1e-5 (the hit's barycentrics carry float rounding of a few 1e-7;
// 1e-5 is far below a texel of a 16k texture, 6e-5). Misses must be 0. Returns the hits checked.
size_t expectAnalyticUvs(const RenderImage& image, const RenderOptions& o, const std::string& backend) {
    const CameraRays camera(o.camera, o.width, o.height);
    size_t checked = 0;
    for (uint32_t y = 0; y < o.height; ++y)
        for (uint32_t x = 0; x < o.width; ++x) {
            const Ray ray = camera.primary(x, y, 0.5f, 0.5f);
            const double t = -double(ray.origin.z) / double(ray.direction.z);
            const double px = ray.origin.x + t * ray.direction.x, py = ray.origin.y + t * ray.direction.y;
            const size_t i = size_t(y) * o.width + x;
            const float u = image.uv[2 * i], v = image.uv[2 * i + 1];
            if (px < -1e-4 || px > 1 + 1e-4 || py < -1e-4 || py > 1 + 1e-4) {
                EXPECT_EQ(u, 0.0f) << backend << " miss at pixel " << x << ", " << y;
                EXPECT_EQ(v, 0.0f) << backend << " miss at pixel " << x << ", " << y;
                continue;
            }
            if (px < 1e-4 || px > 1 - 1e-4 || py < 1e-4 || py > 1 - 1e-4) continue;
            EXPECT_NEAR(u, 0.5 * px + 0.25, 1e-5) << backend << " pixel " << x << ", " << y;
            EXPECT_NEAR(v, 1.0 - py, 1e-5) << backend << " pixel " << x << ", " << y;
            ++checked;
        }
    return checked;
}

TEST(UvRender, BothBackendsGiveTheAnalyticUvAtPixelCentres) {
    const std::string path = package("uv-quad", unitQuad(24, true));
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    ASSERT_TRUE((*reader)->info().hasUvs);
    ASSERT_GT((*reader)->info().chunks.size(), 2u);
    const RenderOptions o = headOn();
    // The slots hold 8 bytes a vertex for UVs when the render reads them, none otherwise.
    const ChunkAttributes withUvs = requiredAttributes((*reader)->info(), o);
    ChunkAttributes withoutUvs = withUvs;
    withoutUvs.uvs = false;
    ASSERT_TRUE(withUvs.uvs);
    for (const ChunkInfo& c : (*reader)->info().chunks)
        EXPECT_EQ(chunkLayout(c, withUvs).totalBytes - chunkLayout(c, withoutUvs).totalBytes,
                  (8 * uint64_t(c.vertexCount) + 15) / 16 * 16);
    RenderOptions noAov = o;
    noAov.aovs = kAovPrimId;
    EXPECT_FALSE(requiredAttributes((*reader)->info(), noAov).uvs) << "a render without the uv AOV uploads none";
    auto reference = test::renderEmbree(path, o);
    ASSERT_TRUE(reference) << reference.message();
    StreamingStats stats;
    auto device = test::renderVulkan(path, o, 256ull << 20, &stats);
    ASSERT_TRUE(device) << device.message();
    EXPECT_GT(expectAnalyticUvs(*reference, o, "embree"), 600u);
    EXPECT_GT(expectAnalyticUvs(*device, o, "vulkan"), 600u);
    // The same hit gives the same UV up to the two traversals' barycentrics (both watertight, in
    // f32): within 1e-6.
    for (size_t i = 0; i < device->primId.size(); ++i) {
        if (device->primId[i] != reference->primId[i]) continue;
        EXPECT_NEAR(device->uv[2 * i], reference->uv[2 * i], 1e-6) << "pixel " << i;
        EXPECT_NEAR(device->uv[2 * i + 1], reference->uv[2 * i + 1], 1e-6) << "pixel " << i;
    }
    // Two slots: chunks come and go between passes, the hit's UV is kept in the path's record.
    const uint64_t tight = test::budgetForSlots(path, 2, o.aovs);
    ASSERT_GT(tight, 0u);
    auto streamed = test::renderVulkan(path, o, tight);
    ASSERT_TRUE(streamed) << streamed.message();
    EXPECT_EQ(std::memcmp(streamed->uv.data(), device->uv.data(), device->uv.size() * 4), 0);

    // The EXR keeps them as float channels uv.u and uv.v.
    const std::string exr = (test::testTmpDir("uv-render") / "uv.exr").string();
    ASSERT_TRUE(writeImageFile(exr, *device));
    auto channels = readImageChannels(exr, {"uv.u", "uv.v"});
    ASSERT_TRUE(channels) << channels.message();
    for (size_t i = 0; i < device->primId.size(); ++i) {
        EXPECT_EQ(channels->planes[0][i], device->uv[2 * i]) << i;
        EXPECT_EQ(channels->planes[1][i], device->uv[2 * i + 1]) << i;
    }
}

// A scene without UVs: the uv AOV is 0 everywhere on both backends, and nothing is uploaded for it.
TEST(UvRender, SceneWithoutUvsWritesZeros) {
    const std::string path = package("uv-none", unitQuad(24, false));
    const RenderOptions o = headOn();
    auto reference = test::renderEmbree(path, o);
    ASSERT_TRUE(reference) << reference.message();
    auto device = test::renderVulkan(path, o, 256ull << 20);
    ASSERT_TRUE(device) << device.message();
    size_t hits = 0;
    for (size_t i = 0; i < device->primId.size(); ++i) {
        hits += device->primId[i] != kMissPrimId;
        for (int c = 0; c < 2; ++c) {
            EXPECT_EQ(device->uv[2 * i + c], 0.0f) << i;
            EXPECT_EQ(reference->uv[2 * i + c], 0.0f) << i;
        }
    }
    EXPECT_GT(hits, 600u);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    EXPECT_FALSE(requiredAttributes((*reader)->info(), o).uvs) << "nothing to upload";
}

}  // namespace
}  // namespace vastray
