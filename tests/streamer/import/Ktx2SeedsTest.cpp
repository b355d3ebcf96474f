// fuzz_ktx2's seeds (fuzz/corpus/ktx2), replayed as the target reads them: every seed is a valid
// KTX2 file of a kind the reader takes (so that the fuzzer starts from every path: stored and
// Zstandard RGBA8, R8 with a swizzle and an upward orientation, hand-made UASTC, basisu's ETC1S
// and UASTC), and decodes to the texels its sides promise. Under `make test-asan` this is the
// sanitizers' pass over them.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "vastray/core/ImageFile.h"

namespace vastray::test {
namespace {

TEST(Ktx2Seeds, EverySeedDecodes) {
    size_t seeds = 0;
    for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(VASTRAY_FUZZ_CORPUS) / "ktx2")) {
        std::ifstream file(entry.path(), std::ios::binary);
        const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
        const std::string name = entry.path().filename().string();
        auto d = describeKtx2Image(name, bytes);
        ASSERT_TRUE(d) << d.message();
        EXPECT_TRUE(d->readable) << name << ": " << d->format;
        auto image = decodeRgba8Image(name, ".ktx2", bytes, uint64_t(1) << 22);
        ASSERT_TRUE(image) << image.message();
        EXPECT_EQ(image->texels.size(), size_t(image->width) * image->height * 4) << name;
        ++seeds;
    }
    EXPECT_GE(seeds, 6u);
}

}  // namespace
}  // namespace vastray::test
