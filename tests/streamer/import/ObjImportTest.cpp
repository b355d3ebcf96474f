// OBJ importer features on hand-written files.
#include <array>
#include <cmath>
#include <tuple>

#include "ImportTestFiles.h"
#include "Ktx2Writer.h"

namespace vastray::test {
namespace {

constexpr const char* kSquareVertices = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

TEST(ObjImport, AllCornerFormsGiveTheSameTriangles) {
    const std::string obj = std::string(kSquareVertices) +
                            "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n"
                            "f 1 2 3\nf 1/1 3/3 4/2\nf 1//1 2//1 3//1\nf 1/1/1 3/2/1 4/3/1\n";
    auto r = importObj(writeFile("forms.obj", obj));
    ASSERT_TRUE(r.isOk()) << r.message();
    // Corners with the normal are vertices of their own (position, normal) pairs.
    EXPECT_EQ(r->mesh.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7}));
    EXPECT_EQ(r->mesh.normals.size(), 8u);
    EXPECT_EQ(r->report.texcoordsRead, 3u);
    EXPECT_EQ(r->report.normalsRead, 1u);
    EXPECT_EQ(r->report.format, "obj");
}

TEST(ObjImport, NegativeIndicesAreRelativeToTheLastVertex) {
    const std::string obj = "v 9 9 9\n" + std::string(kSquareVertices) + "f -4 -3 -2\nv 5 5 1\nf -1 -5 -4\n";
    auto r = importObj(writeFile("negative.obj", obj));
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(r->mesh.indices, (std::vector<uint32_t>{1, 2, 3, 5, 1, 2}));
}

// Convex polygons: every second corner clipped, round after round (TriangulateTest.cpp has
// the concave cases).
TEST(ObjImport, ConvexPolygonsAreClippedCornerByCorner) {
    const std::string obj = "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 2 2 0\nv 0 2 0\nf 1 2 3 4 5\n";
    auto r = importObj(writeFile("pentagon.obj", obj));
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(r->mesh.indices, (std::vector<uint32_t>{0, 1, 2, 2, 3, 4, 0, 2, 4}));
    EXPECT_EQ(r->report.inputTriangles, 3u);
}

TEST(ObjImport, UsemtlGivesMaterialsInFirstUseOrderWithMtlColours) {
    writeFile("colours.mtl", "newmtl red\nKd 1 0 0\nd 0.5\nnewmtl lamp\nKd 0 0 0\nKe 4 3 2\nTr 0.1\n");
    const std::string obj = "mtllib colours.mtl\n" + std::string(kSquareVertices) +
                            "f 1 2 3\nusemtl lamp\nf 1 3 4\nusemtl red\nf 1 2 4\nusemtl lamp\nf 2 3 4\n";
    auto r = importObj(writeFile("materials.obj", obj));
    ASSERT_TRUE(r.isOk()) << r.message();
    const auto& m = r->mesh.materials;
    ASSERT_EQ(m.size(), 3u);  // default (faces before usemtl), lamp, red
    EXPECT_EQ(m[1].name, "lamp");
    EXPECT_EQ(m[2].name, "red");
    EXPECT_EQ(r->mesh.materialIds, (std::vector<uint32_t>{0, 1, 2, 1}));
    EXPECT_EQ(m[2].baseColor, (std::array<float, 4>{1, 0, 0, 0.5f}));  // d: the alpha of a blend
    EXPECT_TRUE(m[2].alphaBlend);
    EXPECT_NEAR(m[1].baseColor[3], 0.9f, 1e-6f);  // Tr 0.1
    EXPECT_FALSE(m[0].alphaBlend);
    EXPECT_EQ(m[1].emissive, (std::array<float, 3>{4, 3, 2}));
    EXPECT_TRUE(m[0].doubleSided);  // OBJ has no sidedness: Material's default
}

// The error of importing one face of material x from an OBJ whose library is `mtl` (written as
// <stem>.mtl); empty if the import succeeds.
std::string mtlRefusal(const std::string& stem, const std::string& mtl) {
    writeFile(stem + ".mtl", mtl);
    auto r = importObj(writeFile(stem + ".obj", "mtllib " + stem + ".mtl\n" + std::string(kSquareVertices) +
                                                     "usemtl x\nf 1 2 3\n"));
    return r.isOk() ? std::string() : r.message();
}

