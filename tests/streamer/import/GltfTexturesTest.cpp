// readGltfTextures (streamer/src/import/GltfTextures.h): each material's maps, their samplers'
// wrap modes, KHR_texture_transform, the scene's textures shared where image, sampler and
// encoding agree, and the images' bytes from a file, a data URI and a buffer view alike.
#include <gtest/gtest.h>

#include <filesystem>

#include "ImportTestFiles.h"
#include "GltfTextureRead.h"
#include "import/GltfLoader.h"
#include "import/GltfTextures.h"

namespace vastray::test {
namespace {

using import::GltfTextures;

// A 1 x 1 PNG and the start of a WebP file ("RIFF", a size, "WEBPVP8 "), as data URIs.
constexpr const char* kPngUri =
    "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mNkYPhfDwAChwGA60e6kgAAAABJRU5ErkJggg==";
constexpr const char* kWebpUri = "data:application/octet-stream;base64,UklGRhoAAABXRUJQVlA4IA==";

// A triangle whose materials, textures, samplers and images are the caller's.
std::string texturedGltf(const std::string& materials, const std::string& rest) {
    GltfBuilder b;
    const int pos = b.addPositions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    return b.json(R"("meshes":[{"primitives":[{"attributes":{"POSITION":)" + std::to_string(pos) +
                  R"(},"material":0}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"materials":)" + materials +
                  "," + rest);
}

TEST(GltfTextures, MapsSamplersAndTransformsAreReadAndSharedTexturesStored) {
    const std::string json = texturedGltf(
        R"([{"name":"Brick","pbrMetallicRoughness":{"baseColorTexture":{"index":0,"extensions":{"KHR_texture_transform":
              {"offset":[0.5,0.25],"rotation":1.5707963,"scale":[2,4]}}},"metallicRoughnessTexture":{"index":0}},
            "normalTexture":{"index":1,"scale":0.5},"occlusionTexture":{"index":0,"strength":0.25}},
           {"pbrMetallicRoughness":{"baseColorTexture":{"index":2}},"emissiveTexture":{"index":0}}])",
        std::string(R"("textures":[{"source":0,"sampler":0},{"source":1,"sampler":1},{"source":0,"sampler":0}],
           "samplers":[{"wrapS":33071,"wrapT":33648},{}],
           "images":[{"uri":")") + kPngUri + R"(","name":"bricks"},{"uri":")" + kPngUri + R"("}])");
    ImportReport report;
    auto textures = readTextures("maps.gltf", json, report);
    ASSERT_TRUE(textures) << textures.message();
    ASSERT_EQ(textures->materials.size(), 2u);
    // Image 0 with sampler 0 as colour (base colour of both materials, emissive) and as data
    // (metallic-roughness, occlusion); image 1 with the default sampler as data (normal).
    ASSERT_EQ(textures->textures.size(), 3u);
    const MaterialTextures& brick = textures->materials[0];
    const uint32_t colour = brick.slots[uint32_t(TextureSlot::BaseColor)].texture;
    const uint32_t data = brick.slots[uint32_t(TextureSlot::MetallicRoughness)].texture;
    const uint32_t normal = brick.slots[uint32_t(TextureSlot::Normal)].texture;
    EXPECT_EQ(brick.slots[uint32_t(TextureSlot::Occlusion)].texture, data);
    EXPECT_EQ(brick.slots[uint32_t(TextureSlot::Emissive)].texture, kNoTexture);
    EXPECT_EQ(textures->materials[1].slots[uint32_t(TextureSlot::BaseColor)].texture, colour);
    EXPECT_EQ(textures->materials[1].slots[uint32_t(TextureSlot::Emissive)].texture, colour);
    EXPECT_EQ(textures->textures[colour].encoding, TextureEncoding::Srgb);
    EXPECT_EQ(textures->textures[colour].wrapS, TextureWrap::Clamp);
    EXPECT_EQ(textures->textures[colour].wrapT, TextureWrap::Mirror);
    EXPECT_EQ(textures->textures[data].encoding, TextureEncoding::Linear);
    EXPECT_EQ(textures->textures[normal].encoding, TextureEncoding::Linear);
    EXPECT_EQ(textures->textures[normal].wrapS, TextureWrap::Repeat);
    EXPECT_EQ(textures->textures[colour].extension, ".png");
    EXPECT_NE(textures->textures[colour].name.find("image 0 ('bricks') of maps.gltf"), std::string::npos)
        << textures->textures[colour].name;
    EXPECT_EQ(brick.normalScale, 0.5f);
    EXPECT_EQ(brick.occlusionStrength, 0.25f);
    // Offset (0.5, 0.25), a quarter turn, scale (2, 4): uv (1, 0) -> R (2, 0) = (0, -2) + offset.
    float u = 0, v = 0;
    applyUvTransform(brick.slots[uint32_t(TextureSlot::BaseColor)].transform, 1.0f, 0.0f, u, v);
    EXPECT_NEAR(u, 0.5f, 1e-5f);
    EXPECT_NEAR(v, 0.25f - 2.0f, 1e-5f);
    applyUvTransform(brick.slots[uint32_t(TextureSlot::BaseColor)].transform, 0.0f, 1.0f, u, v);
    EXPECT_NEAR(u, 0.5f + 4.0f, 1e-5f);
    EXPECT_NEAR(v, 0.25f, 1e-5f);
    EXPECT_EQ(brick.slots[uint32_t(TextureSlot::Normal)].transform, kIdentityUvTransform);
    EXPECT_TRUE(report.warnings.empty());
}

