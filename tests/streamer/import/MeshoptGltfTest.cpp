// EXT_meshopt_compression: files written here with meshoptimizer's encoders (as gltfpack
// does) import to the same mesh as their uncompressed form; broken ones fail by name.
#include "ImportTestFiles.h"

#include <meshoptimizer.h>

#include <algorithm>

namespace vastray::test {
namespace {

struct Grid {
    std::vector<float> xyz;
    std::vector<uint32_t> indices;
};

// A bent 8x8 grid of quads: enough vertices for the codecs' blocks, positions not trivial.
Grid grid() {
    Grid g;
    const int n = 8;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x) g.xyz.insert(g.xyz.end(), {float(x), float(y), 0.1f * float(x * y % 5)});
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const uint32_t a = uint32_t(y * (n + 1) + x), b = a + 1, c = a + n + 1, d = c + 1;
            g.indices.insert(g.indices.end(), {a, b, d, a, d, c});
        }
    return g;
}

std::string bytesOf(const void* data, size_t size) { return std::string(static_cast<const char*>(data), size); }

// Buffer 0: the compressed positions then the compressed indices (a data: URI); buffer 1:
// the fallback, no data. `mode` and `extra` let a test break the extension's fields.
// With `glbBin`, buffer 0 is the GLB's BIN chunk instead, returned there.
std::string meshoptGltf(const Grid& g, const std::string& indexMode = "TRIANGLES", const std::string& extra = "",
                        bool corrupt = false, std::string* glbBin = nullptr) {
    const size_t vertices = g.xyz.size() / 3, indexCount = g.indices.size();
    std::vector<unsigned char> vb(meshopt_encodeVertexBufferBound(vertices, 12));
    vb.resize(meshopt_encodeVertexBuffer(vb.data(), vb.size(), g.xyz.data(), vertices, 12));
    std::vector<unsigned char> ib(indexMode == "TRIANGLES" ? meshopt_encodeIndexBufferBound(indexCount, vertices)
                                                           : meshopt_encodeIndexSequenceBound(indexCount, vertices));
    ib.resize(indexMode == "TRIANGLES" ? meshopt_encodeIndexBuffer(ib.data(), ib.size(), g.indices.data(), indexCount)
                                       : meshopt_encodeIndexSequence(ib.data(), ib.size(), g.indices.data(), indexCount));
    if (corrupt) std::fill(vb.begin() + 1, vb.end(), 0xFF);
    std::string compressed = bytesOf(vb.data(), vb.size());
    while (compressed.size() % 4) compressed += '\0';
    const size_t indexOffset = compressed.size();
    compressed += bytesOf(ib.data(), ib.size());
    const size_t positionBytes = vertices * 12, indexBytes = indexCount * 4;
    const std::string ext = R"("extensions":{"EXT_meshopt_compression":{"buffer":0,"byteOffset":)";
    return std::string(R"({"asset":{"version":"2.0"},"extensionsUsed":["EXT_meshopt_compression"],)") +
           R"("extensionsRequired":["EXT_meshopt_compression"],)" +
           R"("buffers":[{"byteLength":)" + std::to_string(compressed.size()) +
           (glbBin ? (*glbBin = compressed, std::string("},"))
                   : R"(,"uri":"data:application/octet-stream;base64,)" + base64(compressed) + R"("},)") +
           R"({"byteLength":)" + std::to_string(positionBytes + indexBytes) +
           R"(,"extensions":{"EXT_meshopt_compression":{"fallback":true}}}],)" +
           R"("bufferViews":[{"buffer":1,"byteOffset":0,"byteLength":)" + std::to_string(positionBytes) +
           R"(,"byteStride":12,)" + ext + "0,\"byteLength\":" + std::to_string(vb.size()) +
           R"(,"byteStride":12,"count":)" + std::to_string(vertices) + R"(,"mode":"ATTRIBUTES")" + extra + "}}}," +
           R"({"buffer":1,"byteOffset":)" + std::to_string(positionBytes) + R"(,"byteLength":)" +
           std::to_string(indexBytes) + "," + ext + std::to_string(indexOffset) + ",\"byteLength\":" +
           std::to_string(ib.size()) + R"(,"byteStride":4,"count":)" + std::to_string(indexCount) +
           R"(,"mode":")" + indexMode + R"("}}}],)" +
           R"("accessors":[{"bufferView":0,"componentType":5126,"count":)" + std::to_string(vertices) +
           R"(,"type":"VEC3"},{"bufferView":1,"componentType":5125,"count":)" + std::to_string(indexCount) +
           R"(,"type":"SCALAR"}],)" +
           R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],"nodes":[{"mesh":0}]})";
}

