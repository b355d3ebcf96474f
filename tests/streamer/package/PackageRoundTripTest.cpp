// Chunk round trip: what a chunk decodes to against what was imported.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "Bvh4Walk.h"
#include "PackageTestUtil.h"

namespace vastray::test {
namespace {

struct DecodedTriangles {
    // primitive id -> canonical corners, from the first chunk that holds it
    std::map<uint32_t, std::array<Vec3f, 3>> corners;
    uint64_t references = 0;
    uint64_t mismatchedDuplicates = 0;  // same triangle decoded differently in two chunks
};

DecodedTriangles decodeAll(const PackageReader& reader) {
    DecodedTriangles out;
    for (const ChunkInfo& info : reader.info().chunks) {
        auto chunk = reader.readChunk(info.id);
        EXPECT_TRUE(chunk.isOk()) << chunk.message();
        if (!chunk) continue;
        // The leaf order the blob stores was applied to the decoded faces.
        expectBvhHoldsItsTriangles(chunk->bvh, chunk->positions, chunk->indices, nullptr);
        for (size_t t = 0; t < chunk->primitiveIds.size(); ++t) {
            const uint32_t* i = &chunk->indices[3 * t];
            const auto c = canonicalCorners(chunk->positions[i[0]], chunk->positions[i[1]], chunk->positions[i[2]]);
            auto [it, inserted] = out.corners.emplace(chunk->primitiveIds[t], c);
            if (!inserted && it->second != c) out.mismatchedDuplicates++;
            out.references++;
        }
    }
    return out;
}

// Each corner of each decoded triangle is within half a grid step (per axis) of the imported
// corner, plus the float rounding of the dequantized value (one ulp of the coordinate).
void expectWithinHalfStep(const TriangleMesh& original, const DecodedTriangles& decoded, double step) {
    size_t checked = 0;
    for (const auto& [id, corners] : decoded.corners) {
        const uint32_t* i = &original.indices[3 * size_t(id)];
        const Vec3f v[3] = {original.positions[i[0]], original.positions[i[1]], original.positions[i[2]]};
        // The decoder may rotate corners; find the rotation that matches best.
        double bestError = 1e30;
        for (int r = 0; r < 3; ++r) {
            double error = 0;
            for (int k = 0; k < 3; ++k)
                for (int axis = 0; axis < 3; ++axis)
                    error = std::max(error, std::abs(double(corners[k][axis]) - v[(k + r) % 3][axis]));
            bestError = std::min(bestError, error);
        }
        const double tolerance = step / 2 + 2 * std::ldexp(1.0, -23) * 4.0;  // coordinates here are |x| <= 4
        EXPECT_LE(bestError, tolerance) << "triangle " << id;
        if (++checked > 100000) break;
    }
}

// Every round-trip case runs with both chunk codecs (import --codec draco|meshopt): 16- and
// 30-bit grids take meshopt's 16- and 32-bit vertex layouts, lossless its float-bit words.
class PackageRoundTrip : public ::testing::TestWithParam<GeometryCodec> {
protected:
    static std::string codecName() { return geometryCodecName(GetParam()); }
};

TEST_P(PackageRoundTrip, QuantizedPositionsWithinHalfStepAndNoCracks) {
    const TriangleMesh mesh = generatedMesh(GeneratorKind::Sphere, 20000);
    const std::string path = tempPath(codecName() + "-roundtrip16.vast");
    PackageBuildOptions options;
    options.codec = GetParam();
    options.chunkSizeBytes = 64 << 10;
    options.quantizeBits = 16;
    auto reader = buildAndOpen(mesh, path, options);
    ASSERT_TRUE(reader);
    EXPECT_EQ(reader->info().codec, GetParam());
    const DecodedTriangles decoded = decodeAll(*reader);
    EXPECT_EQ(decoded.corners.size() + reader->info().collapsedDropped, mesh.triangleCount());
    EXPECT_EQ(decoded.references, reader->info().referenceCount);
    EXPECT_GT(reader->info().duplicatedReferences(), 0u) << "the sphere must straddle cell planes";
    EXPECT_EQ(decoded.mismatchedDuplicates, 0u) << "a triangle shared by two chunks must decode identically";
    expectWithinHalfStep(mesh, decoded, reader->info().grid.step());
}

TEST_P(PackageRoundTrip, LosslessIsExact) {
    const TriangleMesh mesh = generatedMesh(GeneratorKind::Soup, 5000);
    const std::string path = tempPath(codecName() + "-lossless.vast");
    PackageBuildOptions options;
    options.codec = GetParam();
    options.chunkSizeBytes = 64 << 10;
    options.quantizeBits = 0;
    auto reader = buildAndOpen(mesh, path, options);
    ASSERT_TRUE(reader);
    const DecodedTriangles decoded = decodeAll(*reader);
    ASSERT_EQ(decoded.corners.size(), mesh.triangleCount());
    for (const auto& [id, corners] : decoded.corners) {
        const uint32_t* i = &mesh.indices[3 * size_t(id)];
        EXPECT_EQ(corners, canonicalCorners(mesh.positions[i[0]], mesh.positions[i[1]], mesh.positions[i[2]]));
    }
}

TEST_P(PackageRoundTrip, ThirtyBitGridRoundTrips) {
    const TriangleMesh mesh = generatedMesh(GeneratorKind::Terrain, 4000);
    PackageBuildOptions options;
    options.codec = GetParam();
    options.chunkSizeBytes = 64 << 10;
    options.quantizeBits = 30;
    auto reader = buildAndOpen(mesh, tempPath(codecName() + "-bits30.vast"), options);
    ASSERT_TRUE(reader);
    const DecodedTriangles decoded = decodeAll(*reader);
    EXPECT_EQ(decoded.mismatchedDuplicates, 0u);
    expectWithinHalfStep(mesh, decoded, reader->info().grid.step());
}

TEST_P(PackageRoundTrip, CoarseGridDropsAndCountsCollapsedTriangles) {
    const TriangleMesh mesh = generatedMesh(GeneratorKind::Sphere, 20000);
    PackageBuildOptions options;
    options.codec = GetParam();
    options.chunkSizeBytes = 64 << 10;
    options.quantizeBits = 6;  // 63 steps across the sphere: small triangles collapse
    auto reader = buildAndOpen(mesh, tempPath(codecName() + "-bits6.vast"), options);
    ASSERT_TRUE(reader);
    const PackageInfo& info = reader->info();
    EXPECT_GT(info.collapsedDropped, 0u);
    EXPECT_EQ(info.triangleCount + info.collapsedDropped, mesh.triangleCount());
    EXPECT_EQ(decodeAll(*reader).corners.size(), info.triangleCount);
}

TEST_P(PackageRoundTrip, MaterialIdsFollowTheirTriangles) {
    TriangleMesh mesh = generatedMesh(GeneratorKind::City, 3000);
    mesh.materials.resize(3);
    mesh.materialIds.resize(mesh.triangleCount());
    for (size_t t = 0; t < mesh.materialIds.size(); ++t) mesh.materialIds[t] = uint32_t(t * 7 % 3);
    PackageBuildOptions options;
    options.codec = GetParam();
    options.chunkSizeBytes = 32 << 10;
    auto reader = buildAndOpen(mesh, tempPath(codecName() + "-materials.vast"), options);
    ASSERT_TRUE(reader);
    ASSERT_EQ(reader->info().materials.size(), 3u);
    for (const ChunkInfo& info : reader->info().chunks) {
        auto chunk = reader->readChunk(info.id);
        ASSERT_TRUE(chunk.isOk()) << chunk.message();
        ASSERT_EQ(chunk->materialIds.size(), chunk->primitiveIds.size());
        for (size_t t = 0; t < chunk->primitiveIds.size(); ++t)
            EXPECT_EQ(chunk->materialIds[t], chunk->primitiveIds[t] * 7 % 3);
    }
}

// Identical triangles (the same corners listed several times, some through copied vertices)
// are told apart by their ids alone: each id is stored once per cell it overlaps, with its own
// material, and nothing is lost or doubled when the codec's output is matched back.
TEST_P(PackageRoundTrip, IdenticalTrianglesEachKeepTheirOwnId) {
    const TriangleMesh base = generatedMesh(GeneratorKind::Sphere, 2000);
    TriangleMesh mesh = base;
    const uint32_t n = uint32_t(base.triangleCount());
    for (int copy = 1; copy < 3; ++copy)
        for (uint32_t t = 0; t < n; ++t)
            for (int k = 0; k < 3; ++k) {
                uint32_t v = base.indices[3 * size_t(t) + k];
                if (copy == 2) {  // the third copy through vertices of its own
                    v = uint32_t(mesh.positions.size());
                    mesh.positions.push_back(base.positions[base.indices[3 * size_t(t) + k]]);
                }
                mesh.indices.push_back(v);
            }
    mesh.materials.resize(3);
    mesh.materialIds.resize(mesh.triangleCount());
    for (size_t t = 0; t < mesh.materialIds.size(); ++t) mesh.materialIds[t] = uint32_t(t / n);
    PackageBuildOptions options;
    options.codec = GetParam();
    options.chunkSizeBytes = 32 << 10;
    auto reader = buildAndOpen(mesh, tempPath(codecName() + "-identical.vast"), options);
    ASSERT_TRUE(reader);
    ASSERT_GT(reader->info().chunks.size(), 1u);
    std::map<std::pair<uint32_t, uint32_t>, int> storedPerChunk;  // (chunk, id) -> count
    std::vector<int> chunksPerId(mesh.triangleCount(), 0);
    for (const ChunkInfo& info : reader->info().chunks) {
        auto chunk = reader->readChunk(info.id);
        ASSERT_TRUE(chunk.isOk()) << chunk.message();
        for (size_t t = 0; t < chunk->primitiveIds.size(); ++t) {
            const uint32_t id = chunk->primitiveIds[t];
            ASSERT_LT(id, mesh.triangleCount());
            EXPECT_EQ(++storedPerChunk[std::make_pair(info.id, id)], 1) << "id " << id << " twice in chunk " << info.id;
            chunksPerId[id]++;
            EXPECT_EQ(chunk->materialIds[t], id / n);
        }
    }
    const DecodedTriangles decoded = decodeAll(*reader);
    ASSERT_EQ(decoded.corners.size(), mesh.triangleCount());
    EXPECT_EQ(decoded.mismatchedDuplicates, 0u);
    expectWithinHalfStep(mesh, decoded, reader->info().grid.step());
    // The copies of a triangle overlap the same cells.
    for (uint32_t t = 0; t < n; ++t) {
        EXPECT_GE(chunksPerId[t], 1) << t;
        EXPECT_EQ(chunksPerId[t + n], chunksPerId[t]) << t;
        EXPECT_EQ(chunksPerId[t + 2 * n], chunksPerId[t]) << t;
        EXPECT_EQ(decoded.corners.at(t + n), decoded.corners.at(t)) << t;
        EXPECT_EQ(decoded.corners.at(t + 2 * n), decoded.corners.at(t)) << t;
    }
}

TEST_P(PackageRoundTrip, SameInputGivesByteIdenticalPackageWhateverTheThreads) {
    const TriangleMesh mesh = generatedMesh(GeneratorKind::Soup, 6000, 3);
    PackageBuildOptions options;
    options.codec = GetParam();
    options.chunkSizeBytes = 48 << 10;
    options.threads = 1;
    const std::string one = tempPath(codecName() + "-det1.vast"), two = tempPath(codecName() + "-det2.vast");
    ASSERT_TRUE(buildAndOpen(mesh, one, options));
    options.threads = 2;
    ASSERT_TRUE(buildAndOpen(mesh, two, options));
    const auto a = readFile(one), b = readFile(two);
    ASSERT_FALSE(a.empty());
    EXPECT_TRUE(a == b);
    EXPECT_FALSE(std::filesystem::exists(two + ".tmp"));
}

INSTANTIATE_TEST_SUITE_P(Codecs, PackageRoundTrip, ::testing::Values(GeometryCodec::Draco, GeometryCodec::Meshopt),
                         [](const auto& info) { return std::string(geometryCodecName(info.param)); });

TEST(PackageBuild, RejectsBadOptions) {
    const TriangleMesh mesh = generatedMesh(GeneratorKind::Sphere, 2000);
    PackageBuildOptions options;
    options.progress = Progress::Mode::None;
    options.chunkSizeBytes = 1024;
    auto r = buildPackage(mesh, tempPath("bad.vast"), options);
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.message().find("minimum"), std::string::npos) << r.message();
    options.chunkSizeBytes = 1 << 20;
    options.quantizeBits = 31;
    r = buildPackage(mesh, tempPath("bad.vast"), options);
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.message().find("31"), std::string::npos) << r.message();
    options.quantizeBits = 20;
    for (double cap : {-1.0, std::nan(""), 1e9}) {
        options.residentBytesPerTriangle = cap;
        r = buildPackage(mesh, tempPath("bad.vast"), options);
        ASSERT_FALSE(r.isOk()) << cap;
        EXPECT_NE(r.message().find("resident bytes per triangle"), std::string::npos) << r.message();
    }
    EXPECT_FALSE(std::filesystem::exists(tempPath("bad.vast")));
}

TEST(PackageBuild, ChunkSizeTooSmallForOverlappingTrianglesIsAnError) {
    // 3000 large triangles all crossing the centre: no plane separates them.
    TriangleMesh mesh;
    for (uint32_t t = 0; t < 3000; ++t) {
        const float a = float(t) * 0.002f;
        mesh.positions.push_back({-1.0f, std::sin(a), std::cos(a)});
        mesh.positions.push_back({1.0f, -std::sin(a), std::cos(a) * 0.5f});
        mesh.positions.push_back({0.0f, std::cos(a), -std::sin(a)});
        mesh.indices.insert(mesh.indices.end(), {3 * t, 3 * t + 1, 3 * t + 2});
    }
    mesh.materials.push_back({});
    PackageBuildOptions options;
    options.progress = Progress::Mode::None;
    options.chunkSizeBytes = 16 << 10;
    auto r = buildPackage(mesh, tempPath("dense.vast"), options);
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.message().find("--chunk-size"), std::string::npos) << r.message();
}

}  // namespace
}  // namespace vastray::test
