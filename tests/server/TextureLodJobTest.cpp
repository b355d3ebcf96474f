// SubmitJobRequest.texture_lod picks the maps' level of detail as `vastray render --texture-lod`
// does (docs/RENDERING.md, "Texture level of detail"): a job's image equals the CLI's render with
// the same mode, on both job renderers; absent is cone; any other value is refused at submit.
#include <grpcpp/grpcpp.h>

#include "TestTextures.h"
#include "ZipUploadSupport.h"
#include "vastray/core/ImageFile.h"
#include "vastray/v1/render_service.grpc.pb.h"

namespace vastray::test {
namespace {

// A 2 x 2 quad at z = 0 facing +z with UVs 0..1 under a 256 x 256 noise base colour map. The
// camera below sees it fill a 32 x 32 image, 8 texels a pixel: cones sample level 3 (one texel a
// pixel), finest level 0, whose texels the 2 samples of a pixel do not average out.
std::string texturedQuadBin() {
    const float positions[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    const float uvs[] = {0, 1, 1, 1, 1, 0, 0, 0};
    const uint16_t indices[] = {0, 1, 2, 0, 2, 3};
    std::string bin(reinterpret_cast<const char*>(positions), sizeof positions);
    bin.append(reinterpret_cast<const char*>(uvs), sizeof uvs);
    bin.append(reinterpret_cast<const char*>(indices), sizeof indices);
    return bin;
}

const char* kTexturedQuadGltf = R"({"asset":{"version":"2.0"},
  "buffers":[{"byteLength":92,"uri":"quad.bin"}],
  "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":32},
                 {"buffer":0,"byteOffset":80,"byteLength":12}],
  "accessors":[{"bufferView":0,"componentType":5126,"type":"VEC3","count":4,"min":[-1,-1,0],"max":[1,1,0]},
               {"bufferView":1,"componentType":5126,"type":"VEC2","count":4},
               {"bufferView":2,"componentType":5123,"type":"SCALAR","count":6}],
  "images":[{"uri":"albedo.png"}],"textures":[{"source":0}],
  "materials":[{"name":"noise","pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],
  "meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1},"indices":2,"material":0}]}],
  "nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0})";

class TextureLodJobTest : public ZipUploadServerTest {
protected:
    std::string uploadTexturedQuad() {
        const Rgba8Image noise = noiseImage(256, 256, 7);
        const auto png = dir_ / "albedo.png";
        const Status written = writeRgba8Png(png.string(), noise.width, noise.height, noise.texels);
        EXPECT_TRUE(written) << written.message();
        const auto zip = dir_ / "quad.zip";
        writeZip(zip, {{"quad.gltf", kTexturedQuadGltf},
                       {"quad.bin", texturedQuadBin()},
                       {"albedo.png", readBytes(png)}});
        auto res = put(zip, "quad.zip");
        EXPECT_TRUE(res);
        if (!res) return "";
        EXPECT_EQ(res->status, 200) << res->body;
        return json::parse(res->body)["id"];
    }

    // smallJob looking at the quad head-on (the CLI's flags: cameraFlags_).
    json job(const std::string& sceneId) {
        json body = smallJob(sceneId);
        body["camera"] = {{"eye", {0, 0, 2.5}}, {"target", {0, 0, 0}}, {"fov_y_degrees", 45}};
        return body;
    }

    // The submitted job's stored request and, once it succeeded, its image ("" otherwise).
    std::pair<json, std::string> renderOverHttp(const json& body) {
        auto res = submit(body);
        EXPECT_TRUE(res);
        if (!res) return {};
        EXPECT_EQ(res->status, 202) << res->body;
        if (res->status != 202) return {};
        const std::string id = json::parse(res->body)["id"];
        if (waitForState(id, "JOB_STATE_SUCCEEDED")["state"] != "JOB_STATE_SUCCEEDED") return {};
        return {json::parse(http().Get(("/v1/jobs/" + id).c_str())->body)["request"], result(id)};
    }

    grpc::Status submitOverGrpc(const std::string& textureLod, v1::SubmitJobResponse* submitted) {
        auto channel = grpc::CreateChannel(server_.grpcAddress(), grpc::InsecureChannelCredentials());
        auto renders = v1::RenderService::NewStub(channel);
        v1::SubmitJobRequest request;
        request.set_scene_id(sceneId_);
        request.set_width(32);
        request.set_height(32);
        request.set_spp(2);
        for (float x : {0.0f, 0.0f, 2.5f}) request.mutable_camera()->add_eye(x);
        for (int i = 0; i < 3; ++i) request.mutable_camera()->add_target(0);
        request.mutable_camera()->set_fov_y_degrees(45);
        request.set_texture_lod(textureLod);
        grpc::ClientContext context;
        context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
        return renders->SubmitJob(&context, request, submitted);
    }

    std::string cliRenderOn(const std::string& backend, const std::string& flags) {
        const auto out = dir_ / ("cli-" + backend + "-" + std::to_string(++cliRenders_) + ".png");
        const auto package = dataDir() / "scenes" / (sceneId_ + ".vast");
        auto run = runVastray("render " + package.string() + " -o " + out.string() + " --backend " + backend +
                              " --progress none " + cameraFlags_ + " " + flags);
        EXPECT_EQ(run.exitCode, 0) << run.output;
        return readBytes(out);
    }

    // The job's finest and absent (cone) renders equal the CLI's on `backend`, and differ (PNG
    // bytes compared with ==: the images are byte for byte the CLI's, and a failure prints no PNG).
    void expectModesRenderAsTheCli(const std::string& backend) {
        sceneId_ = uploadTexturedQuad();
        ASSERT_FALSE(sceneId_.empty());
        const std::string cones = cliRenderOn(backend, "--texture-lod cone"),
                          finest = cliRenderOn(backend, "--texture-lod finest");
        ASSERT_FALSE(cones.empty());
        ASSERT_TRUE(cones != finest) << "the levels must differ for the test to tell the modes apart";

        json body = job(sceneId_);
        const auto [absentRequest, absentImage] = renderOverHttp(body);
        EXPECT_EQ(absentRequest.value("texture_lod", ""), "cone") << "absent is cone: " << absentRequest.dump();
        EXPECT_TRUE(absentImage == cones) << "absent texture_lod";

        body["texture_lod"] = "finest";
        const auto [finestRequest, finestImage] = renderOverHttp(body);
        EXPECT_EQ(finestRequest.value("texture_lod", ""), "finest") << finestRequest.dump();
        EXPECT_TRUE(finestImage == finest) << "texture_lod finest";

        body["texture_lod"] = "cone";
        EXPECT_TRUE(renderOverHttp(body).second == cones) << "texture_lod cone";
    }

    const std::string cameraFlags_ = "--resolution 32x32 --spp 2 --eye 0,0,2.5 --target 0,0,0 --fov 45";
    std::string sceneId_;
};

// The server's default backend: vulkan (StreamingJobRenderer); gRPC too.
TEST_F(TextureLodJobTest, EachModeRendersAsTheCliOnVulkan) {
    startServer();
    expectModesRenderAsTheCli("vulkan");
    v1::SubmitJobResponse submitted;
    const grpc::Status status = submitOverGrpc("finest", &submitted);
    ASSERT_TRUE(status.ok()) << status.error_message();
    EXPECT_EQ(submitted.job().request().texture_lod(), "finest");
    ASSERT_EQ(waitForState(submitted.job().id(), "JOB_STATE_SUCCEEDED")["state"], "JOB_STATE_SUCCEEDED");
    EXPECT_TRUE(result(submitted.job().id()) == cliRenderOn("vulkan", "--texture-lod finest")) << "gRPC";
}

TEST_F(TextureLodJobTest, EachModeRendersAsTheCliOnEmbree) {
    startServer({"--backend", "embree"});
    expectModesRenderAsTheCli("embree");
}

// Refused at submit, naming the field and the modes: HTTP 400 and gRPC INVALID_ARGUMENT, no job.
TEST_F(TextureLodJobTest, AnUnknownModeIsRefusedNamingTheFieldAndTheModes) {
    startServer({"--paused"});
    sceneId_ = uploadSphere()["id"];
    for (const char* bad : {"blurry", "Finest", " cone"}) {
        json body = job(sceneId_);
        body["texture_lod"] = bad;
        auto res = submit(body);
        ASSERT_TRUE(res);
        EXPECT_EQ(res->status, 400) << res->body;
        const json error = json::parse(res->body, nullptr, false).value("error", json::object());
        EXPECT_EQ(error.value("code", ""), "INVALID_ARGUMENT") << res->body;
        EXPECT_EQ(error.value("message", ""), std::string("texture_lod: '") + bad + "': expected cone or finest");
    }
    v1::SubmitJobResponse submitted;
    const grpc::Status status = submitOverGrpc("blurry", &submitted);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << status.error_message();
    EXPECT_EQ(status.error_message(), "texture_lod: 'blurry': expected cone or finest");
    EXPECT_EQ(json::parse(http().Get("/v1/jobs")->body).value("jobs", json::array()).size(), 0u)
        << "a refused job was stored";
}

}  // namespace
}  // namespace vastray::test
