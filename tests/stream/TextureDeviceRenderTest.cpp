// The Vulkan renderer samples the materials' maps (issue 13, docs/RENDERING.md "Textures"): a
// textured quad's texels land on the pixels whose centres they cover, as on the Embree reference
// (exact through the albedo AOV); base colour, metallic-roughness and emissive maps render as the
// reference renders them; textures four times the texture pool render the same image as with an
// ample pool, the pool's bytes within the budget; a budget below the textures' minimum is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "HeadOnView.h"
#include "StreamTestSupport.h"
#include "TestTextures.h"
#include "TestTmp.h"
#include "vastray/core/ImageFile.h"
#include "vastray/core/Texture.h"
#include "vastray/streamer/Import.h"
#include "vastray/streamer/PackageBuilder.h"

namespace vastray {
namespace {

std::filesystem::path folder() {
    const std::filesystem::path dir = test::testTmpDir("device-textures");
    std::filesystem::create_directories(dir);
    return dir;
}

std::vector<uint8_t> pngBytes(const Rgba8Image& image, const std::string& name) {
    const std::string png = (folder() / name).string();
    EXPECT_TRUE(writeRgba8Png(png, image.width, image.height, image.texels));
    std::ifstream in(png, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// `mesh` as the package NAME.vast in the test's folder, in chunks of at most chunkSizeBytes.
std::string writePackage(const std::string& name, TriangleMesh mesh, uint64_t chunkSizeBytes = 16ull << 20) {
    return test::meshPackage("device-textures", name, std::move(mesh), chunkSizeBytes);
}

// The unit quad [0, 1]^2 at z = 0 facing +z, its UVs in glTF's space (v down from the image's
// top), material `m` (its maps name `textures`), as the package NAME.vast.
std::string quadPackage(const std::string& name, const Material& m, std::vector<TextureSource> textures) {
    TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    mesh.materials = {m};
    mesh.textures = std::move(textures);
    return writePackage(name, std::move(mesh));
}

TextureSource source(const Rgba8Image& image, const std::string& name, TextureWrap wrap, TextureEncoding encoding) {
    return {name, ".png", pngBytes(image, name), wrap, wrap, encoding};
}

// Looking straight at the quad from +z, the quad exactly filling a side x side image.
RenderOptions headOn(uint32_t side) { return test::headOnUnitQuad(side); }

// Seen from above and aside, lit by the sky and the sun: glossy and Lambertian, emission.
RenderOptions lit(uint32_t side, uint32_t spp) {
    RenderOptions o;
    o.width = o.height = side;
    o.samplesPerPixel = spp;
    o.maxDepth = 3;
    o.frameScene = false;
    o.camera = {{0.2f, -0.6f, 1.4f}, {0.5f, 0.5f, 0}, {0, 0, 1}, 50.0f};
    return o;
}

// The device's render (every page resident) and the Embree reference's.
struct BothBackends {
    RenderImage device, reference;
};
Result<BothBackends> renderBothBackends(const std::string& path, const RenderOptions& o) {
    auto device = test::renderVulkan(path, o, 256ull << 20);
    if (!device) return device.status().withContext("vulkan: ");
    auto reference = test::renderEmbree(path, o);
    if (!reference) return reference.status().withContext("embree: ");
    return BothBackends{std::move(device).value(), std::move(reference).value()};
}

// A render with every page resident and one through a pool of `budget` bytes (stats of each).
struct InCoreAndPaged {
    RenderImage inCore, paged;
    StreamingStats ample, tight;
};
Result<InCoreAndPaged> renderInCoreAndPaged(const std::string& path, const RenderOptions& o, uint64_t budget) {
    InCoreAndPaged r;
    auto inCore = test::renderVulkan(path, o, 256ull << 20, &r.ample);
    if (!inCore) return inCore.status();
    auto paged = test::renderVulkan(path, o, budget, &r.tight);
    if (!paged) return paged.status();
    r.inCore = std::move(inCore).value(), r.paged = std::move(paged).value();
    return r;
}

// The same beauty and albedo, bit for bit.
void expectSameImages(const RenderImage& a, const RenderImage& b) {
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    ASSERT_EQ(a.albedo.size(), b.albedo.size());
    EXPECT_EQ(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * 4), 0);
    EXPECT_EQ(std::memcmp(a.albedo.data(), b.albedo.data(), a.albedo.size() * 4), 0);
}

Material mapped(bool metalRough, bool emissive) {
    Material m;
    m.baseColor = {1, 1, 1, 1};
    m.textures.slots[uint32_t(TextureSlot::BaseColor)].texture = 0;
    if (metalRough) {
        m.metallic = 1.0f, m.roughness = 1.0f, m.specular = 1.0f;
        m.textures.slots[uint32_t(TextureSlot::MetallicRoughness)] = {1, khrTextureTransform(0.1f, 0.2f, 0.3f, 2, 2)};
    }
    if (emissive) {
        m.emissive = {0.5f, 0.5f, 0.5f};
        m.textures.slots[uint32_t(TextureSlot::Emissive)].texture = 0;
    }
    return m;
}

TEST(TextureDeviceRender, TexelsLandOnThePixelsTheyCoverAsOnTheReference) {
    constexpr uint32_t kTexels = 8;
    const Rgba8Image image = test::noiseImage(kTexels, kTexels, 5);
    const std::string path =
        quadPackage("checker", mapped(false, false), {source(image, "checker.png", TextureWrap::Clamp, TextureEncoding::Srgb)});
    RenderOptions o = headOn(kTexels);
    o.aovs = kAovAlbedo;
    o.textureLod = TextureLodMode::Finest;  // level 0: one texel a pixel (cones: the next test)
    auto both = renderBothBackends(path, o);
    ASSERT_TRUE(both) << both.message();
    const RenderImage *device = &both->device, *reference = &both->reference;
    for (uint32_t y = 0; y < kTexels; ++y)
        for (uint32_t x = 0; x < kTexels; ++x)
            for (int c = 0; c < 3; ++c) {
                const size_t p = size_t(y) * kTexels + x;
                const float texel = srgb8ToLinear(image.texels[4 * p + c]);  // the image's top row at the top
                EXPECT_NEAR(device->albedo[3 * p + c], texel, 2e-5f) << "pixel " << x << "," << y << " channel " << c;
                EXPECT_NEAR(device->albedo[3 * p + c], reference->albedo[3 * p + c], 2e-5f)
                    << "pixel " << x << "," << y << " channel " << c;
            }
}

// Ray cones (docs/RENDERING.md, "Texture level of detail"): a 32 x 32 texture over an 8 x 8
// image asks for level 2 at the pixel centres (the reference's test, TextureRender.ConesPick...):
// the device's albedo equals the reference's at every pixel, and the beauty (cones through
// bounces) too; the four centre pixels show level 2, not level 0.
TEST(TextureDeviceRender, ConesPickTheLevelsTheReferencePicks) {
    constexpr uint32_t kSide = 8;
    const Rgba8Image image = test::noiseImage(4 * kSide, 4 * kSide, 31);
    const TextureSource texture = source(image, "cones.png", TextureWrap::Clamp, TextureEncoding::Srgb);
    const std::string path = quadPackage("cones", mapped(false, false), {texture});
    auto decoded = decodeTexture(texture);
    ASSERT_TRUE(decoded) << decoded.message();
    RenderOptions o = headOn(kSide);
    o.aovs = kAovAlbedo;
    o.samplesPerPixel = 4;
    o.maxDepth = 2;
    auto both = renderBothBackends(path, o);
    ASSERT_TRUE(both) << both.message();
    const RenderImage *device = &both->device, *reference = &both->reference;
    float largest = 0.0f, apart = 0.0f;
    for (size_t i = 0; i < device->albedo.size(); ++i)
        largest = std::max(largest, std::fabs(device->albedo[i] - reference->albedo[i]));
    EXPECT_LE(largest, 2e-5f);
    for (uint32_t y = kSide / 2 - 1; y <= kSide / 2; ++y)
        for (uint32_t x = kSide / 2 - 1; x <= kSide / 2; ++x) {
            const float u = (float(x) + 0.5f) / kSide, v = (float(y) + 0.5f) / kSide;
            const TextureSample level2 = sampleTexture(*decoded, u, v, 2.0f), level0 = sampleTexture(*decoded, u, v, 0.0f);
            const float want[3] = {level2.r, level2.g, level2.b}, fine[3] = {level0.r, level0.g, level0.b};
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(device->albedo[3 * (size_t(y) * kSide + x) + c], want[c], 2e-3f)
                    << "pixel " << x << "," << y << " channel " << c;
                apart = std::max(apart, std::fabs(want[c] - fine[c]));
            }
        }
    EXPECT_GT(apart, 0.05f) << "levels 0 and 2 must differ for the test to tell them apart";
    const double rmse = test::relativeRmse(device->rgb, reference->rgb);
    std::printf("cones: device vs Embree relative RMSE %.2e\n", rmse);
    EXPECT_LE(rmse, 1e-5);
}

// Base colour, metallic-roughness (transformed UVs, repeated) and emissive maps: the device's
// image within the relative RMSE the glossy comparisons allow (1e-2, MaterialRenderTest); the
// maps show (not the factors' image).
TEST(TextureDeviceRender, MapsRenderAsOnTheReference) {
    const Rgba8Image albedo = test::noiseImage(40, 24, 7), metalRough = test::noiseImage(16, 16, 9);
    std::vector<TextureSource> textures{source(albedo, "albedo.png", TextureWrap::Repeat, TextureEncoding::Srgb),
                                        source(metalRough, "mr.png", TextureWrap::Repeat, TextureEncoding::Linear)};
    const std::string path = quadPackage("maps", mapped(true, true), textures);
    const RenderOptions o = lit(40, 8);
    auto both = renderBothBackends(path, o);
    ASSERT_TRUE(both) << both.message();
    const RenderImage *device = &both->device, *reference = &both->reference;
    const double rmse = test::relativeRmse(device->rgb, reference->rgb);
    std::printf("textured quad: device vs Embree relative RMSE %.2e\n", rmse);
    EXPECT_LE(rmse, 1e-2);
    Material factors = mapped(true, true);
    factors.textures = {};
    auto plain = test::renderVulkan(quadPackage("factors", factors, {}), o, 256ull << 20);
    ASSERT_TRUE(plain) << plain.message();
    EXPECT_GT(test::relativeRmse(device->rgb, plain->rgb), 0.1);
}

// A 1024^2 texture (64 pages at level 0, 92 in all) and a 64^2 one (7) through a pool of at most
// a quarter of their pages: the same image and albedo, bit for bit, as with every page resident; pages loaded more
// than once; the device's peak within the budget.
TEST(TextureDeviceRender, TexturesFourTimesThePoolRenderTheSame) {
    const Rgba8Image albedo = test::noiseImage(1024, 1024, 11, 0x3F), metalRough = test::noiseImage(64, 64, 13);
    std::vector<TextureSource> textures{source(albedo, "big.png", TextureWrap::Clamp, TextureEncoding::Srgb),
                                        source(metalRough, "mr.png", TextureWrap::Repeat, TextureEncoding::Linear)};
    const std::string path = quadPackage("big", mapped(true, true), textures);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    const uint64_t textureBytes = gpu::textureBytes((*reader)->info());
    uint64_t pages = 0;
    for (const PackageTexture& t : (*reader)->info().textures) pages += t.layout.pageCount;
    ASSERT_EQ(pages, 99u);
    RenderOptions o = lit(64, 4);  // every page of level 0 in view
    o.aovs = kAovAlbedo;
    o.textureLod = TextureLodMode::Finest;  // level 0 everywhere: the most pages (cones below)
    // The textures' share (a quarter of the budget) a quarter of their bytes.
    const uint64_t budget = textureBytes;
    auto finest = renderInCoreAndPaged(path, o, budget);
    ASSERT_TRUE(finest) << finest.message();
    const StreamingStats &ample = finest->ample, &tight = finest->tight;
    EXPECT_EQ(ample.texturePageSlots, 0u) << "every page resident";
    std::printf("textures %llu bytes in core; budget %llu: %llu page slots, %llu page loads, %llu read, peak %llu bytes\n",
                (unsigned long long)textureBytes, (unsigned long long)budget, (unsigned long long)tight.texturePageSlots,
                (unsigned long long)tight.texturePageLoads, (unsigned long long)tight.texturePagesRead,
                (unsigned long long)tight.peakDeviceBytes);
    EXPECT_GE(tight.texturePageSlots, gpu::kMinTexturePageSlots);
    EXPECT_LE(tight.texturePageSlots * 4, pages) << "the pool holds at most a quarter of the pages";
    EXPECT_GT(tight.texturePageLoads, pages) << "pages paged in more than once";
    EXPECT_LE(tight.texturePagesRead, pages) << "each read from the package once at most (the host cache)";
    EXPECT_EQ(ample.texturePagesRead, pages) << "in core, every page once";
    EXPECT_LE(tight.peakDeviceBytes, budget);
    expectSameImages(finest->paged, finest->inCore);
    // Ray cones read the coarser levels the footprints ask for: fewer pages, the same image paged
    // as in core.
    o.textureLod = TextureLodMode::Cone;
    auto cones = renderInCoreAndPaged(path, o, budget);
    ASSERT_TRUE(cones) << cones.message();
    std::printf("cones: %llu page loads (level 0: %llu)\n", (unsigned long long)cones->tight.texturePageLoads,
                (unsigned long long)tight.texturePageLoads);
    EXPECT_LT(cones->tight.texturePageLoads * 4, tight.texturePageLoads);
    expectSameImages(cones->paged, cones->inCore);
}

// A normal map of random tilts (scaled by 0.8, its UVs turned and scaled) over a base colour map:
// the device bends the shading normal as the reference does (docs/RENDERING.md "Normal maps"):
// the beauty within the glossy comparisons' 1e-2 and the normal AOV within 1e-4; the map shows.
TEST(TextureDeviceRender, NormalMapsBendAsOnTheReference) {
    const Rgba8Image albedo = test::noiseImage(32, 32, 17), normals = test::noiseImage(24, 24, 19);
    Material m = mapped(false, false);
    m.textures.slots[uint32_t(TextureSlot::Normal)] = {1, khrTextureTransform(0.0f, 0.0f, 0.7f, 1.5f, 1.5f)};
    m.textures.normalScale = 0.8f;
    const std::string path = quadPackage("normal-mapped", m,
                                         {source(albedo, "base.png", TextureWrap::Repeat, TextureEncoding::Srgb),
                                          source(normals, "normals.png", TextureWrap::Mirror, TextureEncoding::Linear)});
    RenderOptions o = lit(40, 8);
    o.aovs = kAovNormal;
    auto both = renderBothBackends(path, o);
    ASSERT_TRUE(both) << both.message();
    const RenderImage *device = &both->device, *reference = &both->reference;
    const double rmse = test::relativeRmse(device->rgb, reference->rgb);
    float normalError = 0;
    for (size_t i = 0; i < device->normal.size(); ++i)
        normalError = std::max(normalError, std::fabs(device->normal[i] - reference->normal[i]));
    std::printf("normal-mapped quad: device vs Embree relative RMSE %.2e, normal AOV largest difference %.2e\n", rmse,
                normalError);
    EXPECT_LE(rmse, 1e-2);
    EXPECT_LE(normalError, 1e-4f);
    Material flat = m;
    flat.textures.slots[uint32_t(TextureSlot::Normal)].texture = kNoTexture;
    auto unmapped = test::renderVulkan(quadPackage("normal-unmapped", flat,
                                                   {source(albedo, "base.png", TextureWrap::Repeat, TextureEncoding::Srgb),
                                                    source(normals, "normals.png", TextureWrap::Mirror,
                                                           TextureEncoding::Linear)}),
                                       o, 256ull << 20);
    ASSERT_TRUE(unmapped) << unmapped.message();
    EXPECT_GT(test::relativeRmse(device->rgb, unmapped->rgb), 0.05);
}

// A side x side image of one texel value (r, g, 0, 255), or checkered in r (0 and r in
// `cell`-texel squares) when cell > 0.
Rgba8Image coatImage(uint32_t side, uint8_t r, uint8_t g, uint32_t cell = 0) {
    Rgba8Image image;
    image.width = image.height = side;
    image.texels.resize(size_t(side) * side * 4);
    for (uint32_t y = 0; y < side; ++y)
        for (uint32_t x = 0; x < side; ++x) {
            uint8_t* t = &image.texels[4 * (size_t(y) * side + x)];
            t[0] = cell > 0 && (x / cell + y / cell) % 2 ? 0 : r, t[1] = g, t[2] = 0, t[3] = 255;
        }
    return image;
}

// KHR_materials_clearcoat's maps (package format 13): the coat's weight times its map's R and
// its roughness times its roughness map's G. A map of one value renders as that value in the
// factor does (the same random numbers: only the texel filter's rounding differs), on both
// backends; a checkered coat renders as on the reference within 1e-4 (the two draw the same
// random numbers; the view's coat is 1.5 % of the image, so a map one backend ignored would
// differ by ~1e-2), and unlike no coat.
TEST(TextureDeviceRender, CoatMapsRenderAsTheirFactorsAndAsOnTheReference) {
    Material coated;
    coated.baseColor = {0.05f, 0.05f, 0.3f, 1};
    coated.roughness = 0.8f;
    coated.clearcoat = 1.0f, coated.clearcoatRoughness = 1.0f;
    coated.textures.slots[uint32_t(TextureSlot::Clearcoat)].texture = 0;
    coated.textures.slots[uint32_t(TextureSlot::ClearcoatRoughness)].texture = 0;
    Material factors = coated;
    factors.textures = {};
    factors.clearcoat = 191.0f / 255.0f, factors.clearcoatRoughness = 51.0f / 255.0f;
    const RenderOptions o = lit(32, 8);
    auto uniform = renderBothBackends(
        quadPackage("coat-uniform", coated,
                    {source(coatImage(16, 191, 51), "coat-uniform.png", TextureWrap::Repeat, TextureEncoding::Linear)}),
        o);
    ASSERT_TRUE(uniform) << uniform.message();
    auto asFactors = renderBothBackends(quadPackage("coat-factors", factors, {}), o);
    ASSERT_TRUE(asFactors) << asFactors.message();
    const double deviceDiff = test::relativeRmse(uniform->device.rgb, asFactors->device.rgb);
    const double referenceDiff = test::relativeRmse(uniform->reference.rgb, asFactors->reference.rgb);
    std::printf("uniform coat map against its factor: device %.2e, Embree %.2e\n", deviceDiff, referenceDiff);
    EXPECT_LE(deviceDiff, 1e-3);
    EXPECT_LE(referenceDiff, 1e-3);

    auto checker = renderBothBackends(
        quadPackage("coat-checker", coated,
                    {source(coatImage(64, 255, 26, 8), "coat-checker.png", TextureWrap::Repeat, TextureEncoding::Linear)}),
        o);
    ASSERT_TRUE(checker) << checker.message();
    Material bare = coated;
    bare.textures = {}, bare.clearcoat = 0.0f, bare.clearcoatRoughness = 0.0f;
    auto uncoated = test::renderVulkan(quadPackage("coat-none", bare, {}), o, 256ull << 20);
    ASSERT_TRUE(uncoated) << uncoated.message();
    const double rmse = test::relativeRmse(checker->device.rgb, checker->reference.rgb);
    const double coatShare = test::relativeRmse(checker->device.rgb, uncoated->rgb);
    std::printf("checkered coat map: device vs Embree relative RMSE %.2e; against no coat %.2e\n", rmse, coatShare);
    EXPECT_LE(rmse, 1e-4);
    EXPECT_GT(coatShare, 0.01);
}

// KHR_materials_clearcoat without a clearcoatNormalTexture: the base's normal map does not bend
// the coat (docs/RENDERING.md "Materials"). A coat over a black layerless base (the coat alone
// reflects) under a map that tilts every normal by ~15 degrees renders as it does without the
// map: the same random numbers, and only directions above the coat's normal but below the bent
// one are cut (a coat bent by the map moves its sky and sun reflections by ~30 degrees). The
// device agrees with the reference; a white Lambertian base under the same map differs from its
// unmapped render, so the map does bend the base.
TEST(TextureDeviceRender, ABaseNormalMapDoesNotBendTheCoat) {
    Rgba8Image tilt{8, 8, std::vector<uint8_t>(8 * 8 * 4)};
    for (size_t i = 0; i < 64; ++i)
        tilt.texels[4 * i] = 160, tilt.texels[4 * i + 1] = 128, tilt.texels[4 * i + 2] = 250, tilt.texels[4 * i + 3] = 255;
    const auto quad = [&](const std::string& name, Material m, bool normalMapped) {
        if (normalMapped) m.textures.slots[uint32_t(TextureSlot::Normal)].texture = 0;
        return quadPackage(name, m, {source(tilt, "tilt.png", TextureWrap::Repeat, TextureEncoding::Linear)});
    };
    Material coatOnly;
    coatOnly.baseColor = {0, 0, 0, 1};
    coatOnly.specular = 0.0f, coatOnly.roughness = 0.5f;
    coatOnly.clearcoat = 1.0f, coatOnly.clearcoatRoughness = 0.3f;
    const RenderOptions o = lit(32, 8);
    auto mapped = renderBothBackends(quad("coat-tilted-base", coatOnly, true), o);
    ASSERT_TRUE(mapped) << mapped.message();
    auto flat = renderBothBackends(quad("coat-flat-base", coatOnly, false), o);
    ASSERT_TRUE(flat) << flat.message();
    const double device = test::relativeRmse(mapped->device.rgb, flat->device.rgb);
    const double reference = test::relativeRmse(mapped->reference.rgb, flat->reference.rgb);
    const double backends = test::relativeRmse(mapped->device.rgb, mapped->reference.rgb);
    Material white;
    white.baseColor = {1, 1, 1, 1};
    white.specular = 0.0f;
    auto whiteMapped = test::renderVulkan(quad("white-tilted", white, true), o, 256ull << 20);
    ASSERT_TRUE(whiteMapped) << whiteMapped.message();
    auto whiteFlat = test::renderVulkan(quad("white-flat", white, false), o, 256ull << 20);
    ASSERT_TRUE(whiteFlat) << whiteFlat.message();
    const double base = test::relativeRmse(whiteMapped->rgb, whiteFlat->rgb);
    std::printf("coat over a normal-mapped base against no map: device %.2e, Embree %.2e; device vs Embree %.2e; "
                "a Lambertian base mapped against not %.2e\n",
                device, reference, backends, base);
    EXPECT_LE(device, 1e-2);
    EXPECT_LE(reference, 1e-2);
    EXPECT_LE(backends, 1e-3);
    EXPECT_GT(base, 0.05);
}

// KhronosGroup's ClearCoatTest (assimp-testmodels, which scripts/install-deps.sh installs): rows
// of coated spheres, three rows normal-mapped (a PNG and a JPEG map), imported into a package and
// rendered by both backends: the device within the glossy comparisons' 1e-2 of the reference.
TEST(TextureDeviceRender, AKhronosSampleRendersAsOnTheReference) {
    const std::string file = "/usr/share/assimp/models/glTF2/ClearCoat-glTF/ClearCoatTest.gltf";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " is absent (assimp-testmodels not installed)";
    auto imported = importMesh(file);
    ASSERT_TRUE(imported) << imported.message();
    const std::string package = (folder() / "clearcoat-test.vast").string();
    PackageBuildOptions build;
    build.quantizeBits = 0;  // lossless: the same positions on both sides
    build.progress = Progress::Mode::None;
    ASSERT_TRUE(buildPackage(imported->mesh, package, build));
    RenderOptions o;
    o.width = o.height = 64;
    o.samplesPerPixel = 4;
    o.maxDepth = 3;
    auto both = renderBothBackends(package, o);
    ASSERT_TRUE(both) << both.message();
    const RenderImage *device = &both->device, *reference = &both->reference;
    const double rmse = test::relativeRmse(device->rgb, reference->rgb);
    std::printf("ClearCoatTest: device vs Embree relative RMSE %.2e\n", rmse);
    EXPECT_LE(rmse, 1e-2);
}

// A noise image whose alpha is a checker of `cell`-texel squares, 0 and 255 (a cut-out's mask).
Rgba8Image checkerAlpha(uint32_t side, uint32_t cell, uint32_t seed) {
    Rgba8Image image = test::noiseImage(side, side, seed);
    for (uint32_t y = 0; y < side; ++y)
        for (uint32_t x = 0; x < side; ++x) image.texels[4 * (size_t(y) * side + x) + 3] = ((x / cell + y / cell) % 2) ? 255 : 0;
    return image;
}

// A cut-out quad [0, 1]^2 at z = 0.5 (material 0: its base colour map's alpha checkered, cutoff
// `cutoff`) over an opaque quad [-1, 2]^2 at z = 0 (material 1: plain kBackColour, or with a
// base colour map `back`), as NAME.vast.
constexpr std::array<float, 4> kBackColour{0.1f, 0.9f, 0.2f, 1.0f};
std::string cutoutPackage(const std::string& name, const Rgba8Image& mask, float cutoff, const Rgba8Image* back) {
    TriangleMesh mesh;
    mesh.positions = {{0, 0, 0.5f}, {1, 0, 0.5f}, {1, 1, 0.5f}, {0, 1, 0.5f}, {-1, -1, 0}, {2, -1, 0}, {2, 2, 0}, {-1, 2, 0}};
    mesh.indices = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
    mesh.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}, {0, 1}, {1, 1}, {1, 0}, {0, 0}};
    mesh.materialIds = {0, 0, 1, 1};
    Material front = mapped(false, false), under;
    front.alphaCutoff = cutoff;
    under.baseColor = kBackColour;
    mesh.textures = {source(mask, name + "-mask.png", TextureWrap::Clamp, TextureEncoding::Srgb)};
    if (back) {
        under.baseColor = {1, 1, 1, 1};
        under.textures.slots[uint32_t(TextureSlot::BaseColor)].texture = 1;
        mesh.textures.push_back(source(*back, name + "-back.png", TextureWrap::Repeat, TextureEncoding::Srgb));
    }
    mesh.materials = {front, under};
    return writePackage(name, std::move(mesh));
}

