// Basis Universal KTX2 files written by Binomial's own encoder (basisu 2.50, the commit of
// third_party/basisu; docs/HARDENING.md "Fuzzing", fuzz_ktx2, says how), read through the vendored
// transcoder: ETC1S (BasisLZ, with an alpha slice) and UASTC with Zstandard, both lossy encodings
// of one 20 x 12 RGBA gradient whose texels are known.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iterator>

#include "vastray/core/ImageFile.h"

namespace vastray::test {
namespace {

// The gradient the samples encode, as a 20 x 12 RGBA PNG given to the encoder.
int gradient(uint32_t x, uint32_t y, int channel) {
    const int c[4] = {int(x) * 12, int(y) * 20, 128, 255 - int(x) * 8};
    return c[channel];
}

std::vector<uint8_t> sample(const std::string& name) {
    std::ifstream file(std::string(VASTRAY_FUZZ_CORPUS) + "/ktx2/" + name, std::ios::binary);
    return std::vector<uint8_t>((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
}

// Per channel (R, G, B, A): the mean and the largest absolute difference from the gradient.
struct Error {
    double mean[4] = {};
    int max[4] = {};
};

Error errorAgainstGradient(const Rgba8Image& image) {
    Error e;
    for (uint32_t y = 0; y < image.height; ++y)
        for (uint32_t x = 0; x < image.width; ++x)
            for (int c = 0; c < 4; ++c) {
                const int d = std::abs(int(image.texels[(size_t(y) * image.width + x) * 4 + size_t(c)]) - gradient(x, y, c));
                e.mean[c] += d;
                e.max[c] = std::max(e.max[c], d);
            }
    for (double& m : e.mean) m /= double(image.width) * image.height;
    return e;
}

TEST(Ktx2BasisSample, EncoderOutputTranscodesToTheGradientItEncodes) {
    const struct {
        const char* file;
        const char* format;
        double meanTolerance;
        int maxTolerance;
    } samples[] = {{"gradient_etc1s.ktx2", "ETC1S", 16, 48}, {"gradient_uastc_zstd.ktx2", "UASTC", 3.5, 4}};
    // Tolerances: what the encodings lose on this steep gradient (measured per channel: ETC1S mean
    // 2.6-14.7, largest 39; UASTC mean 0.9-3.0, largest 3), with some room. Mistakes in the
    // plumbing are far outside them: rows flipped move G by 120 on average, R and B swapped by
    // ~60, alpha lost by 76.
    for (const auto& s : samples) {
        const std::vector<uint8_t> bytes = sample(s.file);
        ASSERT_FALSE(bytes.empty()) << s.file;
        auto d = describeKtx2Image(s.file, bytes);
        ASSERT_TRUE(d) << d.message();
        EXPECT_EQ(d->format, s.format);
        EXPECT_TRUE(d->readable);
        EXPECT_TRUE(d->srgb);  // basisu's default transfer function
        auto image = decodeRgba8Image(s.file, ".ktx2", bytes, 1u << 20);
        ASSERT_TRUE(image) << image.message();
        ASSERT_EQ(image->width, 20u);
        ASSERT_EQ(image->height, 12u);
        const Error e = errorAgainstGradient(*image);
        for (int c = 0; c < 4; ++c) {
            EXPECT_LE(e.mean[c], s.meanTolerance) << s.file << " channel " << c;
            EXPECT_LE(e.max[c], s.maxTolerance) << s.file << " channel " << c;
        }
    }
}

}  // namespace
}  // namespace vastray::test
