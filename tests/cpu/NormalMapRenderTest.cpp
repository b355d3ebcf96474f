// The Embree reference bends shading normals by normal maps (docs/RENDERING.md, "Normal maps"):
// a flat quad whose map tilts it along +u, or up the image, is lit by the sun as the quad tilted
// by that much (closed form, and the tilted geometry itself), on its front and, double-sided,
// on its back; maps that bend nothing (normal scale 0, degenerate UVs) leave the image bit for
// bit; a real glTF sample's normal-mapped spheres change where, and only where, they are mapped.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "TestRenders.h"
#include "TestScenes.h"
#include "vastray/core/PathShading.h"
#include "vastray/core/Sampling.h"
#include "vastray/cpu/EmbreeRenderer.h"
#include "vastray/cpu/RenderScene.h"

namespace vastray {
namespace {

using test::renderEmbree;

constexpr float kAlbedo = 0.5f;
constexpr uint32_t kSide = 8;

struct Texel {
    uint8_t r, g, b;
};

// A 1 x 1 linear texture of one texel (its page's extra column and row too).
DecodedTexture oneTexel(Texel t) {
    DecodedTexture texture;
    texture.layout = *makeTextureLayout(1, 1);
    texture.encoding = TextureEncoding::Linear;
    texture.wrapS = texture.wrapT = TextureWrap::Clamp;
    texture.pages.assign(kTexturePageBytes, 255);
    for (size_t i = 0; i < kTexturePageBytes; i += 4) {
        texture.pages[i] = t.r;
        texture.pages[i + 1] = t.g;
        texture.pages[i + 2] = t.b;
    }
    return texture;
}

// The unit quad [0, 1]^2 at z = 0 facing +z, UVs in glTF's space (u along +x, v down: the
// image's top at y = 1), Lambertian, its normal map the texel (none when null).
RenderScene mappedQuad(const Texel* texel, float normalScale = 1.0f) {
    RenderScene scene;
    TriangleMesh& mesh = scene.mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    Material m;
    m.baseColor = {kAlbedo, kAlbedo, kAlbedo, 1};
    if (texel) {
        m.textures.slots[uint32_t(TextureSlot::Normal)].texture = 0;
        m.textures.normalScale = normalScale;
        scene.textures.push_back(oneTexel(*texel));
    }
    mesh.materials = {m};
    scene.bounds = mesh.bounds();
    return scene;
}

// The same quad's centre, turned so that its geometric normal is unit `n`; no map.
RenderScene tiltedQuad(Vec3f n) {
    const Vec3f a = normalize(cross(Vec3f{0, 1, 0}, n));  // cross(a, b) = n: counter-clockwise seen along -n
    const Vec3f b = cross(n, a);
    const Vec3f c{0.5f, 0.5f, 0};
    RenderScene scene = mappedQuad(nullptr);
    TriangleMesh& mesh = scene.mesh;
    const Vec3f ha = a * 0.5f, hb = b * 0.5f;
    mesh.positions = {c - ha - hb, c + ha - hb, c + ha + hb, c - ha + hb};
    scene.bounds = mesh.bounds();
    return scene;
}

// Looking at the quad's centre along -z (from the back: along +z), black sky, the sun (unit
// irradiance) towards `sun`, direct light only.
RenderOptions sunlit(Vec3f sun, bool fromBehind = false) {
    RenderOptions o;
    o.width = o.height = kSide;
    o.samplesPerPixel = 1;
    o.maxDepth = 1;
    o.frameScene = false;
    o.camera = {{0.5f, 0.5f, fromBehind ? -1.5f : 1.5f}, {0.5f, 0.5f, 0}, {0, 1, 0}, 30};
    o.environment.zenith = o.environment.horizon = o.environment.ground = {0, 0, 0};
    o.environment.sunDirection = sun;
    o.environment.sunIrradiance = {1, 1, 1};
    return o;
}

// What glTF's decoding makes of a texel: normalize(rgb * 2 - 1) (scale 1).
Vec3f decoded(Texel t) { return normalize(decodeNormalTexel(t.r / 255.0f, t.g / 255.0f, t.b / 255.0f, 1.0f)); }

// Every pixel of a flat-quad render (the quad fills the view) against the Lambertian closed form
// for shading normal n: albedo / pi * cos(n, sun). Float rounding of a few products: 1e-5.
void expectLambertian(const RenderImage& image, Vec3f n, Vec3f sun) {
    const float expected = kAlbedo / kPi * std::fmax(0.0f, dot(n, normalize(sun)));
    ASSERT_EQ(image.pixelCount(), uint64_t(kSide) * kSide);
    for (size_t p = 0; p < image.pixelCount(); ++p)
        ASSERT_NEAR(image.rgb[3 * p], expected, 1e-5f) << "pixel " << p;
}

// 30 degrees: sin 0.5 -> red 191, cos 0.866 -> blue 238. With the sun 45 degrees off the normal
// on the tilt's side, the right sign gives cos 15 degrees (0.97), the wrong one cos 75 (0.26).
constexpr Texel kTiltAlongU{191, 128, 238};
constexpr Texel kTiltUpImage{128, 191, 238};

TEST(NormalMapRender, TiltAlongPlusULightsAsTheQuadTurnedTowardsPlusX) {
    const Vec3f sun{1, 0, 1};
    const RenderImage mapped = renderEmbree(mappedQuad(&kTiltAlongU), sunlit(sun));
    expectLambertian(mapped, decoded(kTiltAlongU), sun);
    const RenderImage turned = renderEmbree(tiltedQuad(decoded(kTiltAlongU)), sunlit(sun));
    const size_t centre = 3 * (size_t(kSide / 2) * kSide + kSide / 2);
    EXPECT_NEAR(mapped.rgb[centre], turned.rgb[centre], 1e-5f);
}

TEST(NormalMapRender, TiltUpTheImageLightsAsTheQuadTurnedTowardsPlusY) {
    // Up the image is -v in glTF's texture space, +y on this quad.
    const Vec3f sun{0, 1, 1};
    const RenderImage mapped = renderEmbree(mappedQuad(&kTiltUpImage), sunlit(sun));
    expectLambertian(mapped, decoded(kTiltUpImage), sun);
    const RenderImage turned = renderEmbree(tiltedQuad(decoded(kTiltUpImage)), sunlit(sun));
    const size_t centre = 3 * (size_t(kSide / 2) * kSide + kSide / 2);
    EXPECT_NEAR(mapped.rgb[centre], turned.rgb[centre], 1e-5f);
}

TEST(NormalMapRender, SeenFromBehindTheBentNormalIsTurnedWhole) {
    // Double-sided, seen from -z: the map bends the front's normal, then the whole of it turns
    // to the back, (-x, -y, -z) of the front's bent normal; the sun behind, towards +x.
    const Vec3f sun{-1, 0, -1};
    const Vec3f front = decoded(kTiltAlongU);
    expectLambertian(renderEmbree(mappedQuad(&kTiltAlongU), sunlit(sun, true)), front * -1.0f, sun);
}

TEST(NormalMapRender, AFlatEightBitMapTiltsOnlyByItsRounding) {
    // (0.5, 0.5, 1) has no 8-bit texel: 128 decodes to 2 * 128 / 255 - 1 = 1 / 255 (glTF's
    // decoding, not snapped), a tilt of 0.32 degrees that the closed form sees: it moves the
    // cosine by at most sin 0.32 degrees = 0.0055, under 1 % of this sun's cosine (0.67).
    const Texel flat{128, 128, 255};
    const Vec3f sun{1, 0.5f, 1};
    const RenderImage mapped = renderEmbree(mappedQuad(&flat), sunlit(sun));
    const RenderImage plain = renderEmbree(mappedQuad(nullptr), sunlit(sun));
    expectLambertian(mapped, decoded(flat), sun);
    for (size_t i = 0; i < plain.rgb.size(); ++i)
        ASSERT_NEAR(mapped.rgb[i], plain.rgb[i], 1e-2f * plain.rgb[i]) << i;
}

TEST(NormalMapRender, NormalScaleZeroChangesNothing) {
    const Vec3f sun{1, 0.5f, 1};
    const Texel full{255, 255, 255};  // scale 0 leaves (0, 0, 1)
    const RenderImage mapped = renderEmbree(mappedQuad(&full, 0.0f), sunlit(sun));
    const RenderImage plain = renderEmbree(mappedQuad(nullptr), sunlit(sun));
    EXPECT_EQ(mapped.rgb, plain.rgb);
    // And scale 1 does change it (the map is read).
    EXPECT_NE(renderEmbree(mappedQuad(&full, 1.0f), sunlit(sun)).rgb, plain.rgb);
}

TEST(NormalMapRender, DegenerateUvsLeaveTheNormalAndNoNaN) {
    const Vec3f sun{1, 0.5f, 1};
    const RenderImage plain = renderEmbree(mappedQuad(nullptr), sunlit(sun));
    // All four corners at one UV, then on one line: no triangle spans a UV area.
    for (const std::vector<std::array<float, 2>>& uvs :
         {std::vector<std::array<float, 2>>(4, {0.5f, 0.5f}),
          std::vector<std::array<float, 2>>{{0, 0}, {0.5f, 0.5f}, {1, 1}, {0.25f, 0.25f}}}) {
        RenderScene scene = mappedQuad(&kTiltAlongU);
        scene.mesh.uvs = uvs;
        const RenderImage image = renderEmbree(scene, sunlit(sun));
        for (float v : image.rgb) ASSERT_TRUE(std::isfinite(v));
        EXPECT_EQ(image.rgb, plain.rgb);
    }
}

TEST(NormalMapRender, AKhronosSampleBendsItsMappedSpheresAndNothingElse) {
    // KhronosGroup's ClearCoatTest (assimp-testmodels, which scripts/install-deps.sh installs):
    // rows of spheres, three rows with normal maps (RibsNormal.png, PlasticWrap_normals.jpg).
    const std::string file = "/usr/share/assimp/models/glTF2/ClearCoat-glTF/ClearCoatTest.gltf";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " is absent (assimp-testmodels not installed)";
    auto mapped = loadRenderScene(file);
    ASSERT_TRUE(mapped) << mapped.message();
    RenderScene plain = *mapped;
    size_t mappedMaterials = 0;
    for (Material& m : plain.mesh.materials) {
        TextureBinding& normal = m.textures.slots[uint32_t(TextureSlot::Normal)];
        mappedMaterials += normal.texture != kNoTexture;
        normal.texture = kNoTexture;
    }
    ASSERT_GE(mappedMaterials, 5u);
    RenderOptions o;
    o.width = o.height = 96;
    o.samplesPerPixel = 2;
    o.maxDepth = 1;  // direct light only: an unmapped surface's pixels cannot see the maps
    o.aovs = kAovPrimId;
    const RenderImage a = renderEmbree(*mapped, o);
    const RenderImage b = renderEmbree(plain, o);
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    size_t mappedPixels = 0, mappedChanged = 0, otherPixels = 0, otherChanged = 0;
    for (size_t p = 0; p < a.pixelCount(); ++p) {
        for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(a.rgb[3 * p + c])) << p;
        if (a.primId[p] == kMissPrimId) continue;
        const Material& m = materialAt(mapped->mesh.materials, mapped->mesh.materialOf(a.primId[p]));
        const bool isMapped = m.textures.slots[uint32_t(TextureSlot::Normal)].texture != kNoTexture;
        const bool changed = a.rgb[3 * p] != b.rgb[3 * p] || a.rgb[3 * p + 1] != b.rgb[3 * p + 1] ||
                             a.rgb[3 * p + 2] != b.rgb[3 * p + 2];
        (isMapped ? mappedPixels : otherPixels) += 1;
        (isMapped ? mappedChanged : otherChanged) += changed;
    }
    ASSERT_GT(mappedPixels, 100u);
    // Nearly every mapped pixel changes; other pixels only where a jittered sample strays onto a
    // mapped neighbour (the primid comes from the pixel centre): a few per cent at most.
    EXPECT_GT(mappedChanged, mappedPixels * 9 / 10) << mappedChanged << " of " << mappedPixels;
    EXPECT_LT(otherChanged, otherPixels / 20 + 1) << otherChanged << " of " << otherPixels;
}

}  // namespace
}  // namespace vastray
