// Shading normals and vertex colours from each importer (issue "Real assets"): one per vertex
// or none, in the codes of core/VertexAttributes.h, with OBJ's separately indexed normals split
// into vertices and glTF's normals transformed like the positions' surfaces.
#include "ImportTestFiles.h"
#include "vastray/core/VecMath.h"
#include "vastray/core/VertexAttributes.h"

namespace vastray::test {
namespace {

void expectNormal(uint32_t code, Vec3f expected, const std::string& where) {
    ASSERT_NE(code, kNoNormal) << where;
    const Vec3f n = decodeOctahedral(code);
    const Vec3f e = normalize(expected);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(n[a], e[a], 2e-4f) << where << " axis " << a;
}

TEST(VertexAttributesImport, PlyNormalsAndByteOrFloatColours) {
    for (const char* type : {"uchar", "float"}) {
        const bool bytes = std::string(type) == "uchar";
        const std::string c0 = bytes ? "255 0 128" : "1 0 0.5", c1 = bytes ? "0 255 0" : "0 1 0";
        const std::string ply = std::string("ply\nformat ascii 1.0\nelement vertex 3\n") +
                                "property float x\nproperty float y\nproperty float z\n"
                                "property float nx\nproperty float ny\nproperty float nz\n"
                                "property " + type + " red\nproperty " + type + " green\nproperty " + type + " blue\n"
                                "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                "0 0 0 0 0 2 " + c0 + "\n1 0 0 0 1 1 " + c1 + "\n0 1 0 1 0 0 " + c1 + "\n3 0 1 2\n";
        auto r = importPly(writeFile(std::string("attributes-") + type + ".ply", ply));
        ASSERT_TRUE(r.isOk()) << r.message();
        ASSERT_EQ(r->mesh.normals.size(), 3u);
        expectNormal(r->mesh.normals[0], {0, 0, 1}, type);
        expectNormal(r->mesh.normals[1], {0, 1, 1}, type);
        ASSERT_EQ(r->mesh.colors.size(), 3u);
        EXPECT_EQ(r->mesh.colors[0], packSrgb8(255, 0, 128)) << type;
        EXPECT_EQ(r->mesh.colors[1], packSrgb8(0, 255, 0)) << type;
        EXPECT_EQ(r->report.normalsRead, 3u);
        EXPECT_EQ(r->report.coloursRead, 3u);
        EXPECT_TRUE(r->report.warnings.empty()) << ::testing::PrintToString(r->report.warnings);
    }
}

// A colour needs red, green and blue: a lone red property is skipped (and nothing is stored).
TEST(VertexAttributesImport, PlyIncompleteColourOrNormalIsNotStored) {
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0 1 9\n1 0 0 1 9\n0 1 0 1 9\n3 0 1 2\n";
    auto r = importPly(writeFile("incomplete.ply", ply));
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_TRUE(r->mesh.normals.empty());
    EXPECT_TRUE(r->mesh.colors.empty());
    EXPECT_EQ(r->mesh.triangleCount(), 1u);
}

// A position used with two normals becomes two vertices; corners without a normal get none.
TEST(VertexAttributesImport, ObjNormalsSplitVerticesAndColoursFollowPositions) {
    const std::string obj =
        "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 1 1 1\nv 5 5 5 1\n"
        "vn 0 0 1\nvn 0 1 0\n"
        "f 1//1 2//1 3//1\nf 1//2 3//2 4//2\nf 1 2 4\n";
    auto r = importObj(writeFile("split.obj", obj));
    ASSERT_TRUE(r.isOk()) << r.message();
    // (1,n1) (2,n1) (3,n1) | (1,n2) (3,n2) (4,n2) | (1,-) (2,-) (4,-)
    EXPECT_EQ(r->mesh.indices, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5, 6, 7, 8}));
    ASSERT_EQ(r->mesh.positions.size(), 9u);
    ASSERT_EQ(r->mesh.normals.size(), 9u);
    ASSERT_EQ(r->mesh.colors.size(), 9u);
    EXPECT_EQ(r->mesh.positions[3], (Vec3f{0, 0, 0}));
    expectNormal(r->mesh.normals[0], {0, 0, 1}, "vertex 0");
    expectNormal(r->mesh.normals[3], {0, 1, 0}, "vertex 3");
    EXPECT_EQ(r->mesh.normals[6], kNoNormal);
    EXPECT_EQ(r->mesh.colors[0], packSrgb8(255, 0, 0));
    EXPECT_EQ(r->mesh.colors[3], packSrgb8(255, 0, 0)) << "the split vertex keeps its position's colour";
    EXPECT_EQ(r->mesh.colors[5], kWhiteColor) << "v 0 1 0 1 1 1 is white";
    EXPECT_EQ(r->report.coloursRead, 4u);
}

