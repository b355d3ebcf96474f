// Bad input: every case is an error value whose message names the file and the element.
#include "DracoTestFile.h"
#include "ImportTestFiles.h"

namespace vastray::test {
namespace {

const std::string kPlyXyz = "property float x\nproperty float y\nproperty float z\n";

std::string gltfTriangle(const std::string& bufferUri, const std::string& extra = "") {
    return R"({"asset":{"version":"2.0"},)" + extra + R"("buffers":[{"byteLength":36,"uri":")" + bufferUri +
           R"("}],"bufferViews":[{"buffer":0,"byteLength":36}],
           "accessors":[{"bufferView":0,"componentType":5126,"type":"VEC3","count":3}],
           "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}]})";
}

TEST(BadInput, NanCoordinateInObj) {
    EXPECT_IMPORT_ERROR(importMesh(writeFile("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n")), "nan.obj: ",
                        "vertex 1 has a non-finite coordinate");
}

TEST(BadInput, InfCoordinateInPly) {
    const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\n" + kPlyXyz +
                            "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                            "0 0 0\n1 0 0\n0 inf 0\n3 0 1 2\n";
    EXPECT_IMPORT_ERROR(importMesh(writeFile("inf.ply", ply)), "inf.ply: ", "vertex 2 has a non-finite coordinate");
}

TEST(BadInput, ObjIndexBeyondVertexCount) {
    EXPECT_IMPORT_ERROR(importMesh(writeFile("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n")), "range.obj: ",
                        "line 4: vertex index 4 is out of range");
}

TEST(BadInput, ObjRelativeIndexBeforeFirstVertex) {
    EXPECT_IMPORT_ERROR(importMesh(writeFile("relative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n")),
                        "relative.obj: ", "line 4: vertex index -4 is out of range");
}

TEST(BadInput, ObjZeroIndexAndBadTexcoordIndex) {
    EXPECT_IMPORT_ERROR(importMesh(writeFile("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n")), "zero.obj: ",
                        "line 4: vertex index 0");
    EXPECT_IMPORT_ERROR(importMesh(writeFile("vt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n")),
                        "vt.obj: ", "line 5: texcoord index 2");
}

TEST(BadInput, PlyFaceIndexBeyondVertexCount) {
    const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\n" + kPlyXyz +
                            "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
                            "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 7\n";
    EXPECT_IMPORT_ERROR(importMesh(writeFile("faces.ply", ply)), "faces.ply: ", "face 1: index 7 >= vertex count 3");
}

TEST(BadInput, PlyNegativeFaceIndex) {
    const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\n" + kPlyXyz +
                            "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                            "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n";
    EXPECT_IMPORT_ERROR(importMesh(writeFile("negative.ply", ply)), "negative.ply: ", "face 0: index -1 is negative");
}

TEST(BadInput, GltfIndexBeyondVertexCount) {
    GltfBuilder b;
    b.addPositions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    b.addIndices<uint16_t>({0, 1, 3});
    const std::string json = b.json(R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],"nodes":[{"mesh":0}])");
    EXPECT_IMPORT_ERROR(importMesh(writeFile("range.gltf", json)), "range.gltf: ",
                        "mesh 0 primitive 0: index 2 value 3 >= vertex count 3");
}

TEST(BadInput, GltfTriangleIndexCountNotMultipleOfThree) {
    GltfBuilder b;
    b.addPositions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    b.addIndices<uint32_t>({0, 1, 2, 0});
    const std::string json = b.json(R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],"nodes":[{"mesh":0}])");
    EXPECT_IMPORT_ERROR(importMesh(writeFile("count.gltf", json)), "count.gltf: ",
                        "mesh 0 primitive 0: index count 4 is not a multiple of 3");
}

TEST(BadInput, PlyCountLargerThanTheFileCouldHold) {
    std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n" + kPlyXyz +
                      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    ply.resize(1024, '\0');
    EXPECT_IMPORT_ERROR(importMesh(writeFile("huge.ply", ply)), "huge.ply: ",
                        "element vertex count 4000000000 is larger than the file could hold");
}

