// Image files as other tools read them: channel names and types, primid round trip, diff.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>

#include "TestScenes.h"
#include "vastray/core/Camera.h"
#include "vastray/core/EnvironmentMap.h"
#include "vastray/core/ImageDiff.h"
#include "vastray/core/ImageFile.h"
#include "vastray/core/RenderOptions.h"

namespace vastray {
namespace {

RenderImage gradientImage(uint32_t aovs, float scale = 1.0f) {
    RenderImage image;
    image.allocate(8, 4, aovs);
    for (uint32_t p = 0; p < image.pixelCount(); ++p) {
        for (int c = 0; c < 3; ++c) image.rgb[3 * p + c] = scale * 0.1f * float(p % 7 + c);
        image.alpha[p] = 1.0f;
        if (aovs & kAovDepth) image.depth[p] = p % 5 == 0 ? INFINITY : 1.0f + float(p);
        if (aovs & kAovPrimId) image.primId[p] = p % 5 == 0 ? kMissPrimId : 0xFFFFFF00u + p;  // above 2^24
        if (aovs & kAovNormal) image.normal[3 * p + 2] = 1.0f;
        if (aovs & kAovAlbedo) image.albedo[3 * p] = 0.5f;
    }
    return image;
}

constexpr uint32_t kAllAovs = kAovDepth | kAovNormal | kAovAlbedo | kAovPrimId;

TEST(ImageFile, ExrHasTheDocumentedChannelsAndTypes) {
    const std::string path = test::tmpPath("aovs.exr");
    ASSERT_TRUE(writeImageFile(path, gradientImage(kAllAovs)));
    auto in = OIIO::ImageInput::open(path);
    ASSERT_TRUE(in);
    const OIIO::ImageSpec& spec = in->spec();
    // EXR stores channels sorted by name, so the set is the contract, not the order.
    std::vector<std::string> names = spec.channelnames,
                             expected{"R",   "G",   "B",        "A",        "Z",        "N.x",
                                      "N.y", "N.z", "albedo.R", "albedo.G", "albedo.B", "primid"};
    std::sort(names.begin(), names.end());
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(names, expected);
    for (int c = 0; c < spec.nchannels; ++c)
        EXPECT_EQ(spec.channelformat(c),
                  spec.channelnames[c] == "primid" ? OIIO::TypeDesc::UINT32 : OIIO::TypeDesc::FLOAT)
            << spec.channelnames[c];
}

TEST(ImageFile, PrimIdsAboveFloatPrecisionSurviveTheRoundTrip) {
    const RenderImage image = gradientImage(kAllAovs);
    const std::string path = test::tmpPath("primid.exr");
    ASSERT_TRUE(writeImageFile(path, image));
    auto in = OIIO::ImageInput::open(path);
    ASSERT_TRUE(in);
    const auto& names = in->spec().channelnames;
    const int channel = int(std::find(names.begin(), names.end(), "primid") - names.begin());
    std::vector<uint32_t> ids(image.pixelCount());
    ASSERT_TRUE(in->read_image(0, 0, channel, channel + 1, OIIO::TypeDesc::UINT32, ids.data()));
    EXPECT_EQ(ids, image.primId);
}

// The camera goes into the EXR header as OpenEXR's worldToCamera and worldToNDC (checked by
// their names in the file, through OIIO's raw attribute list) and comes back unchanged.
TEST(ImageFile, ExrRecordsTheCameraMatrices) {
    RenderImage image = gradientImage(kAovNone);
    recordCamera(image, Camera{{1, 2, 3}, {-2, 0.5f, 1}, {0, 1, 0}, 40}, image.width, image.height);
    const std::string path = test::tmpPath("camera.exr");
    ASSERT_TRUE(writeImageFile(path, image));
    auto stored = readStoredImage(path);
    ASSERT_TRUE(stored) << stored.message();
    ASSERT_TRUE(stored->hasCamera);
    EXPECT_EQ(stored->worldToCamera, image.worldToCamera);
    EXPECT_EQ(stored->worldToNdc, image.worldToNdc);
    // The names in the file: OIIO's "worldtocamera"/"worldtoscreen" are EXR's worldToCamera/worldToNDC.
    OIIO::ImageSpec config;
    config.attribute("oiio:RawColor", 1);
    auto in = OIIO::ImageInput::open(path, &config);
    ASSERT_TRUE(in);
    EXPECT_TRUE(in->spec().find_attribute("worldtocamera", OIIO::TypeMatrix44));
    // A stored image written again keeps them (what `vastray assemble` does with tiles).
    const std::string copy = test::tmpPath("camera-copy.exr");
    ASSERT_TRUE(writeStoredImage(copy, *stored));
    auto again = readStoredImage(copy);
    ASSERT_TRUE(again && again->hasCamera);
    EXPECT_EQ(again->worldToNdc, image.worldToNdc);
    // A PNG has no such attributes; an image rendered without a camera writes none.
    auto plain = gradientImage(kAovNone);
    ASSERT_TRUE(writeImageFile(test::tmpPath("nocamera.exr"), plain));
    auto none = readStoredImage(test::tmpPath("nocamera.exr"));
    ASSERT_TRUE(none);
    EXPECT_FALSE(none->hasCamera);
}

TEST(ImageFile, PngRefusesAovs) {
    EXPECT_FALSE(writeImageFile(test::tmpPath("aovs.png"), gradientImage(kAovDepth)));
    EXPECT_TRUE(writeImageFile(test::tmpPath("beauty.png"), gradientImage(kAovNone)));
}

// A partly covered pixel keeps its displayed colour: OIIO divided it by alpha on write (an
// edge pixel at alpha 0.25 came out 4x too bright, clipped).
TEST(ImageFile, PngStoresTheDisplayedColourOfPartlyCoveredPixels) {
    RenderImage image = gradientImage(kAovNone);
    for (uint32_t p = 0; p < image.pixelCount(); ++p) image.alpha[p] = float(p % 4 + 1) / 4.0f;
    const std::string path = test::tmpPath("alpha.png");
    ASSERT_TRUE(writeImageFile(path, image));
    auto stored = readStoredImage(path);
    ASSERT_TRUE(stored.isOk()) << stored.message();
    ASSERT_EQ(stored->pixels.size(), image.pixelCount() * 4);
    auto channels = readImageChannels(path, {"R", "A"});
    ASSERT_TRUE(channels.isOk()) << channels.message();
    for (uint32_t p = 0; p < image.pixelCount(); ++p) {
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(stored->pixels[4 * p + c], uint8_t(std::lround(255.0f * toneMapToDisplay(image.rgb[3 * p + c]))))
                << "pixel " << p << " alpha " << image.alpha[p];
        EXPECT_EQ(stored->pixels[4 * p + 3], uint8_t(std::lround(255.0f * image.alpha[p])));
        EXPECT_NEAR(channels->planes[0][p], toneMapToDisplay(image.rgb[3 * p]), 0.5f / 255.0f) << "read back as stored";
    }
}

TEST(ImageFile, ToneMapIsMonotoneAndBounded) {
    EXPECT_EQ(toneMapToDisplay(0.0f), 0.0f);
    EXPECT_EQ(toneMapToDisplay(-1.0f), 0.0f);
    EXPECT_FLOAT_EQ(toneMapToDisplay(4.0f), 1.0f);  // the white point
    EXPECT_FLOAT_EQ(toneMapToDisplay(100.0f), 1.0f);
    EXPECT_LT(toneMapToDisplay(0.2f), toneMapToDisplay(0.3f));
}

TEST(ImageDiff, IdenticalImagesAgreeEverywhere) {
    const std::string a = test::tmpPath("diff-a.exr"), b = test::tmpPath("diff-b.exr");
    ASSERT_TRUE(writeImageFile(a, gradientImage(kAllAovs)));
    ASSERT_TRUE(writeImageFile(b, gradientImage(kAllAovs)));
    auto report = diffImageFiles(a, b);
    ASSERT_TRUE(report) << report.message();
    EXPECT_EQ(report->beautyRmse, 0.0);
    EXPECT_EQ(report->depthMeanRelativeError, 0.0);
    EXPECT_EQ(report->depthHitMismatch, 0u);
    EXPECT_EQ(report->primIdAgreement, 1.0);
}

TEST(ImageDiff, MeasuresBeautyDepthAndPrimIdDifferences) {
    RenderImage changed = gradientImage(kAllAovs, 1.0f);
    for (float& v : changed.rgb) v += 0.1f;                  // RMSE exactly 0.1 (float: 1e-6)
    for (float& z : changed.depth) z *= 1.02f;               // 2% relative everywhere
    for (uint32_t p = 0; p < 8; ++p) changed.primId[p] = 7;  // 8 of 32 pixels changed
    const std::string a = test::tmpPath("diff-c.exr"), b = test::tmpPath("diff-d.exr");
    ASSERT_TRUE(writeImageFile(a, changed));
    ASSERT_TRUE(writeImageFile(b, gradientImage(kAllAovs)));
    auto report = diffImageFiles(a, b);
    ASSERT_TRUE(report) << report.message();
    EXPECT_NEAR(report->beautyRmse, 0.1, 1e-6);
    EXPECT_NEAR(report->depthMeanRelativeError, 0.02, 1e-6);
    EXPECT_DOUBLE_EQ(report->primIdAgreement, 24.0 / 32.0);
}

TEST(ImageDiff, DifferentSizesOrChannelsAreErrors) {
    RenderImage wide;
    wide.allocate(9, 4, kAovNone);
    const std::string a = test::tmpPath("size-a.exr"), b = test::tmpPath("size-b.exr"),
                      c = test::tmpPath("chan-c.exr");
    ASSERT_TRUE(writeImageFile(a, wide));
    ASSERT_TRUE(writeImageFile(b, gradientImage(kAovNone)));
    ASSERT_TRUE(writeImageFile(c, gradientImage(kAovDepth)));
    auto sizes = diffImageFiles(a, b);
    ASSERT_FALSE(sizes);
    EXPECT_NE(sizes.message().find("sizes differ"), std::string::npos) << sizes.message();
    auto channels = diffImageFiles(b, c);
    ASSERT_FALSE(channels);
    EXPECT_NE(channels.message().find("channels differ"), std::string::npos) << channels.message();
}

// A .pfm environment map is read without the OpenImageIO module (core/src/image/PfmFile.cpp):
// what vastray writes reads back exactly, either byte order and grey maps are read, and a
// damaged file is refused with its name and what is wrong.
TEST(ImageFile, PfmEnvironmentMapsAreReadAndDamagedOnesNamed) {
    const std::string written = test::tmpPath("written.pfm");
    const RenderImage image = gradientImage(kAovNone, 3.0f);
    ASSERT_TRUE(writeImageFile(written, image));
    auto map = readEnvironmentMap(written);
    ASSERT_TRUE(map) << map.message();
    ASSERT_EQ((*map)->width, image.width);
    ASSERT_EQ((*map)->height, image.height);
    EXPECT_EQ((*map)->rgb, image.rgb) << "rows in the same order, values unchanged";

    auto write = [](const std::string& name, const std::string& header, const std::vector<float>& values, bool bigEndian) {
        const std::string path = test::tmpPath(name);
        std::ofstream out(path, std::ios::binary);
        out << header;
        for (float v : values) {
            uint32_t bits;
            std::memcpy(&bits, &v, 4);
            if (bigEndian) bits = __builtin_bswap32(bits);
            out.write(reinterpret_cast<const char*>(&bits), 4);
        }
        return path;
    };
    // Big-endian grey, 2x1, scale 2: each value doubled and copied to R, G and B.
    auto grey = readEnvironmentMap(write("grey.pfm", "Pf\n2 1\n2.0\n", {0.25f, 1.5f}, true));
    ASSERT_TRUE(grey) << grey.message();
    EXPECT_EQ((*grey)->rgb, (std::vector<float>{0.5f, 0.5f, 0.5f, 3.0f, 3.0f, 3.0f}));
    const std::vector<std::pair<std::string, std::string>> damaged{
        {write("short.pfm", "PF\n2 2\n-1.0\n", std::vector<float>(11, 1.0f), false), "44 bytes of pixels where the header says 48"},
        {write("long.pfm", "PF\n1 1\n-1.0\n", std::vector<float>(4, 1.0f), false), "bytes after the pixels"},
        {write("magic.pfm", "P6\n1 1\n255\n", {}, false), "not a portable float map"},
        {write("size.pfm", "PF\n-2 1\n-1.0\n", {}, false), "is not two whole numbers"},
        {write("scale.pfm", "PF\n1 1\nnan\n", {1, 1, 1}, false), "scale 'nan'"},
        {write("zero.pfm", "PF\n1 1\n0\n", {1, 1, 1}, false), "scale '0'"},
        {write("token.pfm", "PF\n" + std::string(40, '1') + " 1\n-1.0\n", {}, false), "is not two whole numbers"},
        {write("huge.pfm", "PF\n99999 99999\n-1.0\n", {}, false), "99999x99999 pixels is more than the 67108864"},
        {write("inf.pfm", "PF\n1 1\n-1.0\n", {1.0f, INFINITY, 1.0f}, false), "texel (0, 0) channel G is inf"},
        {test::tmpPath("absent.pfm"), "cannot open"},
    };
    for (const auto& [path, message] : damaged) {
        auto result = readEnvironmentMap(path);
        ASSERT_FALSE(result) << path;
        EXPECT_NE(result.message().find(path), std::string::npos) << result.message();
        EXPECT_NE(result.message().find(message), std::string::npos) << result.message();
    }
}

// .exr and .hdr maps come through the OpenImageIO module with their values (RGBE keeps 8 bits of
// mantissa: within 1 %), row 0 at the top.
TEST(ImageFile, ExrAndHdrEnvironmentMapsAreReadThroughOpenImageIo) {
    const uint32_t w = 6, h = 3;
    std::vector<float> pixels(3 * w * h);
    for (uint32_t i = 0; i < w * h; ++i)
        for (uint32_t c = 0; c < 3; ++c) pixels[3 * i + c] = 0.25f + float(i) * 1.5f + float(c) * 0.125f;
    for (const char* name : {"map.exr", "map.hdr"}) {
        const std::string path = test::tmpPath(name);
        auto out = OIIO::ImageOutput::create(path);
        ASSERT_TRUE(out) << name;
        ASSERT_TRUE(out->open(path, OIIO::ImageSpec(int(w), int(h), 3, OIIO::TypeDesc::FLOAT)));
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
        ASSERT_TRUE(out->close());
        auto map = readEnvironmentMap(path, 2.0f);
        ASSERT_TRUE(map) << map.message();
        ASSERT_EQ((*map)->width, w);
        ASSERT_EQ((*map)->height, h);
        for (size_t i = 0; i < pixels.size(); ++i)
            EXPECT_NEAR((*map)->rgb[i], 2.0f * pixels[i], 0.01f * 2.0f * pixels[i]) << name << " value " << i;
        EXPECT_TRUE((*map)->sampleable);
    }
}

}  // namespace
}  // namespace vastray