// Cut-outs (docs/RENDERING.md, "Cut-outs"): where the mask's alpha is 0 the camera sees the quad
// behind (its plain colour in the albedo AOV), where it is 255 the mask's colours; light passes
// the holes (the beauty, sun from aside). The device agrees with the reference pixel for pixel
// (a pixel whose bilinear alpha lies within rounding of the cutoff may differ: at most 0.5 %);
// a cutoff of 0 (opaque) shows no hole.
TEST(TextureDeviceRender, CutoutsLetRaysThroughTheirHolesAsOnTheReference) {
    const Rgba8Image mask = checkerAlpha(64, 8, 37);
    RenderOptions o = lit(64, 4);
    o.aovs = kAovAlbedo;
    o.environment.sunDirection = {0.3f, 0.2f, 1.0f};
    const std::string path = cutoutPackage("cutout", mask, 0.5f, nullptr);
    auto both = renderBothBackends(path, o);
    ASSERT_TRUE(both) << both.message();
    const RenderImage *device = &both->device, *reference = &both->reference;
    auto isBack = [](const float* albedo) {
        return std::fabs(albedo[0] - kBackColour[0]) < 1e-6f && std::fabs(albedo[1] - kBackColour[1]) < 1e-6f &&
               std::fabs(albedo[2] - kBackColour[2]) < 1e-6f;
    };
    const size_t pixels = size_t(o.width) * o.height;
    size_t holes = 0, differ = 0;
    for (size_t p = 0; p < pixels; ++p) {
        holes += isBack(&reference->albedo[3 * p]);
        bool same = true;
        for (int c = 0; c < 3; ++c) same = same && std::fabs(device->albedo[3 * p + c] - reference->albedo[3 * p + c]) <= 2e-5f;
        differ += !same;
    }
    const double rmse = test::relativeRmse(device->rgb, reference->rgb);
    std::printf("cut-out: %zu of %zu pixels see the quad behind; %zu differ; beauty relative RMSE %.2e\n", holes, pixels,
                differ, rmse);
    EXPECT_LE(differ * 200, pixels);
    EXPECT_LE(rmse, 1e-2);
    auto opaque = test::renderEmbree(cutoutPackage("cutout-opaque", mask, 0.0f, nullptr), o);
    ASSERT_TRUE(opaque) << opaque.message();
    auto opaqueDevice = test::renderVulkan(cutoutPackage("cutout-opaque", mask, 0.0f, nullptr), o, 256ull << 20);
    ASSERT_TRUE(opaqueDevice) << opaqueDevice.message();
    size_t outside = 0, opaqueDeviceOutside = 0;  // the quad behind where the front quad does not reach
    for (size_t p = 0; p < pixels; ++p) {
        outside += isBack(&opaque->albedo[3 * p]);
        opaqueDeviceOutside += isBack(&opaqueDevice->albedo[3 * p]);
    }
    EXPECT_EQ(opaqueDeviceOutside, outside);
    // The checker's holes are half the front quad's pixels.
    const size_t inside = pixels - outside, seenThrough = holes - outside;
    std::printf("cut-out: the front quad covers %zu pixels, %zu of them holes\n", inside, seenThrough);
    EXPECT_GT(seenThrough * 4, inside) << "the holes show the quad behind";
    EXPECT_LT(seenThrough * 4, inside * 3);
}

