// Opacity through assimp (docs/RENDERING.md, "Cut-outs"): a Collada effect's <transparent>
// texture is assimp's OPACITY map. On another image than the diffuse map it is baked into the
// base colour map's alpha in the parent process (import/AlphaMask.h) and the material cuts at
// 0.5; on the diffuse map's own image (with alpha) that image's alpha cuts as it is. glTF 2.0's
// alphaMode keys, as assimp's glTF reader sets them, make MASK cut-outs.
#include "ImportTestFiles.h"

#include <assimp/GltfMaterial.h>
#include <assimp/material.h>
#include <assimp/scene.h>

#include <array>

#include "import/AssimpTextures.h"
#include "PngBytes.h"
#include "import/PngWriter.h"
#include "vastray/core/ImageFile.h"

namespace vastray::test {
namespace {

// A textured quad whose Phong effect reads `diffuse` and, as <transparent>, `opacity`.
std::string opacityCollada(const std::string& diffuse, const std::string& opacity) {
    return R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_images>
    <image id="diffuse-img"><init_from>)" + diffuse + R"(</init_from></image>
    <image id="opacity-img"><init_from>)" + opacity + R"(</init_from></image>
  </library_images>
  <library_effects>
    <effect id="leaf-fx"><profile_COMMON>
      <newparam sid="diffuse-surface"><surface type="2D"><init_from>diffuse-img</init_from></surface></newparam>
      <newparam sid="diffuse-sampler"><sampler2D><source>diffuse-surface</source></sampler2D></newparam>
      <newparam sid="opacity-surface"><surface type="2D"><init_from>opacity-img</init_from></surface></newparam>
      <newparam sid="opacity-sampler"><sampler2D><source>opacity-surface</source></sampler2D></newparam>
      <technique sid="common"><phong>
        <diffuse><texture texture="diffuse-sampler" texcoord="UVMap"/></diffuse>
        <transparent opaque="A_ONE"><texture texture="opacity-sampler" texcoord="UVMap"/></transparent>
        <transparency><float>1</float></transparency>
      </phong></technique></profile_COMMON></effect>
  </library_effects>
  <library_materials><material id="leaf" name="leaf"><instance_effect url="#leaf-fx"/></material></library_materials>
  <library_geometries>
    <geometry id="quad-mesh" name="quad"><mesh>
      <source id="quad-positions"><float_array id="quad-positions-array" count="12">0 0 0 1 0 0 1 1 0 0 1 0</float_array>
        <technique_common><accessor source="#quad-positions-array" count="4" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <source id="quad-uvs"><float_array id="quad-uvs-array" count="8">0 0 1 0 1 1 0 1</float_array>
        <technique_common><accessor source="#quad-uvs-array" count="4" stride="2">
          <param name="S" type="float"/><param name="T" type="float"/>
        </accessor></technique_common></source>
      <vertices id="quad-vertices"><input semantic="POSITION" source="#quad-positions"/></vertices>
      <triangles count="2" material="leafSymbol">
        <input semantic="VERTEX" source="#quad-vertices" offset="0"/>
        <input semantic="TEXCOORD" source="#quad-uvs" offset="0" set="0"/>
        <p>0 1 2 0 2 3</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="Scene" name="Scene">
      <node id="quad" name="quad"><instance_geometry url="#quad-mesh"><bind_material><technique_common>
        <instance_material symbol="leafSymbol" target="#leaf">
          <bind_vertex_input semantic="UVMap" input_semantic="TEXCOORD" input_set="0"/>
        </instance_material>
      </technique_common></bind_material></instance_geometry></node>
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
)";
}

const Material& leafOf(const ImportedMesh& m) {
    for (const Material& material : m.mesh.materials)
        if (material.name == "leaf") return material;
    ADD_FAILURE() << "no material 'leaf'";
    return m.mesh.materials.at(0);
}

// An opacity map on a grey PNG (its luminance) is baked into the diffuse map's alpha; the
// diffuse RGB stays; only the baked texture is kept; no warning about the opacity map.
TEST(AssimpOpacity, OpacityMapOnAnotherImageIsBakedIntoTheBaseColourAlpha) {
    writeFile("op-diffuse.png", png(2, 1, 3, {200, 100, 50, 10, 20, 30}));
    writeFile("op-mask.png", png(2, 1, 1, {0, 255}));
    auto r = importMesh(writeFile("op-baked.dae", opacityCollada("op-diffuse.png", "op-mask.png")));
    ASSERT_TRUE(r.isOk()) << r.message();
    const Material& leaf = leafOf(*r);
    EXPECT_EQ(leaf.alphaCutoff, 0.5f);
    EXPECT_EQ(leaf.baseColor[3], 1.0f);
    ASSERT_EQ(r->mesh.textures.size(), 1u);
    EXPECT_EQ(leaf.textures.slots[uint32_t(TextureSlot::BaseColor)].texture, 0u);
    const TextureSource& t = r->mesh.textures[0];
    auto image = decodeRgba8Image(t.name, t.extension, t.bytes, 1u << 20);
    ASSERT_TRUE(image.isOk()) << image.message();
    EXPECT_EQ(image->texels, (std::vector<uint8_t>{200, 100, 50, 0, 10, 20, 30, 255}));
    for (const std::string& w : r->report.warnings) EXPECT_EQ(w.find("opacity"), std::string::npos) << w;
}

// The diffuse map's own image as the opacity map: its alpha cuts as it is (nothing baked).
TEST(AssimpOpacity, OpacityMapOnTheDiffuseImageCutsWithItsAlpha) {
    const std::string leaf = png(2, 1, 4, {1, 2, 3, 0, 4, 5, 6, 255});
    writeFile("op-leaf.png", leaf);
    auto r = importMesh(writeFile("op-same.dae", opacityCollada("op-leaf.png", "op-leaf.png")));
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(leafOf(*r).alphaCutoff, 0.5f);
    ASSERT_EQ(r->mesh.textures.size(), 1u);
    EXPECT_EQ(r->mesh.textures[0].bytes, std::vector<uint8_t>(leaf.begin(), leaf.end()));
}

// A missing opacity image is warned as a missing map's is; the material stays opaque.
TEST(AssimpOpacity, MissingOpacityImageIsWarnedAndLeftOut) {
    writeFile("op-diffuse2.png", png(1, 1, 3, {1, 2, 3}));
    auto r = importMesh(writeFile("op-missing.dae", opacityCollada("op-diffuse2.png", "op-gone.png")));
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(leafOf(*r).alphaCutoff, 0.0f);
    EXPECT_EQ(r->mesh.textures.size(), 1u);
    bool warned = false;
    for (const std::string& w : r->report.warnings)
        warned = warned || w.find("1 texture maps whose image file is missing or unreadable") == 0;
    EXPECT_TRUE(warned) << ::testing::PrintToString(r->report.warnings);
}

// glTF 2.0's alphaMode as assimp's glTF reader stores it: MASK with a diffuse map cuts at its
// alphaCutoff (0.5 without one, clamped to [0, 1]); MASK without a map and BLEND are warned.
TEST(AssimpOpacity, GltfAlphaModeKeysMakeMaskCutouts) {
    writeFile("gm-base.png", png(1, 1, 4, {1, 2, 3, 4}));
    struct Case {
        const char* mode;
        float cutoff;  // < 0: none given
        bool mapped;
        float expected;
    };
    const Case cases[] = {{"MASK", 0.3f, true, 0.3f}, {"MASK", -1.0f, true, 0.5f}, {"MASK", 7.0f, true, 1.0f},
                          {"OPAQUE", 0.3f, true, 0.0f}, {"MASK", 0.3f, false, 0.0f}, {"BLEND", 0.3f, true, 0.0f}};
    aiScene scene;
    scene.mNumMaterials = unsigned(std::size(cases));
    scene.mMaterials = new aiMaterial*[scene.mNumMaterials];
    for (unsigned i = 0; i < scene.mNumMaterials; ++i) {
        aiMaterial* m = scene.mMaterials[i] = new aiMaterial;
        const aiString mode(cases[i].mode), file("gm-base.png");
        m->AddProperty(&mode, AI_MATKEY_GLTF_ALPHAMODE);
        if (cases[i].cutoff >= 0.0f) m->AddProperty(&cases[i].cutoff, 1, AI_MATKEY_GLTF_ALPHACUTOFF);
        if (cases[i].mapped) m->AddProperty(&file, AI_MATKEY_TEXTURE_DIFFUSE(0));
    }
    ImportReport report;
    auto textures = import::assimpTextures(scene, tmpPath(""), "gm.gltf", report);
    ASSERT_TRUE(textures.isOk()) << textures.message();
    ASSERT_EQ(textures->alphaCutoffs.size(), std::size(cases));
    for (size_t i = 0; i < std::size(cases); ++i)
        EXPECT_EQ(textures->alphaCutoffs[i], cases[i].expected) << i << " " << cases[i].mode;
    const std::vector<std::string> expected = {
        "1 materials with glTF alphaMode MASK without a base colour map read but not used (rendered opaque)",
        "1 materials with glTF alphaMode BLEND read but not used (rendered opaque)"};
    for (const std::string& w : expected)
        EXPECT_EQ(std::count(report.warnings.begin(), report.warnings.end(), w), 1) << w;
}

}  // namespace
}  // namespace vastray::test
