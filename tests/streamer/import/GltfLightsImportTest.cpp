// Issue 13 ("Real assets"): glTF KHR_lights_punctual lights. Each kind is imported with its
// values and placed by its node's world transform (as cameras are); hostile values are refused
// with the file, the JSON path and the limit named.
#include <gtest/gtest.h>

#include <cmath>

#include "ImportTestFiles.h"

namespace vastray::test {
namespace {

constexpr float kPi = 3.14159265358979323846f;

// One triangle, and `rest` (lights, nodes, scenes) around it.
std::string lightsGltf(const std::string& lights, const std::string& nodes) {
    GltfBuilder b;
    const int positions = b.addPositions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    return b.json(R"("meshes":[{"primitives":[{"attributes":{"POSITION":)" + std::to_string(positions) +
                  R"(}}]}],"extensionsUsed":["KHR_lights_punctual"],"extensions":{"KHR_lights_punctual":{"lights":[)" +
                  lights + R"(]}},"nodes":[)" + nodes + R"(],"scenes":[{"nodes":[0]}])");
}

Result<ImportedMesh> importLights(const std::string& name, const std::string& lights, const std::string& children) {
    return importGltf(writeFile(name, lightsGltf(lights, R"({"mesh":0,"children":[1]},)" + children)));
}

constexpr const char* kThreeLights =
    R"({"type":"directional","name":"Sun","color":[1,0.5,0.25],"intensity":3},)"
    R"({"type":"point","name":"Bulb","intensity":40,"range":12},)"
    R"({"type":"spot","intensity":100,"spot":{"innerConeAngle":0.2,"outerConeAngle":0.5}})";

TEST(GltfLightsImport, EachKindKeepsItsValuesAndItsNodesPlacement) {
    // Node 1 moves its children up 2 and scales them by 3; node 2 (the directional light) turns
    // -Z down to -Y (-90 degrees about +X); node 3 places the point light at (1, 0, 0) locally;
    // node 4 the spot at the origin, shining down its (turned) -Z.
    const double s = std::sqrt(0.5);
    const std::string rotateX = "[" + std::to_string(-s) + ",0,0," + std::to_string(s) + "]";
    auto r = importLights("three-lights.gltf", kThreeLights,
                          R"({"translation":[0,2,0],"scale":[3,3,3],"children":[2,3,4]},)"
                          R"({"extensions":{"KHR_lights_punctual":{"light":0}},"rotation":)" + rotateX + R"(},)"
                          R"({"extensions":{"KHR_lights_punctual":{"light":1}},"translation":[1,0,0]},)"
                          R"({"name":"Lamp","extensions":{"KHR_lights_punctual":{"light":2}},"rotation":)" + rotateX + "}");
    ASSERT_TRUE(r) << r.message();
    const auto& lights = r->mesh.lights;
    ASSERT_EQ(lights.size(), 3u);
    // Positions and directions within 1e-6 (float rounding of the composed transforms).
    auto near = [](Vec3f a, Vec3f b) { return std::fabs(a.x - b.x) < 1e-6f && std::fabs(a.y - b.y) < 1e-6f && std::fabs(a.z - b.z) < 1e-6f; };
    EXPECT_EQ(lights[0].name, "Sun");
    EXPECT_EQ(lights[0].type, LightType::Directional);
    EXPECT_EQ(lights[0].color, (std::array<float, 3>{1, 0.5f, 0.25f}));
    EXPECT_EQ(lights[0].intensity, 3.0f);
    EXPECT_TRUE(near(lights[0].direction, {0, -1, 0})) << lights[0].direction.y << " " << lights[0].direction.z;
    EXPECT_EQ(lights[1].name, "Bulb");
    EXPECT_EQ(lights[1].type, LightType::Point);
    EXPECT_EQ(lights[1].color, (std::array<float, 3>{1, 1, 1}));  // the extension's default
    EXPECT_EQ(lights[1].intensity, 40.0f);
    EXPECT_EQ(lights[1].range, 12.0f);
    EXPECT_TRUE(near(lights[1].position, {3, 2, 0}));
    EXPECT_EQ(lights[2].name, "Lamp");  // no light name: the node's
    EXPECT_EQ(lights[2].type, LightType::Spot);
    EXPECT_EQ(lights[2].innerConeAngle, 0.2f);
    EXPECT_EQ(lights[2].outerConeAngle, 0.5f);
    EXPECT_TRUE(near(lights[2].position, {0, 2, 0}));
    EXPECT_TRUE(near(lights[2].direction, {0, -1, 0}));
}

// A file that requires the extension imports (the loader refuses required extensions it lacks).
TEST(GltfLightsImport, RequiredExtensionIsSupported) {
    std::string json = lightsGltf(R"({"type":"point"})", R"({"mesh":0,"children":[1]},{"extensions":{"KHR_lights_punctual":{"light":0}}})");
    json.replace(json.find("\"extensionsUsed\""), 0, R"("extensionsRequired":["KHR_lights_punctual"],)");
    auto r = importGltf(writeFile("required-lights.gltf", json));
    ASSERT_TRUE(r) << r.message();
    EXPECT_EQ(r->mesh.lights.size(), 1u);
}

TEST(GltfLightsImport, SpotDefaultsAreTheExtensionsAndUnplacedLightsAreReported) {
    auto r = importLights("spot-defaults.gltf", R"({"type":"spot","spot":{}},{"type":"point"})",
                          R"({"extensions":{"KHR_lights_punctual":{"light":0}}})");
    ASSERT_TRUE(r) << r.message();
    ASSERT_EQ(r->mesh.lights.size(), 1u);
    EXPECT_EQ(r->mesh.lights[0].innerConeAngle, 0.0f);
    EXPECT_FLOAT_EQ(r->mesh.lights[0].outerConeAngle, kPi / 4);
    EXPECT_EQ(r->mesh.lights[0].intensity, 1.0f);
    bool reported = false;
    for (const std::string& w : r->report.warnings) reported |= w.find("KHR_lights_punctual lights") != std::string::npos;
    EXPECT_TRUE(reported) << "the point light no node places is not reported";
}

struct Hostile {
    const char* light;
    const char* expected;
};

TEST(GltfLightsImport, HostileValuesAreRefusedByPathAndLimit) {
    const Hostile cases[] = {
        {R"({"type":"point","intensity":1e12})", "lights/0: intensity 1e+12 is outside [0, 1e+09]"},
        {R"({"type":"point","intensity":-1})", "lights/0: intensity -1 is outside [0, 1e+09]"},
        {R"({"type":"point","intensity":1e300})", "lights/0: intensity inf is outside [0, 1e+09]"},
        {R"({"type":"point","color":[1.5,0,0]})", "lights/0: color component 1.5 is outside [0, 1]"},
        {R"({"type":"point","range":-2})", "lights/0: range -2"},
        {R"({"type":"area"})", "lights/0: type 'area' is not directional, point or spot"},
        {R"({"type":"spot","spot":{"innerConeAngle":0.5,"outerConeAngle":0.5}})",
         "lights/0: innerConeAngle 0.5 is not below outerConeAngle 0.5"},
        {R"({"type":"spot","spot":{"outerConeAngle":2}})", "lights/0: outerConeAngle 2 is outside [0, 1.5708]"},
        {R"({"type":"spot","spot":{"innerConeAngle":-0.1}})", "lights/0: innerConeAngle -0.1 is outside [0, 1.5708]"},
        {R"({"type":"point","intensity":"bright"})",
         "JSON /extensions/KHR_lights_punctual/lights/0/intensity: expected a number, found string \"bright\""},
        {R"({"type":"point","color":[1,1]})", "JSON /extensions/KHR_lights_punctual/lights/0/color: expected 3 numbers"},
        {R"({"intensity":2})", "JSON /extensions/KHR_lights_punctual/lights/0/type: required field is missing"},
    };
    for (const Hostile& c : cases) {
        auto r = importLights("hostile-light.gltf", c.light, R"({"extensions":{"KHR_lights_punctual":{"light":0}}})");
        EXPECT_IMPORT_ERROR(r, "hostile-light.gltf", c.expected);
    }
}

TEST(GltfLightsImport, MissingOrMistypedLightReferenceIsRefusedByNode) {
    auto missing = importLights("missing-light.gltf", R"({"type":"point"})",
                                R"({"extensions":{"KHR_lights_punctual":{"light":4}}})");
    EXPECT_IMPORT_ERROR(missing, "missing-light.gltf",
                        "JSON /nodes/1/extensions/KHR_lights_punctual/light: light 4 does not exist (1 lights)");
    auto typed = importLights("typed-light.gltf", R"({"type":"point"})",
                              R"({"extensions":{"KHR_lights_punctual":{"light":"zero"}}})");
    EXPECT_IMPORT_ERROR(typed, "typed-light.gltf", "JSON /nodes/1/extensions/KHR_lights_punctual/light: expected");
}

TEST(GltfLightsImport, MoreLightsThanTheLimitAreRefused) {
    std::string lights, placed;
    for (uint32_t i = 0; i <= kMaxLights; ++i) lights += std::string(i ? "," : "") + R"({"type":"point"})";
    auto many = importLights("many-lights.gltf", lights, R"({"extensions":{"KHR_lights_punctual":{"light":0}}})");
    EXPECT_IMPORT_ERROR(many, "many-lights.gltf", "4097 lights exceed the limit of 4096");
    // One light placed by more nodes than the limit.
    std::string children;
    for (uint32_t i = 0; i <= kMaxLights; ++i) {
        children += std::string(i ? "," : "") + std::to_string(i + 2);
        placed += R"(,{"extensions":{"KHR_lights_punctual":{"light":0}}})";
    }
    auto r = importGltf(writeFile("many-placed.gltf",
                                  lightsGltf(R"({"type":"point"})", R"({"mesh":0,"children":[1]},{"children":[)" +
                                                                        children + "]}" + placed)));
    EXPECT_IMPORT_ERROR(r, "many-placed.gltf", "more than 4096 lights are placed (the limit)");
}

}  // namespace
}  // namespace vastray::test
