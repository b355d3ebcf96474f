// The Embree reference samples the materials' maps (docs/RENDERING.md, "Textures"): a textured
// quad's texels land on the pixels whose centres they cover (exact UV checks through the albedo
// AOV, at texel centres where bilinear filtering weighs one texel), its emissive map is the
// radiance seen with no light, its metallic-roughness map scales the factors; a package renders
// as the file it was imported from.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "TestRenders.h"
#include "TestScenes.h"
#include "TestTextures.h"
#include "vastray/core/ImageFile.h"
#include "vastray/core/PathShading.h"
#include "vastray/cpu/EmbreeRenderer.h"
#include "vastray/cpu/RenderScene.h"
#include "vastray/streamer/Import.h"
#include "vastray/streamer/PackageBuilder.h"

namespace vastray {
namespace {

constexpr uint32_t kTexels = 8;

// The unit quad [0, 1]^2 at z = 0 facing +z, its UVs in glTF's space (v down from the image's
// top): the image's top row at y = 1. One material whose base colour and emissive maps are
// texture 0 (an 8 x 8 sRGB image, clamped).
RenderScene texturedQuad(const Rgba8Image& image, bool emissive) {
    RenderScene scene;
    TriangleMesh& mesh = scene.mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    Material m;
    m.baseColor = {1, 1, 1, 1};
    m.textures.slots[uint32_t(TextureSlot::BaseColor)].texture = 0;
    if (emissive) {
        m.emissive = {2, 2, 2};
        m.textures.slots[uint32_t(TextureSlot::Emissive)].texture = 0;
    }
    mesh.materials = {m};
    scene.bounds = mesh.bounds();
    const std::string png = test::tmpPath("checker.png");
    EXPECT_TRUE(writeRgba8Png(png, image.width, image.height, image.texels));
    std::ifstream in(png, std::ios::binary);
    const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    auto texture = decodeTexture({"checker.png", ".png", bytes, TextureWrap::Clamp, TextureWrap::Clamp,
                                  TextureEncoding::Srgb});
    EXPECT_TRUE(texture) << texture.message();
    if (texture) scene.textures.push_back(std::move(texture).value());
    return scene;
}

TEST(TextureRender, AnImageWithoutBytesIsRefusedByName) {
    auto texture = decodeTexture({"image 4 of a.glb", ".png", {}, TextureWrap::Clamp, TextureWrap::Clamp,
                                  TextureEncoding::Srgb});
    ASSERT_FALSE(texture);
    EXPECT_NE(texture.message().find("image 4 of a.glb"), std::string::npos) << texture.message();
}

TEST(TextureRender, TexelsLandOnThePixelsTheyCover) {
    const Rgba8Image image = test::noiseImage(kTexels, kTexels, 3);
    const RenderScene scene = texturedQuad(image, false);
    ASSERT_EQ(scene.textures.size(), 1u);
    RenderOptions o = test::headOnAlbedo(kTexels);
    o.textureLod = TextureLodMode::Finest;  // level 0: one texel a pixel (cones: "ConesPick...")
    auto rendered = renderWithEmbree(scene, o, nullptr, {});
    ASSERT_TRUE(rendered) << rendered.message();
    for (uint32_t y = 0; y < kTexels; ++y)
        for (uint32_t x = 0; x < kTexels; ++x) {
            const uint8_t* texel = &image.texels[(size_t(y) * kTexels + x) * 4];
            const float* albedo = &rendered->albedo[3 * (size_t(y) * kTexels + x)];
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(albedo[c], srgb8ToLinear(texel[c]), 2e-3f) << "pixel " << x << "," << y << " channel " << c;
        }
}

// Ray cones (docs/RENDERING.md, "Texture level of detail"): a 32 x 32 texture over the quad that
// fills an 8 x 8 image, 4 texels a pixel: the pixel-centre cone's footprint asks for level 2 (its
// width at the quad is a pixel, 1/8 of the quad; the four centre pixels' rays are within 2.5 deg
// of the normal, so within 0.002 of level 2), whose texels lie one a pixel. --texture-lod finest
// samples level 0 there instead.
TEST(TextureRender, ConesPickTheLevelTheFootprintAsksFor) {
    const Rgba8Image image = test::noiseImage(4 * kTexels, 4 * kTexels, 29);
    const RenderScene scene = texturedQuad(image, false);
    ASSERT_EQ(scene.textures.size(), 1u);
    const DecodedTexture& texture = scene.textures[0];
    ASSERT_GE(texture.layout.levelCount, 3u);
    RenderOptions o = test::headOnAlbedo(kTexels);
    auto cones = renderWithEmbree(scene, o, nullptr, {});
    ASSERT_TRUE(cones) << cones.message();
    o.textureLod = TextureLodMode::Finest;
    auto finest = renderWithEmbree(scene, o, nullptr, {});
    ASSERT_TRUE(finest) << finest.message();
    float apart = 0.0f;
    for (uint32_t y = kTexels / 2 - 1; y <= kTexels / 2; ++y)
        for (uint32_t x = kTexels / 2 - 1; x <= kTexels / 2; ++x) {
            const float u = (float(x) + 0.5f) / kTexels, v = (float(y) + 0.5f) / kTexels;
            const TextureSample level2 = sampleTexture(texture, u, v, 2.0f), level0 = sampleTexture(texture, u, v, 0.0f);
            const float* a = &cones->albedo[3 * (size_t(y) * kTexels + x)];
            const float* b = &finest->albedo[3 * (size_t(y) * kTexels + x)];
            const float want[3] = {level2.r, level2.g, level2.b}, fine[3] = {level0.r, level0.g, level0.b};
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(a[c], want[c], 2e-3f) << "pixel " << x << "," << y << " channel " << c;
                EXPECT_NEAR(b[c], fine[c], 1e-5f) << "pixel " << x << "," << y << " channel " << c;
                apart = std::max(apart, std::fabs(want[c] - fine[c]));
            }
        }
    EXPECT_GT(apart, 0.05f) << "levels 0 and 2 must differ for the test to tell them apart";
}

// Cut-outs (docs/RENDERING.md, "Cut-outs"): a hit is cut where the base colour factor's alpha
// times the map's alpha (level 0, the map's UV transform applied) is below the cutoff; never
// without a cutoff or a map.
TEST(TextureRender, CutOutWhereTheMapsAlphaFallsBelowTheCutoff) {
    Rgba8Image image = test::noiseImage(kTexels, kTexels, 33);
    for (uint32_t i = 0; i < kTexels * kTexels; ++i) image.texels[4 * i + 3] = (i % 2) ? 255 : 102;  // 0.4
    const RenderScene scene = texturedQuad(image, false);
    Material m = scene.mesh.materials[0];
    const std::array<float, 2> dim{0.5f / kTexels, 0.5f / kTexels}, solid{1.5f / kTexels, 0.5f / kTexels};
    EXPECT_FALSE(cutOut(m, scene.textures, dim)) << "no cutoff: opaque";
    m.alphaCutoff = 0.5f;
    EXPECT_TRUE(cutOut(m, scene.textures, dim));
    EXPECT_FALSE(cutOut(m, scene.textures, solid));
    m.alphaCutoff = 0.35f;
    EXPECT_FALSE(cutOut(m, scene.textures, dim)) << "0.4 is not below 0.35";
    m.baseColor[3] = 0.5f;
    EXPECT_TRUE(cutOut(m, scene.textures, dim)) << "0.5 x 0.4 is";
    m.textures.slots[uint32_t(TextureSlot::BaseColor)].transform = khrTextureTransform(1.0f / kTexels, 0, 0, 1, 1);
    EXPECT_FALSE(cutOut(m, scene.textures, dim)) << "the transform moves the sample onto the solid texel";
    m.textures.slots[uint32_t(TextureSlot::BaseColor)].texture = kNoTexture;
    EXPECT_FALSE(cutOut(m, scene.textures, dim)) << "no map: opaque";
}

TEST(TextureRender, TheEmissiveMapIsTheRadianceSeenWithoutLight) {
    // One colour: the beauty's camera rays are jittered inside their pixels, so bilinear filtering
    // blends neighbouring texels (the placement is the albedo test's).
    Rgba8Image image{kTexels, kTexels, {}};
    for (uint32_t i = 0; i < kTexels * kTexels; ++i) image.texels.insert(image.texels.end(), {200, 100, 50, 255});
    const RenderScene scene = texturedQuad(image, true);
    RenderOptions o = test::headOnAlbedo(kTexels);
    o.maxDepth = 0;  // emitters and sky only
    auto rendered = renderWithEmbree(scene, o, nullptr, {});
    ASSERT_TRUE(rendered) << rendered.message();
    for (uint32_t p = 0; p < kTexels * kTexels; ++p)
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(rendered->rgb[3 * p + c], 2.0f * srgb8ToLinear(image.texels[4 * p + c]), 4e-3f) << p;
}

TEST(TextureRender, MetallicRoughnessMapScalesTheFactors) {
    // A 1 x 1 linear map: G 128 (roughness 0.5 of the factor), B 64 (metallic 0.25 of it).
    auto pyramidOf = [](uint8_t r, uint8_t g, uint8_t b) {
        DecodedTexture t;
        t.layout = *makeTextureLayout(1, 1);
        t.encoding = TextureEncoding::Linear;
        t.pages.assign(kTexturePageBytes, 0);
        for (size_t i = 0; i < kTexturePageBytes; i += 4) t.pages[i] = r, t.pages[i + 1] = g, t.pages[i + 2] = b;
        return t;
    };
    const DecodedTexture map = pyramidOf(0, 128, 64);
    Material m;
    m.metallic = 0.8f;
    m.roughness = 0.6f;
    m.textures.slots[uint32_t(TextureSlot::MetallicRoughness)].texture = 0;
    const std::vector<DecodedTexture> textures{map};
    const MaterialSample s = sampleMaterial(m, textures, {0.3f, 0.7f}, nullptr);
    EXPECT_NEAR(s.roughness, 0.6f * 128.0f / 255.0f, 1e-6f);
    EXPECT_NEAR(s.metallic, 0.8f * 64.0f / 255.0f, 1e-6f);
    EXPECT_EQ(s.baseColor.x, m.baseColor[0]);  // no base colour map: the factor
    const MaterialSample plain = sampleMaterial(Material{}, textures, {0.3f, 0.7f}, nullptr);
    EXPECT_EQ(plain.roughness, 1.0f);
}

TEST(TextureRender, APackageRendersAsTheFileItWasImportedFrom) {
    const std::string file = "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " is absent (assimp-testmodels not installed)";
    auto imported = importMesh(file);
    ASSERT_TRUE(imported) << imported.message();
    const std::string package = test::tmpPath("box-textured.vast");
    PackageBuildOptions build;
    build.quantizeBits = 0;  // lossless: the same positions, so the same hits
    build.progress = Progress::Mode::None;
    ASSERT_TRUE(buildPackage(imported->mesh, package, build));
    auto fromFile = loadRenderScene(file);
    auto fromPackage = loadRenderScene(package);
    ASSERT_TRUE(fromFile) << fromFile.message();
    ASSERT_TRUE(fromPackage) << fromPackage.message();
    ASSERT_EQ(fromPackage->textures.size(), 1u);
    EXPECT_EQ(fromPackage->textures[0].pages, fromFile->textures[0].pages);
    RenderOptions o;
    o.width = o.height = 48;
    o.samplesPerPixel = 2;
    o.aovs = kAovAlbedo;
    auto a = renderWithEmbree(*fromFile, o, nullptr, {});
    auto b = renderWithEmbree(*fromPackage, o, nullptr, {});
    ASSERT_TRUE(a && b);
    // The package's chunk stores the triangles' corners in another order (Draco), so barycentrics
    // and UVs differ in the last bits: every albedo pixel within 1e-3, but for the few whose
    // centre ray grazes an edge of the box.
    size_t differing = 0;
    for (size_t i = 0; i < a->albedo.size(); ++i) differing += std::fabs(a->albedo[i] - b->albedo[i]) > 1e-3f;
    EXPECT_LE(differing, a->albedo.size() / 100) << differing << " of " << a->albedo.size();
    // The logo's colours, not the material's white factor alone.
    float darkest = 1.0f;
    for (float v : a->albedo) darkest = std::min(darkest, v);
    EXPECT_LT(darkest, 0.5f);
}

}  // namespace
}  // namespace vastray
