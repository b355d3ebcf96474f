#pragma once
// Meshes and helpers for the package tests.
#include "TestTmp.h"
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "vastray/streamer/Generate.h"
#include "vastray/streamer/PackageBuilder.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray::test {

inline TriangleMesh generatedMesh(GeneratorKind kind, uint64_t triangles, uint64_t seed = 1) {
    auto mesh = generateMesh({kind, triangles, seed});
    EXPECT_TRUE(mesh) << mesh.message();
    if (!mesh) return {};
    TriangleMesh out = std::move(mesh).value();
    out.materials = {Material{}};  // the tests' packages use the default material as before
    return out;
}

inline std::string tempPath(const std::string& name) {
    const std::filesystem::path dir = vastray::test::testTmpDir("package");
    std::filesystem::create_directories(dir);
    return (dir / name).string();
}

inline std::vector<uint8_t> readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void writeFile(const std::string& path, const std::vector<uint8_t>& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// Builds a package and opens it; fails the test on any error.
inline std::unique_ptr<PackageReader> buildAndOpen(TriangleMesh mesh, const std::string& path,
                                                   PackageBuildOptions options) {
    options.progress = Progress::Mode::None;
    auto report = buildPackage(std::move(mesh), path, options);
    EXPECT_TRUE(report.isOk()) << report.message();
    if (!report) return nullptr;
    auto reader = PackageReader::open(path);
    EXPECT_TRUE(reader.isOk()) << reader.message();
    return reader ? std::move(*reader) : nullptr;
}

// The 6,000-triangle generated city in 64 KiB chunks of `codec`, built as `name`-<codec>.vast and opened.
inline std::unique_ptr<PackageReader> smallCity(GeometryCodec codec, const std::string& name) {
    PackageBuildOptions options;
    options.codec = codec;
    options.chunkSizeBytes = 64 << 10;
    return buildAndOpen(generatedMesh(GeneratorKind::City, 6000),
                        tempPath(name + "-" + geometryCodecName(codec) + ".vast"), options);
}

// A forger's edit: `value`'s bytes at byte `at`.
template <typename T>
void putAt(std::vector<uint8_t>& bytes, size_t at, T value) {
    std::memcpy(&bytes[at], &value, sizeof value);
}

// Writes forged package bytes to `path` and expects PackageReader to refuse them with a
// message that holds "PATH: expected".
inline void expectOpenRefused(const std::vector<uint8_t>& bytes, const std::string& path, const std::string& expected) {
    writeFile(path, bytes);
    auto reader = PackageReader::open(path);
    ASSERT_FALSE(reader.isOk()) << "accepted; expected '" << expected << "'";
    EXPECT_NE(reader.message().find(path + ": " + expected), std::string::npos) << reader.message();
}

// A triangle's corners rotated so the smallest (lexicographic) comes first: equal for the
// same triangle whatever corner the decoder starts at.
inline std::array<Vec3f, 3> canonicalCorners(Vec3f a, Vec3f b, Vec3f c) {
    std::array<Vec3f, 3> v{a, b, c};
    auto less = [](Vec3f p, Vec3f q) {
        return std::tie(p.x, p.y, p.z) < std::tie(q.x, q.y, q.z);
    };
    int first = 0;
    for (int k = 1; k < 3; ++k)
        if (less(v[k], v[first])) first = k;
    return {v[first], v[(first + 1) % 3], v[(first + 2) % 3]};
}

}  // namespace vastray::test
