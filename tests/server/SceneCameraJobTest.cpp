// A job's scene_camera (a glTF camera kept in the package) renders what `vastray render
// --camera` renders; the default is the scene's first camera; scene_camera and camera exclude
// each other at submit; an unknown name fails the job naming the cameras there are.
#include "CamerasGltf.h"
#include "ServerTestSupport.h"

namespace vastray::test {
namespace {

TEST_F(ServerTest, SceneCameraOfAJobIsTheCliRendersCamera) {
    startServer();
    auto uploaded = http().Put("/v1/scenes?name=cameras.gltf", kCamerasGltf, "application/octet-stream");
    ASSERT_TRUE(uploaded);
    ASSERT_EQ(uploaded->status, 200) << uploaded->body;
    const std::string sceneId = json::parse(uploaded->body)["id"];
    json far = smallJob(sceneId), near = smallJob(sceneId), fallback = smallJob(sceneId);
    far["scene_camera"] = "Far";
    near["scene_camera"] = "0";
    std::map<std::string, std::string> images;
    for (const auto& [name, body] : {std::pair{"far", far}, {"near", near}, {"default", fallback}}) {
        auto res = submit(body);
        ASSERT_TRUE(res);
        ASSERT_EQ(res->status, 202) << res->body;
        const std::string id = json::parse(res->body)["id"];
        EXPECT_EQ(waitForState(id, "JOB_STATE_SUCCEEDED")["state"], "JOB_STATE_SUCCEEDED");
        images[name] = result(id);
    }
    const std::string flags = "--resolution 32x32 --spp 2";
    EXPECT_EQ(images["far"], cliRender(sceneId, flags + " --camera Far"));
    EXPECT_EQ(images["near"], cliRender(sceneId, flags + " --camera Near"));
    EXPECT_EQ(images["default"], images["near"]) << "without scene_camera the first camera is used";
    EXPECT_NE(images["far"], images["near"]);

    json both = smallJob(sceneId);
    both["scene_camera"] = "Far";
    both["camera"] = {{"eye", {0, 0, 3}}, {"target", {0, 0, 0}}};
    auto refused = submit(both);
    ASSERT_TRUE(refused);
    EXPECT_EQ(refused->status, 400) << refused->body;
    EXPECT_NE(refused->body.find("scene_camera"), std::string::npos) << refused->body;

    json unknown = smallJob(sceneId);
    unknown["scene_camera"] = "Top";
    auto res = submit(unknown);
    ASSERT_TRUE(res && res->status == 202);
    const json failed = waitForState(json::parse(res->body)["id"], "JOB_STATE_FAILED");
    EXPECT_NE(failed.dump().find("scene camera 'Top': no camera of that name or index; the scene has 0 'Near', 1 'Far'"),
              std::string::npos)
        << failed.dump();
}

// A package keeps camera names to 64 bytes: a longer scene_camera can name no camera, so it is
// refused at submit, naming the field and the limit; 64 bytes is still a name to look for.
// Scene.cameras lists the package's cameras (what a client offers for scene_camera) in the
// upload's answer, GetScene and ListScenes alike. Positions are exact in float (node
// translations 3, 6 and 0.5); the fov is yfov 0.8 rad in degrees, within float rounding.
TEST_F(ServerTest, SceneListsItsCameras) {
    startServer();
    auto uploaded = http().Put("/v1/scenes?name=cameras.gltf", kCamerasGltf, "application/octet-stream");
    ASSERT_TRUE(uploaded);
    ASSERT_EQ(uploaded->status, 200) << uploaded->body;
    const std::string sceneId = json::parse(uploaded->body)["id"];
    auto got = http().Get(("/v1/scenes/" + sceneId).c_str());
    ASSERT_TRUE(got && got->status == 200);
    auto listed = http().Get("/v1/scenes");
    ASSERT_TRUE(listed && listed->status == 200);
    const json listedScene = json::parse(listed->body)["scenes"][0];
    for (const json& scene : {json::parse(uploaded->body), json::parse(got->body), listedScene}) {
        const json& cameras = scene["cameras"];
        ASSERT_EQ(cameras.size(), 2u) << scene.dump();
        EXPECT_EQ(cameras[0]["name"], "Near");
        EXPECT_EQ(cameras[0]["index"], 0);
        EXPECT_EQ(cameras[0]["eye"], json({0, 0, 3}));
        EXPECT_EQ(cameras[1]["name"], "Far");
        EXPECT_EQ(cameras[1]["index"], 1);
        EXPECT_EQ(cameras[1]["eye"], json({0.5, 0, 6}));
        EXPECT_EQ(cameras[1]["up"], json({0, 1, 0}));
        EXPECT_NEAR(cameras[1]["fov_y_degrees"].get<double>(), 0.8 * 180 / 3.14159265358979, 1e-4);
        EXPECT_EQ(cameras[1]["target"].size(), 3u);
    }

    auto plain = http().Put("/v1/scenes?name=plain.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
                            "application/octet-stream");
    ASSERT_TRUE(plain && plain->status == 200) << (plain ? plain->body : "");
    EXPECT_EQ(json::parse(plain->body)["cameras"], json::array()) << "a scene without cameras lists none";
}

TEST_F(ServerTest, SceneCameraLongerThan64BytesIsRefusedAtSubmit) {
    startServer();
    auto uploaded = http().Put("/v1/scenes?name=cameras.gltf", kCamerasGltf, "application/octet-stream");
    ASSERT_TRUE(uploaded);
    ASSERT_EQ(uploaded->status, 200) << uploaded->body;
    const std::string sceneId = json::parse(uploaded->body)["id"];
    json tooLong = smallJob(sceneId);
    tooLong["scene_camera"] = std::string(65, 'c');
    auto refused = submit(tooLong);
    ASSERT_TRUE(refused);
    EXPECT_EQ(refused->status, 400) << refused->body;
    EXPECT_NE(refused->body.find("scene_camera: is 65 bytes long (at most 64, the longest camera name a package keeps"),
              std::string::npos)
        << refused->body;

    json longest = smallJob(sceneId);
    longest["scene_camera"] = std::string(64, 'c');
    auto accepted = submit(longest);
    ASSERT_TRUE(accepted);
    EXPECT_EQ(accepted->status, 202) << accepted->body;
    const json failed = waitForState(json::parse(accepted->body)["id"], "JOB_STATE_FAILED");
    EXPECT_NE(failed.dump().find("no camera of that name or index; the scene has 0 'Near', 1 'Far'"), std::string::npos)
        << failed.dump();
}

}  // namespace
}  // namespace vastray::test
