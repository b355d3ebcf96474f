// Texture coordinates in the package (format 9, issue 13): both codecs carry them bit for bit
// through a multi-chunk build, UV seams included; a scene without them stores none and counts
// no bytes for them; a format 8 package still opens; hostile UVs are refused by name.
#include "PackageTestUtil.h"
#include "package/PackageFormat.h"
#include "vastray/core/Checksum.h"

namespace vastray::test {
namespace {

using Uv = std::array<float, 2>;

// A grid of `side` x `side` quads whose UVs are an atlas with a seam down the middle column:
// the vertices there are duplicated, the left faces' copy with u = x / side, the right faces'
// with u = x / side + 0.5. Values are chosen to need all 32 bits (thirds, not binary fractions).
TriangleMesh seamGrid(uint32_t side) {
    TriangleMesh mesh;
    mesh.materials = {Material{}};
    const uint32_t seam = side / 2, row = side + 1;
    std::vector<uint32_t> left(row * row), right(row * row);
    for (uint32_t y = 0; y <= side; ++y)
        for (uint32_t x = 0; x <= side; ++x) {
            const Vec3f p{float(x), 0.1f * float((x * 7 + y * 3) % 5), float(y)};
            const float v = float(y) / 3.0f;
            left[y * row + x] = right[y * row + x] = uint32_t(mesh.positions.size());
            mesh.positions.push_back(p);
            mesh.uvs.push_back({float(x) / float(side) / 3.0f, v});
            if (x == seam) {
                right[y * row + x] = uint32_t(mesh.positions.size());
                mesh.positions.push_back(p);
                mesh.uvs.push_back({float(x) / float(side) / 3.0f + 0.5f, -v});
            }
        }
    for (uint32_t y = 0; y < side; ++y)
        for (uint32_t x = 0; x < side; ++x) {
            const std::vector<uint32_t>& s = x < seam ? left : right;
            const uint32_t a = y * row + x, b = a + 1, c = a + row, d = c + 1;
            mesh.indices.insert(mesh.indices.end(), {s[a], s[b], s[d], s[a], s[d], s[c]});
        }
    return mesh;
}

class UvPackage : public ::testing::TestWithParam<GeometryCodec> {
protected:
    std::string name(const std::string& what) const {
        return tempPath(what + "-" + geometryCodecName(GetParam()) + ".vast");
    }
    PackageBuildOptions options() const {
        PackageBuildOptions o;
        o.codec = GetParam();
        o.chunkSizeBytes = kMinChunkSizeBytes;  // several chunks: the seam crosses cells
        return o;
    }
};

// Every decoded corner carries the UV its triangle had at that corner in the input, bit for bit
// (positions are quantized, so corners are matched by their place in the input triangle's
// winding: the decoded face keeps it, perhaps rotated).
TEST_P(UvPackage, UvsRoundTripBitForBitAcrossChunksAndSeams) {
    const TriangleMesh mesh = seamGrid(48);
    auto reader = buildAndOpen(mesh, name("uv-seam"), options());
    ASSERT_TRUE(reader);
    const PackageInfo& info = reader->info();
    EXPECT_TRUE(info.hasUvs);
    EXPECT_EQ(info.formatVersion, format::kVersion);
    ASSERT_GT(info.chunks.size(), 1u);
    for (const ChunkInfo& c : info.chunks) {
        auto chunk = reader->readChunk(c.id);
        ASSERT_TRUE(chunk) << chunk.message();
        ASSERT_EQ(chunk->uvs.size(), chunk->positions.size());
        EXPECT_EQ(c.residentBytes, chunk->residentBytes()) << "the directory counts 8 bytes a vertex for UVs";
        for (size_t t = 0; t < chunk->primitiveIds.size(); ++t) {
            const uint32_t* in = &mesh.indices[3 * size_t(chunk->primitiveIds[t])];
            std::array<Uv, 3> expected{mesh.uvs[in[0]], mesh.uvs[in[1]], mesh.uvs[in[2]]};
            std::array<Uv, 3> got;
            for (int k = 0; k < 3; ++k) got[k] = chunk->uvs[chunk->indices[3 * t + k]];
            bool rotated = false;
            for (int r = 0; r < 3 && !rotated; ++r)
                rotated = std::memcmp(got[0].data(), expected[r].data(), 8) == 0 &&
                          std::memcmp(got[1].data(), expected[(r + 1) % 3].data(), 8) == 0 &&
                          std::memcmp(got[2].data(), expected[(r + 2) % 3].data(), 8) == 0;
            ASSERT_TRUE(rotated) << "chunk " << c.id << " triangle " << t << " (primitive " << chunk->primitiveIds[t]
                                 << ") lost its corners' UVs";
        }
    }
}

// A scene without UVs: the header bit is clear, no chunk carries any, and the directory's resident
// bytes are those of positions, indices, ids and BVH alone.
TEST_P(UvPackage, MeshWithoutUvsStoresNone) {
    TriangleMesh mesh = seamGrid(48);
    mesh.uvs.clear();
    auto reader = buildAndOpen(mesh, name("uv-none"), options());
    ASSERT_TRUE(reader);
    EXPECT_FALSE(reader->info().hasUvs);
    for (const ChunkInfo& c : reader->info().chunks) {
        auto chunk = reader->readChunk(c.id);
        ASSERT_TRUE(chunk) << chunk.message();
        EXPECT_TRUE(chunk->uvs.empty());
        EXPECT_EQ(c.residentBytes, chunk->positions.size() * 12 + chunk->indices.size() * 4 +
                                       chunk->primitiveIds.size() * 4 + chunk->bvh.nodes.size() * sizeof(Bvh4Node));
    }
}

// The package reader holds decoded UVs to the importers' rule: a package written with a NaN or a
// too large UV (what a forger or another writer could produce) fails to read that chunk, named.
TEST_P(UvPackage, HostileUvsInAChunkAreRefusedByName) {
    for (float bad : {std::numeric_limits<float>::quiet_NaN(), 2e6f}) {
        TriangleMesh mesh = seamGrid(4);
        mesh.uvs[5][1] = bad;
        auto reader = buildAndOpen(mesh, name("uv-hostile"), options());
        ASSERT_TRUE(reader);
        const std::vector<std::string> problems = reader->verify();
        ASSERT_EQ(problems.size(), 1u);
        EXPECT_NE(problems[0].find("uv-hostile-"), std::string::npos) << problems[0];
        EXPECT_NE(problems[0].find(": chunk 0: vertex "), std::string::npos) << problems[0];
        EXPECT_NE(problems[0].find(std::string(bad > 0 ? ", 2000000)" : ", nan)") + " is not finite or beyond +-1e6"),
                  std::string::npos)
            << problems[0];
    }
}

INSTANTIATE_TEST_SUITE_P(Codecs, UvPackage, ::testing::Values(GeometryCodec::Draco, GeometryCodec::Meshopt),
                         [](const auto& info) { return std::string(geometryCodecName(info.param)); });

// A format 8 package (the fuzz corpus' coated.vast) reads as it did: no UVs. One that claims
// them, resealed, is refused: version 8 had no such bit.
TEST(UvPackageFormat, VersionEightStillReadsAndCannotClaimUvs) {
    const std::string seed = std::string(VASTRAY_FUZZ_CORPUS) + "/vast/coated.vast";
    auto reader = PackageReader::open(seed);
    ASSERT_TRUE(reader) << reader.message();
    EXPECT_EQ((*reader)->info().formatVersion, 8u);
    EXPECT_FALSE((*reader)->info().hasUvs);
    EXPECT_TRUE((*reader)->verify().empty());

    std::vector<uint8_t> bytes = readFile(seed);
    constexpr size_t kFlagsAt = 8 + 4 + 4 + 7 * 8;
    uint32_t flags;
    std::memcpy(&flags, &bytes[kFlagsAt], 4);
    putAt(bytes, kFlagsAt, flags | uint32_t(format::kHasUvs));
    putAt(bytes, format::kHeaderBytes - 8, checksum64(bytes.data(), format::kHeaderBytes - 8));
    const std::string forged = tempPath("v8-with-uvs.vast");
    writeFile(forged, bytes);
    auto refused = PackageReader::open(forged);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.message().find("a version 8 package with the texture coordinate flag"), std::string::npos)
        << refused.message();
}

}  // namespace
}  // namespace vastray::test
