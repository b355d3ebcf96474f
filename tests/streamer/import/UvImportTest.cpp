// One UV set from each importer (issue 13): kept only when a material references a texture map,
// in glTF's texture space (v down: OBJ, PLY and assimp files' v is stored as 1 - v), split into
// vertices where a position is used with several UVs, and refused by name when not finite or
// beyond +-kMaxAbsUv.
#include <filesystem>

#include "ImportTestFiles.h"
#include "vastray/core/VertexAttributes.h"

namespace vastray::test {
namespace {

using Uv = std::array<float, 2>;

// The UV of the vertex at `position` used by triangle `t` (the importers may renumber vertices).
Uv uvAt(const TriangleMesh& mesh, size_t t, Vec3f position) {
    for (int c = 0; c < 3; ++c) {
        const uint32_t v = mesh.indices[3 * t + c];
        if (mesh.positions[v] == position) return mesh.uvs[v];
    }
    ADD_FAILURE() << "triangle " << t << " has no corner at the position";
    return {-1, -1};
}

// Two triangles sharing the edge (1,0,0)-(0,1,0), each with its own UVs there: a seam.
constexpr const char* kSeamObj =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
    "vt 0 0\nvt 0.25 0\nvt 0 0.25\nvt 0.75 0\nvt 0.5 0.5\nvt 1 1\n"
    "f 1/1 2/2 3/3\nf 2/4 4/6 3/5\n";

TEST(UvImport, ObjSplitsSeamsAndFlipsV) {
    const std::string path = writeFile("uv-seam.obj", std::string("mtllib uv-seam.mtl\nusemtl painted\n") + kSeamObj);
    writeFile("uv-seam.mtl", "newmtl painted\nKd 1 1 1\nmap_Kd wood.png\n");
    auto r = importObj(path);
    ASSERT_TRUE(r.isOk()) << r.message();
    const TriangleMesh& m = r->mesh;
    ASSERT_EQ(m.uvs.size(), m.positions.size());
    EXPECT_EQ(m.positions.size(), 6u) << "positions 2 and 3 are used with two UVs each";
    EXPECT_EQ(r->report.textureMaps, 1u);
    EXPECT_EQ(uvAt(m, 0, {1, 0, 0}), (Uv{0.25f, 1.0f}));
    EXPECT_EQ(uvAt(m, 1, {1, 0, 0}), (Uv{0.75f, 1.0f}));
    EXPECT_EQ(uvAt(m, 0, {0, 1, 0}), (Uv{0.0f, 0.75f}));
    EXPECT_EQ(uvAt(m, 1, {0, 1, 0}), (Uv{0.5f, 0.5f}));
    EXPECT_EQ(uvAt(m, 1, {1, 1, 0}), (Uv{1.0f, 0.0f}));
}

// Without a texture map nothing reads UVs: none are kept, no vertex is split for them, and the
// report says so.
TEST(UvImport, ObjWithoutATextureMapKeepsNoUvs) {
    auto r = importObj(writeFile("uv-plain.obj", kSeamObj));
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_TRUE(r->mesh.uvs.empty());
    EXPECT_EQ(r->mesh.positions.size(), 4u);
    EXPECT_EQ(r->report.texcoordsRead, 6u);
    bool warned = false;
    for (const std::string& w : r->report.warnings)
        warned |= w == "6 texture coordinates read but not used (no material has a texture map)";
    EXPECT_TRUE(warned) << ::testing::PrintToString(r->report.warnings);
}

TEST(UvImport, ObjHostileTexcoordsAreNamed) {
    EXPECT_IMPORT_ERROR(importObj(writeFile("nan-vt.obj", "v 0 0 0\nvt 0 nan\n")), "nan-vt.obj: ",
                        "line 2: vt (0, nan) is not finite");
    EXPECT_IMPORT_ERROR(importObj(writeFile("big-vt.obj", "v 0 0 0\nvt 2e6 0\n")), "big-vt.obj: ",
                        "line 2: vt (2000000, 0) lies beyond the texture coordinate limit of +-1e6");
}

std::string plyWithUvs(const char* names, const char* type, const std::string& comment, const char* rows) {
    const std::string u = std::string(names).substr(0, std::string(names).find(' '));
    const std::string v = std::string(names).substr(u.size() + 1);
    return "ply\nformat ascii 1.0\n" + comment + "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n" +
           "property " + type + " " + u + "\nproperty " + type + " " + v + "\n" +
           "element face 1\nproperty list uchar int vertex_indices\nend_header\n" + rows + "3 0 1 2\n";
}

TEST(UvImport, PlyUvNamesFloatOrDouble) {
    for (const char* names : {"u v", "s t", "texture_u texture_v"})
        for (const char* type : {"float", "double"}) {
            const std::string where = std::string(names) + " " + type;
            auto r = importPly(writeFile("uv.ply", plyWithUvs(names, type, "comment TextureFile wood.png\n",
                                                             "0 0 0 0 0\n1 0 0 1 0.25\n0 1 0 0.125 1\n")));
            ASSERT_TRUE(r.isOk()) << where << ": " << r.message();
            ASSERT_EQ(r->mesh.uvs.size(), 3u) << where;
            EXPECT_EQ(r->mesh.uvs[0], (Uv{0.0f, 1.0f})) << where;
            EXPECT_EQ(r->mesh.uvs[1], (Uv{1.0f, 0.75f})) << where;
            EXPECT_EQ(r->mesh.uvs[2], (Uv{0.125f, 0.0f})) << where;
            EXPECT_EQ(r->report.texcoordsRead, 3u) << where;
        }
    auto plain = importPly(writeFile("uv-plain.ply", plyWithUvs("u v", "float", "", "0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n")));
    ASSERT_TRUE(plain.isOk()) << plain.message();
    EXPECT_TRUE(plain->mesh.uvs.empty()) << "no TextureFile comment: nothing reads them";
}

TEST(UvImport, PlyHostileTexcoordsAreNamed) {
    EXPECT_IMPORT_ERROR(importPly(writeFile("nan-uv.ply", plyWithUvs("u v", "float", "", "0 0 0 0 0\n1 0 0 inf 0\n0 1 0 0 1\n"))),
                        "nan-uv.ply: ", "vertex 1: texture coordinate (inf, 0) is not finite");
    EXPECT_IMPORT_ERROR(importPly(writeFile("big-uv.ply", plyWithUvs("u v", "double", "", "0 0 0 0 0\n1 0 0 0 -1e7\n0 1 0 0 1\n"))),
                        "big-uv.ply: ", "vertex 1: texture coordinate (0, -10000000) lies beyond the texture coordinate limit");
}

// A quad of two primitives: the first without TEXCOORD_1, the second with it; the material's
// base colour texture uses set 1, so TEXCOORD_0 (present on both) is not what is kept.
std::string gltfQuad(const std::string& materials, const std::vector<float>& uv1) {
    GltfBuilder b;
    b.addPositions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    std::string zeros, ones;
    for (int i = 0; i < 6; ++i) appendRaw(zeros, 0.5f);
    for (float f : uv1) appendRaw(ones, f);
    b.addAccessor(zeros, 5126, "VEC2", 3);
    b.addAccessor(ones, 5126, "VEC2", uv1.size() / 2);
    return b.json(
        R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1},"material":0},
                                    {"attributes":{"POSITION":0,"TEXCOORD_0":1,"TEXCOORD_1":2},"material":0}]}],
           "nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0,)" + materials);
}

