// Materials of files read through assimp (Collada here) in the metallic-roughness model
// (docs/RENDERING.md, "Materials"): a Phong effect's specular colour and shininess become the
// dielectric layer (weight max(specular), roughness (2 / (shininess + 2))^(1/4)), a Lambert
// effect stays Lambertian; the factors survive the assimp child process's answer.
#include "ImportTestFiles.h"

#include <array>
#include <cmath>
#include <filesystem>

#include "import/AssimpTextures.h"

namespace vastray::test {
namespace {

// Two triangles, one per effect: "shiny" (Phong, specular 0.6 0.3 0.2, shininess 48) and "matte"
// (Lambert).
const char* const kCollada = R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_effects>
    <effect id="shiny-fx"><profile_COMMON><technique sid="common"><phong>
      <diffuse><color>0.8 0.1 0.1 1</color></diffuse>
      <specular><color>0.6 0.3 0.2 1</color></specular>
      <shininess><float>48</float></shininess>
    </phong></technique></profile_COMMON></effect>
    <effect id="matte-fx"><profile_COMMON><technique sid="common"><lambert>
      <diffuse><color>0.1 0.8 0.1 1</color></diffuse>
    </lambert></technique></profile_COMMON></effect>
  </library_effects>
  <library_materials>
    <material id="shiny" name="shiny"><instance_effect url="#shiny-fx"/></material>
    <material id="matte" name="matte"><instance_effect url="#matte-fx"/></material>
  </library_materials>
  <library_geometries>
    <geometry id="tri-mesh" name="tri"><mesh>
      <source id="tri-positions"><float_array id="tri-positions-array" count="12">0 0 0 1 0 0 0 1 0 1 1 0</float_array>
        <technique_common><accessor source="#tri-positions-array" count="4" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <vertices id="tri-vertices"><input semantic="POSITION" source="#tri-positions"/></vertices>
      <triangles count="1" material="shinySymbol"><input semantic="VERTEX" source="#tri-vertices" offset="0"/><p>0 1 2</p></triangles>
      <triangles count="1" material="matteSymbol"><input semantic="VERTEX" source="#tri-vertices" offset="0"/><p>1 3 2</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="Scene" name="Scene">
      <node id="tri" name="tri"><instance_geometry url="#tri-mesh"><bind_material><technique_common>
        <instance_material symbol="shinySymbol" target="#shiny"/>
        <instance_material symbol="matteSymbol" target="#matte"/>
      </technique_common></bind_material></instance_geometry></node>
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
)";

TEST(AssimpMaterials, PhongSpecularBecomesTheDielectricLayerAndLambertStaysLambertian) {
    auto r = importMesh(writeFile("materials.dae", kCollada));
    ASSERT_TRUE(r.isOk()) << r.message();
    const Material* shiny = nullptr;
    const Material* matte = nullptr;
    for (const Material& m : r->mesh.materials) {
        if (m.name == "shiny") shiny = &m;
        if (m.name == "matte") matte = &m;
    }
    ASSERT_TRUE(shiny && matte) << r->mesh.materials.size() << " materials";
    EXPECT_NEAR(shiny->baseColor[0], 0.8f, 1e-6f);
    EXPECT_NEAR(shiny->specular, 0.6f, 1e-6f);
    EXPECT_NEAR(shiny->roughness, std::sqrt(std::sqrt(2.0f / 50.0f)), 1e-6f);
    EXPECT_EQ(shiny->metallic, 0.0f);
    EXPECT_EQ(matte->specular, 0.0f);
    EXPECT_EQ(matte->metallic, 0.0f);
    EXPECT_NEAR(matte->baseColor[1], 0.8f, 1e-6f);
}

}  // namespace
}  // namespace vastray::test