TEST(VertexAttributesImport, ObjVertexWithFiveValuesIsNamed) {
    EXPECT_IMPORT_ERROR(importObj(writeFile("five.obj", "v 0 0 0 1 1\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")), "five.obj: ",
                        "line 1: vertex has 5 values (expected 3, 4 with a weight, or 6 with a colour)");
}

// glTF: NORMAL goes through the node's inverse transpose (a non-uniform scale tilts it), and
// COLOR_0 is linear: 0.5 becomes sRGB byte 188. A second primitive without them gets kNoNormal and white.
TEST(VertexAttributesImport, GltfNormalsFollowTheTransformAndColoursAreLinear) {
    GltfBuilder b;
    b.addPositions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    std::string normals;
    for (float f : {1.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 1.0f}) appendRaw(normals, f);
    b.addAccessor(normals, 5126, "VEC3", 3);
    std::string colours;
    for (float f : {0.5f, 0.0f, 1.0f, 1.0f, 1.0f, 1.0f, 0.0f, 0.0f, 0.0f}) appendRaw(colours, f);
    b.addAccessor(colours, 5126, "VEC3", 3);
    const std::string json = b.json(
        R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1,"COLOR_0":2}},{"attributes":{"POSITION":0}}]}],
           "nodes":[{"scale":[2,1,1],"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0)");
    auto r = importGltf(writeFile("attributes.gltf", json));
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->mesh.positions.size(), 6u);
    ASSERT_EQ(r->mesh.normals.size(), 6u);
    ASSERT_EQ(r->mesh.colors.size(), 6u);
    expectNormal(r->mesh.normals[0], {0.5f, 1, 0}, "scaled x halves the normal's x");
    expectNormal(r->mesh.normals[1], {0, 0, 1}, "vertex 1");
    EXPECT_EQ(r->mesh.normals[3], kNoNormal);
    EXPECT_EQ(r->mesh.colors[0], packSrgb8(188, 0, 255));
    EXPECT_EQ(r->mesh.colors[4], kWhiteColor);
    EXPECT_EQ(r->report.coloursRead, 3u);
}

// The mesh has an attribute on every vertex or on none, whichever primitive brings it: here the
// first primitive has neither, the second both, so the first's vertices are back-filled.
TEST(VertexAttributesImport, GltfAttributesOfALaterPrimitiveFillTheEarlierOnes) {
    GltfBuilder b;
    b.addPositions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    std::string normals, colours;
    for (int i = 0; i < 3; ++i)
        for (float f : {0.0f, 0.0f, 1.0f}) appendRaw(normals, f);
    for (int i = 0; i < 3; ++i)
        for (float f : {1.0f, 0.0f, 0.0f}) appendRaw(colours, f);
    b.addAccessor(normals, 5126, "VEC3", 3);
    b.addAccessor(colours, 5126, "VEC3", 3);
    const std::string json = b.json(
        R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}},{"attributes":{"POSITION":0,"NORMAL":1,"COLOR_0":2}}]}],
           "nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0)");
    auto r = importGltf(writeFile("attributes-later.gltf", json));
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->mesh.normals.size(), 6u);
    ASSERT_EQ(r->mesh.colors.size(), 6u);
    for (size_t v = 0; v < 3; ++v) {
        EXPECT_EQ(r->mesh.normals[v], kNoNormal) << v;
        EXPECT_EQ(r->mesh.colors[v], kWhiteColor) << v;
        expectNormal(r->mesh.normals[3 + v], {0, 0, 1}, "vertex " + std::to_string(3 + v));
        EXPECT_EQ(r->mesh.colors[3 + v], packSrgb8(255, 0, 0)) << 3 + v;
    }
}

