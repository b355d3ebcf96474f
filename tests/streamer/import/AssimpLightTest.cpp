// Punctual lights of files read through assimp (Collada here) become the same records as glTF's
// KHR_lights_punctual: placed by their node's world transform, colour * intensity split into a
// colour with largest component 1 and that component, full cone angles halved, a quadratic
// attenuation honoured exactly; hostile values refused by file, light and limit.
#include "ImportTestFiles.h"
#include "vastray/core/VecMath.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace vastray::test {
namespace {

constexpr float kDegree = 3.14159265358979323846f / 180.0f;

// One triangle and four lights: point "Bulb" inside a translated parent (colour 2 4 1, pure
// quadratic attenuation 0.5), spot "Cone" turned to shine down (full cone angles 40 and 60
// degrees, FCOLLADA's outer_cone), directional "Sun" turned 90 degrees about +Y, ambient "Fill".
const std::string kLightCollada = R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_lights>
    <light id="bulb-light" name="bulb"><technique_common><point>
      <color>2 4 1</color><constant_attenuation>0</constant_attenuation>
      <linear_attenuation>0</linear_attenuation><quadratic_attenuation>0.5</quadratic_attenuation>
    </point></technique_common></light>
    <light id="cone-light" name="cone"><technique_common><spot>
      <color>3 3 3</color><constant_attenuation>1</constant_attenuation>
      <falloff_angle>40</falloff_angle><outer_cone>60</outer_cone>
    </spot></technique_common></light>
    <light id="sun-light" name="sun"><technique_common><directional>
      <color>0.5 0.5 0.25</color>
    </directional></technique_common></light>
    <light id="fill-light" name="fill"><technique_common><ambient>
      <color>0.2 0.2 0.2</color>
    </ambient></technique_common></light>
  </library_lights>
)" + std::string(kColladaTriangle) + R"(      <node id="rig" name="rig"><translate>0 0 10</translate>
        <node id="Bulb" name="Bulb"><translate>1 2 0</translate><instance_light url="#bulb-light"/></node>
      </node>
      <node id="Cone" name="Cone"><translate>0 5 0</translate><rotate>1 0 0 -90</rotate>
        <instance_light url="#cone-light"/></node>
      <node id="Sun" name="Sun"><rotate>0 1 0 90</rotate><instance_light url="#sun-light"/></node>
      <node id="Fill" name="Fill"><instance_light url="#fill-light"/></node>
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
)";

const PunctualLight* find(const std::vector<PunctualLight>& lights, const std::string& name) {
    for (const PunctualLight& l : lights)
        if (l.name == name) return &l;
    return nullptr;
}

bool warned(const ImportReport& report, const std::string& text) {
    for (const std::string& warning : report.warnings)
        if (warning.find(text) != std::string::npos) return true;
    return false;
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    text.replace(text.find(from), from.size(), to);
    return text;
}

