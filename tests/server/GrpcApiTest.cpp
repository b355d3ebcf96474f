// The gRPC front end of a real `vastray serve`, driven with the generated C++ stubs, plus
// the health and reflection services through generic calls (no .proto needed, as grpcurl).
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>

#include <future>
#include <set>

#include <google/protobuf/descriptor.pb.h>

#include "CamerasGltf.h"
#include "GrpcUpload.h"
#include "ServerTestSupport.h"
#include "grpc/reflection/v1alpha/reflection.grpc.pb.h"
#include "vastray/v1/render_service.grpc.pb.h"
#include "vastray/v1/scene_service.grpc.pb.h"

namespace vastray::test {
namespace {

class GrpcTest : public ServerTest {
protected:
    void connect() {
        channel_ = grpc::CreateChannel(server_.grpcAddress(), grpc::InsecureChannelCredentials());
        scenes_ = v1::SceneService::NewStub(channel_);
        renders_ = v1::RenderService::NewStub(channel_);
    }

    std::unique_ptr<grpc::ClientContext> context() const {
        auto c = std::make_unique<grpc::ClientContext>();
        c->set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
        if (!token_.empty()) c->AddMetadata("authorization", "Bearer " + token_);
        return c;
    }

    // GetResult's chunks joined (each at the offset the ones before it reached, of `type` when
    // given); the call's status in `status`.
    std::string readResult(const v1::GetResultRequest& request, grpc::Status& status, const std::string& type = "") {
        auto c = context();
        auto chunks = renders_->GetResult(c.get(), request);
        std::string bytes;
        for (v1::GetResultResponse chunk; chunks->Read(&chunk);) {
            EXPECT_EQ(chunk.offset(), request.offset() + bytes.size());
            if (!type.empty()) {
                EXPECT_EQ(chunk.content_type(), type);
            }
            bytes += chunk.data();
        }
        status = chunks->Finish();
        return bytes;
    }

    // Streams the sphere in 64 KiB messages; `scene` is the response's scene.
    grpc::Status upload(v1::Scene* scene) {
        auto c = context();
        return uploadSceneOverGrpc(*scenes_, *c, "sphere.ply", readBytes(spherePath_), 65536, false, scene);
    }

    v1::SubmitJobRequest smallRequest(const std::string& sceneId) const {
        v1::SubmitJobRequest request;
        request.set_scene_id(sceneId);
        request.set_width(32);
        request.set_height(32);
        request.set_spp(2);
        return request;
    }

    // A unary call by method name with raw bytes, as a client without the .proto makes it.
    grpc::Status genericCall(const std::string& method, const std::string& request, std::string* response) {
        grpc::GenericStub stub(channel_);
        grpc::Slice slice(request);
        grpc::ByteBuffer in(&slice, 1), out;
        auto c = context();
        std::promise<grpc::Status> done;
        stub.UnaryCall(c.get(), method, grpc::StubOptions(), &in, &out,
                       [&](grpc::Status s) { done.set_value(s); });
        grpc::Status status = done.get_future().get();
        std::vector<grpc::Slice> slices;
        (void)out.Dump(&slices);
        for (auto& s : slices) response->append(reinterpret_cast<const char*>(s.begin()), s.size());
        return status;
    }