// What a library says and the renderer does not use is warned about once per kind: maps without
// a glTF slot, bump (height) maps, map_Pr/map_Pm, map options that change the look,
// maps whose file is missing (map_Kd's and map_d's; a bump map's options are not even read), the
// PBR extension's statements. Transparency (d below 1, Tr above 0) blends, unwarned; d 1 and Tr 0
// are opaque.
TEST(ObjImport, MtlMapsTransparencyAndPbrStatementsAreWarnedOncePerKind) {
    writeFile("unused.mtl", "newmtl a\nKd 1 0 0\nd 0.5\nmap_Kd -mm 0.2 2 -t 1 1 -blendv off gone.png\nbump a-n.png\nPr 0.3\nPm 1\n"
                            "map_Pr r.png\nmap_Pm m.png\nmap_d -texres 64 a.png\n"
                            "newmtl b\nKd 0 1 0\nd 1\nTr 0\nmap_Ks b.png\nmap_Bump -bm 2 b.png\nnewmtl c\nTr 0.25\n");
    auto r = importObj(writeFile("unused.obj", "mtllib unused.mtl\n" + std::string(kSquareVertices) +
                                                   "usemtl a\nf 1 2 3\nusemtl b\nf 1 3 4\n"));
    ASSERT_TRUE(r.isOk()) << r.message();
    const std::vector<std::string> expected = {
        "2 MTL PBR statements (Pr, Pm, Ps, Pc, Pcr, aniso) read but not used (Kd, Ks and Ns decide the material)",
        "1 MTL texture maps without a glTF slot (map_Ka, map_Ks, map_Ns, disp, decal, refl, ...) read but not used "
        "(materials use their colours there)",
        "2 MTL bump (height) maps read but not used (not rendered: only norm normal maps are read)",
        "2 MTL roughness and metallic maps (map_Pr, map_Pm) read but not used (glTF's one metallic-roughness image "
        "is not assembled from two files)",
        "1 MTL map options -mm (value range) read but not used (the map is read without it)",
        "1 MTL map options -t (turbulence) read but not used (the map is read without it)",
        "1 MTL map options -blendv off read but not used (the map is read without it)",
        "2 texture maps whose image file is missing or unreadable read but not used (their maps are rendered "
        "without them)"};
    for (const std::string& w : expected)
        EXPECT_EQ(std::count(r->report.warnings.begin(), r->report.warnings.end(), w), 1) << w;
    EXPECT_EQ(r->report.warnings.size(), expected.size());
    EXPECT_EQ(r->report.textureMaps, 7u);  // every map statement keeps the UVs, read or not
    EXPECT_TRUE(r->mesh.textures.empty());
    EXPECT_FALSE(r->mesh.materials[0].textures.any());  // the missing map_Kd is left out
    // d below 1 (or Tr above 0) blends with that alpha; d 1 and Tr 0 are opaque.
    ASSERT_EQ(r->mesh.materials.size(), 2u);
    EXPECT_EQ(r->mesh.materials[0].name, "a");
    EXPECT_TRUE(r->mesh.materials[0].alphaBlend);
    EXPECT_EQ(r->mesh.materials[0].baseColor[3], 0.5f);
    EXPECT_FALSE(r->mesh.materials[1].alphaBlend);
    EXPECT_EQ(r->mesh.materials[1].baseColor[3], 1.0f);
}

// The texel an OBJ vt (u, v) reads through an MTL map's -s and -o: (s_u u + o_u, s_v v + o_v) in
// MTL space, v up; in the package's space (v down) its v is 1 minus that.
std::array<float, 2> mtlTexel(float u, float v, float su, float sv, float ou, float ov) {
    return {su * u + ou, 1.0f - (sv * v + ov)};
}

