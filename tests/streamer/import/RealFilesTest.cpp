// Real meshes: the shared test meshes and Debian's assimp-testmodels.
#include "ImportTestFiles.h"

namespace vastray::test {
namespace {

const std::string kShared = std::string(VASTRAY_SHARED_DATA) + "/meshes/";
const std::string kAssimp = "/usr/share/assimp/models/";

struct SharedMesh {
    const char* file;
    uint64_t triangles;  // after fan triangulation
};

class SharedMeshes : public ::testing::TestWithParam<SharedMesh> {};

TEST_P(SharedMeshes, TriangleCountAndBounds) {
    if (!std::filesystem::exists(kShared)) GTEST_SKIP() << kShared << " is absent (shared test data not checked out)";
    const SharedMesh& m = GetParam();
    auto r = importMesh(kShared + m.file);
    ASSERT_TRUE(r.isOk()) << r.message();
    // Published counts are before dropping: every triangle is either kept or counted.
    EXPECT_EQ(r->report.inputTriangles, m.triangles);
    EXPECT_EQ(r->mesh.triangleCount() + r->report.degenerateDropped, m.triangles);
    EXPECT_EQ(r->report.degenerateDropped, 0u);
    const Aabb box = r->mesh.bounds();
    EXPECT_FALSE(box.isEmpty());
    EXPECT_GT(box.surfaceArea(), 0.0);
    EXPECT_LT(box.surfaceArea(), 1e8) << "bounds far larger than any of these models";
}

// data/README.md lists suzanne at 500: those are polygons (32 triangles + 468 quads),
// which fan-triangulate to 32 + 2 * 468 = 968 triangles. None of the five has a
// degenerate triangle (checked: degenerateDropped == 0 for all).
INSTANTIATE_TEST_SUITE_P(Obj, SharedMeshes,
                         ::testing::Values(SharedMesh{"stanford-bunny.obj", 69451}, SharedMesh{"fandisk.obj", 12946},
                                           SharedMesh{"teapot.obj", 6320}, SharedMesh{"spot.obj", 5856},
                                           SharedMesh{"suzanne.obj", 968}),
                         [](const auto& info) {
                             std::string name = info.param.file;
                             return name.substr(0, name.find_first_of(".-"));
                         });

#define REQUIRE_ASSIMP_MODELS()                                                                   \
    if (!std::filesystem::exists(kAssimp)) GTEST_SKIP() << kAssimp << " is absent (install assimp-testmodels)"

TEST(AssimpModels, PlyAsciiAndBinaryCubesAgree) {
    REQUIRE_ASSIMP_MODELS();
    auto ascii = importMesh(kAssimp + "PLY/cube.ply");
    auto binary = importMesh(kAssimp + "PLY/cube_binary.ply");
    ASSERT_TRUE(ascii.isOk()) << ascii.message();
    ASSERT_TRUE(binary.isOk()) << binary.message();
    EXPECT_EQ(ascii->mesh.triangleCount(), 12u);  // 6 quads
    EXPECT_EQ(binary->mesh.triangleCount(), 12u);
    EXPECT_EQ(ascii->mesh.bounds(), binary->mesh.bounds());
}

TEST(AssimpModels, PlyWithNormalsAndTexcoords) {
    REQUIRE_ASSIMP_MODELS();
    auto r = importMesh(kAssimp + "PLY/Wuson.ply");
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(r->report.verticesRead, 11184u);
    EXPECT_EQ(r->report.normalsRead, 11184u);
    EXPECT_EQ(r->report.texcoordsRead, 11184u);
    EXPECT_EQ(r->report.inputTriangles, 3732u);  // every face is a triangle
}

TEST(AssimpModels, BrokenPlyFilesAreErrors) {
    REQUIRE_ASSIMP_MODELS();
    // pond.0.ply is 69 bytes short of its 70,051 31-byte vertices.
    EXPECT_IMPORT_ERROR(importMesh(kAssimp + "PLY/pond.0.ply"), "pond.0.ply: ",
                        "element vertex count 70051 is larger than the file could hold");
    // issue623.ply declares a vertex_indices list on vertices that its rows do not have.
    EXPECT_IMPORT_ERROR(importMesh(kAssimp + "PLY/issue623.ply"), "issue623.ply: ", "vertex 0: malformed value");
}

TEST(AssimpModels, PlyPointCloudHasNoTriangles) {
    REQUIRE_ASSIMP_MODELS();
    auto r = importMesh(kAssimp + "PLY/points.ply");
    EXPECT_IMPORT_ERROR(r, "points.ply", "no triangles");
}

TEST(AssimpModels, ObjFilesWithMaterialsAndOddFormatting) {
    REQUIRE_ASSIMP_MODELS();
    for (const char* file : {"box.obj", "box_without_lineending.obj", "multiple_spaces.obj", "cube_usemtl.obj",
                             "space_in_material_name.obj", "spider.obj", "WusonOBJ.obj", "concave_polygon.obj", "empty_mat.obj",
                             "cube_mtllib_after_g.obj", "regr01.obj", "testmixed.obj"}) {
        auto r = importMesh(kAssimp + "OBJ/" + file);
        EXPECT_TRUE(r.isOk()) << file << ": " << r.message();
        if (r.isOk()) {
            EXPECT_GT(r->mesh.triangleCount(), 0u) << file;
        }
    }
}

TEST(AssimpModels, GlbAndDracoGltfOfTheSameEngineAgree) {
    REQUIRE_ASSIMP_MODELS();
    auto glb = importMesh(kAssimp + "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb");
    auto draco = importMesh(kAssimp + "glTF2/draco/2CylinderEngine.gltf");
    ASSERT_TRUE(glb.isOk()) << glb.message();
    ASSERT_TRUE(draco.isOk()) << draco.message();
    EXPECT_EQ(glb->report.format, "glb");
    // The Draco encoder dropped the 11,160 degenerate triangles of the original before
    // writing; we drop the same ones, so what we keep from the GLB is the Draco input.
    EXPECT_EQ(glb->mesh.triangleCount(), draco->report.inputTriangles);
    EXPECT_EQ(glb->report.degenerateDropped, 11160u);
    // Draco quantizes positions: bounds agree to about 1% of the model's size.
    const Aabb a = glb->mesh.bounds(), b = draco->mesh.bounds();
    const float tolerance = 0.01f * std::max({a.extent().x, a.extent().y, a.extent().z});
    for (int axis = 0; axis < 3; ++axis) {
        EXPECT_NEAR(a.lo[axis], b.lo[axis], tolerance);
        EXPECT_NEAR(a.hi[axis], b.hi[axis], tolerance);
    }
}

TEST(AssimpModels, TexturedBoxInAllThreeContainers) {
    REQUIRE_ASSIMP_MODELS();
    for (const char* file : {"BoxTextured-glTF/BoxTextured.gltf", "BoxTextured-glTF-Binary/BoxTextured.glb",
                             "BoxTextured-glTF-Embedded/BoxTextured.gltf"}) {
        auto r = importMesh(kAssimp + "glTF2/" + file);
        ASSERT_TRUE(r.isOk()) << file << ": " << r.message();
        EXPECT_EQ(r->mesh.triangleCount(), 12u) << file;
    }
}

TEST(AssimpModels, BrokenGltfFilesAreErrorsNotCrashes) {
    REQUIRE_ASSIMP_MODELS();
    EXPECT_IMPORT_ERROR(importMesh(kAssimp + "glTF2/IndexOutOfRange/IndexOutOfRange.gltf"), "IndexOutOfRange.gltf",
                        "mesh 0 primitive 0");
    EXPECT_IMPORT_ERROR(importMesh(kAssimp + "glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb"),
                        "BoxWithInfinites.glb", "non-finite");
    EXPECT_IMPORT_ERROR(importMesh(kAssimp + "glTF2/MissingBin/BoxTextured.gltf"), "BoxTextured.gltf", "BoxTextured0.bin");
    EXPECT_IMPORT_ERROR(importMesh(kAssimp + "glTF2/RecursiveNodes/RecursiveNodes.gltf"), "RecursiveNodes.gltf", "node");
}

}  // namespace
}  // namespace vastray::test