// Paged textures (the back quad's map four times the pool): the cut-out's level-0 pages stay
// resident (the walk tests them and cannot wait), the others are paged, and the image equals the
// in-core one bit for bit; at a budget whose quarter holds the fewest slots alone, the texture
// reserve grows to hold the mask's four level-0 pages beside them.
TEST(TextureDeviceRender, CutoutMasksStayResidentWhileOtherPagesArePaged) {
    const Rgba8Image mask = checkerAlpha(256, 16, 41), back = test::noiseImage(1024, 1024, 43);
    const std::string path = cutoutPackage("cutout-paged", mask, 0.5f, &back);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    const uint64_t textureBytes = gpu::textureBytes((*reader)->info());
    RenderOptions o = lit(48, 2);
    o.aovs = kAovAlbedo;
    o.textureLod = TextureLodMode::Finest;  // level 0: the back map's pages all read
    auto r = renderInCoreAndPaged(path, o, textureBytes);
    ASSERT_TRUE(r) << r.message();
    const StreamingStats& tight = r->tight;
    std::printf("cut-out paged: %llu slots, %llu page loads\n", (unsigned long long)tight.texturePageSlots,
                (unsigned long long)tight.texturePageLoads);
    EXPECT_GT(tight.texturePageSlots, 0u) << "paged";
    EXPECT_GT(tight.texturePageLoads, tight.texturePageSlots) << "pages paged in more than once";
    expectSameImages(r->paged, r->inCore);
    StreamingStats fewest;
    auto small = test::renderVulkan(path, o, 16 * kTexturePageBytes * 4, &fewest);
    ASSERT_TRUE(small) << small.message();
    EXPECT_GE(fewest.texturePageSlots, gpu::kMinTexturePageSlots + 4);
    expectSameImages(*small, r->inCore);
}