// map_d naming map_Kd's own image (with the same options) makes the material a cut-out at
// glTF's default cutoff (docs/RENDERING.md, "Cut-outs"): that image's alpha cuts, and nothing is
// baked (one texture); map_d on another image is baked into map_Kd's alpha (AlphaMaskTest.cpp);
// map_d with other options than map_Kd's is warned and left out (the material stays opaque).
TEST(ObjImport, MapDOnTheBaseColourImageIsACutout) {
    writeFile("leaf.png", tinyPng());
    writeFile("mask.png", tinyPng());
    writeFile("cutouts.mtl", "newmtl leaf\nmap_Kd -s 2 2 1 leaf.png\nmap_d -s 2 2 1 leaf.png\n"
                             "newmtl masked\nmap_Kd leaf.png\nmap_d mask.png\n"
                             "newmtl shifted\nmap_Kd leaf.png\nmap_d -o 0.5 leaf.png\n");
    auto r = importObj(writeFile("cutouts.obj", "mtllib cutouts.mtl\n" + std::string(kSquareVertices) +
                                                    "vt 0 0\nvt 1 1\nusemtl leaf\nf 1/1 2/2 3/1\nusemtl masked\nf 1/1 3/2 4/1\n"
                                                    "usemtl shifted\nf 2/1 3/2 4/1\n"));
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->mesh.materials.size(), 3u);
    EXPECT_EQ(r->mesh.materials[0].alphaCutoff, 0.5f);
    EXPECT_EQ(r->mesh.materials[1].alphaCutoff, 0.5f);
    EXPECT_EQ(r->mesh.materials[2].alphaCutoff, 0.0f);
    // leaf.png (read with repeat and with -s), and the baked leaf.png with mask.png's alpha.
    EXPECT_EQ(r->mesh.textures.size(), 2u);
    EXPECT_EQ(r->mesh.materials[0].textures.slots[0].texture, r->mesh.materials[2].textures.slots[0].texture);
    EXPECT_EQ(std::count(r->report.warnings.begin(), r->report.warnings.end(),
                         "1 MTL alpha maps (map_d) with other -s, -o or -clamp than map_Kd read but not used (rendered "
                         "opaque: a mask is baked into map_Kd's alpha texel for texel)"),
              1);
}

// map_Kd, norm and map_Ke become base colour (sRGB), normal (linear) and emissive (sRGB) maps
// of PNG files beside the library (names with spaces, options before them); -s and -o give the
// UV transform in the package's v-down space, -clamp on clamps; one image read with one
// sampling and encoding is one texture, shared by materials.
TEST(ObjImport, MtlMapsBecomeTheMaterialsTexturesWithTheirTransforms) {
    std::filesystem::create_directories(tmpPath("maps dir"));
    writeFile("maps dir/my bricks.png", tinyPng());
    writeFile("maps dir/n.png", tinyPng());
    writeFile("maps.mtl", "newmtl a\nKd 1 1 1\nmap_Kd -s 2 3 1 -o 0.25 0.5 -clamp on -texres 512 maps dir/my bricks.png\n"
                          "norm maps dir\\n.png\nmap_Ke -blendu on maps dir/my bricks.png\n"
                          "newmtl b\nmap_Kd -o 0.5 maps dir/my bricks.png\n");
    auto r = importObj(writeFile("maps.obj", "mtllib maps.mtl\n" + std::string(kSquareVertices) +
                                                 "vt 0 0\nvt 1 1\nusemtl a\nf 1/1 2/2 3/1\nusemtl b\nf 1/1 3/2 4/1\n"));
    ASSERT_TRUE(r.isOk()) << r.message();
    for (const std::string& w : r->report.warnings)  // nothing left out (the one warning says which backend renders the textures)
        EXPECT_EQ(w.find("read but not used"), std::string::npos) << w;
    const auto& t = r->mesh.textures;
    ASSERT_EQ(t.size(), 3u);  // bricks clamped (sRGB), n (linear), bricks repeated (sRGB) for map_Ke and b
    const MaterialTextures& a = r->mesh.materials[0].textures;
    const MaterialTextures& b = r->mesh.materials[1].textures;
    const TextureBinding& colour = a.slots[uint32_t(TextureSlot::BaseColor)];
    const TextureBinding& normal = a.slots[uint32_t(TextureSlot::Normal)];
    const TextureBinding& emissive = a.slots[uint32_t(TextureSlot::Emissive)];
    ASSERT_LT(colour.texture, 3u);
    ASSERT_LT(normal.texture, 3u);
    ASSERT_LT(emissive.texture, 3u);
    EXPECT_EQ(t[colour.texture].name, "'maps dir/my bricks.png' of maps.obj");
    const std::string png = tinyPng();
    EXPECT_EQ(t[colour.texture].bytes, std::vector<uint8_t>(png.begin(), png.end()));
    EXPECT_EQ(t[colour.texture].extension, ".png");
    EXPECT_EQ(t[colour.texture].wrapS, TextureWrap::Clamp);
    EXPECT_EQ(t[colour.texture].wrapT, TextureWrap::Clamp);
    EXPECT_EQ(t[colour.texture].encoding, TextureEncoding::Srgb);
    EXPECT_EQ(t[normal.texture].name, "'maps dir/n.png' of maps.obj");  // a Windows separator read as '/'
    EXPECT_EQ(t[normal.texture].encoding, TextureEncoding::Linear);
    EXPECT_EQ(t[emissive.texture].wrapS, TextureWrap::Repeat);
    EXPECT_EQ(t[emissive.texture].encoding, TextureEncoding::Srgb);
    EXPECT_EQ(b.slots[uint32_t(TextureSlot::BaseColor)].texture, emissive.texture);
    EXPECT_FALSE(a.slots[uint32_t(TextureSlot::MetallicRoughness)].texture != kNoTexture);
    EXPECT_EQ(emissive.transform, kIdentityUvTransform);
    // vt (0, 0) and (1, 1), stored as (u, 1 - v), land where the MTL's options put them. The
    // arithmetic is a few float operations on small values: 1e-6 covers its rounding.
    for (const auto& [binding, s, o] : {std::tuple{colour, std::array{2.0f, 3.0f}, std::array{0.25f, 0.5f}},
                                        std::tuple{b.slots[0], std::array{1.0f, 1.0f}, std::array{0.5f, 0.0f}}})
        for (const std::array<float, 2>& vt : {std::array{0.0f, 0.0f}, std::array{1.0f, 1.0f}}) {
            float u = 0.0f, v = 0.0f;
            applyUvTransform(binding.transform, vt[0], 1.0f - vt[1], u, v);
            const std::array<float, 2> expected = mtlTexel(vt[0], vt[1], s[0], s[1], o[0], o[1]);
            EXPECT_NEAR(u, expected[0], 1e-6f) << vt[0] << "," << vt[1];
            EXPECT_NEAR(v, expected[1], 1e-6f) << vt[0] << "," << vt[1];
        }
    ASSERT_EQ(r->mesh.uvs.size(), r->mesh.positions.size());
}