    std::shared_ptr<grpc::Channel> channel_;
    std::unique_ptr<v1::SceneService::Stub> scenes_;
    std::unique_ptr<v1::RenderService::Stub> renders_;
};

TEST_F(GrpcTest, UploadSubmitWatchAndGetResult) {
    startServer();
    connect();
    v1::Scene scene;
    ASSERT_TRUE(upload(&scene).ok());
    EXPECT_EQ(scene.id(), uploadSphere()["id"]) << "gRPC and HTTP uploads of one file are one scene";

    v1::FindMissingRequest find;
    find.add_digests(scene.id());
    find.add_digests(std::string(64, 'b'));
    v1::FindMissingResponse missing;
    ASSERT_TRUE(scenes_->FindMissing(context().get(), find, &missing).ok());
    ASSERT_EQ(missing.missing_size(), 1);
    EXPECT_EQ(missing.missing(0), std::string(64, 'b'));

    v1::SubmitJobResponse submitted;
    ASSERT_TRUE(renders_->SubmitJob(context().get(), smallRequest(scene.id()), &submitted).ok());
    const v1::Job& job = submitted.job();
    EXPECT_EQ(job.state(), v1::JOB_STATE_QUEUED);

    v1::WatchJobRequest watch;
    watch.set_id(job.id());
    auto c = context();
    auto events = renders_->WatchJob(c.get(), watch);
    std::vector<v1::JobEvent> seen;
    for (v1::WatchJobResponse response; events->Read(&response);) seen.push_back(response.event());
    ASSERT_TRUE(events->Finish().ok());
    ASSERT_FALSE(seen.empty());
    EXPECT_EQ(seen.front().kind(), v1::JobEvent::KIND_SNAPSHOT);
    EXPECT_EQ(seen.back().state(), v1::JOB_STATE_SUCCEEDED);

    v1::GetResultRequest get;
    get.set_job_id(job.id());
    grpc::Status status;
    const std::string image = readResult(get, status);
    ASSERT_TRUE(status.ok()) << status.error_message();
    EXPECT_EQ(image, result(job.id())) << "same bytes over gRPC and HTTP";
    get.set_offset(4);
    get.set_limit(10);
    EXPECT_EQ(readResult(get, status), image.substr(4, 10));
    ASSERT_TRUE(status.ok()) << status.error_message();

    // A PNG preview, as HTTP's ?aov= gives it; offset and limit count its bytes.
    v1::GetResultRequest preview;
    preview.set_job_id(job.id());
    preview.set_aov("beauty");
    const std::string png = readResult(preview, status, "image/png");
    ASSERT_TRUE(status.ok()) << status.error_message();
    auto httpPng = http().Get(("/v1/jobs/" + job.id() + "/result?aov=beauty").c_str());
    ASSERT_TRUE(httpPng && httpPng->status == 200);
    EXPECT_EQ(png, httpPng->body) << "the same preview over gRPC and HTTP";
    EXPECT_EQ(png.substr(1, 3), "PNG");
    preview.set_offset(8);
    preview.set_limit(4);
    EXPECT_EQ(readResult(preview, status, "image/png"), png.substr(8, 4));
    ASSERT_TRUE(status.ok()) << status.error_message();
    preview.set_offset(0);
    preview.set_aov("colour");
    EXPECT_EQ(readResult(preview, status), "");
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << status.error_message();
    EXPECT_NE(status.error_message().find("colour"), std::string::npos) << status.error_message();

    v1::SubmitJobRequest again = smallRequest(scene.id());
    again.set_request_id("grpc-1");
    v1::SubmitJobResponse first, second;
    ASSERT_TRUE(renders_->SubmitJob(context().get(), again, &first).ok());
    ASSERT_TRUE(renders_->SubmitJob(context().get(), again, &second).ok());
    EXPECT_EQ(first.job().id(), second.job().id()) << "request_id makes SubmitJob idempotent";

    v1::GetJobRequest getJob;
    getJob.set_id(job.id());
    v1::GetJobResponse got;
    ASSERT_TRUE(renders_->GetJob(context().get(), getJob, &got).ok());
    EXPECT_EQ(got.job().state(), v1::JOB_STATE_SUCCEEDED);
    v1::GetSceneRequest getScene;
    getScene.set_id(scene.id());
    v1::GetSceneResponse stored;
    ASSERT_TRUE(scenes_->GetScene(context().get(), getScene, &stored).ok());
    EXPECT_EQ(stored.scene().id(), scene.id());
}

// Scene.cameras over gRPC: the upload's answer and ListScenes carry the package's cameras in
// file order (positions exact in float; yfov 0.8 rad in degrees within float rounding).
TEST_F(GrpcTest, ScenesListTheirCameras) {
    startServer();
    connect();
    v1::Scene uploaded;
    auto c = context();
    ASSERT_TRUE(uploadSceneOverGrpc(*scenes_, *c, "cameras.gltf", kCamerasGltf, 65536, false, &uploaded).ok());
    v1::ListScenesResponse listed;
    ASSERT_TRUE(scenes_->ListScenes(context().get(), v1::ListScenesRequest(), &listed).ok());
    ASSERT_EQ(listed.scenes_size(), 1);
    for (const v1::Scene& scene : {uploaded, listed.scenes(0)}) {
        ASSERT_EQ(scene.cameras_size(), 2);
        EXPECT_EQ(scene.cameras(0).name(), "Near");
        EXPECT_EQ(scene.cameras(1).name(), "Far");
        EXPECT_EQ(scene.cameras(1).index(), 1u);
        ASSERT_EQ(scene.cameras(1).eye_size(), 3);
        EXPECT_EQ(scene.cameras(1).eye(0), 0.5f);
        EXPECT_EQ(scene.cameras(1).eye(2), 6.0f);
        EXPECT_EQ(scene.cameras(0).eye(2), 3.0f);
        EXPECT_NEAR(scene.cameras(0).fov_y_degrees(), 0.8 * 180 / 3.14159265358979, 1e-4);
    }
}

TEST_F(GrpcTest, ErrorCodes) {
    startServer({"--paused", "--max-queue", "1"});
    connect();
    v1::Scene scene;
    ASSERT_TRUE(upload(&scene).ok());
    v1::SubmitJobResponse submitted;
    v1::SubmitJobRequest bad = smallRequest(scene.id());
    bad.set_spp(0);
    grpc::Status status = renders_->SubmitJob(context().get(), bad, &submitted);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_EQ(status.error_message().rfind("spp:", 0), 0u) << status.error_message();

    status = renders_->SubmitJob(context().get(), smallRequest(std::string(64, 'c')), &submitted);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);