// Chunks paged (two slots) under a grid of cut-out quads: the rays that pass a hole in one chunk
// go on into the others, and the render equals the in-core one bit for bit (beauty and albedo),
// which agrees with the reference.
TEST(TextureDeviceRender, CutoutsOutOfCoreRenderAsInCore) {
    constexpr uint32_t kCells = 40;
    TriangleMesh mesh;
    for (uint32_t layer = 0; layer < 2; ++layer)  // the cut-out grid at z = 0.5, the opaque one at 0
        for (uint32_t y = 0; y <= kCells; ++y)
            for (uint32_t x = 0; x <= kCells; ++x) {
                const float px = float(x) / kCells, py = float(y) / kCells;
                mesh.positions.push_back({layer ? 3 * px - 1 : px, layer ? 3 * py - 1 : py, layer ? 0.0f : 0.5f});
                mesh.uvs.push_back({px, 1.0f - py});
            }
    for (uint32_t layer = 0; layer < 2; ++layer)
        for (uint32_t y = 0; y < kCells; ++y)
            for (uint32_t x = 0; x < kCells; ++x) {
                const uint32_t a = layer * (kCells + 1) * (kCells + 1) + y * (kCells + 1) + x, b = a + 1,
                               c = a + kCells + 1, d = c + 1;
                mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
                mesh.materialIds.insert(mesh.materialIds.end(), {layer, layer});
            }
    Material front = mapped(false, false), under;
    front.alphaCutoff = 0.5f;
    under.baseColor = kBackColour;
    mesh.materials = {front, under};
    mesh.textures = {source(checkerAlpha(64, 4, 47), "grid-mask.png", TextureWrap::Repeat, TextureEncoding::Srgb)};
    const std::string path = writePackage("cutout-grid", std::move(mesh), kMinChunkSizeBytes);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    ASSERT_GT((*reader)->info().chunks.size(), 2u);
    RenderOptions o = lit(48, 2);
    o.aovs = kAovAlbedo;
    const uint64_t twoSlots = test::budgetForSlots(path, 2, o.aovs);
    ASSERT_GT(twoSlots, 0u);
    auto r = renderInCoreAndPaged(path, o, twoSlots);
    ASSERT_TRUE(r) << r.message();
    std::printf("cut-out grid: %zu chunks, %llu chunk loads through two slots\n", (*reader)->info().chunks.size(),
                (unsigned long long)r->tight.chunkLoads);
    EXPECT_GT(r->tight.chunkLoads, (*reader)->info().chunks.size()) << "chunks paged in more than once";
    expectSameImages(r->paged, r->inCore);
    auto reference = test::renderEmbree(path, o);
    ASSERT_TRUE(reference) << reference.message();
    EXPECT_LE(test::relativeRmse(r->inCore.rgb, reference->rgb), 1e-2);
}

