// Generated scenes must be identical on every machine, compiler and thread count: a bug
// report or a benchmark names a scene by (kind, triangles, seed) alone. These digests were
// recorded once; a change here means every stored scene and golden image changes too, so
// update them only on purpose.
#include <gtest/gtest.h>

#include <cstring>

#include "streamer/generate/RecordingSink.h"

namespace vastray::test {
namespace {

// FNV-1a over the raw bytes of the stream (positions as IEEE floats, then indices).
uint64_t digest(const RecordingSink& mesh) {
    uint64_t h = 0xcbf29ce484222325ull;
    auto addBytes = [&h](const void* data, size_t size) {
        const auto* bytes = static_cast<const unsigned char*>(data);
        for (size_t i = 0; i < size; ++i) h = (h ^ bytes[i]) * 0x100000001b3ull;
    };
    for (Vec3f p : mesh.vertices) {
        const float xyz[3] = {p.x, p.y, p.z};
        addBytes(xyz, sizeof xyz);
    }
    for (const auto& f : mesh.faces) addBytes(f.data(), sizeof f);
    return h;
}

TEST(GoldenStream, DigestsMatchTheRecordedOnes) {
    struct Case {
        GeneratorKind kind;
        uint64_t digest;
    };
    for (Case c : {Case{GeneratorKind::Sphere, 0x02f4765012d664f5ull},
                   Case{GeneratorKind::Terrain, 0x52d90153fcf3da7cull},
                   Case{GeneratorKind::Soup, 0x2222df39c2df4343ull},
                   Case{GeneratorKind::City, 0xd8e7df8b64f47049ull}}) {
        // Large enough that terrain and soup span several parallel batches.
        RecordingSink mesh = record(c.kind, 300'000, 1);
        EXPECT_EQ(digest(mesh), c.digest) << generatorKindName(c.kind) << " 0x" << std::hex << digest(mesh);
    }
}

}  // namespace
}  // namespace vastray::test