namespace vastray::test {
namespace {

// A DirectX .x quad (assimp's X reader: TextureFilename is a diffuse map, UVs v-down in the file)
// whose material names `texture`.
std::string texturedX(const std::string& texture) { return texturedQuadX(texture); }

// A diffuse map of a PNG beside the model becomes the base colour map (sRGB, repeat, no
// transform), its bytes carried through the assimp child process's answer.
TEST(AssimpMaterials, DiffuseMapOfAPngBesideTheModelIsTheBaseColourMap) {
    writeFile("x-wood.png", tinyPng());
    auto r = importMesh(writeFile("x-textured.x", texturedX("x-wood.png")));
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->mesh.textures.size(), 1u);
    const TextureSource& t = r->mesh.textures[0];
    EXPECT_EQ(t.name, "'x-wood.png' of x-textured.x");
    EXPECT_EQ(t.extension, ".png");
    const std::string png = tinyPng();
    EXPECT_EQ(t.bytes, std::vector<uint8_t>(png.begin(), png.end()));
    EXPECT_EQ(t.encoding, TextureEncoding::Srgb);
    EXPECT_EQ(t.wrapS, TextureWrap::Repeat);
    bool found = false;
    for (const Material& m : r->mesh.materials) {
        const TextureBinding& b = m.textures.slots[uint32_t(TextureSlot::BaseColor)];
        if (b.texture == kNoTexture) continue;
        found = true;
        EXPECT_EQ(b.texture, 0u);
        EXPECT_EQ(b.transform, kIdentityUvTransform);
        EXPECT_EQ(m.textures.slots[uint32_t(TextureSlot::Normal)].texture, kNoTexture);
    }
    EXPECT_TRUE(found);
    EXPECT_EQ(r->mesh.uvs.size(), r->mesh.positions.size());
}

// A map whose file is missing, is not PNG/JPEG, or lies outside the model's folder (FBX files
// often name absolute paths) is left out and warned once per kind; the import succeeds.
TEST(AssimpMaterials, MapsNotReadableHereAreWarnedAndLeftOut) {
    writeFile("x-picture.tga", "not a PNG or JPEG");
    const std::pair<const char*, const char*> cases[] = {
        {"x-gone.png", "1 texture maps whose image file is missing or unreadable read but not used"},
        {"x-picture.tga", "1 texture maps with an image neither PNG, JPEG nor a KTX2 of a format read here read but not used"},
        {"../x-outside.png", "1 texture maps whose file lies outside the model's folder read but not used"},
        {"/etc/hostname", "1 texture maps whose file lies outside the model's folder read but not used"}};
    for (const auto& [texture, warning] : cases) {
        auto r = importMesh(writeFile("x-unread.x", texturedX(texture)));
        ASSERT_TRUE(r.isOk()) << r.message();
        EXPECT_TRUE(r->mesh.textures.empty()) << texture;
        for (const Material& m : r->mesh.materials) EXPECT_FALSE(m.textures.any()) << texture;
        bool warned = false;
        for (const std::string& w : r->report.warnings) warned = warned || w.find(warning) == 0;
        EXPECT_TRUE(warned) << texture << ": " << ::testing::PrintToString(r->report.warnings);
    }
}

// A link inside the folder that leads out of it is refused by name, as an OBJ's map is.
TEST(AssimpMaterials, MapLinkedOutOfTheFolderIsRefused) {
    const std::string link = tmpPath("x-link-out.png");
    std::filesystem::remove(link);
    std::filesystem::create_symlink("/etc/hostname", link);
    auto r = importMesh(writeFile("x-link.x", texturedX("x-link-out.png")));
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.message().find("x-link.x: material 0 ('Painted') baseColorTexture: image 'x-link-out.png' resolves "
                               "outside the model's folder"),
              std::string::npos)
        << r.message();
}

// aiUVTransform in assimp's convention (TransformUVCoords: translate, then rotate counter-clockwise
// and scale about (0.5, 0.5), v up) lands a v-up UV where that convention says, read in the
// package's v-down space. Tolerance 1e-6: a few float operations on values near 1.
TEST(AssimpMaterials, UvTransformFollowsAssimpsConventionInVDownSpace) {
    EXPECT_EQ(import::assimpUvTransform(0.0f, 0.0f, 1.0f, 1.0f, 0.0f), kIdentityUvTransform);
    const float pi = 3.14159265358979f;
    struct Case {
        float tu, tv, su, sv, rotation;
    };
    for (const Case& c : {Case{0.25f, 0.5f, 1.0f, 1.0f, 0.0f}, Case{0.0f, 0.0f, 2.0f, 3.0f, 0.0f},
                          Case{0.0f, 0.0f, 1.0f, 1.0f, pi / 2}, Case{0.1f, -0.2f, 2.0f, 0.5f, 0.3f}}) {
        const UvTransform m = import::assimpUvTransform(c.tu, c.tv, c.su, c.sv, c.rotation);
        for (const std::array<float, 2>& uv : {std::array{0.0f, 0.0f}, std::array{1.0f, 0.5f}, std::array{0.3f, 0.9f}}) {
            // assimp, v up: S R (uv + t - 0.5) + 0.5.
            const float x = uv[0] + c.tu - 0.5f, y = uv[1] + c.tv - 0.5f;
            const float up = c.su * (std::cos(c.rotation) * x - std::sin(c.rotation) * y) + 0.5f;
            const float vp = c.sv * (std::sin(c.rotation) * x + std::cos(c.rotation) * y) + 0.5f;
            float u = 0.0f, g = 0.0f;
            applyUvTransform(m, uv[0], 1.0f - uv[1], u, g);
            EXPECT_NEAR(u, up, 1e-6f) << uv[0] << "," << uv[1] << " rotation " << c.rotation;
            EXPECT_NEAR(g, 1.0f - vp, 1e-6f) << uv[0] << "," << uv[1] << " rotation " << c.rotation;
        }
    }
    // A quarter turn counter-clockwise takes (1, 0.5) to (0.5, 1) (v up), (0.5, 0) stored v-down.
    float u = 0.0f, g = 0.0f;
    applyUvTransform(import::assimpUvTransform(0.0f, 0.0f, 1.0f, 1.0f, pi / 2), 1.0f, 0.5f, u, g);
    EXPECT_NEAR(u, 0.5f, 1e-6f);
    EXPECT_NEAR(g, 0.0f, 1e-6f);
}

}  // namespace
}  // namespace vastray::test