// Positions and directions come through float matrix products: 1e-5 of the unit coordinates.
TEST(AssimpLights, ColladaLightsArePlacedAndConvertedAsGltfLights) {
    auto r = importMesh(writeFile("lights.dae", kLightCollada));
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->mesh.lights.size(), 3u) << "the ambient light is not imported";

    const PunctualLight* bulb = find(r->mesh.lights, "Bulb");
    ASSERT_NE(bulb, nullptr);
    EXPECT_EQ(bulb->type, LightType::Point);
    expectNear(bulb->position, {1, 2, 10}, 1e-5f, "Bulb: parent's translation + its own");
    EXPECT_FLOAT_EQ(bulb->intensity, 8.0f) << "largest component 4 over the quadratic attenuation 0.5";
    EXPECT_FLOAT_EQ(bulb->color[0], 0.5f);
    EXPECT_FLOAT_EQ(bulb->color[1], 1.0f);
    EXPECT_FLOAT_EQ(bulb->color[2], 0.25f);

    const PunctualLight* cone = find(r->mesh.lights, "Cone");
    ASSERT_NE(cone, nullptr);
    EXPECT_EQ(cone->type, LightType::Spot);
    expectNear(cone->position, {0, 5, 0}, 1e-5f, "Cone: position");
    expectNear(cone->direction, {0, -1, 0}, 1e-5f, "Cone: -Z turned -90 degrees about +X shines down");
    EXPECT_NEAR(cone->innerConeAngle, 20.0f * kDegree, 1e-5f) << "half the full falloff_angle of 40 degrees";
    EXPECT_NEAR(cone->outerConeAngle, 30.0f * kDegree, 1e-5f) << "half the full outer_cone of 60 degrees";
    EXPECT_FLOAT_EQ(cone->intensity, 3.0f) << "constant attenuation 1: the file's light at distance 1";

    const PunctualLight* sun = find(r->mesh.lights, "Sun");
    ASSERT_NE(sun, nullptr);
    EXPECT_EQ(sun->type, LightType::Directional);
    expectNear(sun->direction, {-1, 0, 0}, 1e-5f, "Sun: -Z turned 90 degrees about +Y");
    EXPECT_FLOAT_EQ(sun->intensity, 0.5f);
    EXPECT_FLOAT_EQ(sun->color[2], 0.5f);

    EXPECT_TRUE(warned(r->report, "1 ambient or area lights read but not used")) << "the ambient light";
    EXPECT_TRUE(warned(r->report, "1 lights with constant or linear attenuation")) << "the spot's constant term";
    for (const PunctualLight& l : r->mesh.lights) EXPECT_TRUE(validateLight(l).isOk()) << l.name;
}

// The light's value crosses vastray's limit: the import fails naming the file, the light and
// the limit, as a glTF light's does.
TEST(AssimpLights, HostileLightIsRefusedByName) {
    const std::string huge = replaced(kLightCollada, "<color>2 4 1</color>", "<color>1e12 1e12 1e12</color>");
    auto r = importMesh(writeFile("huge-light.dae", huge));
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.message().find("huge-light.dae"), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("light 'Bulb'"), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("intensity 1e+12 is outside [0, 1e+09]"), std::string::npos) << r.message();

    const std::string nan = replaced(kLightCollada, "<color>3 3 3</color>", "<color>nan 1 1</color>");
    r = importMesh(writeFile("nan-light.dae", nan));
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.message().find("light 'Cone'"), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("intensity nan is outside"), std::string::npos) << r.message();

    const std::string negative =
        replaced(kLightCollada, "<quadratic_attenuation>0.5</quadratic_attenuation>", "<quadratic_attenuation>-1</quadratic_attenuation>");
    r = importMesh(writeFile("negative-attenuation.dae", negative));
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.message().find("light 'Bulb': attenuation (constant 0, linear 0, quadratic -1) is not finite and >= 0"),
              std::string::npos)
        << r.message();
}

// A tiny quadratic term (FBX files in centimetres have 2.2e-7) lifts an intensity within the
// limit above it: clamped to the limit with a warning, not refused.
TEST(AssimpLights, IntensityLiftedByTheAttenuationIsClampedToTheLimit) {
    const std::string tiny =
        replaced(kLightCollada, "<quadratic_attenuation>0.5</quadratic_attenuation>", "<quadratic_attenuation>1e-30</quadratic_attenuation>");
    auto r = importMesh(writeFile("tiny-attenuation.dae", tiny));
    ASSERT_TRUE(r.isOk()) << r.message();
    const PunctualLight* bulb = find(r->mesh.lights, "Bulb");
    ASSERT_NE(bulb, nullptr);
    EXPECT_EQ(bulb->intensity, kMaxLightIntensity);
    EXPECT_TRUE(warned(r->report, "1 lights brighter than 1000000000 once divided by their attenuation"));
}