// One triangle whose attribute `name` is the accessor `bytes` of `componentType` and `type`
// with `count` elements; the import must fail with `expected` in its message.
void expectAttributeRefused(const char* name, const std::string& bytes, int componentType, const char* type,
                            size_t count, const std::string& expected) {
    GltfBuilder b;
    b.addPositions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    b.addAccessor(bytes, componentType, type, count);
    const std::string json = b.json(R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,")" + std::string(name) +
                                    R"(":1}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0)");
    auto r = importGltf(writeFile("bad-attribute.gltf", json));
    ASSERT_FALSE(r.isOk()) << name << " " << type << " accepted; expected '" << expected << "'";
    EXPECT_NE(r.message().find("bad-attribute.gltf: mesh 0 primitive 0: " + expected), std::string::npos)
        << r.message();
}

std::string floats(size_t count, float value = 0.5f) {
    std::string bytes;
    for (size_t i = 0; i < count; ++i) appendRaw(bytes, value);
    return bytes;
}

TEST(VertexAttributesImport, GltfColourOfAWrongTypeIsNamed) {
    const std::string wrong = "accessor 1: COLOR_0 must be VEC3 or VEC4 of floats or normalized unsigned bytes or shorts";
    expectAttributeRefused("COLOR_0", floats(3), 5126, "SCALAR", 3, wrong);
    expectAttributeRefused("COLOR_0", floats(6), 5126, "VEC2", 3, wrong);
    expectAttributeRefused("COLOR_0", std::string(12, '\x40'), 5121, "VEC4", 3, wrong);  // bytes, not normalized
    expectAttributeRefused("COLOR_0", std::string(18, '\x10'), 5122, "VEC3", 3, wrong);        // signed shorts
    expectAttributeRefused("COLOR_0", std::string(36, '\x01'), 5125, "VEC3", 3, wrong);        // unsigned ints
}

TEST(VertexAttributesImport, GltfNormalOfAWrongTypeIsNamed) {
    expectAttributeRefused("NORMAL", floats(12), 5126, "VEC4", 3, "accessor 1: NORMAL is not VEC3");
}

TEST(VertexAttributesImport, GltfNormalOrColourCountOtherThanPositionsIsNamed) {
    expectAttributeRefused("NORMAL", floats(6), 5126, "VEC3", 2, "NORMAL has 2 elements for 3 positions");
    expectAttributeRefused("NORMAL", floats(12), 5126, "VEC3", 4, "NORMAL has 4 elements for 3 positions");
    expectAttributeRefused("COLOR_0", floats(6), 5126, "VEC3", 2, "COLOR_0 has 2 elements for 3 positions");
    expectAttributeRefused("COLOR_0", floats(16), 5126, "VEC4", 4, "COLOR_0 has 4 elements for 3 positions");
}

// A camera name longer than the package keeps (64 bytes) is cut at import, at a character
// boundary, and the report says what was stored for what.
TEST(VertexAttributesImport, GltfCameraNameBeyond64BytesIsCutAndReported) {
    GltfBuilder b;
    b.addPositions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    std::string longName = "Shot 12 ";
    while (longName.size() < 100) longName += "\xC3\xA9";  // "é": 2 bytes, so 8 + 46 * 2 = 100
    ASSERT_EQ(longName.size(), 100u);
    const std::string stored = longName.substr(0, 64);
    const std::string json = b.json(R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
        "cameras":[{"name":")" + longName + R"(","type":"perspective","perspective":{"yfov":0.7,"znear":0.1}},
                   {"name":"Short","type":"perspective","perspective":{"yfov":0.5,"znear":0.1}}],
        "nodes":[{"mesh":0},{"camera":0,"translation":[0,0,5]},{"camera":1,"translation":[0,0,6]}],
        "scenes":[{"nodes":[0,1,2]}],"scene":0)");
    auto r = importGltf(writeFile("long-camera.gltf", json));
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->mesh.cameras.size(), 2u);
    EXPECT_EQ(r->mesh.cameras[0].name, stored);
    EXPECT_EQ(r->mesh.cameras[1].name, "Short");
    bool reported = false;
    for (const std::string& w : r->report.warnings)
        reported |= w == "camera 0 name '" + longName + "' (100 bytes) is stored as '" + stored +
                             "' (64 bytes; names are kept to 64); --camera takes either";
    EXPECT_TRUE(reported) << ::testing::PrintToString(r->report.warnings);
    EXPECT_EQ(r->report.warnings.size(), 1u) << "only the long name is reported";
}

}  // namespace
}  // namespace vastray::test
