// Alpha masks on another image than the base colour map's (docs/RENDERING.md, "Cut-outs"): an
// MTL map_d, an assimp opacity map. They are baked at import into the base colour map's alpha
// (import/AlphaMask.h), and the material becomes a cut-out at 0.5. Texel values are exact: the
// bake rounds once, round(base alpha * mask / 255), and PNG stores 8-bit values losslessly.
#include "ImportTestFiles.h"

#include <algorithm>
#include <array>
#include <filesystem>

#include "import/AlphaMask.h"
#include "PngBytes.h"
#include "import/PngWriter.h"
#include "vastray/core/ImageFile.h"
#include "vastray/core/Texture.h"

namespace vastray::test {
namespace {

constexpr const char* kQuad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";

Rgba8Image decoded(const TextureSource& t) {
    auto image = decodeRgba8Image(t.name, t.extension, t.bytes, 1u << 20);
    EXPECT_TRUE(image.isOk()) << image.message();
    return image ? *image : Rgba8Image{};
}

// One quad of material `material` from the library `mtl` (files <stem>.obj and <stem>.mtl).
Result<ImportedMesh> importQuad(const std::string& stem, const std::string& mtl) {
    writeFile(stem + ".mtl", mtl);
    return importObj(writeFile(stem + ".obj", "mtllib " + stem + ".mtl\n" + std::string(kQuad) +
                                                  "usemtl m\nf 1/1 2/2 3/3 4/4\n"));
}

// A 2x2 RGBA base (one texel half transparent) and masks of the same size.
const std::vector<uint8_t> kBase = {10, 20, 30, 255, 40, 50, 60, 255, 70, 80, 90, 128, 100, 110, 120, 255};

// map_d on a grey PNG (no alpha channel: its luminance, which for grey is its value) is baked
// into map_Kd's alpha; RGB stays map_Kd's; the material cuts at 0.5; the mask image is not kept.
TEST(ObjAlphaMask, SeparateMaskImageIsBakedIntoTheBaseColourAlpha) {
    writeFile("am-base.png", png(2, 2, 4, kBase));
    writeFile("am-grey.png", png(2, 2, 1, {0, 64, 200, 255}));
    auto r = importQuad("am-grey", "newmtl m\nKd 1 1 1\nmap_Kd -s 2 2 1 am-base.png\nmap_d -s 2 2 1 am-grey.png\n");
    ASSERT_TRUE(r.isOk()) << r.message();
    const Material& m = r->mesh.materials[0];
    EXPECT_EQ(m.alphaCutoff, 0.5f);
    ASSERT_EQ(r->mesh.textures.size(), 1u);
    const TextureBinding& b = m.textures.slots[uint32_t(TextureSlot::BaseColor)];
    EXPECT_EQ(b.texture, 0u);
    EXPECT_EQ(b.transform, (UvTransform{2, 0, 0, 0, 2, -1}));  // map_Kd's -s 2 2 1 in v-down space
    const TextureSource& t = r->mesh.textures[0];
    EXPECT_EQ(t.encoding, TextureEncoding::Srgb);
    EXPECT_EQ(t.name, "'am-base.png' of am-grey.obj with the alpha of 'am-grey.png' of am-grey.obj");
    const Rgba8Image image = decoded(t);
    ASSERT_EQ(image.width, 2u);
    const std::vector<uint8_t> expected = {10, 20, 30, 0, 40, 50, 60, 64, 70, 80, 90, 100, 100, 110, 120, 255};
    EXPECT_EQ(image.texels, expected);  // 128 * 200 / 255 = 100.39 -> 100
    for (const std::string& w : r->report.warnings) EXPECT_EQ(w.find("map_d"), std::string::npos) << w;
}

// The channel: an RGBA mask's alpha without -imfchan (its image has alpha); -imfchan r, g, b,
// m (alpha) and l (luminance) pick theirs; an RGB PNG without alpha gives its luminance.
TEST(ObjAlphaMask, ImfchanPicksTheMaskChannelAndAlphaIsTheDefaultWhenThereIsOne) {
    writeFile("ch-base.png", png(2, 1, 4, {1, 2, 3, 255, 4, 5, 6, 255}));
    writeFile("ch-rgba.png", png(2, 1, 4, {200, 100, 50, 20, 0, 255, 30, 240}));
    writeFile("ch-rgb.png", png(2, 1, 3, {200, 100, 50, 0, 255, 30}));
    const std::pair<std::string, std::array<uint8_t, 2>> cases[] = {
        {"ch-rgba.png", {20, 240}},
        {"-imfchan m ch-rgba.png", {20, 240}},
        {"-imfchan r ch-rgba.png", {200, 0}},
        {"-imfchan g ch-rgba.png", {100, 255}},
        {"-imfchan b ch-rgba.png", {50, 30}},
        // 0.2126 R + 0.7152 G + 0.0722 B: 42.52 + 71.52 + 3.61 = 117.65; 182.38 + 2.17 = 184.54
        {"-imfchan l ch-rgba.png", {118, 185}},
        {"ch-rgb.png", {118, 185}}};
    for (const auto& [statement, alphas] : cases) {
        auto r = importQuad("ch", "newmtl m\nmap_Kd ch-base.png\nmap_d " + statement + "\n");
        ASSERT_TRUE(r.isOk()) << r.message();
        ASSERT_EQ(r->mesh.textures.size(), 1u) << statement;
        const Rgba8Image image = decoded(r->mesh.textures[0]);
        ASSERT_EQ(image.texels.size(), 8u);
        EXPECT_EQ(image.texels[3], alphas[0]) << statement;
        EXPECT_EQ(image.texels[7], alphas[1]) << statement;
        EXPECT_EQ(image.texels[4], 4) << statement;
    }
}

// A mask of another size is resampled bilinearly at the base image's texel centres
// (x = (i + 0.5) * 2 / 4 - 0.5 = -0.25, 0.25, 0.75, 1.25 over a 2-texel mask 0, 255): clamped
// to its edge under -clamp on, wrapped around under repeat.
TEST(ObjAlphaMask, MaskOfAnotherSizeIsResampledBilinearly) {
    writeFile("rs-base.png", png(4, 1, 4, std::vector<uint8_t>(16, 255)));
    writeFile("rs-mask.png", png(2, 1, 1, {0, 255}));
    const std::pair<std::string, std::array<uint8_t, 4>> cases[] = {
        {"-clamp on ", {0, 64, 191, 255}},  // 63.75, 191.25
        {"", {64, 64, 191, 191}}};           // x = -0.25 blends the last texel: 255 - 0.75 * 255
    for (const auto& [options, alphas] : cases) {
        auto r = importQuad("rs", "newmtl m\nmap_Kd " + options + "rs-base.png\nmap_d " + options + "rs-mask.png\n");
        ASSERT_TRUE(r.isOk()) << r.message();
        ASSERT_EQ(r->mesh.textures.size(), 1u);
        const Rgba8Image image = decoded(r->mesh.textures[0]);
        ASSERT_EQ(image.width, 4u);
        for (int x = 0; x < 4; ++x) EXPECT_EQ(image.texels[4 * x + 3], alphas[x]) << "'" << options << "' " << x;
    }
    // A larger mask than the base: sampled at the base's texel centres (x = 0.5, 2.5 of 4 texels).
    Rgba8Image base{2, 1, std::vector<uint8_t>(8, 255)};
    Rgba8Image mask{4, 1, {0, 0, 0, 0, 0, 0, 0, 100, 0, 0, 0, 200, 0, 0, 0, 255}};
    const Rgba8Image baked = import::bakeAlpha(&base, mask, import::MaskChannel::Alpha, TextureWrap::Clamp,
                                               TextureWrap::Clamp);
    EXPECT_EQ(baked.texels[3], 50);   // (0 + 100) / 2
    EXPECT_EQ(baked.texels[7], 228);  // (200 + 255) / 2 = 227.5, rounded away from zero
}

// map_d without map_Kd: a white base colour map of the mask's size with the mask as its alpha,
// read through map_d's own options; Kd stays the factor.
TEST(ObjAlphaMask, MapDWithoutMapKdMakesAWhiteBaseColourMap) {
    writeFile("nk-mask.png", png(2, 1, 1, {30, 220}));
    auto r = importQuad("nk", "newmtl m\nKd 0.5 0.25 1\nmap_d -o 0.5 0 -clamp on nk-mask.png\n");
    ASSERT_TRUE(r.isOk()) << r.message();
    const Material& m = r->mesh.materials[0];
    EXPECT_EQ(m.alphaCutoff, 0.5f);
    EXPECT_EQ(m.baseColor, (std::array<float, 4>{0.5f, 0.25f, 1.0f, 1.0f}));
    ASSERT_EQ(r->mesh.textures.size(), 1u);
    const TextureBinding& b = m.textures.slots[uint32_t(TextureSlot::BaseColor)];
    EXPECT_EQ(b.texture, 0u);
    EXPECT_EQ(b.transform, (UvTransform{1, 0, 0.5f, 0, 1, 0}));
    EXPECT_EQ(r->mesh.textures[0].wrapS, TextureWrap::Clamp);
    EXPECT_EQ(decoded(r->mesh.textures[0]).texels, (std::vector<uint8_t>{255, 255, 255, 30, 255, 255, 255, 220}));
}

// Two materials with one base and one mask share the baked texture; a material reading the
// base image alone keeps the original.
TEST(ObjAlphaMask, OneBaseAndMaskAreBakedOnce) {
    writeFile("sh-base.png", png(2, 2, 4, kBase));
    writeFile("sh-mask.png", png(2, 2, 1, {0, 64, 200, 255}));
    writeFile("sh.mtl", "newmtl a\nmap_Kd sh-base.png\nmap_d sh-mask.png\nnewmtl b\nmap_Kd sh-base.png\nmap_d "
                        "sh-mask.png\nnewmtl c\nmap_Kd sh-base.png\n");
    auto r = importObj(writeFile("sh.obj", "mtllib sh.mtl\n" + std::string(kQuad) +
                                               "usemtl a\nf 1/1 2/2 3/3\nusemtl b\nf 1/1 3/3 4/4\nusemtl c\nf 2/2 3/3 4/4\n"));
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->mesh.textures.size(), 2u);
    const auto base = [&](int i) { return r->mesh.materials[i].textures.slots[0].texture; };
    EXPECT_EQ(base(0), base(1));
    EXPECT_NE(base(0), base(2));
    EXPECT_EQ(r->mesh.materials[2].alphaCutoff, 0.0f);
    EXPECT_EQ(decoded(r->mesh.textures[base(2)]).texels, kBase);
}

// Hostile or broken masks are handled as map_Kd's images are: a missing file is warned and left
// out (the material stays opaque); a name out of the folder fails the import naming library,
// material and line; a corrupt PNG, or one wider than a texture may be, fails it naming the image
// (as such a map_Kd fails the package's import); a map_d whose -s differs from map_Kd's, or of channel z, is warned.
TEST(ObjAlphaMask, MissingOutsideCorruptAndMismatchedMasks) {
    writeFile("ho-base.png", png(1, 1, 4, {1, 2, 3, 255}));
    auto missing = importQuad("ho-missing", "newmtl m\nmap_Kd ho-base.png\nmap_d ho-gone.png\n");
    ASSERT_TRUE(missing.isOk()) << missing.message();
    EXPECT_EQ(missing->mesh.materials[0].alphaCutoff, 0.0f);
    EXPECT_EQ(missing->mesh.textures.size(), 1u);
    EXPECT_EQ(std::count(missing->report.warnings.begin(), missing->report.warnings.end(),
                         "1 texture maps whose image file is missing or unreadable read but not used (their maps are "
                         "rendered without them)"),
              1)
        << ::testing::PrintToString(missing->report.warnings);

    auto outside = importQuad("ho-outside", "newmtl m\nmap_Kd ho-base.png\nmap_d ../ho-base.png\n");
    EXPECT_IMPORT_ERROR(outside, "ho-outside.mtl: material 'm' line 3: image '../ho-base.png'", "..");

    const std::string link = tmpPath("ho-link.png");
    std::filesystem::remove(link);
    std::filesystem::create_symlink("/etc/hostname", link);
    auto linked = importQuad("ho-link", "newmtl m\nmap_Kd ho-base.png\nmap_d ho-link.png\n");
    EXPECT_IMPORT_ERROR(linked, "ho-link.mtl: material 'm' line 3: image 'ho-link.png'", "outside the model's folder");

    std::string corrupt = png(1, 1, 1, {7});
    corrupt.resize(corrupt.size() - 20);  // IDAT cut short
    corrupt += std::string(20, '\x55');
    writeFile("ho-corrupt.png", corrupt);
    auto broken = importQuad("ho-corrupt", "newmtl m\nmap_Kd ho-base.png\nmap_d ho-corrupt.png\n");
    EXPECT_IMPORT_ERROR(broken, "ho-corrupt.obj: material 'm' alpha mask: 'ho-corrupt.png' of ho-corrupt.obj", "");

    writeFile("ho-mask.png", png(1, 1, 1, {7}));
    auto mismatched = importQuad("ho-mismatch", "newmtl m\nmap_Kd ho-base.png\nmap_d -s 2 2 ho-mask.png\nnewmtl z\n");
    ASSERT_TRUE(mismatched.isOk()) << mismatched.message();
    EXPECT_EQ(mismatched->mesh.materials[0].alphaCutoff, 0.0f);
    EXPECT_EQ(std::count(mismatched->report.warnings.begin(), mismatched->report.warnings.end(),
                         "1 MTL alpha maps (map_d) with other -s, -o or -clamp than map_Kd read but not used (rendered "
                         "opaque: a mask is baked into map_Kd's alpha texel for texel)"),
              1);
    auto depth = importQuad("ho-depth", "newmtl m\nmap_Kd ho-base.png\nmap_d -imfchan z ho-mask.png\n");
    ASSERT_TRUE(depth.isOk()) << depth.message();
    EXPECT_EQ(depth->mesh.materials[0].alphaCutoff, 0.0f);
    EXPECT_EQ(depth->report.warnings,
              std::vector<std::string>{"1 MTL alpha maps (map_d) of channel -imfchan z (depth) read but not used "
                                       "(rendered opaque: PNG and JPEG images have no depth channel)"});
    writeFile("ho-wide.png", png(kMaxTextureSide + 1, 1, 1, std::vector<uint8_t>(kMaxTextureSide + 1, 9)));
    auto wide = importQuad("ho-wide", "newmtl m\nmap_d ho-wide.png\n");
    EXPECT_IMPORT_ERROR(wide, "ho-wide.obj: material 'm' alpha mask: 'ho-wide.png' of ho-wide.obj",
                        "16385 x 1 texels is outside 1..16384 per side");
    auto badChannel = importQuad("ho-channel", "newmtl m\nmap_d -imfchan q ho-mask.png\n");
    EXPECT_IMPORT_ERROR(badChannel, "ho-channel.mtl", "line 2: map_d: -imfchan must be r, g, b, m, l or z");
}

// map_d on map_Kd's own image that has no alpha channel (a JPEG, an RGB PNG) cuts with its
// luminance, per MTL's default channel for scalar maps: it is baked like another image.
TEST(ObjAlphaMask, MapDOnTheBaseImageWithoutAlphaCutsWithItsLuminance) {
    writeFile("lu-rgb.png", png(2, 1, 3, {0, 0, 0, 255, 255, 255}));
    auto r = importQuad("lu", "newmtl m\nmap_Kd lu-rgb.png\nmap_d lu-rgb.png\n");
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(r->mesh.materials[0].alphaCutoff, 0.5f);
    ASSERT_EQ(r->mesh.textures.size(), 1u);
    EXPECT_EQ(decoded(r->mesh.textures[0]).texels, (std::vector<uint8_t>{0, 0, 0, 0, 255, 255, 255, 255}));
}

// PNG alpha detection (the default channel): colour types 4 and 6, a tRNS chunk; not RGB or
// grey PNGs, JPEGs, or bytes too short to say.
TEST(ObjAlphaMask, ImageHasAlphaReadsThePngHeader) {
    const auto bytes = [](const std::string& s) { return std::vector<uint8_t>(s.begin(), s.end()); };
    EXPECT_TRUE(import::imageHasAlpha(bytes(png(1, 1, 4, {1, 2, 3, 4}))));
    EXPECT_TRUE(import::imageHasAlpha(bytes(png(1, 1, 2, {1, 2}))));
    EXPECT_FALSE(import::imageHasAlpha(bytes(png(1, 1, 3, {1, 2, 3}))));
    EXPECT_FALSE(import::imageHasAlpha(bytes(png(1, 1, 1, {1}))));
    std::vector<uint8_t> trns = bytes(png(1, 1, 3, {1, 2, 3}));
    const std::vector<uint8_t> chunk = {0, 0, 0, 6, 't', 'R', 'N', 'S', 0, 1, 0, 2, 0, 3, 0, 0, 0, 0};
    trns.insert(trns.begin() + 33, chunk.begin(), chunk.end());  // after IHDR
    EXPECT_TRUE(import::imageHasAlpha(trns));
    EXPECT_FALSE(import::imageHasAlpha({0xFF, 0xD8, 0xFF, 0xE0}));
    EXPECT_FALSE(import::imageHasAlpha({}));
}

// The PNG writer's images decode to the texels it was given, for each channel count.
TEST(ObjAlphaMask, PngWriterRoundTrips) {
    std::vector<uint8_t> texels(300 * 7 * 4);
    for (size_t i = 0; i < texels.size(); ++i) texels[i] = uint8_t(i * 37 + i / 11);
    TextureSource source{"round trip", ".png", {}, TextureWrap::Repeat, TextureWrap::Repeat, TextureEncoding::Srgb};
    const std::string bytes = png(300, 7, 4, texels);
    source.bytes.assign(bytes.begin(), bytes.end());
    const Rgba8Image image = decoded(source);
    EXPECT_EQ(image.width, 300u);
    EXPECT_EQ(image.height, 7u);
    EXPECT_EQ(image.texels, texels);
    EXPECT_FALSE(import::encodePng(2, 2, 4, std::vector<uint8_t>(15)).isOk());
}

}  // namespace
}  // namespace vastray::test