// A library in a sub-folder names its maps relative to its own folder.
TEST(ObjImport, MtlMapsAreRelativeToTheLibrarysFolder) {
    std::filesystem::create_directories(tmpPath("mtl-sub"));
    writeFile("mtl-sub/tex.png", tinyPng());
    writeFile("mtl-sub/lib.mtl", "newmtl x\nmap_Kd tex.png\n");
    auto r = importObj(writeFile("mtl-sub.obj", "mtllib mtl-sub/lib.mtl\n" + std::string(kSquareVertices) +
                                                    "vt 0 0\nusemtl x\nf 1/1 2/1 3/1\n"));
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->mesh.textures.size(), 1u);
    EXPECT_EQ(r->mesh.textures[0].name, "'mtl-sub/tex.png' of mtl-sub.obj");
    EXPECT_EQ(r->mesh.materials[0].textures.slots[uint32_t(TextureSlot::BaseColor)].texture, 0u);
}

// A map's file stays inside the model's folder (as mtllib names do): '..', absolute paths and
// schemes are refused by library, material, line and name; malformed options by line.
TEST(ObjImport, MtlMapsOutsideTheFolderAndBadOptionsAreRefused) {
    for (const char* file : {"../outside.png", "/etc/passwd", "file:///etc/passwd"}) {
        const std::string bad = mtlRefusal("outmap", std::string("newmtl x\nmap_Kd ") + file + "\n");
        EXPECT_NE(bad.find("outmap.mtl: material 'x' line 2: image '" + std::string(file) + "'"), std::string::npos)
            << bad;
    }
    const std::pair<const char*, const char*> options[] = {
        {"map_Kd -s\n", "line 2: map_Kd: -s needs one to three numbers"},
        {"norm -o 1e9 0 n.png\n", "line 2: norm: -o value 1000000000.000000 is outside +-1e6"},
        {"map_Ke -clamp yes e.png\n", "line 2: map_Ke: -clamp must be on or off"},
        {"map_Kd -s 1 1\n", "line 2: map_Kd: the map names no file"}};
    for (const auto& [statement, message] : options) {
        const std::string bad = mtlRefusal("badmap", std::string("newmtl x\n") + statement);
        EXPECT_NE(bad.find(std::string("badmap.mtl: ") + message), std::string::npos) << bad;
    }
}

