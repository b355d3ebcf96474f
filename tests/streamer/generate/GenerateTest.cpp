// Properties every generator kind must have: exact announced counts, valid indices, no
// degenerate triangle, determinism per seed, and options validated with clear messages.
#include <gtest/gtest.h>

#include <chrono>

#include "streamer/generate/RecordingSink.h"

namespace vastray::test {
namespace {

const GeneratorKind kAllKinds[] = {GeneratorKind::Sphere, GeneratorKind::Terrain, GeneratorKind::Soup,
                                   GeneratorKind::City};

class EveryKind : public ::testing::TestWithParam<GeneratorKind> {};

TEST_P(EveryKind, StreamMatchesAnnouncedAndPredictedCounts) {
    for (uint64_t n : {20u, 21u, 333u, 5000u, 12345u}) {
        RecordingSink mesh = record(GetParam(), n);
        Result<GeneratedCounts> counts = generatedCounts({GetParam(), n, 1});
        ASSERT_TRUE(counts) << counts.message();
        EXPECT_EQ(mesh.beginCalls, 1);
        EXPECT_EQ(mesh.endCalls, 1);
        EXPECT_EQ(mesh.announcedVertices, counts->vertices);
        EXPECT_EQ(mesh.announcedFaces, counts->triangles);
        EXPECT_EQ(mesh.vertices.size(), counts->vertices);
        EXPECT_EQ(mesh.faces.size(), counts->triangles);
        EXPECT_FALSE(mesh.faceBeforeLastVertex) << "vertices must all come before faces";
    }
}

TEST_P(EveryKind, IndicesInRangeAndNoDegenerateTriangle) {
    RecordingSink mesh = record(GetParam(), 20000);
    for (const auto& f : mesh.faces) {
        for (uint32_t i : f) ASSERT_LT(i, mesh.vertices.size());
        ASSERT_TRUE(f[0] != f[1] && f[1] != f[2] && f[0] != f[2]);
        DVec n = faceNormal(mesh, f);
        ASSERT_GT(dot(n, n), 0.0) << "zero-area triangle " << f[0] << " " << f[1] << " " << f[2];
    }
    for (Vec3f p : mesh.vertices) ASSERT_TRUE(isFinite(p));
}

TEST_P(EveryKind, SameOptionsGiveIdenticalStreams) {
    RecordingSink a = record(GetParam(), 3000, 7), b = record(GetParam(), 3000, 7);
    EXPECT_EQ(a.vertices, b.vertices);  // bit-exact, not approximately equal
    EXPECT_EQ(a.faces, b.faces);
}

TEST_P(EveryKind, CountIsCloseToRequested) {
    // Each kind rounds a grid side to an integer: the sphere's 20 f^2 is within sqrt(20/N)
    // (3.2% at 20000), the city's 10 g^2 within sqrt(10/N); terrain and soup are closer.
    for (uint64_t n : {20000u, 99999u}) {
        Result<GeneratedCounts> counts = generatedCounts({GetParam(), n, 1});
        ASSERT_TRUE(counts);
        EXPECT_NEAR(static_cast<double>(counts->triangles), static_cast<double>(n), 0.035 * n);
    }
}

// Fails the n-th vertex or face call; a generator must stop there and pass the error on
// (that is how a full disk ends a 100M-triangle run early).
struct FailingSink : CountingSink {
    uint64_t failVertex = UINT64_MAX, failFace = UINT64_MAX;
    Status vertex(Vec3f p) override {
        if (vertices == failVertex) return Status::error("sink refused vertex");
        return CountingSink::vertex(p);
    }
    Status face(uint32_t a, uint32_t b, uint32_t c) override {
        if (faces == failFace) return Status::error("sink refused face");
        return CountingSink::face(a, b, c);
    }
};

TEST_P(EveryKind, SinkErrorsStopGenerationAndArePassedOn) {
    FailingSink vertexFails;
    vertexFails.failVertex = 100;
    Status status = generate({GetParam(), 5000, 1}, vertexFails);
    EXPECT_EQ(status.message(), "sink refused vertex");
    EXPECT_EQ(vertexFails.vertices, 100u);
    EXPECT_EQ(vertexFails.faces, 0u);

    FailingSink faceFails;
    faceFails.failFace = 100;
    status = generate({GetParam(), 5000, 1}, faceFails);
    EXPECT_EQ(status.message(), "sink refused face");
    EXPECT_EQ(faceFails.faces, 100u);
}

INSTANTIATE_TEST_SUITE_P(Generate, EveryKind, ::testing::ValuesIn(kAllKinds),
                         [](const auto& info) { return std::string(generatorKindName(info.param)); });

TEST(Generate, DifferentSeedsGiveDifferentScenes) {
    for (GeneratorKind kind : {GeneratorKind::Terrain, GeneratorKind::Soup, GeneratorKind::City}) {
        EXPECT_NE(record(kind, 3000, 1).vertices, record(kind, 3000, 2).vertices) << generatorKindName(kind);
    }
}

TEST(Generate, KindNamesRoundTrip) {
    for (GeneratorKind kind : kAllKinds) {
        Result<GeneratorKind> parsed = parseGeneratorKind(generatorKindName(kind));
        ASSERT_TRUE(parsed);
        EXPECT_EQ(*parsed, kind);
    }
    Result<GeneratorKind> bad = parseGeneratorKind("cube");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.message().find("cube"), std::string::npos);
    EXPECT_NE(bad.message().find("sphere, terrain, soup, city"), std::string::npos);
}

TEST(Generate, TooFewTrianglesIsAnErrorStatingTheMinimum) {
    struct Case {
        GeneratorKind kind;
        uint64_t min;
    };
    for (Case c : {Case{GeneratorKind::Sphere, 20}, Case{GeneratorKind::Terrain, 2},
                   Case{GeneratorKind::Soup, 1}, Case{GeneratorKind::City, 12}}) {
        Result<GeneratedCounts> low = generatedCounts({c.kind, c.min - 1, 1});
        ASSERT_FALSE(low) << generatorKindName(c.kind);
        EXPECT_NE(low.message().find("at least " + std::to_string(c.min)), std::string::npos)
            << low.message();
        EXPECT_TRUE(generatedCounts({c.kind, c.min, 1})) << generatorKindName(c.kind);
        CountingSink sink;
        EXPECT_FALSE(generate({c.kind, c.min - 1, 1}, sink));
    }
}

TEST(Generate, TooManyTrianglesOrVerticesIsAnError) {
    Result<GeneratedCounts> huge = generatedCounts({GeneratorKind::Sphere, 4'000'000'001ull, 1});
    ASSERT_FALSE(huge);
    EXPECT_NE(huge.message().find("at most 4000000000"), std::string::npos) << huge.message();
    // 3 vertices per soup triangle overflow uint32 indices long before 4e9 triangles.
    Result<GeneratedCounts> soup = generatedCounts({GeneratorKind::Soup, 2'000'000'000ull, 1});
    ASSERT_FALSE(soup);
    EXPECT_NE(soup.message().find("uint32"), std::string::npos) << soup.message();
    for (GeneratorKind kind : {GeneratorKind::Sphere, GeneratorKind::Terrain, GeneratorKind::City}) {
        Result<GeneratedCounts> max = generatedCounts({kind, 4'000'000'000ull, 1});
        ASSERT_TRUE(max) << max.message();
        EXPECT_LE(max->vertices, 0xFFFFFFFFull);
    }
}

TEST(Generate, CountsFor100MillionTrianglesAreArithmeticOnly) {
    auto start = std::chrono::steady_clock::now();
    for (GeneratorKind kind : kAllKinds) {
        Result<GeneratedCounts> counts = generatedCounts({kind, 100'000'000, 1});
        ASSERT_TRUE(counts);
        // Within sqrt(20/N) = 0.045% for the coarsest rounding (sphere).
        EXPECT_NEAR(static_cast<double>(counts->triangles), 1e8, 1e8 * 0.0005) << generatorKindName(kind);
    }
    // Generating would take seconds; arithmetic takes microseconds. 100 ms leaves room for a
    // loaded CI machine.
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(100));
}

TEST(Generate, TwoMillionSphereTrianglesIntoACountingSink) {
    CountingSink sink;
    ASSERT_TRUE(generate({GeneratorKind::Sphere, 2'000'000, 1}, sink));
    EXPECT_EQ(sink.vertices, sink.announcedVertices);
    EXPECT_EQ(sink.faces, sink.announcedFaces);
    EXPECT_LT(sink.maxIndex, sink.vertices);
    EXPECT_NEAR(static_cast<double>(sink.faces), 2e6, 2e6 * 0.0035);  // sqrt(20/N) = 0.32%
}

}  // namespace
}  // namespace vastray::test