TEST(UvImport, GltfKeepsTheSetTheTexturesUse) {
    const std::string materials =
        R"("images":[{"uri":"wood.png"}],"textures":[{"source":0}],
           "materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0,"texCoord":1}}}])";
    auto r = importGltf(writeFile("uv-set.gltf", gltfQuad(materials, {0.25f, 0.75f, 1, 0, 0, 1})));
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->mesh.uvs.size(), 6u);
    for (int v = 0; v < 3; ++v) EXPECT_EQ(r->mesh.uvs[v], (Uv{0, 0})) << "the first primitive has no TEXCOORD_1";
    EXPECT_EQ(r->mesh.uvs[3], (Uv{0.25f, 0.75f}));
    EXPECT_EQ(r->mesh.uvs[4], (Uv{1, 0}));
    EXPECT_EQ(r->mesh.uvs[5], (Uv{0, 1}));

    auto untextured = importGltf(writeFile("uv-none.gltf", gltfQuad(R"("materials":[{}])", {0, 0, 1, 0, 0, 1})));
    ASSERT_TRUE(untextured.isOk()) << untextured.message();
    EXPECT_TRUE(untextured->mesh.uvs.empty());
}

TEST(UvImport, GltfMaterialsUsingSeveralSetsKeepTheMostUsedAndWarnOnce) {
    const std::string materials =
        R"("images":[{"uri":"a.png"}],"textures":[{"source":0}],
           "materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0,"texCoord":1},
                                                 "metallicRoughnessTexture":{"index":0,"texCoord":1}},
                         "normalTexture":{"index":0}}])";
    auto r = importGltf(writeFile("uv-sets.gltf", gltfQuad(materials, {0.25f, 0.75f, 1, 0, 0, 1})));
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->mesh.uvs.size(), 6u);
    EXPECT_EQ(r->mesh.uvs[3], (Uv{0.25f, 0.75f})) << "TEXCOORD_1: two maps use it, one uses set 0";
    size_t warned = 0;
    for (const std::string& w : r->report.warnings)
        warned += w == "uv-sets.gltf: materials' textures use 2 UV sets; TEXCOORD_1 (the most used) is kept, "
                       "textures on the others will be placed by it";
    EXPECT_EQ(warned, 1u) << ::testing::PrintToString(r->report.warnings);
}