// A KTX2 map_Kd of a format read here is stored as the map's texture (decoded at the package's
// build like a PNG); one of a block format is warned and left out; a broken container fails the
// import naming it.
TEST(ObjImport, MtlMapsMayBeKtx2) {
    test::Ktx2Spec rgba;
    rgba.width = 2, rgba.level = {255, 0, 0, 255, 0, 255, 0, 255};
    const std::vector<uint8_t> good = test::writeKtx2(rgba);
    writeFile("red-green.ktx2", std::string(good.begin(), good.end()));
    test::Ktx2Spec block = rgba;
    block.vkFormat = 145;  // BC7_SRGB_BLOCK: not read here
    const std::vector<uint8_t> bc7 = test::writeKtx2(block);
    writeFile("block.ktx2", std::string(bc7.begin(), bc7.end()));
    writeFile("ktx2.mtl", "newmtl x\nmap_Kd red-green.ktx2\nnewmtl y\nmap_Kd block.ktx2\n");
    auto r = importObj(writeFile("ktx2.obj", "mtllib ktx2.mtl\n" + std::string(kSquareVertices) +
                                                 "vt 0 0\nvt 1 0\nvt 1 1\nusemtl x\nf 1/1 2/2 3/3\nusemtl y\nf 1/1 3/3 4/2\n"));
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->mesh.textures.size(), 1u);
    EXPECT_EQ(r->mesh.textures[0].extension, ".ktx2");
    EXPECT_EQ(r->mesh.materials[0].textures.slots[uint32_t(TextureSlot::BaseColor)].texture, 0u);
    EXPECT_EQ(r->mesh.materials[1].textures.slots[uint32_t(TextureSlot::BaseColor)].texture, kNoTexture);
    EXPECT_EQ(std::count(r->report.warnings.begin(), r->report.warnings.end(),
                         "1 texture maps with an image neither PNG, JPEG nor a KTX2 of a format read here read but not "
                         "used (their maps are rendered without them)"),
              1);
    std::vector<uint8_t> broken = good;
    broken.resize(broken.size() - 4);  // level 0 runs past the end
    writeFile("broken.ktx2", std::string(broken.begin(), broken.end()));
    const std::string refusal = mtlRefusal("broken-ktx2", "newmtl x\nmap_Kd broken.ktx2\n");
    EXPECT_NE(refusal.find("broken.ktx2"), std::string::npos) << refusal;
}

// A map whose image is neither PNG nor JPEG is left out, warned once; a link out of the
// folder is refused like a '..' name.
TEST(ObjImport, MtlMapsNotPngOrJpegAreWarnedAndLinksOutRefused) {
    writeFile("picture.tga", "not a PNG or JPEG");
    const std::string mtl = "newmtl x\nmap_Kd picture.tga\n";
    writeFile("tga.mtl", mtl);
    auto r = importObj(writeFile("tga.obj", "mtllib tga.mtl\n" + std::string(kSquareVertices) + "usemtl x\nf 1 2 3\n"));
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->report.warnings.size(), 1u);
    EXPECT_EQ(r->report.warnings[0],
              "1 texture maps with an image neither PNG, JPEG nor a KTX2 of a format read here read but not used (their maps "
              "are rendered without them)");
    EXPECT_TRUE(r->mesh.textures.empty());
    const std::string link = tmpPath("link-out.png");
    std::filesystem::remove(link);
    std::filesystem::create_symlink("/etc/hostname", link);
    const std::string bad = mtlRefusal("linkmap", "newmtl x\nmap_Kd link-out.png\n");
    EXPECT_NE(bad.find("linkmap.mtl: material 'x' line 2: image 'link-out.png' resolves outside the model's folder"),
              std::string::npos)
        << bad;
}

