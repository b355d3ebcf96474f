#pragma once
// Image files through OpenImageIO, which lives in a module loaded on the first image read or
// write (src/image/ImageModule.h says why); no OIIO type here.
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "vastray/core/RenderImage.h"
#include "vastray/core/Result.h"

namespace vastray {

// By extension: .png writes the beauty tone mapped to 8-bit sRGB (no AOVs: an error if
// any were requested); .pfm writes the beauty's linear RGB as 32-bit floats without the
// OpenImageIO module (no alpha; AOVs or a region are errors); .exr writes 32-bit float linear R,G,B,A and, when present, the
// channels Z, N.x, N.y, N.z, albedo.R, albedo.G, albedo.B, cost.cells, cost.triangles (float)
// and primid, chunkid (uint32).
// An EXR also records the camera (RenderImage::hasCamera) as OpenEXR's worldToCamera and
// worldToNDC attributes. An image that is a region of its frame (RenderImage::isRegion) records where it lies: in an
// EXR as the data window (the region) inside the display window (the frame, origin 0,0); in a
// PNG as the text chunk kRegionTextKey, "X0,Y0,X1,Y1 WxH" (x1, y1 exclusive; W x H the frame).
Status writeImageFile(const std::string& path, const RenderImage& image);

constexpr const char* kRegionTextKey = "vastray:region";

// The sample types an image file stores.
enum class SampleType : uint8_t { UInt8, UInt16, Half, Float, UInt32 };
uint32_t sampleBytes(SampleType type);

// An image file's pixels exactly as stored (no conversion, no alpha association): every channel
// in its own sample type, interleaved per pixel, row 0 at the top; and where the image lies in
// its frame (a file that records no region is a whole frame). `vastray assemble` joins these.
struct StoredImage {
    uint32_t width = 0, height = 0;
    uint32_t originX = 0, originY = 0, frameWidth = 0, frameHeight = 0;
    std::vector<std::string> channels;
    std::vector<SampleType> types;  // one per channel
    std::vector<uint8_t> pixels;    // width * height * pixelBytes()
    // An EXR's worldToCamera and worldToNDC, when it has them (RenderImage's).
    bool hasCamera = false;
    std::array<float, 16> worldToCamera{}, worldToNdc{};
    uint32_t pixelBytes() const {
        uint32_t bytes = 0;
        for (SampleType t : types) bytes += sampleBytes(t);
        return bytes;
    }
};

// .exr or .png; errors name the file.
Result<StoredImage> readStoredImage(const std::string& path);
// Writes `image` with its channels and types unchanged (EXR zip-compressed, PNG sRGB), recording
// its region as writeImageFile does.
Status writeStoredImage(const std::string& path, const StoredImage& image);

// Some channels of an image file, each as one plane of width x height floats (row 0 at the top).
struct ImageChannels {
    uint32_t width = 0, height = 0;
    std::vector<std::vector<float>> planes;  // in the order asked for; empty where the file lacks it
};

// Reads the channels named `names` (EXR names as writeImageFile writes them: "R", "Z", "N.x",
// "chunkid", ...). Float channels come as they are; 32-bit integer channels (primid, chunkid) as
// their values (exact below 2^24; kMissPrimId becomes 2^32); 8-bit channels (PNG) as 0..1.
// An image of more than maxPixels pixels is refused (naming the file and the limit) before its
// pixels are read.
Result<ImageChannels> readImageChannels(const std::string& path, const std::vector<std::string>& names,
                                        uint64_t maxPixels = UINT64_MAX);

// 8-bit RGBA texels of a texture image, row 0 at the top (the file's first row: glTF's uv (0, 0)
// is its upper-left corner, as core/Texture.h addresses it).
struct Rgba8Image {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> texels;  // width * height * 4
};

// A texture image (PNG, JPEG, or any 8- or 16-bit format OpenImageIO reads) as 8-bit RGBA: grey
// is copied to R, G and B, a missing alpha is 255, 16-bit samples are rounded to 8 bits, float
// samples clamped to [0, 1] and rounded. `name` is what errors call it (a file, or "image 3 of
// scene.glb"); an image of more than maxPixels pixels, of no or more than 4 channels, is refused
// naming it and the limit before its pixels are read. decodeRgba8Image reads the file's bytes
// from memory (an image embedded in a glTF buffer or data URI); `extension` (".png", ".jpg")
// picks the reader.
// ".ktx2" (either function; read without OpenImageIO) reads level 0 of a 2D KTX 2.0 texture:
// R8, R8G8, R8G8B8 or R8G8B8A8 (UNORM or SRGB), stored as it is or Zstandard-supercompressed, or
// Basis Universal (ETC1S/BasisLZ, UASTC with or without Zstandard) transcoded to RGBA. Its
// texels are taken as they are stored, whatever the transfer function (the caller decides the
// encoding, as for a PNG); channels map as Vulkan samples them (R8: R, 0, 0, 255), or through
// the file's KTXswizzle; a KTXorientation other than "rd" is flipped to row 0 at the top. Errors
// name the image and the field: see describeKtx2Image.
Result<Rgba8Image> readRgba8Image(const std::string& path, uint64_t maxPixels);
Result<Rgba8Image> decodeRgba8Image(const std::string& name, const std::string& extension,
                                    const std::vector<uint8_t>& bytes, uint64_t maxPixels);

// What an importer needs to know of a KTX2 image before decoding it.
struct Ktx2Description {
    std::string format;     // "R8G8B8A8_SRGB", "UASTC", "ETC1S", "vkFormat 131 (a BC1-BC7 block format)"
    bool readable = false;  // decodeRgba8Image(".ktx2") reads this format and supercompression
    bool srgb = false;      // the DFD's transfer function is sRGB (else linear, or another)
};

// Reads and checks a KTX2 container (not its texels). Errors name `name` and the field ("image 2
// ('x.ktx2') of model.gltf: KTX2 level 0 byte length 99 at offset 80 exceeds the file's 150
// bytes"): a wrong identifier, a header, index, level index, DFD or key/value data past the end
// of the file, sides of 0 or beyond kMaxTextureSide (core/Texture.h), a 1D, 3D, array or cube map
// texture, more levels than its sides allow, an unknown supercompression scheme.
Result<Ktx2Description> describeKtx2Image(const std::string& name, const std::vector<uint8_t>& bytes);

// Writes 8-bit sRGB RGBA pixels (4 bytes per pixel, row 0 at the top) as a PNG file.
Status writeRgba8Png(const std::string& path, uint32_t width, uint32_t height,
                     const std::vector<uint8_t>& rgba);

// Loads the image module now (it is otherwise loaded by the first read or write): commands
// call it before long work, so that a missing or broken module fails at once, not after a
// render. The error names the module and every place it was looked for.
Status loadImageModule();

// Tone mapping of the PNG beauty (docs/RENDERING.md): extended Reinhard with white
// point 4 per channel, then the sRGB transfer function. Input linear, output [0, 1].
inline uint32_t sampleBytes(SampleType type) {
    switch (type) {
        case SampleType::UInt8: return 1;
        case SampleType::UInt16:
        case SampleType::Half: return 2;
        case SampleType::Float:
        case SampleType::UInt32: return 4;
    }
    return 0;
}

inline float toneMapToDisplay(float linear) {
    constexpr float kWhiteSquared = 16.0f;
    const float x = std::fmax(linear, 0.0f);
    const float mapped = std::fmin(x * (1.0f + x / kWhiteSquared) / (1.0f + x), 1.0f);
    return mapped <= 0.0031308f ? 12.92f * mapped : 1.055f * std::pow(mapped, 1.0f / 2.4f) - 0.055f;
}

}  // namespace vastray