// A spot cone wider than a hemisphere (Collada's default falloff_angle is 180 degrees) is
// narrowed to one with a warning.
TEST(AssimpLights, WideSpotIsNarrowedToAHemisphere) {
    const std::string wide = replaced(kLightCollada, "<outer_cone>60</outer_cone>", "<outer_cone>300</outer_cone>");
    auto r = importMesh(writeFile("wide-spot.dae", wide));
    ASSERT_TRUE(r.isOk()) << r.message();
    const PunctualLight* cone = find(r->mesh.lights, "Cone");
    ASSERT_NE(cone, nullptr);
    EXPECT_NEAR(cone->outerConeAngle, 90.0f * kDegree, 1e-6f);
    EXPECT_NEAR(cone->innerConeAngle, 20.0f * kDegree, 1e-5f);
    EXPECT_TRUE(warned(r->report, "1 spot lights wider than a hemisphere"));
}

// assimp-testmodels' Collada/lights.dae (Blender 2.74, Z up): a point, a sun, a spot, an
// ambient ("Hemi") and an area light exported as a point. The file has no geometry, which an
// import needs: the test's copy gets one triangle. assimp turns Z up into Y up: (x, y, z) ->
// (x, z, -y).
TEST(AssimpLights, BlenderColladaLightsFromAssimpTestModels) {
    const std::string path = "/usr/share/assimp/models/Collada/lights.dae";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent (install assimp-testmodels)";
    std::stringstream original;
    original << std::ifstream(path).rdbuf();
    std::string text = replaced(original.str(), "<library_visual_scenes>",
                                R"(<library_geometries><geometry id="tri-mesh"><mesh>
      <source id="p"><float_array id="pa" count="9">0 0 0 1 0 0 0 1 0</float_array>
        <technique_common><accessor source="#pa" count="3" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
      <triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles>
    </mesh></geometry></library_geometries>
  <library_visual_scenes>)");
    text = replaced(text, "</visual_scene>", R"(<node id="tri" name="tri"><instance_geometry url="#tri-mesh"/></node></visual_scene>)");
    auto r = importMesh(writeFile("blender-lights.dae", text));
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->mesh.lights.size(), 4u) << "Lamp, Sun, Spot, Area; not the ambient Hemi";

    const PunctualLight* lamp = find(r->mesh.lights, "Lamp");
    ASSERT_NE(lamp, nullptr);
    EXPECT_EQ(lamp->type, LightType::Point);
    expectNear(lamp->position, {0, 1, -1}, 1e-5f, "Lamp: Blender's (0, 1, 1)");
    EXPECT_NEAR(lamp->intensity, 1.0f / (1.0f + 0.00111109f), 1e-6f) << "colour 1 over attenuation 1 + 0.00111109 at d = 1";

    const PunctualLight* sun = find(r->mesh.lights, "Sun");
    ASSERT_NE(sun, nullptr);
    EXPECT_EQ(sun->type, LightType::Directional);
    expectNear(sun->direction, {0, -1, 0}, 1e-5f, "Sun: Blender's -Z, straight down");

    const PunctualLight* spot = find(r->mesh.lights, "Spot");
    ASSERT_NE(spot, nullptr);
    EXPECT_EQ(spot->type, LightType::Spot);
    expectNear(spot->position, {8.888217f, 5.336025f, 5.016863f}, 1e-4f, "Spot: Blender's (8.89, -5.02, 5.34)");
    expectNear(spot->direction, {0, -1, 0}, 1e-5f, "Spot: down");
    EXPECT_NEAR(spot->innerConeAngle, 22.5f * kDegree, 1e-5f) << "half of Blender's spot size of 45 degrees";
    // assimp's Collada reader guesses the outer cone from falloff_exponent 0.15:
    // acos(0.1^(1 / 0.15)) + 45 degrees, full; halved.
    EXPECT_NEAR(spot->outerConeAngle, 0.5f * (std::acos(std::pow(0.1f, 1.0f / 0.15f)) + 45.0f * kDegree), 1e-5f);

    ASSERT_NE(find(r->mesh.lights, "Area"), nullptr);
    EXPECT_TRUE(warned(r->report, "1 ambient or area lights read but not used")) << "Hemi";
}

}  // namespace
}  // namespace vastray::test