// Ks and Ns: a dielectric layer of weight max(Ks), roughness (2 / (Ns + 2))^(1/4); illum 0 and 1
// have no highlight; "Ks 0" (one value) is grey; Ns outside [0, 1e6] is refused by line.
TEST(ObjImport, MtlSpecularBecomesAMetallicRoughnessLayer) {
    writeFile("shiny.mtl",
              "newmtl gloss\nKd 0.5 0.5 0.5\nKs 0.5 0.25 0.1\nNs 98\nnewmtl matte\nKs 0\nNs 10\n"
              "newmtl flat\nKs 1 1 1\nillum 1\nnewmtl strong\nKs 3\n");
    const std::string obj = "mtllib shiny.mtl\n" + std::string(kSquareVertices) +
                            "usemtl gloss\nf 1 2 3\nusemtl matte\nf 1 3 4\nusemtl flat\nf 1 2 4\nusemtl strong\nf 2 3 4\n";
    auto r = importObj(writeFile("shiny.obj", obj));
    ASSERT_TRUE(r.isOk()) << r.message();
    const auto& m = r->mesh.materials;
    ASSERT_EQ(m.size(), 4u);
    EXPECT_EQ(m[0].specular, 0.5f);
    EXPECT_NEAR(m[0].roughness, std::sqrt(std::sqrt(2.0f / 100.0f)), 1e-6f);
    EXPECT_EQ(m[0].metallic, 0.0f);
    for (int i : {1, 2}) {
        EXPECT_EQ(m[i].specular, 0.0f) << m[i].name;  // Lambertian
        EXPECT_EQ(m[i].roughness, 1.0f) << m[i].name;
    }
    EXPECT_EQ(m[3].specular, 1.0f);  // clamped
    EXPECT_EQ(m[3].roughness, 1.0f);  // no Ns: exponent 0, the roughest lobe
    const std::string bad = mtlRefusal("badns", "newmtl x\nNs -3\n");
    EXPECT_NE(bad.find("badns.mtl: line 2: Ns must be a number in [0, 1e6]"), std::string::npos) << bad;
}

// illum outside the MTL spec's models 0 to 10 is refused by file and line, above and below.
TEST(ObjImport, MtlIllumOutsideZeroToTenIsRefusedByLine) {
    for (const char* value : {"11", "-1"}) {
        const std::string bad = mtlRefusal("badillum", std::string("newmtl x\nKs 1\nillum ") + value + "\n");
        EXPECT_NE(bad.find("badillum.mtl: line 3: illum must be an integer in [0, 10]"), std::string::npos)
            << "illum " << value << ": " << (bad.empty() ? "accepted" : bad);
    }
    EXPECT_EQ(mtlRefusal("illum10", "newmtl x\nKs 1\nillum 10\n"), "");  // the limit itself is a model
}

TEST(ObjImport, MissingMtlIsNotAnError) {
    const std::string obj = "mtllib nowhere.mtl\n" + std::string(kSquareVertices) + "usemtl x\nf 1 2 3\n";
    auto r = importObj(writeFile("nomtl.obj", obj));
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(r->mesh.materials[0].name, "x");
}

TEST(ObjImport, CrlfCommentsAndUnknownStatementsAreHandled) {
    const std::string obj =
        "# comment\r\no thing\r\ng group\r\ns 1\r\nv 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nv 0 0 1\r\n"
        "l 1 2\r\np 1\r\nvp 0.5\r\nf 1 2 3\r\nf 1 2 4";  // last line without a line ending
    auto r = importObj(writeFile("crlf.obj", obj));
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(r->mesh.triangleCount(), 2u);
    EXPECT_EQ(r->mesh.positions[3].z, 1.0f);
}

TEST(ObjImport, DegenerateTrianglesAreDroppedAndCounted) {
    const std::string obj = std::string(kSquareVertices) + "v 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\nf 2 5 3\nf 1 2 6\nf 1 2 2\n";
    // f 1 1 2: repeated index; f 2 5 3: coincident positions; f 1 2 6: zero area (collinear).
    auto r = importObj(writeFile("degenerate.obj", obj));
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(r->report.inputTriangles, 5u);
    EXPECT_EQ(r->report.degenerateDropped, 4u);
    EXPECT_EQ(r->mesh.triangleCount(), 1u);
    EXPECT_EQ(r->mesh.materialIds.size(), 1u);
}

TEST(ObjImport, SidednessOverrideAppliesToEveryMaterial) {
    const std::string obj = std::string(kSquareVertices) + "usemtl a\nf 1 2 3\nusemtl b\nf 1 3 4\n";
    ImportOptions options;
    options.sidedness = ImportOptions::Sidedness::ForceSingleSided;
    auto r = importMesh(writeFile("sided.OBJ", obj), options);  // extension is case-insensitive
    ASSERT_TRUE(r.isOk()) << r.message();
    for (const Material& m : r->mesh.materials) EXPECT_FALSE(m.doubleSided) << m.name;
}

}  // namespace
}  // namespace vastray::test
