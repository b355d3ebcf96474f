// Issue 13 ("Real assets"): glTF alphaMode BLEND (and MTL d) as stochastic transparency on both
// backends (docs/RENDERING.md, "Blending"): a ray meets a blended surface with the
// probability of its alpha, by a coin per ray and primitive. Closed forms: a sunlit quad of alpha
// a shows a times its light over a black sky; a floor under a blended roof receives 1 - a of the
// sun; a map's alpha multiplies the factor's. The device draws the reference's coins (same
// floats), and a streamed render equals the in-core one.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "StreamTestSupport.h"
#include "TestTmp.h"
#include "vastray/core/ImageFile.h"
#include "vastray/streamer/PackageBuilder.h"

namespace vastray {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr float kSun = 2.0f;

std::filesystem::path folder() {
    const std::filesystem::path dir = test::testTmpDir("blend");
    std::filesystem::create_directories(dir);
    return dir;
}

std::string package(const std::string& name, TriangleMesh mesh, uint64_t chunkBytes = 64 << 10) {
    return test::meshPackage("blend", name, std::move(mesh), chunkBytes);
}

// Appends the square of half side s centred on `centre` in the plane spanned by axes a and b
// (cells x cells squares), with material `material` and UVs from 0 to 1 over it.
void addSquare(TriangleMesh& mesh, Vec3f centre, int a, int b, float s, uint32_t material, uint32_t cells = 1) {
    const auto base = uint32_t(mesh.positions.size());
    for (uint32_t j = 0; j <= cells; ++j)
        for (uint32_t i = 0; i <= cells; ++i) {
            Vec3f p = centre;
            p[a] += -s + 2 * s * float(i) / float(cells);
            p[b] += -s + 2 * s * float(j) / float(cells);
            mesh.positions.push_back(p);
            mesh.uvs.push_back({float(i) / float(cells), float(j) / float(cells)});
        }
    for (uint32_t j = 0; j < cells; ++j)
        for (uint32_t i = 0; i < cells; ++i) {
            const uint32_t v = base + j * (cells + 1) + i;
            mesh.indices.insert(mesh.indices.end(), {v, v + 1, v + cells + 2, v, v + cells + 2, v + cells + 1});
            mesh.materialIds.insert(mesh.materialIds.end(), {material, material});
        }
}

Material white(const char* name, float albedo) {
    Material m{name};
    m.baseColor = {albedo, albedo, albedo, 1};
    return m;
}
Material blended(float alpha) {
    Material m = white("glass", 1.0f);
    m.baseColor[3] = alpha;
    m.alphaBlend = true;
    return m;
}

// Sky black, the sun of irradiance kSun along `sun`, one scattering event.
RenderOptions view(Vec3f eye, Vec3f target, float fov, Vec3f sun, uint32_t spp) {
    RenderOptions o;
    o.width = o.height = 16;
    o.samplesPerPixel = spp;
    o.maxDepth = 1;
    o.frameScene = false;
    o.camera = {eye, target, {0, 1, 0}, fov};
    o.environment.zenith = o.environment.horizon = o.environment.ground = {0, 0, 0};
    o.environment.sunIrradiance = {kSun, kSun, kSun};
    o.environment.sunDirection = sun;
    return o;
}

using test::Mean;
using test::pixelMean;

// Renders on both backends, expects the closed form within 4 standard errors of the samples
// (each pixel averages spp binary outcomes: the standard error is sqrt(p (1 - p) / samples)
// times the lit value) and the device equal to the reference.
void expectBoth(const std::string& path, const RenderOptions& o, double lit, double probability, const char* what) {
    auto device = test::renderVulkan(path, o, 256ull << 20);
    auto reference = test::renderEmbree(path, o);
    ASSERT_TRUE(device && reference) << device.message() << reference.message();
    const double samples = double(o.width) * o.height * o.samplesPerPixel;
    const double error = lit * std::sqrt(probability * (1 - probability) / samples);
    const Mean d = pixelMean(*device), r = pixelMean(*reference);
    std::printf("%s: device %.5f, Embree %.5f, expected %.5f (standard error %.5f)\n", what, d.mean, r.mean,
                lit * probability, error);
    EXPECT_NEAR(r.mean, lit * probability, 4 * error) << what;
    EXPECT_NEAR(d.mean, lit * probability, 4 * error) << what;
    EXPECT_LE(test::relativeRmse(device->rgb, reference->rgb), 1e-5) << what << ": the same coins";
}

TEST(BlendRender, SunlitQuadShowsAlphaTimesItsLight) {
    TriangleMesh mesh;
    mesh.materials = {blended(0.3f)};
    addSquare(mesh, {0, 0, 0}, 0, 1, 2.0f, 0);  // facing +z
    const std::string path = package("quad", std::move(mesh));
    // Facing the sun: albedo 1 / pi x E; the camera sees only the quad.
    expectBoth(path, view({0, 0, 5}, {0, 0, 0}, 20.0f, {0, 0, 1}, 64), kSun / kPi, 0.3, "quad of alpha 0.3");
}

TEST(BlendRender, FloorUnderABlendedRoofReceivesOneMinusAlphaOfTheSun) {
    TriangleMesh mesh;
    mesh.materials = {white("floor", 0.5f), blended(0.3f)};
    addSquare(mesh, {0, 0, 0}, 2, 0, 20.0f, 0);  // the floor y = 0, facing +y
    addSquare(mesh, {0, 1, 0}, 2, 0, 3.0f, 1);   // the roof at y = 1
    const std::string path = package("roof", std::move(mesh));
    // From under the roof, looking down at the floor's centre: the sun straight above.
    expectBoth(path, view({0, 0.5f, 2.5f}, {0, 0, 0}, 10.0f, {0, 1, 0}, 64), 0.5 / kPi * kSun, 0.7,
               "floor under a roof of alpha 0.3");
}

TEST(BlendRender, MapAlphaMultipliesTheFactors) {
    // A 1 x 1 map of alpha 128 (maps' alpha is linear) over a factor alpha of 0.8.
    const std::string png = (folder() / "half.png").string();
    ASSERT_TRUE(writeRgba8Png(png, 1, 1, {255, 255, 255, 128}));
    std::ifstream in(png, std::ios::binary);
    TextureSource texture{"half.png", ".png", {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()}};
    TriangleMesh mesh;
    Material m = blended(0.8f);
    m.textures.slots[uint32_t(TextureSlot::BaseColor)].texture = 0;
    mesh.materials = {m};
    mesh.textures = {texture};
    addSquare(mesh, {0, 0, 0}, 0, 1, 2.0f, 0);
    const std::string path = package("mapped", std::move(mesh));
    expectBoth(path, view({0, 0, 5}, {0, 0, 0}, 20.0f, {0, 0, 1}, 64), kSun / kPi, 0.8 * 128.0 / 255.0,
               "quad of alpha 0.8 x 128/255");
}

TEST(BlendRender, StreamedEqualsInCoreWithBlends) {
    TriangleMesh mesh;
    mesh.materials = {white("floor", 0.5f), blended(0.4f)};
    addSquare(mesh, {0, 0, 0}, 2, 0, 20.0f, 0, 40);
    addSquare(mesh, {0, 1, 0}, 2, 0, 3.0f, 1, 8);
    const std::string path = package("roof-chunked", std::move(mesh), 16 << 10);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    const uint64_t chunks = (*reader)->info().chunks.size();
    ASSERT_GT(chunks, 2u);
    RenderOptions o = view({0, 3, 6}, {0, 0, 0}, 60.0f, {0.3f, 1, 0.2f}, 4);
    o.width = o.height = 32;
    o.maxDepth = 3;
    o.environment.zenith = {0.3f, 0.4f, 0.8f};
    o.aovs = kAovAlbedo | kAovPrimId;
    auto inCore = test::renderVulkan(path, o, 512ull << 20);
    ASSERT_TRUE(inCore) << inCore.message();
    test::expectTwoSlotRenderEquals(path, o, 0, *inCore, chunks);
    // The AOVs' pixel-centre rays draw the reference's coins too.
    auto reference = test::renderEmbree(path, o);
    ASSERT_TRUE(reference) << reference.message();
    EXPECT_EQ(inCore->primId, reference->primId);
    EXPECT_LE(test::relativeRmse(inCore->rgb, reference->rgb), 1e-4);
}

}  // namespace
}  // namespace vastray
