// The importer fuzz targets' seeds (fuzz/corpus), replayed as the targets read them: each
// imports or fails by name. `make fuzz` mutates them under ASan/UBSan; this keeps the seeds
// themselves honest in every `make test`.
#include "ImportTestFiles.h"

#include <fstream>
#include <iterator>
#include <cstring>
#include <sstream>

#include "vastray/streamer/ScenePackage.h"

namespace vastray::test {
namespace {

std::string readAll(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    return bytes.str();
}

TEST(FuzzSeeds, EveryImporterSeedImportsOrFailsByName) {
    const std::filesystem::path corpus = VASTRAY_FUZZ_CORPUS;
    size_t seeds = 0;
    for (const char* kind : {"obj", "ply", "gltf", "glb", "assimp"}) {
        for (const auto& entry : std::filesystem::directory_iterator(corpus / kind)) {
            std::string bytes = readAll(entry.path());
            std::string name = std::string("seed.") + kind;
            if (std::string(kind) == "assimp") {  // fuzz_import_assimp: the first byte picks the format
                ASSERT_FALSE(bytes.empty()) << entry.path();
                name = std::string("seed.") + kAssimpFormats[uint8_t(bytes[0]) % std::size(kAssimpFormats)];
                bytes.erase(0, 1);
            }
            auto r = importMesh(writeFile(name, bytes));
            if (!r.isOk()) {
                EXPECT_EQ(r.message().rfind(name + ": ", 0), 0u) << entry.path() << ": " << r.message();
            }
            ++seeds;
        }
    }
    EXPECT_GT(seeds, 10u);
}

// The seeds of fuzz_import_assimp are valid files of their formats.
TEST(FuzzSeeds, AssimpSeedsImport) {
    for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(VASTRAY_FUZZ_CORPUS) / "assimp")) {
        std::string bytes = readAll(entry.path());
        const std::string name = std::string("valid.") + kAssimpFormats[uint8_t(bytes[0]) % std::size(kAssimpFormats)];
        auto r = importMesh(writeFile(name, bytes.substr(1)));
        ASSERT_TRUE(r.isOk()) << entry.path() << ": " << r.message();
        EXPECT_GE(r->mesh.triangleCount(), 1u) << entry.path();
    }
}

// The package and chunk seeds of fuzz_package and fuzz_chunk are of a format this reader reads
// (a seed of an older format stops at the version check, and the fuzzer never reaches the
// decoders; version 3 seeds still read, volume.vast is version 4 with a volume, volume-bricks.vast
// version 6 with a volume and its emission, volume-leaves.vast version 14 with the same as Fp16
// NanoVDB leaves):
// each package opens and verifies, and each chunk seed is its package's chunk 0 plus the byte
// fuzz_chunk reads as the grid selector. Regenerate them as docs/HARDENING.md says.
TEST(FuzzSeeds, PackageAndChunkSeedsAreOfTheCurrentFormat) {
    const std::filesystem::path corpus = VASTRAY_FUZZ_CORPUS;
    size_t seeds = 0;
    for (const auto& entry : std::filesystem::directory_iterator(corpus / "vast")) {
        auto reader = PackageReader::open(entry.path().string());
        ASSERT_TRUE(reader) << entry.path() << ": " << reader.message();
        const std::vector<std::string> problems = (*reader)->verify();
        EXPECT_TRUE(problems.empty()) << entry.path() << ": " << (problems.empty() ? "" : problems.front());
        auto blob = (*reader)->readChunkBlob(0);
        ASSERT_TRUE(blob) << blob.message();
        const std::filesystem::path chunkSeed = corpus / "chunk" / (entry.path().stem().string() + "-0.blob");
        const std::string bytes = readAll(chunkSeed);
        ASSERT_EQ(bytes.size(), blob->size() + 1) << chunkSeed;
        EXPECT_EQ(0, std::memcmp(bytes.data(), blob->data(), blob->size())) << chunkSeed << " is not chunk 0 of " << entry.path();
        ++seeds;
    }
    EXPECT_EQ(seeds, 18u);  // emissivemap (version 15: emitter records with UVs, a mapped lamp); volume-leaves (version 14: a volume's bricks as NanoVDB Fp16 leaves); coatmap (version 13: a material's coat maps); emissive (version 12: an emitter section); small, coloured (normals and colours), cameras, textured (version 9: UVs); Draco and meshopt; a volume
                            // (version 4) and one read brick by brick with emission (version 6); glossy
                            // (version 5 materials); lights (version 7); coated (version 8 materials:
                            // specular colour and clear coat); texturemap (version 10: two textures,
                            // a material's maps)
}

// Every chunk seed through the decoder as fuzz_chunk feeds it (the directory entry from the
// blob's own counts, the last byte choosing the grid): no crash, and under the sanitizer build
// (scripts/asan-tests.sh) no undefined behaviour. draco-minimum-overflow.blob, found by the
// fuzzer, overflowed a signed addition of the chunk minimum.
TEST(FuzzSeeds, EveryChunkSeedDecodesOrFails) {
    size_t seeds = 0;
    for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(VASTRAY_FUZZ_CORPUS) / "chunk")) {
        const std::string bytes = readAll(entry.path());
        ASSERT_GE(bytes.size(), 25u) << entry.path();
        ChunkInfo info;
        std::memcpy(&info.triangleCount, bytes.data() + 8, 4);
        std::memcpy(&info.vertexCount, bytes.data() + 12, 4);
        std::memcpy(&info.bvhNodeCount, bytes.data() + 16, 4);
        QuantizationGrid grid;
        grid.bits = uint8_t(bytes.back()) % 2 ? 0 : 20;
        const std::vector<uint8_t> blob(bytes.begin(), bytes.end() - 1);
        auto decoded = decodeChunkBlob(blob, info, grid, 4, 1u << 20);
        if (entry.path().filename() == "small-0.blob") {
            EXPECT_TRUE(decoded) << decoded.message();
        }
        ++seeds;
    }
    EXPECT_GE(seeds, 3u);
}

}  // namespace
}  // namespace vastray::test
