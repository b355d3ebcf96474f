// A job renders a scene's glTF KHR_lights_punctual lights (kept in the package) as `vastray
// render` does: the job's image equals the CLI's, which differs from the CLI's --no-lights one.
#include "ServerTestSupport.h"

namespace vastray::test {
namespace {

// A floor quad ([-2, 2]^2 at y = 0, facing +y) with a point light half a unit above it.
const char* kLitFloorGltf = R"({"asset":{"version":"2.0"},
 "buffers":[{"byteLength":60,"uri":"data:application/octet-stream;base64,AAAAwAAAAAAAAADAAAAAQAAAAAAAAADAAAAAQAAAAAAAAABAAAAAwAAAAAAAAABAAAACAAEAAAADAAIA"}],
 "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":12}],
 "accessors":[{"bufferView":0,"componentType":5126,"type":"VEC3","count":4,"min":[-2,0,-2],"max":[2,0,2]},
              {"bufferView":1,"componentType":5123,"type":"SCALAR","count":6}],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],
 "extensionsUsed":["KHR_lights_punctual"],
 "extensions":{"KHR_lights_punctual":{"lights":[{"name":"Bulb","type":"point","intensity":4}]}},
 "nodes":[{"mesh":0},{"extensions":{"KHR_lights_punctual":{"light":0}},"translation":[0.3,0.5,0]}],
 "scenes":[{"nodes":[0,1]}]})";

TEST_F(ServerTest, SceneLightsOfAJobAreTheCliRendersLights) {
    startServer();
    auto uploaded = http().Put("/v1/scenes?name=floor.gltf", kLitFloorGltf, "application/octet-stream");
    ASSERT_TRUE(uploaded);
    ASSERT_EQ(uploaded->status, 200) << uploaded->body;
    const std::string sceneId = json::parse(uploaded->body)["id"];
    auto res = submit(smallJob(sceneId));
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 202) << res->body;
    const std::string id = json::parse(res->body)["id"];
    EXPECT_EQ(waitForState(id, "JOB_STATE_SUCCEEDED")["state"], "JOB_STATE_SUCCEEDED");
    const std::string image = result(id);
    const std::string flags = "--resolution 32x32 --spp 2";
    EXPECT_EQ(image, cliRender(sceneId, flags));
    EXPECT_NE(image, cliRender(sceneId, flags + " --no-lights")) << "the light changes nothing";
}

}  // namespace
}  // namespace vastray::test
