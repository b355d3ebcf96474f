// PLY importer: the three encodings, odd scalar types, skipped elements, tristrips.
#include "ImportTestFiles.h"

namespace vastray::test {
namespace {

// A unit square as two triangles (one quad face), plus a tetra apex so bounds are 3D.
const std::vector<float> kSquare = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};

TEST(PlyImport, AsciiWithExtraPropertiesAndElements) {
    const std::string ply =
        "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\n"
        "element vertex 4\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\n"
        "property float nx\r\nproperty float ny\r\nproperty float nz\r\nproperty uchar red\r\n"
        "element material 2\r\nproperty list uchar float values\r\nproperty int id\r\n"
        "element face 1\r\nproperty uchar flags\r\nproperty list uchar int vertex_indices\r\n"
        "end_header\r\n"
        "0 0 0 0 0 1 255\r\n1 0 0 0 0 1 255\r\n1 1 0 0 0 1 255\r\n0 1 0 0 0 1 255\r\n"
        "3 0.5 0.5 0.5 7\r\n0 8\r\n"
        "9 4 0 1 2 3\r\n";
    auto r = importPly(writeFile("ascii.ply", ply));
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(r->report.format, "ply-ascii");
    EXPECT_EQ(r->mesh.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
    EXPECT_EQ(r->report.normalsRead, 4u);
    EXPECT_TRUE(r->mesh.materials.at(0).doubleSided);
}

// Binary body: double coordinates, an extra element with a list before the faces,
// a uchar count + ushort index face list, and a trailing element after the faces.
std::string binaryPly(bool bigEndian) {
    std::string ply = std::string("ply\nformat ") + (bigEndian ? "binary_big_endian" : "binary_little_endian") +
                      " 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
                      "property uchar alpha\nelement edge 2\nproperty list ushort int ends\nproperty short weight\n"
                      "element face 2\nproperty list uchar ushort vertex_indices\n"
                      "element tail 1\nproperty list int char junk\nend_header\n";
    for (size_t i = 0; i < 4; ++i) {
        for (int c = 0; c < 3; ++c) appendRaw(ply, double(kSquare[i * 3 + c]), bigEndian);
        appendRaw(ply, uint8_t(200), bigEndian);
    }
    for (int e = 0; e < 2; ++e) {
        appendRaw(ply, uint16_t(3), bigEndian);
        for (int k = 0; k < 3; ++k) appendRaw(ply, int32_t(k + 100), bigEndian);
        appendRaw(ply, int16_t(-5), bigEndian);
    }
    for (uint16_t f : {0, 1}) {
        appendRaw(ply, uint8_t(3), bigEndian);
        for (uint16_t i : {uint16_t(0), uint16_t(f + 1), uint16_t(f + 2)}) appendRaw(ply, i, bigEndian);
    }
    appendRaw(ply, int32_t(2), bigEndian);
    ply += "ab";
    return ply;
}

TEST(PlyImport, BinaryLittleAndBigEndianGiveTheSameMesh) {
    auto le = importPly(writeFile("le.ply", binaryPly(false)));
    auto be = importPly(writeFile("be.ply", binaryPly(true)));
    ASSERT_TRUE(le.isOk()) << le.message();
    ASSERT_TRUE(be.isOk()) << be.message();
    EXPECT_EQ(le->report.format, "ply-binary-le");
    EXPECT_EQ(be->report.format, "ply-binary-be");
    EXPECT_EQ(le->mesh.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
    EXPECT_EQ(le->mesh.indices, be->mesh.indices);
    EXPECT_EQ(le->mesh.positions, be->mesh.positions);
    EXPECT_EQ(be->mesh.positions[2], (Vec3f{1, 1, 0}));
}

TEST(PlyImport, IntegerAndFloatAliasesForCoordinates) {
    std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty int16 x\n"
                      "property uint8 y\nproperty float32 z\nelement face 1\n"
                      "property list uint32 uint32 vertex_index\nend_header\n";
    const int16_t xs[] = {-3, 4, 0};
    const uint8_t ys[] = {0, 0, 250};
    for (int i = 0; i < 3; ++i) {
        appendRaw(ply, xs[i]);
        appendRaw(ply, ys[i]);
        appendRaw(ply, 0.5f);
    }
    appendRaw(ply, uint32_t(3));
    for (uint32_t i : {0u, 1u, 2u}) appendRaw(ply, i);
    auto r = importPly(writeFile("aliases.ply", ply));
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(r->mesh.positions[0], (Vec3f{-3, 0, 0.5f}));
    EXPECT_EQ(r->mesh.positions[2], (Vec3f{0, 250, 0.5f}));
}

TEST(PlyImport, TristripsRestartAndAlternateWinding) {
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\n"
        "element tristrips 1\nproperty list int int vertex_indices\nend_header\n"
        "0 0 0\n0 1 0\n1 0 0\n1 1 0\n2 0 0\n2 1 0\n"
        "8 0 1 2 3 -1 2 3 4\n";
    auto r = importPly(writeFile("strips.ply", ply));
    ASSERT_TRUE(r.isOk()) << r.message();
    // Strip 0 1 2 3 -> (0 1 2), (2 1 3); restart; strip 2 3 4 -> (2 3 4).
    EXPECT_EQ(r->mesh.indices, (std::vector<uint32_t>{0, 1, 2, 2, 1, 3, 2, 3, 4}));
}

}  // namespace
}  // namespace vastray::test
