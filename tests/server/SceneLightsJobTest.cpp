// A job renders a scene's glTF KHR_lights_punctual lights (kept in the package) as `vastray
// render` does: the job's image equals the CLI's, which differs from the CLI's --no-lights one.
#include "LitFloorGltf.h"
#include "ServerTestSupport.h"

namespace vastray::test {
namespace {

// The floor with a point light half a unit above it.
const std::string kLitFloorGltf = litFloorGltf(R"({"name":"Bulb","type":"point","intensity":4})",
                                               R"({"extensions":{"KHR_lights_punctual":{"light":0}},"translation":[0.3,0.5,0]})");

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