TEST(UvImport, GltfHostileOrMistypedTexcoordsAreNamed) {
    const std::string materials =
        R"("images":[{"uri":"a.png"}],"textures":[{"source":0}],
           "materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0,"texCoord":1}}}])";
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_IMPORT_ERROR(importGltf(writeFile("uv-nan.gltf", gltfQuad(materials, {0, 0, 1, nan, 0, 1}))), "uv-nan.gltf: ",
                        "mesh 0 primitive 1: accessor 2: TEXCOORD_1 element 1 (1, nan) is not finite");
    EXPECT_IMPORT_ERROR(importGltf(writeFile("uv-far.gltf", gltfQuad(materials, {0, 0, 1, 0, 0, 3e6f}))), "uv-far.gltf: ",
                        "accessor 2: TEXCOORD_1 element 2 (0, 3000000) lies beyond the texture coordinate limit of +-1e6");
    EXPECT_IMPORT_ERROR(importGltf(writeFile("uv-count.gltf", gltfQuad(materials, {0, 0, 1, 0}))), "uv-count.gltf: ",
                        "TEXCOORD_1 has 2 elements for 3 positions");
}

// assimp: a DirectX .x quad whose material names a texture file (assimp's X reader turns the
// file's v-down UVs into its own v-up ones; the importer turns them back).
TEST(UvImport, AssimpReadsTheFirstUvSetOfATexturedMaterial) {
    const std::string x = texturedQuadX("wood.png", "0.0;1.0;, 0.5;1.0;, 0.5;0.25;, 0.0;0.25;");
    auto r = importWithAssimp(writeFile("uv-quad.x", x));
    ASSERT_TRUE(r.isOk()) << r.message();
    const TriangleMesh& m = r->mesh;
    ASSERT_EQ(m.uvs.size(), m.positions.size());
    EXPECT_GT(r->report.textureMaps, 0u);
    for (size_t t = 0; t < m.triangleCount(); ++t)
        for (int c = 0; c < 3; ++c) {
            const Vec3f p = m.positions[m.indices[3 * t + c]];
            const Uv uv = m.uvs[m.indices[3 * t + c]];
            EXPECT_NEAR(uv[0], p.x * 0.5f, 1e-6f) << "corner at " << p.x << ", " << p.y;
            EXPECT_NEAR(uv[1], 1.0f - p.y * 0.75f, 1e-6f) << "corner at " << p.x << ", " << p.y;
        }
}

// Debian's assimp-testmodels: the Khronos BoxTextured sample (glTF 2.0, one base colour texture
// on TEXCOORD_0) through our glTF importer keeps its 24 UVs.
TEST(UvImport, BoxTexturedSampleKeepsItsUvs) {
    const std::string path = "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent (install assimp-testmodels)";
    auto r = importMesh(path);
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(r->mesh.uvs.size(), r->mesh.positions.size());
    EXPECT_EQ(r->report.texcoordsRead, 24u);
    for (const Uv& uv : r->mesh.uvs)
        for (float c : uv) EXPECT_TRUE(c >= 0.0f && c <= 6.0f) << c;
}

}  // namespace
}  // namespace vastray::test