    ASSERT_TRUE(renders_->SubmitJob(context().get(), smallRequest(scene.id()), &submitted).ok());
    const v1::Job job = submitted.job();
    v1::SubmitJobResponse refused;
    status = renders_->SubmitJob(context().get(), smallRequest(scene.id()), &refused);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);

    v1::GetResultRequest get;
    get.set_job_id(job.id());
    auto c = context();
    auto reader = renders_->GetResult(c.get(), get);
    v1::GetResultResponse chunk;
    EXPECT_FALSE(reader->Read(&chunk));
    EXPECT_EQ(reader->Finish().error_code(), grpc::StatusCode::FAILED_PRECONDITION);

    v1::CancelJobRequest cancel;
    cancel.set_id(job.id());
    v1::CancelJobResponse cancelled;
    ASSERT_TRUE(renders_->CancelJob(context().get(), cancel, &cancelled).ok());
    EXPECT_EQ(cancelled.job().state(), v1::JOB_STATE_CANCELLED);
    EXPECT_EQ(renders_->CancelJob(context().get(), cancel, &cancelled).error_code(),
              grpc::StatusCode::FAILED_PRECONDITION);

    v1::GetJobRequest unknown;
    unknown.set_id("job-ffffffffffffffffffffffffffffffff");
    v1::GetJobResponse got;
    EXPECT_EQ(renders_->GetJob(context().get(), unknown, &got).error_code(), grpc::StatusCode::NOT_FOUND);

