// A job renders a scene's glTF KHR_lights_punctual lights (kept in the package) as `vastray
// render` does: the job's image equals the CLI's, which differs from the CLI's --no-lights one.
// A job with no_lights (HTTP JSON or gRPC) renders what --no-lights renders.
#include <grpcpp/grpcpp.h>

#include "LitFloorGltf.h"
#include "ServerTestSupport.h"
#include "vastray/v1/render_service.grpc.pb.h"

namespace vastray::test {
namespace {

// The floor with a point light half a unit above it.
const std::string kLitFloorGltf = litFloorGltf(R"({"name":"Bulb","type":"point","intensity":4})",
                                               R"({"extensions":{"KHR_lights_punctual":{"light":0}},"translation":[0.3,0.5,0]})");

class SceneLightsJobTest : public ServerTest {
protected:
    std::string uploadLitFloor() {
        auto uploaded = http().Put("/v1/scenes?name=floor.gltf", kLitFloorGltf, "application/octet-stream");
        EXPECT_TRUE(uploaded);
        if (!uploaded) return "";
        EXPECT_EQ(uploaded->status, 200) << uploaded->body;
        return json::parse(uploaded->body)["id"];
    }

    // The finished job's image ("" when it did not succeed).
    std::string renderedImage(const std::string& jobId) {
        if (waitForState(jobId, "JOB_STATE_SUCCEEDED")["state"] != "JOB_STATE_SUCCEEDED") return "";
        return result(jobId);
    }

    std::string renderOverHttp(const json& body) {
        auto res = submit(body);
        EXPECT_TRUE(res);
        if (!res) return "";
        EXPECT_EQ(res->status, 202) << res->body;
        return renderedImage(json::parse(res->body)["id"]);
    }

    std::string renderOverGrpc(const v1::SubmitJobRequest& request) {
        auto channel = grpc::CreateChannel(server_.grpcAddress(), grpc::InsecureChannelCredentials());
        auto renders = v1::RenderService::NewStub(channel);
        grpc::ClientContext context;
        context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
        v1::SubmitJobResponse submitted;
        const grpc::Status status = renders->SubmitJob(&context, request, &submitted);
        EXPECT_TRUE(status.ok()) << status.error_message();
        return status.ok() ? renderedImage(submitted.job().id()) : "";
    }

    // `vastray render --backend embree` of the stored package (cliRender renders with vulkan).
    std::string cliRenderWithEmbree(const std::string& sceneId, const std::string& flags) {
        const auto out = dir_ / ("cli-embree-" + std::to_string(++cliRenders_) + ".png");
        const auto package = dataDir() / "scenes" / (sceneId + ".vast");
        auto run = runVastray("render " + package.string() + " -o " + out.string() +
                              " --backend embree --progress none " + flags);
        EXPECT_EQ(run.exitCode, 0) << run.output;
        return readBytes(out);
    }

    const std::string flags_ = "--resolution 32x32 --spp 2";
};

TEST_F(SceneLightsJobTest, SceneLightsOfAJobAreTheCliRendersLights) {
    startServer();
    const std::string sceneId = uploadLitFloor();
    const std::string image = renderOverHttp(smallJob(sceneId));
    ASSERT_FALSE(image.empty());
    EXPECT_EQ(image, cliRender(sceneId, flags_));
    EXPECT_NE(image, cliRender(sceneId, flags_ + " --no-lights")) << "the light changes nothing";
}

// no_lights turns the scene's lights off as --no-lights does, by HTTP JSON and by gRPC; the
// job's request keeps the field. The server's default backend: vulkan (StreamingJobRenderer).
TEST_F(SceneLightsJobTest, NoLightsRendersAsTheCliWithoutLights) {
    startServer();
    const std::string sceneId = uploadLitFloor();
    const std::string unlit = cliRender(sceneId, flags_ + " --no-lights");
    ASSERT_NE(unlit, cliRender(sceneId, flags_)) << "the light changes nothing";

    json body = smallJob(sceneId);
    body["no_lights"] = true;
    auto res = submit(body);
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 202) << res->body;
    EXPECT_EQ(json::parse(res->body)["request"].value("no_lights", false), true) << res->body;
    EXPECT_EQ(renderedImage(json::parse(res->body)["id"]), unlit) << "HTTP";

    v1::SubmitJobRequest request;
    request.set_scene_id(sceneId);
    request.set_width(32);
    request.set_height(32);
    request.set_spp(2);
    request.set_no_lights(true);
    EXPECT_EQ(renderOverGrpc(request), unlit) << "gRPC";
}

// The Embree job renderer honours no_lights too.
TEST_F(SceneLightsJobTest, NoLightsOnTheEmbreeBackend) {
    startServer({"--backend", "embree"});
    const std::string sceneId = uploadLitFloor();
    json body = smallJob(sceneId);
    const std::string lit = renderOverHttp(body);
    body["no_lights"] = true;
    const std::string unlit = renderOverHttp(body);
    ASSERT_FALSE(unlit.empty());
    EXPECT_NE(lit, unlit) << "no_lights changes nothing";
    EXPECT_EQ(unlit, cliRenderWithEmbree(sceneId, flags_ + " --no-lights"));
    EXPECT_EQ(lit, cliRenderWithEmbree(sceneId, flags_));
}

}  // namespace
}  // namespace vastray::test