// A budget whose quarter is below the fewest page slots' bytes: the textures get exactly those
// (textureReserveBytes), and the pool holds kMinTexturePageSlots pages (the allocation granules
// of its tables and its pool overlap: counted from above, not from the tables' own allocation).
TEST(TextureDeviceRender, ABudgetAtTheTexturesMinimumRendersWithTheFewestSlots) {
    const Rgba8Image albedo = test::noiseImage(1024, 1024, 23);
    const std::string path = quadPackage(
        "minimum", mapped(false, false), {source(albedo, "minimum.png", TextureWrap::Clamp, TextureEncoding::Srgb)});
    RenderOptions o = lit(24, 2);
    o.aovs = kAovAlbedo;
    StreamingStats stats, ample;
    auto image = test::renderVulkan(path, o, 3ull << 20, &stats);
    ASSERT_TRUE(image) << image.message();
    EXPECT_EQ(stats.texturePageSlots, gpu::kMinTexturePageSlots);
    EXPECT_LE(stats.peakDeviceBytes, 3ull << 20);
    auto inCore = test::renderVulkan(path, o, 256ull << 20, &ample);
    ASSERT_TRUE(inCore) << inCore.message();
    EXPECT_EQ(std::memcmp(image->rgb.data(), inCore->rgb.data(), inCore->rgb.size() * 4), 0);
}

TEST(TextureDeviceRender, ABudgetBelowTheTexturesMinimumIsRefusedNamingIt) {
    const Rgba8Image albedo = test::noiseImage(1024, 1024, 3);
    const std::string path = quadPackage(
        "refused", mapped(false, false), {source(albedo, "refused.png", TextureWrap::Clamp, TextureEncoding::Srgb)});
    auto image = test::renderVulkan(path, headOn(16), 1ull << 20);
    ASSERT_FALSE(image);
    EXPECT_NE(image.message().find("is below this scene's minimum"), std::string::npos) << image.message();
    EXPECT_NE(image.message().find("textures'"), std::string::npos) << image.message();
}

}  // namespace
}  // namespace vastray
