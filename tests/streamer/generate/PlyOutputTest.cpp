// The PLY file is what the CLI hands to importers: its size, header and bytes must be exact,
// and failures must never leave a file under the real name.
#include "TestTmp.h"
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "streamer/generate/RecordingSink.h"

namespace vastray::test {
namespace {

namespace fs = std::filesystem;

fs::path tmpDir() {
    fs::path dir = vastray::test::testTmpDir("generate");
    fs::create_directories(dir);
    return dir;
}

std::string readAll(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(PlyOutput, FileHasExactHeaderSizeAndStreamedBytes) {
    const GenerateOptions options{GeneratorKind::City, 500, 42};
    const fs::path path = tmpDir() / "city.ply";
    fs::remove(path);
    ASSERT_TRUE(generateToPly(options, path.string()));
    EXPECT_FALSE(fs::exists(path.string() + ".tmp"));

    RecordingSink mesh = record(options.kind, options.triangles, options.seed);
    const std::string bytes = readAll(path);
    const size_t headerEnd = bytes.find("end_header\n");
    ASSERT_NE(headerEnd, std::string::npos);
    const size_t headerLength = headerEnd + std::strlen("end_header\n");
    const uint64_t v = mesh.vertices.size(), f = mesh.faces.size();
    EXPECT_EQ(bytes.size(), headerLength + 12 * v + 13 * f);

    std::ostringstream expected;
    expected << "ply\nformat binary_little_endian 1.0\n"
             << "comment vastray generate kind=city seed=42 triangles=500\n"
             << "element vertex " << v << "\nproperty float x\nproperty float y\nproperty float z\n"
             << "element face " << f << "\nproperty list uchar uint vertex_indices\nend_header\n";
    EXPECT_EQ(bytes.substr(0, headerLength), expected.str());

    float xyz[3];
    std::memcpy(xyz, bytes.data() + headerLength, 12);
    EXPECT_EQ((Vec3f{xyz[0], xyz[1], xyz[2]}), mesh.vertices[0]);
    std::memcpy(xyz, bytes.data() + headerLength + 12 * (v - 1), 12);
    EXPECT_EQ((Vec3f{xyz[0], xyz[1], xyz[2]}), mesh.vertices[v - 1]);
    const char* faces = bytes.data() + headerLength + 12 * v;
    for (uint64_t i : {uint64_t{0}, f - 1}) {
        EXPECT_EQ(faces[13 * i], 3);
        std::array<uint32_t, 3> abc;
        std::memcpy(abc.data(), faces + 13 * i + 1, 12);
        EXPECT_EQ(abc, mesh.faces[i]);
    }
}

TEST(PlyOutput, LargerThanTheBufferIsWrittenCompletely) {
    // 300k sphere triangles are ~5.8 MB: several 1 MiB flushes, records straddling them.
    const fs::path path = tmpDir() / "sphere.ply";
    ASSERT_TRUE(generateToPly({GeneratorKind::Sphere, 300'000, 1}, path.string()));
    Result<GeneratedCounts> counts = generatedCounts({GeneratorKind::Sphere, 300'000, 1});
    const std::string bytes = readAll(path);
    const size_t headerLength = bytes.find("end_header\n") + std::strlen("end_header\n");
    EXPECT_EQ(bytes.size(), headerLength + 12 * counts->vertices + 13 * counts->triangles);
    fs::remove(path);
}

// stream_render_bench --write-ply: one generation gives both the in-core mesh and the PLY.
TEST(PlyOutput, MeshAndPlyFromOnePassMatchEachOnItsOwn) {
    const GenerateOptions options{GeneratorKind::City, 2000, 7};
    const fs::path alone = tmpDir() / "alone.ply", both = tmpDir() / "both.ply";
    ASSERT_TRUE(generateToPly(options, alone.string()));
    Result<TriangleMesh> plain = generateMesh(options);
    Result<TriangleMesh> teed = generateMesh(options, both.string());
    ASSERT_TRUE(plain && teed) << teed.message();
    EXPECT_EQ(teed->positions, plain->positions);
    EXPECT_EQ(teed->indices, plain->indices);
    EXPECT_EQ(teed->materials.size(), plain->materials.size());
    EXPECT_EQ(readAll(both), readAll(alone));
    // A bad PLY path fails the mesh too, naming the path, and leaves no file.
    const std::string bad = (tmpDir() / "mesh.obj").string();
    Result<TriangleMesh> refused = generateMesh(options, bad);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.message().find(bad), std::string::npos) << refused.message();
    EXPECT_FALSE(fs::exists(bad));
    fs::remove(alone), fs::remove(both);
}

TEST(PlyOutput, WrongExtensionIsAnErrorNamingThePath) {
    const std::string path = (tmpDir() / "mesh.obj").string();
    Status status = generateToPly({}, path);
    ASSERT_FALSE(status);
    EXPECT_NE(status.message().find(path), std::string::npos) << status.message();
    EXPECT_FALSE(fs::exists(path));
}

TEST(PlyOutput, MissingFolderIsAnErrorNamingThePath) {
    const std::string path = (tmpDir() / "no" / "such" / "folder" / "mesh.ply").string();
    Status status = generateToPly({GeneratorKind::Sphere, 20, 1}, path);
    ASSERT_FALSE(status);
    EXPECT_NE(status.message().find(path), std::string::npos) << status.message();
}

TEST(PlyOutput, InvalidOptionsCreateNoFile) {
    const fs::path path = tmpDir() / "invalid.ply";
    fs::remove(path);
    EXPECT_FALSE(generateToPly({GeneratorKind::City, 3, 1}, path.string()));
    EXPECT_FALSE(fs::exists(path));
    EXPECT_FALSE(fs::exists(path.string() + ".tmp"));
}

TEST(PlyOutput, FullDiskKeepsTheOldFileAndRemovesTheTemporary) {
    if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full to simulate a full disk";
    const fs::path path = tmpDir() / "full.ply";
    const std::string tmp = path.string() + ".tmp";
    std::ofstream(path) << "previous contents";
    fs::remove(tmp);
    fs::create_symlink("/dev/full", tmp);  // writes to the temporary fail with ENOSPC

    Status status = generateToPly({GeneratorKind::Sphere, 20000, 1}, path.string());
    ASSERT_FALSE(status);
    EXPECT_NE(status.message().find(path.string()), std::string::npos) << status.message();
    EXPECT_EQ(readAll(path), "previous contents");
    EXPECT_FALSE(fs::is_symlink(tmp));
    EXPECT_TRUE(fs::exists("/dev/full"));
}

}  // namespace
}  // namespace vastray::test