    // Over the 1 MiB message limit the server sets.
    v1::UploadSceneResponse big;
    auto c2 = context();
    auto writer = scenes_->UploadScene(c2.get(), &big);
    v1::UploadSceneRequest message;
    message.set_name("big.ply");
    message.set_data(std::string((2u << 20), 'x'));
    writer->Write(message);
    writer->WritesDone();
    EXPECT_EQ(writer->Finish().error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
}

TEST_F(GrpcTest, AuthTokenIsRequiredWhenConfigured) {
    const auto tokenFile = dir_ / "token";
    std::ofstream(tokenFile) << "grpc-token";
    startServer({"--auth-token-file", tokenFile.string()});
    connect();
    v1::ListJobsResponse jobs;
    EXPECT_EQ(renders_->ListJobs(context().get(), {}, &jobs).error_code(), grpc::StatusCode::UNAUTHENTICATED);
    token_ = "grpc-token";
    EXPECT_TRUE(renders_->ListJobs(context().get(), {}, &jobs).ok());
    v1::Scene scene;
    EXPECT_TRUE(upload(&scene).ok());
}

TEST_F(GrpcTest, HealthAndReflectionWorkWithoutTheProto) {
    startServer();
    connect();
    // grpc.health.v1.HealthCheckRequest{} is empty; the reply {status: SERVING} is 08 01.
    std::string health;
    ASSERT_TRUE(genericCall("/grpc.health.v1.Health/Check", "", &health).ok());
    EXPECT_EQ(health, std::string("\x08\x01", 2));
    // HealthCheckRequest{service: NAME} (field 1) for each of our services: SERVING too; an
    // unknown name is NOT_FOUND (the health protocol's answer for it).
    for (const std::string name : {"vastray.v1.SceneService", "vastray.v1.RenderService"}) {
        const std::string request = std::string("\x0a") + char(name.size()) + name;
        health.clear();
        const grpc::Status status = genericCall("/grpc.health.v1.Health/Check", request, &health);
        ASSERT_TRUE(status.ok()) << name << ": " << status.error_message();
        EXPECT_EQ(health, std::string("\x08\x01", 2)) << name;
    }
    EXPECT_EQ(genericCall("/grpc.health.v1.Health/Check", std::string("\x0a\x04nope"), &health).error_code(),
              grpc::StatusCode::NOT_FOUND);

    // ServerReflectionRequest{list_services: ""} (field 7) on the bidi reflection stream.
    grpc::GenericStub stub(channel_);
    grpc::CompletionQueue queue;
    auto c = context();
    auto call =
        stub.PrepareCall(c.get(), "/grpc.reflection.v1alpha.ServerReflection/ServerReflectionInfo", &queue);
    void* tag = nullptr;
    bool ok = false;
    call->StartCall(reinterpret_cast<void*>(1));
    ASSERT_TRUE(queue.Next(&tag, &ok) && ok);
    grpc::Slice slice(std::string("\x3a\x00", 2));
    grpc::ByteBuffer request(&slice, 1), response;
    call->WriteLast(request, grpc::WriteOptions(), reinterpret_cast<void*>(2));
    ASSERT_TRUE(queue.Next(&tag, &ok) && ok);
    call->Read(&response, reinterpret_cast<void*>(3));
    ASSERT_TRUE(queue.Next(&tag, &ok) && ok);
    std::vector<grpc::Slice> slices;
    (void)response.Dump(&slices);
    std::string bytes;
    for (auto& s : slices) bytes.append(reinterpret_cast<const char*>(s.begin()), s.size());
    EXPECT_NE(bytes.find("vastray.v1.RenderService"), std::string::npos);
    EXPECT_NE(bytes.find("vastray.v1.SceneService"), std::string::npos);
    EXPECT_NE(bytes.find("grpc.health.v1.Health"), std::string::npos);
    grpc::Status status;
    call->Finish(&status, reinterpret_cast<void*>(4));
    queue.Next(&tag, &ok);
    queue.Shutdown();
    while (queue.Next(&tag, &ok)) {
    }
}

// Reflection sends our .proto files with their comments (the generated C++ descriptors have
// none), the files they import after them, and a named error for what does not exist.
TEST_F(GrpcTest, ReflectionDescribesTheApiWithItsComments) {
    namespace refl = grpc::reflection::v1alpha;
    startServer();
    connect();
    auto stub = refl::ServerReflection::NewStub(channel_);
    auto c = context();
    auto stream = stub->ServerReflectionInfo(c.get());
    refl::ServerReflectionRequest request;
    refl::ServerReflectionResponse response;

    request.set_file_containing_symbol("vastray.v1.RenderService.SubmitJob");
    ASSERT_TRUE(stream->Write(request) && stream->Read(&response));
    ASSERT_TRUE(response.has_file_descriptor_response()) << response.DebugString();
    const auto& files = response.file_descriptor_response().file_descriptor_proto();
    ASSERT_GE(files.size(), 1);
    google::protobuf::FileDescriptorProto file;
    ASSERT_TRUE(file.ParseFromString(files[0]));
    EXPECT_EQ(file.name(), "vastray/v1/render_service.proto");
    ASSERT_GT(file.source_code_info().location_size(), 0) << "sent without its comments";
    bool documented = false;
    for (const auto& location : file.source_code_info().location())
        documented |= location.leading_comments().find("tile") != std::string::npos;
    EXPECT_TRUE(documented) << "no leading comment mentions tiles in render_service.proto";
    std::set<std::string> names;
    for (const std::string& bytes : files) {
        google::protobuf::FileDescriptorProto f;
        ASSERT_TRUE(f.ParseFromString(bytes));
        EXPECT_TRUE(names.insert(f.name()).second) << f.name() << " sent twice";
    }
    for (const std::string& dependency : file.dependency()) EXPECT_TRUE(names.count(dependency)) << dependency;

    request.set_file_by_filename("grpc/health/v1/health.proto");
    ASSERT_TRUE(stream->Write(request) && stream->Read(&response));
    ASSERT_TRUE(response.has_file_descriptor_response()) << response.DebugString();
    ASSERT_TRUE(file.ParseFromString(response.file_descriptor_response().file_descriptor_proto(0)));
    EXPECT_EQ(file.package(), "grpc.health.v1");

    request.set_file_containing_symbol("vastray.v1.NoSuchThing");
    ASSERT_TRUE(stream->Write(request) && stream->Read(&response));
    ASSERT_TRUE(response.has_error_response());
    EXPECT_EQ(response.error_response().error_code(), int(grpc::StatusCode::NOT_FOUND));
    EXPECT_NE(response.error_response().error_message().find("vastray.v1.NoSuchThing"), std::string::npos);
    EXPECT_EQ(response.original_request().file_containing_symbol(), "vastray.v1.NoSuchThing");

    request.set_list_services("");
    ASSERT_TRUE(stream->Write(request) && stream->Read(&response));
    std::set<std::string> services;
    for (const auto& service : response.list_services_response().service()) services.insert(service.name());
    EXPECT_EQ(services, (std::set<std::string>{"vastray.v1.SceneService", "vastray.v1.RenderService",
                                                "grpc.health.v1.Health", "grpc.reflection.v1alpha.ServerReflection"}));

    // A request that asks for nothing gets an error response, and the stream goes on.
    ASSERT_TRUE(stream->Write(refl::ServerReflectionRequest()) && stream->Read(&response));
    ASSERT_TRUE(response.has_error_response()) << response.DebugString();
    EXPECT_EQ(response.error_response().error_code(), int(grpc::StatusCode::INVALID_ARGUMENT));
    EXPECT_NE(response.error_response().error_message().find("message_request is not set"), std::string::npos);
    request.set_file_by_filename("no/such/file.proto");
    ASSERT_TRUE(stream->Write(request) && stream->Read(&response));
    ASSERT_TRUE(response.has_error_response()) << response.DebugString();
    EXPECT_EQ(response.error_response().error_code(), int(grpc::StatusCode::NOT_FOUND));
    stream->WritesDone();
    EXPECT_TRUE(stream->Finish().ok());
}

}  // namespace
}  // namespace vastray::test
