// The chunk geometry codecs on their own: exact round trip of the words; damaged or forged
// meshopt streams give an error (or some geometry that the blob reader then bounds), never a
// crash or an allocation sized by a forged count.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <string>
#include <vector>

#include "package/ChunkCodec.h"

namespace vastray::test {
namespace {

// A small grid of quads with chunk-relative words spanning `bits` bits.
ChunkGeometry gridGeometry(uint32_t side, uint32_t bits) {
    ChunkGeometry g;
    const int32_t step = int32_t(((1u << bits) - 1) / side);
    for (uint32_t y = 0; y <= side; ++y)
        for (uint32_t x = 0; x <= side; ++x)
            g.vertexWords.insert(g.vertexWords.end(), {1000 + int32_t(x) * step, 5 + int32_t((x * y) % 7), int32_t(y) * step});
    for (uint32_t y = 0; y < side; ++y)
        for (uint32_t x = 0; x < side; ++x) {
            const uint32_t a = y * (side + 1) + x, b = a + 1, c = a + side + 1, d = c + 1;
            g.indices.insert(g.indices.end(), {a, b, d, a, d, c});
        }
    return g;
}

// Triangles as corner words, smallest corner first (rotation-invariant, winding kept), sorted.
std::vector<std::array<int32_t, 9>> canonical(const ChunkGeometry& g) {
    std::vector<std::array<int32_t, 9>> out(g.indices.size() / 3);
    for (size_t t = 0; t < out.size(); ++t) {
        std::array<std::array<int32_t, 3>, 3> c;
        for (int k = 0; k < 3; ++k) std::memcpy(c[k].data(), &g.vertexWords[3 * size_t(g.indices[3 * t + k])], 12);
        const int first = int(std::min_element(c.begin(), c.end()) - c.begin());
        for (int k = 0; k < 3; ++k) std::memcpy(&out[t][3 * k], c[(first + k) % 3].data(), 12);
    }
    std::sort(out.begin(), out.end());
    return out;
}

struct Case {
    GeometryCodec codec;
    uint32_t bits;  // 0: lossless (float bit patterns)
};

class ChunkCodecTest : public ::testing::TestWithParam<Case> {};

TEST_P(ChunkCodecTest, RoundTripKeepsEveryTriangleAndItsWinding) {
    const Case c = GetParam();
    ChunkGeometry input = gridGeometry(40, c.bits ? c.bits : 20);
    if (c.bits == 0)
        for (int32_t& w : input.vertexWords) {
            const float f = -3.5f + float(w) * 1e-4f;  // negative and positive floats
            std::memcpy(&w, &f, 4);
        }
    auto encoded = encodeChunkGeometry(input, c.bits == 0, c.codec, 5);
    ASSERT_TRUE(encoded.isOk()) << encoded.message();
    auto decoded = decodeChunkGeometry(encoded->data(), encoded->size(), c.bits == 0, c.codec);
    ASSERT_TRUE(decoded.isOk()) << decoded.message();
    for (uint32_t i : decoded->indices) ASSERT_LT(size_t(i) * 3, decoded->vertexWords.size());
    EXPECT_EQ(canonical(*decoded), canonical(input));
}

INSTANTIATE_TEST_SUITE_P(Codecs, ChunkCodecTest,
                         ::testing::Values(Case{GeometryCodec::Draco, 16}, Case{GeometryCodec::Draco, 0},
                                           Case{GeometryCodec::Meshopt, 12}, Case{GeometryCodec::Meshopt, 24},
                                           Case{GeometryCodec::Meshopt, 0}),
                         [](const auto& info) {
                             return std::string(geometryCodecName(info.param.codec)) +
                                    (info.param.bits ? std::to_string(info.param.bits) + "bits" : "lossless");
                         });

// Normals, colours and texture coordinates come back on the vertex they were given with (UVs bit
// for bit), whatever order the codec puts vertices in (and vertices Draco splits keep them): the
// test's vertex words are unique, so each decoded vertex names its input vertex.
TEST_P(ChunkCodecTest, AttributesFollowTheirVertices) {
    const Case c = GetParam();
    ChunkGeometry input = gridGeometry(24, c.bits ? c.bits : 20);
    const size_t vertices = input.vertexWords.size() / 3;
    for (size_t v = 0; v < vertices; ++v) {
        input.normals.push_back(uint32_t(v * 2654435761u) ^ 0x1234u);
        input.colors.push_back(uint32_t(v * 40503u) | 0xFF000000u);
        input.uvs.push_back({float(v) * 0.37f - 3.0f, 1.0f / float(v + 1)});
    }
    for (int mask = 0; mask < 8; ++mask) {  // every subset of normals, colours and UVs
        const bool normals = mask & 1, colors = mask & 2, uvs = mask & 4;
        ChunkGeometry g = input;
        if (!normals) g.normals.clear();
        if (!colors) g.colors.clear();
        if (!uvs) g.uvs.clear();
        auto encoded = encodeChunkGeometry(g, c.bits == 0, c.codec, 5);
        ASSERT_TRUE(encoded.isOk()) << encoded.message();
        auto decoded =
            decodeChunkGeometry(encoded->data(), encoded->size(), c.bits == 0, c.codec, {normals, colors, uvs});
        ASSERT_TRUE(decoded.isOk()) << decoded.message();
        const size_t n = decoded->vertexWords.size() / 3;
        ASSERT_EQ(decoded->normals.size(), normals ? n : 0);
        ASSERT_EQ(decoded->colors.size(), colors ? n : 0);
        ASSERT_EQ(decoded->uvs.size(), uvs ? n : 0);
        for (size_t d = 0; d < n; ++d) {
            size_t v = 0;
            while (v < vertices && std::memcmp(&input.vertexWords[3 * v], &decoded->vertexWords[3 * d], 12) != 0) ++v;
            ASSERT_LT(v, vertices);
            if (normals) {
                EXPECT_EQ(decoded->normals[d], input.normals[v]) << d;
            }
            if (colors) {
                EXPECT_EQ(decoded->colors[d], input.colors[v]) << d;
            }
            if (uvs) {
                EXPECT_EQ(std::memcmp(decoded->uvs[d].data(), input.uvs[v].data(), 8), 0) << d;
            }
        }
        EXPECT_EQ(canonical(*decoded), canonical(input));
        // A stream asked for an attribute it does not carry is an error, not garbage.
        if (!normals) {
            auto wrong =
                decodeChunkGeometry(encoded->data(), encoded->size(), c.bits == 0, c.codec, {true, colors, uvs});
            EXPECT_FALSE(wrong.isOk());
        }
        if (!uvs) {
            auto wrong =
                decodeChunkGeometry(encoded->data(), encoded->size(), c.bits == 0, c.codec, {normals, colors, true});
            EXPECT_FALSE(wrong.isOk());
        }
    }
}

// Triangles as corner words and UV bits, smallest corner first, sorted: what a face looks like
// to a renderer that reads texture coordinates.
std::vector<std::array<uint32_t, 15>> canonicalWithUvs(const ChunkGeometry& g) {
    std::vector<std::array<uint32_t, 15>> out(g.indices.size() / 3);
    for (size_t t = 0; t < out.size(); ++t) {
        std::array<std::array<uint32_t, 5>, 3> c;
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = g.indices[3 * t + k];
            std::memcpy(c[k].data(), &g.vertexWords[3 * size_t(i)], 12);
            std::memcpy(c[k].data() + 3, g.uvs[i].data(), 8);
        }
        const int first = int(std::min_element(c.begin(), c.end()) - c.begin());
        for (int k = 0; k < 3; ++k) std::memcpy(&out[t][5 * k], c[(first + k) % 3].data(), 20);
    }
    std::sort(out.begin(), out.end());
    return out;
}

// A UV seam: the grid's middle column of positions is there twice, once with the left half's
// UVs and once with the right half's (as a cylinder's wrap or an atlas cut has it). Both codecs
// must keep each face's own corners: two faces sharing a position keep different UVs. The UVs
// include values a lossy path would round: -0, a denormal, 1e6 and non-representable decimals.
TEST_P(ChunkCodecTest, UvSeamsSurviveBitForBit) {
    const Case c = GetParam();
    constexpr uint32_t kSide = 8, kSeam = kSide / 2;
    ChunkGeometry g;
    auto vertex = [&](uint32_t x, uint32_t y, float u) {
        g.vertexWords.insert(g.vertexWords.end(), {int32_t(100 + 37 * x), int32_t(9 + x * y % 5), int32_t(100 + 41 * y)});
        g.uvs.push_back({u, float(y) * 0.1f});
        return uint32_t(g.uvs.size() - 1);
    };
    std::vector<uint32_t> left((kSide + 1) * (kSide + 1)), right((kSide + 1) * (kSide + 1));
    for (uint32_t y = 0; y <= kSide; ++y)
        for (uint32_t x = 0; x <= kSide; ++x) {
            const uint32_t at = y * (kSide + 1) + x;
            left[at] = right[at] = vertex(x, y, x == 0 ? -0.0f : float(x) * 0.1f);
            if (x == kSeam) right[at] = vertex(x, y, y == 0 ? 1.0e-40f : y == 1 ? 1e6f : 0.9f + float(y) * 0.01f);
        }
    for (uint32_t y = 0; y < kSide; ++y)
        for (uint32_t x = 0; x < kSide; ++x) {
            const std::vector<uint32_t>& side = x < kSeam ? left : right;
            const uint32_t a = y * (kSide + 1) + x, b = a + 1, cc = a + kSide + 1, d = cc + 1;
            g.indices.insert(g.indices.end(), {side[a], side[b], side[d], side[a], side[d], side[cc]});
        }
    if (c.bits == 0)  // lossless words are float bits; these integers are valid (tiny) floats
        for (int32_t& w : g.vertexWords) w += 0x3F800000;
    auto encoded = encodeChunkGeometry(g, c.bits == 0, c.codec, 5);
    ASSERT_TRUE(encoded.isOk()) << encoded.message();
    auto decoded = decodeChunkGeometry(encoded->data(), encoded->size(), c.bits == 0, c.codec, {false, false, true});
    ASSERT_TRUE(decoded.isOk()) << decoded.message();
    ASSERT_EQ(decoded->uvs.size(), decoded->vertexWords.size() / 3);
    EXPECT_EQ(canonicalWithUvs(*decoded), canonicalWithUvs(g));
}

// meshoptimizer's decoders validate their input: every single-byte flip or truncation of a
// meshopt stream decodes to an error or to some geometry, never a crash. (Draco streams are
// only decoded after the package's XXH64 has matched.)
TEST(ChunkCodecMeshopt, DamagedStreamsAreErrorsNotCrashes) {
    for (uint32_t bits : {12u, 24u, 0u}) {
        ChunkGeometry input = gridGeometry(12, bits ? bits : 20);
        auto encoded = encodeChunkGeometry(input, bits == 0, GeometryCodec::Meshopt, 5);
        ASSERT_TRUE(encoded.isOk()) << encoded.message();
        const std::vector<uint8_t> pristine = *encoded;
        size_t errors = 0;
        for (size_t at = 0; at < pristine.size(); ++at) {
            std::vector<uint8_t> damaged = pristine;
            damaged[at] ^= 0xA5;
            auto decoded = decodeChunkGeometry(damaged.data(), damaged.size(), bits == 0, GeometryCodec::Meshopt);
            if (!decoded) ++errors;
        }
        // No checksum inside the codec (the package's XXH64 catches damage first): not every
        // flip is detectable here, but the prefix and stream headers are.
        EXPECT_GT(errors, 0u) << bits << " bits";
        for (size_t size : {size_t(0), size_t(16), size_t(27), pristine.size() / 2, pristine.size() - 1}) {
            auto decoded = decodeChunkGeometry(pristine.data(), size, bits == 0, GeometryCodec::Meshopt);
            EXPECT_FALSE(decoded.isOk()) << "truncated to " << size << " of " << pristine.size();
        }
    }
}

// A meshopt prefix claiming billions of indices or vertices is refused before allocating.
TEST(ChunkCodecMeshopt, ForgedCountsAreRefusedBeforeAllocating) {
    auto encoded = encodeChunkGeometry(gridGeometry(8, 12), false, GeometryCodec::Meshopt, 5);
    ASSERT_TRUE(encoded.isOk());
    for (size_t field : {size_t(12), size_t(16)}) {  // vertex count, index count (after the 3 x int32 minimum)
        std::vector<uint8_t> forged = *encoded;
        const uint32_t huge = 0xFFFFFFF0u;
        std::memcpy(&forged[field], &huge, 4);
        auto decoded = decodeChunkGeometry(forged.data(), forged.size(), false, GeometryCodec::Meshopt);
        ASSERT_FALSE(decoded.isOk());
        EXPECT_NE(decoded.message().find("bad meshopt prefix"), std::string::npos) << decoded.message();
    }
}

TEST(ChunkCodecNames, ParseAndPrint) {
    EXPECT_EQ(*parseGeometryCodec("draco"), GeometryCodec::Draco);
    EXPECT_EQ(*parseGeometryCodec("meshopt"), GeometryCodec::Meshopt);
    EXPECT_STREQ(geometryCodecName(GeometryCodec::Meshopt), "meshopt");
    auto bad = parseGeometryCodec("zstd");
    ASSERT_FALSE(bad.isOk());
    EXPECT_NE(bad.message().find("draco or meshopt"), std::string::npos);
}

}  // namespace
}  // namespace vastray::test
