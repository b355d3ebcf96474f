// The importer fuzz targets' seeds (fuzz/corpus), replayed as the targets read them: each
// imports or fails by name. `make fuzz` mutates them under ASan/UBSan; this keeps the seeds
// themselves honest in every `make test`.
#include "ImportTestFiles.h"

#include <fstream>
#include <iterator>
#include <sstream>

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

}  // namespace
}  // namespace vastray::test
