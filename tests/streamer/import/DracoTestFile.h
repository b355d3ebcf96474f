#pragma once
// A KHR_draco_mesh_compression glTF made in the test with Draco's own encoder.
#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>

#include "ImportTestFiles.h"

namespace vastray::test {

// A grid of (n+1)^2 vertices and 2n^2 triangles, Draco-encoded (lossless positions).
inline std::string dracoGrid(int n, int& positionId) {
    draco::TriangleSoupMeshBuilder builder;
    builder.Start(2 * n * n);
    positionId = builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
    int face = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const float p00[3] = {float(x), float(y), 0}, p10[3] = {float(x + 1), float(y), 0};
            const float p01[3] = {float(x), float(y + 1), 0}, p11[3] = {float(x + 1), float(y + 1), 0};
            builder.SetAttributeValuesForFace(positionId, draco::FaceIndex(face++), p00, p10, p11);
            builder.SetAttributeValuesForFace(positionId, draco::FaceIndex(face++), p00, p11, p01);
        }
    std::unique_ptr<draco::Mesh> mesh = builder.Finalize();
    positionId = int(mesh->attribute(positionId)->unique_id());
    draco::Encoder encoder;
    draco::EncoderBuffer buffer;
    EXPECT_TRUE(encoder.EncodeMeshToBuffer(*mesh, &buffer).ok());
    return std::string(buffer.data(), buffer.size());
}

// The grid above as a .gltf with the bitstream in a data: URI. idOffset shifts the
// POSITION attribute id the primitive names, to make one the bitstream lacks.
inline std::string dracoGridGltf(int n, int idOffset = 0) {
    int positionId = 0;
    const std::string draco = dracoGrid(n, positionId);
    const std::string json =
        R"({"asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"],
            "extensionsRequired":["KHR_draco_mesh_compression"],
            "buffers":[{"byteLength":)" + std::to_string(draco.size()) +
        R"(,"uri":"data:application/octet-stream;base64,)" + base64(draco) +
        R"("}],"bufferViews":[{"buffer":0,"byteLength":)" + std::to_string(draco.size()) + R"(}],
            "accessors":[{"componentType":5126,"type":"VEC3","count":)" +
        std::to_string((n + 1) * (n + 1)) + R"(},{"componentType":5125,"type":"SCALAR","count":)" +
        std::to_string(6 * n * n) + R"(}],
            "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,
               "extensions":{"KHR_draco_mesh_compression":{"bufferView":0,"attributes":{"POSITION":)" +
        std::to_string(positionId + idOffset) + R"(}}}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]})";
    return json;
}

}  // namespace vastray::test