// KHR_materials_clearcoat's clearcoatTexture and clearcoatRoughnessTexture are bound like the
// core maps (linear data, their own KHR_texture_transform); its clearcoatNormalTexture is not read.
TEST(GltfTextures, CoatMapsAreBoundWithTheirTransforms) {
    const std::string json = texturedGltf(
        R"([{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}},"extensions":{"KHR_materials_clearcoat":
              {"clearcoatFactor":1,"clearcoatTexture":{"index":1,"extensions":{"KHR_texture_transform":{"scale":[2,2]}}},
               "clearcoatRoughnessTexture":{"index":1},"clearcoatNormalTexture":{"index":0}}}}])",
        std::string(R"("extensionsUsed":["KHR_materials_clearcoat","KHR_texture_transform"],
           "textures":[{"source":0},{"source":1}],"images":[{"uri":")") + kPngUri + R"("},{"uri":")" + kPngUri + R"("}])");
    ImportReport report;
    auto textures = readTextures("coat.gltf", json, report);
    ASSERT_TRUE(textures) << textures.message();
    const MaterialTextures& t = textures->materials[0];
    const uint32_t coat = t.slots[uint32_t(TextureSlot::Clearcoat)].texture;
    ASSERT_NE(coat, kNoTexture);
    EXPECT_EQ(t.slots[uint32_t(TextureSlot::ClearcoatRoughness)].texture, coat);
    EXPECT_EQ(textures->textures[coat].encoding, TextureEncoding::Linear);
    EXPECT_EQ(t.slots[uint32_t(TextureSlot::Clearcoat)].transform, khrTextureTransform(0, 0, 0, 2, 2));
    EXPECT_EQ(t.slots[uint32_t(TextureSlot::ClearcoatRoughness)].transform, kIdentityUvTransform);
    EXPECT_EQ(t.slots[uint32_t(TextureSlot::Normal)].texture, kNoTexture);  // not the coat's normal map
    // A coat map naming a texture the file lacks is refused by material and map.
    const std::string bad = texturedGltf(
        R"([{"extensions":{"KHR_materials_clearcoat":{"clearcoatFactor":1,"clearcoatRoughnessTexture":{"index":4}}}}])",
        std::string(R"("textures":[{"source":0}],"images":[{"uri":")") + kPngUri + R"("}])");
    auto refused = readTextures("badcoat.gltf", bad, report);
    ASSERT_FALSE(refused.isOk());
    EXPECT_EQ(refused.message(), "badcoat.gltf: material 0 clearcoatRoughnessTexture: texture 4 does not exist (the file has 1)");
}

