// Materials of files read through assimp (Collada here) in the metallic-roughness model
// (docs/RENDERING.md, "Materials"): a Phong effect's specular colour and shininess become the
// dielectric layer (weight max(specular), roughness (2 / (shininess + 2))^(1/4)), a Lambert
// effect stays Lambertian; the factors survive the assimp child process's answer.
#include "ImportTestFiles.h"

#include <cmath>

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