// The index codec may rotate a triangle's corners (winding kept): compare rotated so that
// each triangle starts at its smallest index.
std::vector<uint32_t> canonical(std::vector<uint32_t> indices) {
    for (size_t t = 0; t + 2 < indices.size(); t += 3) {
        auto first = indices.begin() + long(t);
        std::rotate(first, std::min_element(first, first + 3), first + 3);
    }
    return indices;
}

void expectGrid(const Result<ImportedMesh>& r, const Grid& g) {
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->mesh.positions.size(), g.xyz.size() / 3);
    for (size_t i = 0; i < r->mesh.positions.size(); ++i) {
        EXPECT_EQ(r->mesh.positions[i].x, g.xyz[i * 3]);
        EXPECT_EQ(r->mesh.positions[i].y, g.xyz[i * 3 + 1]);
        EXPECT_EQ(r->mesh.positions[i].z, g.xyz[i * 3 + 2]);
    }
    EXPECT_EQ(canonical(r->mesh.indices), canonical(g.indices));
}

TEST(MeshoptGltf, CompressedTrianglesDecodeExactly) {
    const Grid g = grid();
    expectGrid(importMesh(writeFile("meshopt.gltf", meshoptGltf(g))), g);
}

TEST(MeshoptGltf, CompressedGlbDecodesExactly) {
    const Grid g = grid();
    std::string bin;
    const std::string json = meshoptGltf(g, "TRIANGLES", "", false, &bin);
    expectGrid(importMesh(writeFile("meshopt.glb", glb(json, bin))), g);
}

TEST(MeshoptGltf, IndexSequencesDecodeExactly) {
    const Grid g = grid();
    expectGrid(importMesh(writeFile("sequence.gltf", meshoptGltf(g, "INDICES"))), g);
}

TEST(MeshoptGltf, BrokenExtensionsFailByName) {
    const Grid g = grid();
    EXPECT_IMPORT_ERROR(importMesh(writeFile("mode.gltf", meshoptGltf(g, "STRIPS"))), "mode.gltf: ",
                        "bufferView 1: EXT_meshopt_compression: mode 'STRIPS' is not ATTRIBUTES, TRIANGLES or INDICES");
    EXPECT_IMPORT_ERROR(importMesh(writeFile("filter.gltf", meshoptGltf(g, "TRIANGLES", R"(,"filter":"QUATERNION")"))),
                        "filter.gltf: ", "bufferView 0: EXT_meshopt_compression: filter QUATERNION does not allow byteStride 12");
    EXPECT_IMPORT_ERROR(importMesh(writeFile("corrupt.gltf", meshoptGltf(g, "TRIANGLES", "", true))), "corrupt.gltf: ",
                        "bufferView 0: EXT_meshopt_compression: the ATTRIBUTES data does not decode");
}

// A few compressed bytes may not ask for gigabytes.
TEST(MeshoptGltf, ExpansionBeyondTheLimitIsRefused) {
    const Grid g = grid();
    std::string json = meshoptGltf(g);
    const std::string count = "\"count\":" + std::to_string(g.xyz.size() / 3) + ",\"mode\":\"ATTRIBUTES\"";
    json.replace(json.find(count), count.size(), "\"count\":4000000000,\"mode\":\"ATTRIBUTES\"");
    EXPECT_IMPORT_ERROR(importMesh(writeFile("bomb.gltf", json)), "bomb.gltf: ",
                        "exceed the expansion limit of 128x");
}

}  // namespace
}  // namespace vastray::test