TEST(BadInput, PlyVertexCountBeyondUint32) {
    const std::string ply = "ply\nformat ascii 1.0\nelement vertex 5000000000\n" + kPlyXyz + "end_header\n0 0 0\n";
    EXPECT_IMPORT_ERROR(importMesh(writeFile("uint32.ply", ply)), "uint32.ply: ", "exceeds the uint32 index range");
}

TEST(BadInput, GltfAccessorLargerThanItsBuffer) {
    GltfBuilder b;
    b.addAccessor(std::string(36, '\0'), 5126, "VEC3", 1000);
    const std::string json = b.json(R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}])");
    EXPECT_IMPORT_ERROR(importMesh(writeFile("accessor.gltf", json)), "accessor.gltf: ",
                        "mesh 0 primitive 0: accessor 0: 1000 elements do not fit");
}

TEST(BadInput, TruncatedBinaryPly) {
    std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 3\n" + kPlyXyz +
                      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    for (int i = 0; i < 9; ++i) appendRaw(ply, float(i % 2));
    appendRaw(ply, uint8_t(3));
    appendRaw(ply, int32_t(0));  // two indices missing
    EXPECT_IMPORT_ERROR(importMesh(writeFile("truncated.ply", ply)), "truncated.ply: ", "face 0: unexpected end of file");
}

TEST(BadInput, TruncatedAsciiPly) {
    const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\n" + kPlyXyz +
                            "element face 1\nproperty list uchar int vertex_indices\nend_header\n0.0000 0 0\n1.0000 0 0\n0.0000 1";
    EXPECT_IMPORT_ERROR(importMesh(writeFile("truncated-ascii.ply", ply)), "truncated-ascii.ply: ",
                        "vertex 2: unexpected end of file in z");
}

TEST(BadInput, ObjNumberWithTrailingJunk) {
    EXPECT_IMPORT_ERROR(importMesh(writeFile("junk.obj", "v 0 0 0\nv 1 0 0\nv 0 1 3.1+e2\nf 1 2 3\n")), "junk.obj: ",
                        "line 3: malformed vertex position");
}

TEST(BadInput, TruncatedObjLine) {
    EXPECT_IMPORT_ERROR(importMesh(writeFile("truncated.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nv 1 1")),
                        "truncated.obj: ", "line 5: malformed vertex position");
}

TEST(BadInput, TruncatedGlb) {
    std::string bin;
    for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) appendRaw(bin, f);
    std::string file = glb(R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":36}],"bufferViews":[{"buffer":0,"byteLength":36}],
        "accessors":[{"bufferView":0,"componentType":5126,"type":"VEC3","count":3}],
        "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}]})", bin);
    file.resize(file.size() - 20);
    EXPECT_IMPORT_ERROR(importMesh(writeFile("truncated.glb", file)), "truncated.glb: ", "GLB header: declared length");
}

TEST(BadInput, BadGlbHeaders) {
    const std::string good = glb(R"({"asset":{"version":"2.0"}})", "");
    std::string magic = good, version = good, chunk = good;
    magic[0] = 'x';
    version[4] = 1;
    chunk[12] = char(0xff);  // JSON chunk longer than the file
    EXPECT_IMPORT_ERROR(importMesh(writeFile("magic.glb", magic)), "magic.glb: ", "GLB header: bad magic");
    EXPECT_IMPORT_ERROR(importMesh(writeFile("version.glb", version)), "version.glb: ", "GLB header: version 1");
    EXPECT_IMPORT_ERROR(importMesh(writeFile("chunk.glb", chunk)), "chunk.glb: ", "GLB header: JSON chunk length");
    EXPECT_IMPORT_ERROR(importMesh(writeFile("short.glb", "glTF")), "short.glb: ", "GLB header");
}