TEST(GltfTextures, ImagesNotReadHereAreWarnedAndTheirMapsLeftOut) {
    const std::string json = texturedGltf(
        R"([{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}},"normalTexture":{"index":1}}])",
        std::string(R"("textures":[{"source":0},{"extensions":{"EXT_texture_webp":{"source":0}}}],
           "extensionsUsed":["EXT_texture_webp"],"images":[{"uri":")") + kWebpUri + R"("}])");
    ImportReport report;
    auto textures = readTextures("webp.gltf", json, report);
    ASSERT_TRUE(textures) << textures.message();
    EXPECT_TRUE(textures->textures.empty());
    EXPECT_FALSE(textures->materials[0].any());
    ASSERT_EQ(report.warnings.size(), 2u);
    EXPECT_NE(report.warnings[0].find("1 texture maps with an image neither PNG, JPEG nor KTX2"), std::string::npos)
        << report.warnings[0];
    EXPECT_NE(report.warnings[1].find("EXT_texture_webp"), std::string::npos) << report.warnings[1];
}

TEST(GltfTextures, BadReferencesSamplersAndTransformsAreRefusedByMaterialAndMap) {
    const std::string images = std::string(R"("images":[{"uri":")") + kPngUri + R"("}])";
    struct Case {
        const char* materials;
        const char* textures;
        const char* element;
    } cases[] = {
        {R"([{"name":"M","normalTexture":{"index":7}}])", R"("textures":[{"source":0}])",
         "material 0 ('M') normalTexture: texture 7 does not exist"},
        {R"([{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}])", R"("textures":[{"source":3}])",
         "image 3 does not exist"},
        {R"([{"emissiveTexture":{"index":0}}])", R"("textures":[{"source":0,"sampler":0}],"samplers":[{"wrapS":1234}])",
         "wrapS: wrap mode 1234"},
        {R"([{"pbrMetallicRoughness":{"baseColorTexture":{"index":0,"extensions":{"KHR_texture_transform":{"scale":[1e9,1]}}}}}])",
         R"("textures":[{"source":0}])", "outside +-1"},
        {R"([{"pbrMetallicRoughness":{"baseColorTexture":{"index":0,"extensions":{"KHR_texture_transform":{"offset":[1]}}}}}])",
         R"("textures":[{"source":0}])", "offset is not an array of two numbers"},
        {R"([{"occlusionTexture":{"index":0,"strength":2}}])", R"("textures":[{"source":0}])",
         "occlusionTexture strength 2"},
    };
    for (const Case& c : cases) {
        ImportReport report;
        auto textures = readTextures("bad.gltf", texturedGltf(c.materials, std::string(c.textures) + "," + images), report);
        EXPECT_IMPORT_ERROR(textures, "bad.gltf", c.element);
    }
}

TEST(GltfTextures, ImageFilesAreReadInsideTheModelsFolderOnly) {
    writeFile("wall%.png", "\x89PNG\r\n\x1a\nnot really a PNG but its signature");
    const std::string materials = R"([{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}},"emissiveTexture":{"index":1}}])";
    ImportReport report;
    auto textures = readTextures("files.gltf", texturedGltf(materials, R"("textures":[{"source":0},{"source":1}],
        "images":[{"uri":"wall%25.png"},{"uri":"gone.png"}])"), report);
    ASSERT_TRUE(textures) << textures.message();
    ASSERT_EQ(textures->textures.size(), 1u);
    EXPECT_EQ(textures->textures[0].bytes.size(), 42u);
    EXPECT_EQ(textures->materials[0].slots[uint32_t(TextureSlot::Emissive)].texture, kNoTexture);
    ASSERT_EQ(report.warnings.size(), 1u);
    EXPECT_NE(report.warnings[0].find("1 texture maps whose image file is missing"), std::string::npos)
        << report.warnings[0];
    for (const char* uri : {"../outside.png", "/etc/passwd", "file:///etc/passwd"}) {
        ImportReport r;
        auto refused = readTextures("escape.gltf", texturedGltf(materials, std::string(R"("textures":[{"source":0},{"source":0}],
            "images":[{"uri":")") + uri + R"("}])"), r);
        ASSERT_FALSE(refused) << uri;
        EXPECT_NE(refused.message().find("image 0 uri"), std::string::npos) << refused.message();
    }
}

TEST(GltfTextures, ImageBytesAreTheSameFromAFileADataUriAndABufferView) {
    const std::string root = "/usr/share/assimp/models/glTF2/";
    const std::string files[] = {root + "BoxTextured-glTF/BoxTextured.gltf",
                                 root + "BoxTextured-glTF-Embedded/BoxTextured.gltf",
                                 root + "BoxTextured-glTF-Binary/BoxTextured.glb"};
    if (!std::filesystem::exists(files[0])) GTEST_SKIP() << files[0] << " is absent (assimp-testmodels not installed)";
    std::vector<uint8_t> first;
    for (const std::string& file : files) {
        auto model = import::loadGltfModel(file, file.ends_with(".glb"));
        ASSERT_TRUE(model) << model.message();
        ImportReport report;
        auto textures = import::readGltfTextures(*model, "BoxTextured", std::filesystem::path(file).parent_path().string(), report);
        ASSERT_TRUE(textures) << textures.message();
        ASSERT_EQ(textures->textures.size(), 1u) << file;
        EXPECT_EQ(textures->materials[0].slots[uint32_t(TextureSlot::BaseColor)].texture, 0u);
        EXPECT_EQ(textures->textures[0].extension, ".png") << file;
        EXPECT_GT(textures->textures[0].bytes.size(), 1000u) << file;
        if (first.empty()) first = textures->textures[0].bytes;
        EXPECT_EQ(textures->textures[0].bytes, first) << file;
    }
}

// alphaMode MASK with a base colour map is a cut-out (docs/RENDERING.md, "Cut-outs"): the cutoff
// (glTF's default 0.5) is carried, and nothing is warned; OPAQUE and BLEND carry none.
TEST(GltfTextures, TexturedMasksCarryTheirCutoff) {
    const std::string json = texturedGltf(
        R"([{"name":"leaf","alphaMode":"MASK","alphaCutoff":0.3,"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}},
           {"name":"fence","alphaMode":"MASK","pbrMetallicRoughness":{"baseColorTexture":{"index":0}}},
           {"name":"wall","pbrMetallicRoughness":{"baseColorTexture":{"index":0}}},
           {"name":"glass","alphaMode":"BLEND","pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}])",
        std::string(R"("textures":[{"source":0}],"images":[{"uri":")") + kPngUri + R"("}])");
    auto imported = importGltf(writeFile("masks.gltf", json));
    ASSERT_TRUE(imported) << imported.message();
    ASSERT_EQ(imported->mesh.materials.size(), 4u);
    EXPECT_FLOAT_EQ(imported->mesh.materials[0].alphaCutoff, 0.3f);
    EXPECT_FLOAT_EQ(imported->mesh.materials[1].alphaCutoff, 0.5f);
    EXPECT_EQ(imported->mesh.materials[2].alphaCutoff, 0.0f);
    EXPECT_EQ(imported->mesh.materials[3].alphaCutoff, 0.0f);
    for (const std::string& w : imported->report.warnings) EXPECT_EQ(w.find("MASK"), std::string::npos) << w;
}

TEST(GltfTextures, ImportCarriesTheMapsAndTheirTexturesWithTheMesh) {
    const std::string file = "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " is absent (assimp-testmodels not installed)";
    auto imported = importGltf(file);
    ASSERT_TRUE(imported) << imported.message();
    ASSERT_EQ(imported->mesh.textures.size(), 1u);
    EXPECT_EQ(imported->mesh.materials[0].textures.slots[uint32_t(TextureSlot::BaseColor)].texture, 0u);
    EXPECT_EQ(imported->mesh.uvs.size(), imported->mesh.positions.size());
    EXPECT_NE(imported->mesh.textures[0].name.find("CesiumLogoFlat.png"), std::string::npos)
        << imported->mesh.textures[0].name;
}

}  // namespace
}  // namespace vastray::test
