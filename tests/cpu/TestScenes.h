#pragma once
// Small scenes built in code for the reference renderer's tests.
#include "TestTmp.h"
#include <filesystem>
#include <string>

#include "vastray/core/Mesh.h"
#include "vastray/core/VecMath.h"
#include "vastray/cpu/RenderScene.h"
#include "vastray/streamer/Generate.h"

namespace vastray::test {

inline std::string tmpPath(const std::string& name) {
    const std::filesystem::path dir = vastray::test::testTmpDir("cpu");
    std::filesystem::create_directories(dir);
    return (dir / name).string();
}

// The square [-1, 1]^2 in the plane z = 0, counter-clockwise seen from +z (its front).
inline TriangleMesh quadFacingPlusZ(bool doubleSided) {
    TriangleMesh mesh;
    mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    Material m;
    m.doubleSided = doubleSided;
    mesh.materials = {m};
    return mesh;
}

// The generated unit icosphere (outward-facing), written once per test binary.
inline RenderScene unitSphere(uint64_t triangles = 20000) {
    const std::string path = tmpPath("sphere-" + std::to_string(triangles) + ".ply");
    if (!std::filesystem::exists(path)) {
        GenerateOptions options;
        options.kind = GeneratorKind::Sphere;
        options.triangles = triangles;
        if (!generateToPly(options, path)) return {};
    }
    auto scene = loadRenderScene(path);
    return scene ? std::move(*scene) : RenderScene{};
}

inline float minPlaneDistanceFromOrigin(const TriangleMesh& mesh) {
    float least = 1e30f;
    for (uint64_t t = 0; t < mesh.triangleCount(); ++t) {
        const Vec3f v0 = mesh.positions[mesh.indices[3 * t]];
        const Vec3f n = normalize(cross(mesh.positions[mesh.indices[3 * t + 1]] - v0,
                                        mesh.positions[mesh.indices[3 * t + 2]] - v0));
        least = std::fmin(least, std::fabs(dot(n, v0)));
    }
    return least;
}

}  // namespace vastray::test