TEST(BadInput, ForbiddenUris) {
    std::string secret;
    for (int i = 0; i < 9; ++i) appendRaw(secret, 0.5f);
    writeFile("secret.bin", secret);  // exists one folder above the model: must still be refused
    std::filesystem::create_directories(tmpPath("model"));
    const struct {
        const char* uri;
        const char* why;
    } cases[] = {{"../secret.bin", "escapes the model folder"},
                 {"sub/../../secret.bin", "escapes the model folder"},
                 {"%2e%2e/secret.bin", "escapes the model folder"},  // tinygltf URL-decodes first
                 {"/etc/passwd", "is an absolute path"},
                 {"file:///etc/passwd", "has a scheme ('file:')"},
                 {"http://example.com/a.bin", "has a scheme ('http:')"},
                 {"https://example.com/a.bin", "has a scheme ('https:')"}};
    for (const auto& c : cases) {
        const std::string path = writeFile("model/uri.gltf", gltfTriangle(c.uri));
        auto r = importMesh(path);
        EXPECT_IMPORT_ERROR(r, "uri.gltf: ", c.why);
    }
}

TEST(BadInput, UnknownRequiredExtension) {
    GltfBuilder b;
    b.addPositions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    const std::string json = b.json(R"("extensionsUsed":["EXT_made_up"],"extensionsRequired":["EXT_made_up"],
        "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}])");
    EXPECT_IMPORT_ERROR(importMesh(writeFile("required.gltf", json)), "required.gltf: ",
                        "required extension 'EXT_made_up' is not supported");
}

TEST(BadInput, DracoExtensionWithDanglingBufferView) {
    const std::string json = R"({"asset":{"version":"2.0"},"buffers":[],"bufferViews":[],
        "accessors":[{"componentType":5126,"type":"VEC3","count":3}],
        "meshes":[{"primitives":[{"attributes":{"POSITION":0},
            "extensions":{"KHR_draco_mesh_compression":{"bufferView":7,"attributes":{"POSITION":0}}}}]}]})";
    EXPECT_IMPORT_ERROR(importMesh(writeFile("dangling.gltf", json)), "dangling.gltf: ",
                        "mesh 0 primitive 0: KHR_draco_mesh_compression: bad bufferView");
}

TEST(BadInput, DracoAttributeIdMissingFromTheBitstream) {
    const std::string bad = dracoGridGltf(4, 9);  // the bitstream has one attribute
    EXPECT_IMPORT_ERROR(importMesh(writeFile("draco-id.gltf", bad)), "draco-id.gltf: ",
                        "mesh 0 primitive 0: KHR_draco_mesh_compression: attribute POSITION id");
}

TEST(BadInput, MalformedJson) {
    EXPECT_IMPORT_ERROR(importMesh(writeFile("broken.gltf", "{\"asset\": [")), "broken.gltf: ", "JSON");
}

TEST(BadInput, NoTrianglesAtAll) {
    EXPECT_IMPORT_ERROR(importMesh(writeFile("empty.obj", "# nothing\nv 0 0 0\n")), "empty.obj: ", "no triangles");
}

TEST(BadInput, UnknownExtensionAndMissingFile) {
    EXPECT_IMPORT_ERROR(importMesh(writeFile("mesh.xyz", "solid")), "mesh.xyz: ", "unknown mesh format '.xyz'");
    EXPECT_IMPORT_ERROR(importMesh(writeFile("mesh.blend", "BLENDER")), "mesh.blend: ",
                        "unknown mesh format '.blend' (supported: .obj, .ply, .gltf, .glb, .stl, .off");
    EXPECT_IMPORT_ERROR(importMesh(writeFile("mesh.stl", "solid")), "mesh.stl: ", "assimp: File is too small");
    EXPECT_IMPORT_ERROR(importMesh(tmpPath("does-not-exist.ply")), "does-not-exist.ply: ", "cannot open");
    std::filesystem::create_directories(tmpPath("folder.obj"));
    EXPECT_IMPORT_ERROR(importMesh(tmpPath("folder.obj")), "folder.obj: ", "is a directory");
}

}  // namespace
}  // namespace vastray::test
