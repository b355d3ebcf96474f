// OBJ importer features on hand-written files.
#include <cmath>

#include "ImportTestFiles.h"

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
    EXPECT_EQ(m[2].baseColor, (std::array<float, 4>{1, 0, 0, 1}));  // d ignored: alpha stays 1
    EXPECT_EQ(m[1].emissive, (std::array<float, 3>{4, 3, 2}));
    EXPECT_TRUE(m[0].doubleSided);  // OBJ has no sidedness: Material's default
}

// What a library says and the renderer does not use is warned about once per kind: texture maps,
// transparency (d below 1, Tr above 0; d 1 and Tr 0 are opaque and say nothing), the PBR
// extension's statements.
TEST(ObjImport, MtlMapsTransparencyAndPbrStatementsAreWarnedOncePerKind) {
    writeFile("unused.mtl", "newmtl a\nKd 1 0 0\nd 0.5\nmap_Kd a.png\nbump a-n.png\nPr 0.3\nPm 1\n"
                            "newmtl b\nKd 0 1 0\nd 1\nTr 0\nmap_Ks b.png\nnewmtl c\nTr 0.25\n");
    auto r = importObj(writeFile("unused.obj", "mtllib unused.mtl\n" + std::string(kSquareVertices) +
                                                   "usemtl a\nf 1 2 3\nusemtl b\nf 1 3 4\n"));
    ASSERT_TRUE(r.isOk()) << r.message();
    const std::vector<std::string> expected = {
        "2 MTL PBR statements (Pr, Pm, Ps, Pc, Pcr, aniso) read but not used (Kd, Ks and Ns decide the material)",
        "3 MTL texture maps read but not used (materials use their colours only)",
        "2 MTL transparency statements (d below 1, Tr above 0) read but not used (rendered opaque)"};
    for (const std::string& w : expected)
        EXPECT_EQ(std::count(r->report.warnings.begin(), r->report.warnings.end(), w), 1) << w;
}

// The error of importing one face of material x from an OBJ whose library is `mtl` (written as
// <stem>.mtl); empty if the import succeeds.
std::string mtlRefusal(const std::string& stem, const std::string& mtl) {
    writeFile(stem + ".mtl", mtl);
    auto r = importObj(writeFile(stem + ".obj", "mtllib " + stem + ".mtl\n" + std::string(kSquareVertices) +
                                                     "usemtl x\nf 1 2 3\n"));
    return r.isOk() ? std::string() : r.message();
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
