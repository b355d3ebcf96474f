// The import's quantization grid (a power-of-two step, origins on the grid) and the device's
// packed positions (QuantizationGrid::packedPosition, 8 bytes a vertex): every position a
// chunk decodes to comes back bit for bit from its 21-bit grid coordinates in fp32, near the
// world's origin and far from it; grids that cannot promise that (an earlier import's, more
// than 20 bits, a scene smaller than its coordinates' float spacing) say so.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <random>

#include "HeaderOffsets.h"
#include "PackageTestUtil.h"
#include "VolumePackageForge.h"
#include "vastray/core/Checksum.h"

namespace vastray::test {
namespace {

bool sameBits(const Vec3f& a, const Vec3f& b) {
    for (int axis = 0; axis < 3; ++axis)
        if (std::bit_cast<uint32_t>(a[axis]) != std::bit_cast<uint32_t>(b[axis])) return false;
    return true;
}

// Grid coordinates all over the grid (both ends too) dequantize to positions that pack exactly.
void expectEveryPositionPacks(const QuantizationGrid& grid, const std::string& what) {
    ASSERT_TRUE(grid.packsPositions()) << what;
    const int32_t top = int32_t((1u << grid.bits) - 1);
    std::mt19937 random(7);
    std::uniform_int_distribution<int32_t> any(0, top);
    uint64_t failures = 0;
    for (int n = 0; n < 20000; ++n) {
        int32_t words[3] = {any(random), any(random), any(random)};
        if (n < 8) words[0] = n & 1 ? top : 0, words[1] = n & 2 ? top : 0, words[2] = n & 4 ? top : 0;
        const Vec3f p = grid.position(words);
        const uint64_t packed = grid.packedPosition(p);
        EXPECT_LT(packed, uint64_t(1) << (3 * kPackedPositionBits)) << what;
        if (!sameBits(grid.unpackedPosition(packed), p) || !grid.packsExactly(p)) ++failures;
    }
    EXPECT_EQ(failures, 0u) << what;
}

TEST(PackedPositions, ImportGridsPackEveryPosition) {
    struct Case {
        const char* what;
        Aabb bounds;
    };
    const Case cases[] = {
        {"unit cube", {{0, 0, 0}, {1, 1, 1}}},
        {"around the origin", {{-4, -0.5f, -3}, {4, 2.5f, 3}}},
        {"a city 100 m wide 60 km from the origin", {{60000, 10, -60100}, {60100, 80, -60000}}},
        {"a part 1 mm wide 1 km away", {{1000, 1000, -1000.001f}, {1000.001f, 1000.001f, -1000}}},
        {"a planet", {{-6.4e6f, -6.4e6f, -6.4e6f}, {6.4e6f, 6.4e6f, 6.4e6f}}},
        {"flat in y", {{-2, 5, -2}, {2, 5, 2}}},
        {"tiny", {{1e-30f, 2e-30f, 3e-30f}, {2e-30f, 3e-30f, 4e-30f}}},
    };
    for (const Case& c : cases) {
        const QuantizationGrid grid = QuantizationGrid::forBounds(c.bounds, 20);
        int exponent = 0;
        EXPECT_EQ(std::frexp(grid.step(), &exponent), 0.5) << c.what << ": the step is a power of two";
        const double extent = std::max({double(c.bounds.extent().x), double(c.bounds.extent().y),
                                        double(c.bounds.extent().z)});
        if (extent > 0) {
            EXPECT_LE(grid.step(), 2.0 * extent / double((1u << 20) - 3)) << c.what << ": at most twice as coarse";
        }
        for (int axis = 0; axis < 3; ++axis) {
            EXPECT_LE(grid.origin[axis], c.bounds.lo[axis]) << c.what;
            EXPECT_GT(grid.origin[axis] + grid.step(), c.bounds.lo[axis]) << c.what;
            // The bounds land on the grid without clamping: within half a step.
            for (float v : {c.bounds.lo[axis], c.bounds.hi[axis]}) {
                const int32_t q = grid.quantize(v, axis);
                EXPECT_LT(q, int32_t((1u << 20) - 1)) << c.what;
                EXPECT_LE(std::fabs(double(grid.dequantize(q, axis)) - v),
                          grid.step() / 2 + std::ldexp(std::fabs(double(v)), -23))
                    << c.what << " axis " << axis;
            }
        }
        expectEveryPositionPacks(grid, c.what);
    }
    // Fewer bits pack too.
    expectEveryPositionPacks(QuantizationGrid::forBounds({{-3, -3, -3}, {7, 1, 2}}, 12), "12 bits");
    expectEveryPositionPacks(QuantizationGrid::forBounds({{-3, -3, -3}, {7, 1, 2}}, 3), "3 bits");
}

TEST(PackedPositions, GridsThatCannotPackSayNo) {
    const Aabb box{{-1, -1, -1}, {3, 2, 1}};
    EXPECT_FALSE(QuantizationGrid::forBounds(box, 0).packsPositions()) << "lossless";
    EXPECT_FALSE(QuantizationGrid::forBounds(box, 21).packsPositions()) << "21 bits leave no margin";
    EXPECT_FALSE(QuantizationGrid::forBounds(box, 30).packsPositions());
    // An earlier import's grid: origin at the bounds, step = extent / (2^20 - 1).
    QuantizationGrid earlier;
    earlier.bits = 20;
    earlier.origin[0] = -1, earlier.origin[1] = -1, earlier.origin[2] = -1;
    earlier.range = 4;
    EXPECT_FALSE(earlier.packsPositions()) << "step not a power of two";
    QuantizationGrid offGrid = QuantizationGrid::forBounds(box, 20);
    offGrid.origin[1] += offGrid.step() / 2;
    EXPECT_FALSE(offGrid.packsPositions()) << "an origin between grid points";
    QuantizationGrid notFloat = QuantizationGrid::forBounds(box, 20);
    notFloat.origin[2] = 0.1;  // not a float
    EXPECT_FALSE(notFloat.packsPositions());
    // A scene smaller than the float spacing of its coordinates (64 at 1e9): 16 wide does not
    // pack, 256 wide (four spacings) does.
    const QuantizationGrid speck = QuantizationGrid::forBounds({{1e9f, 1e9f, 1e9f}, {1e9f, 1e9f, 1e9f + 16}}, 20);
    const QuantizationGrid grain = QuantizationGrid::forBounds({{1e9f, 1e9f, 1e9f}, {1e9f, 1e9f, 1e9f + 256}}, 20);
    expectEveryPositionPacks(grain, "four float spacings wide");
    EXPECT_FALSE(speck.packsPositions());
    // A position that is not a grid point, and a NaN, do not pack exactly.
    const QuantizationGrid grid = QuantizationGrid::forBounds(box, 20);
    ASSERT_TRUE(grid.packsPositions());
    EXPECT_FALSE(grid.packsExactly({0.1f + float(grid.step()) / 3, 0, 0}));
    EXPECT_FALSE(grid.packsExactly({std::nanf(""), 0, 0}));
    EXPECT_FALSE(grid.packsExactly({-5, 0, 0})) << "below the origin";
}

// What a package's chunks decode to packs exactly, whichever codec wrote them.
TEST(PackedPositions, EveryDecodedVertexPacks) {
    for (GeometryCodec codec : {GeometryCodec::Draco, GeometryCodec::Meshopt}) {
        const std::string name = geometryCodecName(codec);
        auto city = smallCity(codec, "packed-city");
        ASSERT_TRUE(city);
        const QuantizationGrid& grid = city->info().grid;
        ASSERT_TRUE(grid.packsPositions()) << name;
        uint64_t vertices = 0, failures = 0;
        for (const ChunkInfo& c : city->info().chunks) {
            auto chunk = city->readChunk(c.id);
            ASSERT_TRUE(chunk) << chunk.message();
            for (const Vec3f& p : chunk->positions) failures += !grid.packsExactly(p), ++vertices;
        }
        EXPECT_GT(vertices, 3000u);
        EXPECT_EQ(failures, 0u) << name;
    }
}

// A forged header whose grid has fewer bits than the chunks' coordinates use: the reader refuses
// the chunk, naming the vertex, its coordinate and the grid, instead of dequantizing it off the
// grid (where the device's packed positions could not follow).
TEST(PackedPositions, CoordinatesBeyondTheGridAreRefused) {
    auto city = smallCity(GeometryCodec::Meshopt, "beyond-grid-city");
    ASSERT_TRUE(city);
    const std::string path = tempPath("beyond-grid-city-meshopt.vast"), forged = tempPath("beyond-grid-forged.vast");
    std::vector<uint8_t> bytes = fileBytes(path);
    putAt(bytes, kGridBitsAt, uint32_t(12));
    setWord64(bytes, kHeaderChecksumAt, checksum64(bytes.data(), kHeaderChecksumAt));
    writeBytes(forged, bytes);
    auto reader = PackageReader::open(forged);
    ASSERT_TRUE(reader) << reader.message();
    ASSERT_EQ((*reader)->info().grid.bits, 12u);
    uint64_t refused = 0;
    for (const ChunkInfo& c : (*reader)->info().chunks) {
        auto chunk = (*reader)->readChunk(c.id);
        if (chunk) continue;
        ++refused;
        EXPECT_NE(chunk.message().find("is outside the 12-bit grid [0, 4095]"), std::string::npos) << chunk.message();
    }
    EXPECT_GT(refused, 0u);
}

}  // namespace
}  // namespace vastray::test
