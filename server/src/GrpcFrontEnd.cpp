// gRPC adapters: each handler checks the token, calls one Service function, puts what it
// returns (a Job, a Scene, a JobEvent) into the method's own response message (buf's lint
// rules: one request and one response type per RPC) and converts the ServiceStatus to a
// grpc::Status.
#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>

#include <fstream>

#include "GrpcReflection.h"
#include "grpc/health/v1/health.pb.h"
#include "vastray/server/FrontEnds.h"
#include "vastray/v1/render_service.grpc.pb.h"
#include "vastray/v1/scene_service.grpc.pb.h"

namespace vastray::server {
namespace {

// The names a grpc.health.v1 check may ask about, besides "" (the whole server).
constexpr const char* kHealthServiceNames[] = {v1::SceneService::service_full_name(),
                                               v1::RenderService::service_full_name()};

// What reflection lists (besides itself): our services and the health service.
std::vector<std::string> reflectedServices() {
    std::vector<std::string> names(std::begin(kHealthServiceNames), std::end(kHealthServiceNames));
    names.push_back("grpc.health.v1.Health");
    return names;
}

// A request message carries at most one upload chunk plus its name.
constexpr int kMaxReceiveBytes = int(kMaxStreamChunkBytes) + (64 << 10);
constexpr int kMaxSendBytes = int(kMaxStreamChunkBytes) + (64 << 10);

class Adapter {
public:
    Adapter(Service& service, const FrontEndOptions& options) : service_(service), options_(options) {}

    // Runs `call` (returning ServiceStatus) once the caller is authenticated.
    template <typename Call>
    grpc::Status handle(grpc::ServerContext* context, Call&& call) {
        ServiceStatus status = authorize(context);
        if (status) status = call();
        service_.metrics().countRequest("grpc", statusCodeName(status.code()));
        return grpc::Status(grpc::StatusCode(int(status.code())), status.message());
    }

    template <typename T, typename Out>
    static ServiceStatus assign(ServiceResult<T> result, Out* out) {
        if (!result) return result.status();
        *out = std::move(*result);
        return {};
    }

    Service& service_;

private:
    ServiceStatus authorize(grpc::ServerContext* context) const {
        if (options_.authToken.empty()) return {};
        const auto& metadata = context->client_metadata();
        auto it = metadata.find("authorization");
        if (it != metadata.end() &&
            bearerMatches(std::string(it->second.data(), it->second.size()), options_.authToken))
            return {};
        return {StatusCode::Unauthenticated,
                "missing or wrong bearer token (metadata 'authorization: Bearer TOKEN')"};
    }

    FrontEndOptions options_;
};

// An upload stream's data (its first message read already) appended to `upload`: every message's
// data at most kMaxStreamChunkBytes; Cancelled when the client went away.
template <typename Message, typename Upload>
ServiceStatus appendStream(grpc::ServerContext* context, grpc::ServerReader<Message>* reader, Message& message,
                           Upload& upload) {
    do {
        if (message.data().size() > kMaxStreamChunkBytes) return invalidArgument("data", "more than 1 MiB in one message");
        if (auto s = upload.append(message.data().data(), message.data().size()); !s) return s;
    } while (reader->Read(&message));
    if (context->IsCancelled()) return {StatusCode::Cancelled, "the client cancelled the upload"};
    return {};
}

class SceneServiceImpl final : public v1::SceneService::Service {
public:
    explicit SceneServiceImpl(Adapter& adapter) : a_(adapter) {}

    grpc::Status UploadScene(grpc::ServerContext* context, grpc::ServerReader<v1::UploadSceneRequest>* reader,
                             v1::UploadSceneResponse* response) override {
        return a_.handle(context, [&]() -> ServiceStatus {
            v1::UploadSceneRequest message;
            if (!reader->Read(&message)) return invalidArgument("name", "the upload stream is empty");
            const bool async = message.async();
            auto upload = a_.service_.beginUpload(message.name(), 0);
            if (!upload) return upload.status();
            if (auto s = appendStream(context, reader, message, **upload); !s) return s;
            return Adapter::assign((*upload)->finish(async), response->mutable_scene());
        });
    }
    grpc::Status FindMissing(grpc::ServerContext* context, const v1::FindMissingRequest* request,
                             v1::FindMissingResponse* response) override {
        return a_.handle(context,
                         [&] { return Adapter::assign(a_.service_.findMissing(*request), response); });
    }
    grpc::Status GetScene(grpc::ServerContext* context, const v1::GetSceneRequest* request,
                          v1::GetSceneResponse* response) override {
        return a_.handle(context, [&] {
            return Adapter::assign(a_.service_.getScene(*request), response->mutable_scene());
        });
    }
    grpc::Status ListScenes(grpc::ServerContext* context, const v1::ListScenesRequest* request,
                            v1::ListScenesResponse* response) override {
        return a_.handle(context,
                         [&] { return Adapter::assign(a_.service_.listScenes(*request), response); });
    }
    grpc::Status DeleteScene(grpc::ServerContext* context, const v1::DeleteSceneRequest* request,
                             v1::DeleteSceneResponse* response) override {
        return a_.handle(context,
                         [&] { return Adapter::assign(a_.service_.deleteScene(*request), response); });
    }
    grpc::Status UploadEnvironment(grpc::ServerContext* context,
                                   grpc::ServerReader<v1::UploadEnvironmentRequest>* reader,
                                   v1::UploadEnvironmentResponse* response) override {
        return a_.handle(context, [&]() -> ServiceStatus {
            v1::UploadEnvironmentRequest message;
            if (!reader->Read(&message)) return invalidArgument("name", "the upload stream is empty");
            auto upload = a_.service_.beginEnvironmentUpload(message.name(), 0);
            if (!upload) return upload.status();
            if (auto s = appendStream(context, reader, message, **upload); !s) return s;
            return Adapter::assign((*upload)->finishEnvironment(), response->mutable_environment());
        });
    }
    grpc::Status GetEnvironment(grpc::ServerContext* context, const v1::GetEnvironmentRequest* request,
                                v1::GetEnvironmentResponse* response) override {
        return a_.handle(context, [&] {
            return Adapter::assign(a_.service_.getEnvironment(*request), response->mutable_environment());
        });
    }
    grpc::Status ListEnvironments(grpc::ServerContext* context, const v1::ListEnvironmentsRequest* request,
                                  v1::ListEnvironmentsResponse* response) override {
        return a_.handle(context,
                         [&] { return Adapter::assign(a_.service_.listEnvironments(*request), response); });
    }
    grpc::Status DeleteEnvironment(grpc::ServerContext* context, const v1::DeleteEnvironmentRequest* request,
                                   v1::DeleteEnvironmentResponse* response) override {
        return a_.handle(context,
                         [&] { return Adapter::assign(a_.service_.deleteEnvironment(*request), response); });
    }

private:
    Adapter& a_;
};

class RenderServiceImpl final : public v1::RenderService::Service {
public:
    explicit RenderServiceImpl(Adapter& adapter) : a_(adapter) {}

    grpc::Status SubmitJob(grpc::ServerContext* context, const v1::SubmitJobRequest* request,
                           v1::SubmitJobResponse* response) override {
        return a_.handle(context, [&]() -> ServiceStatus {
            auto outcome = a_.service_.submitJob(*request);
            if (!outcome) return outcome.status();
            *response->mutable_job() = std::move(outcome->job);
            return {};
        });
    }
    grpc::Status GetJob(grpc::ServerContext* context, const v1::GetJobRequest* request,
                        v1::GetJobResponse* response) override {
        return a_.handle(
            context, [&] { return Adapter::assign(a_.service_.getJob(*request), response->mutable_job()); });
    }
    grpc::Status ListJobs(grpc::ServerContext* context, const v1::ListJobsRequest* request,
                          v1::ListJobsResponse* response) override {
        return a_.handle(context, [&] { return Adapter::assign(a_.service_.listJobs(*request), response); });
    }
    grpc::Status CancelJob(grpc::ServerContext* context, const v1::CancelJobRequest* request,
                           v1::CancelJobResponse* response) override {
        return a_.handle(context, [&] {
            return Adapter::assign(a_.service_.cancelJob(*request), response->mutable_job());
        });
    }
    grpc::Status WatchJob(grpc::ServerContext* context, const v1::WatchJobRequest* request,
                          grpc::ServerWriter<v1::WatchJobResponse>* writer) override {
        return a_.handle(context, [&] {
            v1::WatchJobResponse response;
            return a_.service_.watchJob(
                *request,
                [&](const v1::JobEvent& event) {
                    *response.mutable_event() = event;
                    return writer->Write(response);
                },
                [&] { return context->IsCancelled(); });
        });
    }
    grpc::Status GetResult(grpc::ServerContext* context, const v1::GetResultRequest* request,
                           grpc::ServerWriter<v1::GetResultResponse>* writer) override {
        return a_.handle(context, [&]() -> ServiceStatus {
            // The bytes to send: a preview PNG made now, or the stored file.
            std::string png;
            std::ifstream in;
            uint64_t total = 0;
            v1::GetResultResponse chunk;
            const bool preview = !request->aov().empty();
            if (preview) {
                auto made = a_.service_.resultPreviewPng(request->job_id(), request->aov());
                if (!made) return made.status();
                png = std::move(*made);
                total = png.size();
                chunk.set_content_type("image/png");
            } else {
                auto file = a_.service_.resultFile(request->job_id());
                if (!file) return file.status();
                in.open(file->path, std::ios::binary);
                if (!in) return internalError(file->path.string() + ": cannot read");
                total = file->bytes;
                chunk.set_content_type(file->contentType);
            }
            if (request->offset() > total)
                return invalidArgument("offset", std::to_string(request->offset()) + " is beyond the end of the " +
                                                     std::to_string(total) + "-byte result");
            const uint64_t rest = total - request->offset();
            uint64_t left = request->limit() == 0 ? rest : std::min<uint64_t>(request->limit(), rest);
            if (!preview) in.seekg(std::streamoff(request->offset()));
            chunk.set_total_bytes(total);
            uint64_t offset = request->offset();
            std::string buffer;
            do {
                buffer.resize(std::min<uint64_t>(left, kMaxStreamChunkBytes));
                if (preview) buffer.assign(png, offset, buffer.size());
                else if (!in.read(buffer.data(), std::streamsize(buffer.size())))
                    return internalError("job " + request->job_id() + ": reading its result failed");
                chunk.set_offset(offset);
                chunk.set_data(buffer);
                if (!writer->Write(chunk)) return {StatusCode::Cancelled, "the client went away"};
                offset += buffer.size();
                left -= buffer.size();
            } while (left > 0);
            return {};
        });
    }

private:
    Adapter& a_;
};

Result<std::string> readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return Status::error(path + ": cannot read");
    return std::string(std::istreambuf_iterator<char>(in), {});
}

Result<std::shared_ptr<grpc::ServerCredentials>> credentials(const FrontEndOptions& options) {
    if (options.tlsCertFile.empty()) return grpc::InsecureServerCredentials();
    auto cert = readFile(options.tlsCertFile);
    if (!cert) return cert.status();
    auto key = readFile(options.tlsKeyFile);
    if (!key) return key.status();
    grpc::SslServerCredentialsOptions ssl;
    ssl.pem_key_cert_pairs.push_back({*key, *cert});
    return grpc::SslServerCredentials(ssl);
}

}  // namespace

struct GrpcFrontEnd::Impl {
    Impl(Service& service, const FrontEndOptions& options)
        : adapter(service, options), scenes(adapter), renders(adapter) {}
    Adapter adapter;
    SceneServiceImpl scenes;
    RenderServiceImpl renders;
    std::unique_ptr<grpc::Service> reflection = makeReflectionService(reflectedServices());
    std::unique_ptr<grpc::Server> server;
};

Result<std::unique_ptr<GrpcFrontEnd>> GrpcFrontEnd::start(Service& service, const std::string& address,
                                                          const FrontEndOptions& options) {
    VASTRAY_TRY(splitHostPort(address));
    auto creds = credentials(options);
    if (!creds) return creds.status();
    std::unique_ptr<GrpcFrontEnd> front(new GrpcFrontEnd());
    front->impl_ = std::make_unique<Impl>(service, options);
    grpc::EnableDefaultHealthCheckService(true);
    // gRPC's health service has no descriptor in protobuf's pool; ours (proto/grpc/health/v1)
    // lets reflection describe it (grpcurl needs that to call Health/Check). Naming it here
    // also keeps its object file in the link.
    if (!grpc::health::v1::HealthCheckRequest::descriptor())
        return Status::error("gRPC: grpc.health.v1 descriptor missing");
    grpc::ServerBuilder builder;
    builder.AddListeningPort(address, *creds, &front->port_);
    builder.SetMaxReceiveMessageSize(kMaxReceiveBytes);
    builder.SetMaxSendMessageSize(kMaxSendBytes);
    builder.RegisterService(&front->impl_->scenes);
    builder.RegisterService(&front->impl_->renders);
    builder.RegisterService(front->impl_->reflection.get());
    front->impl_->server = builder.BuildAndStart();
    if (!front->impl_->server || front->port_ == 0) return Status::error("gRPC: cannot listen on " + address);
    // The default health service knows only the server as a whole (""); a check naming one of
    // our services would answer NOT_FOUND. shutdown() turns them all NOT_SERVING.
    auto* health = front->impl_->server->GetHealthCheckService();
    if (!health) return Status::error("gRPC: the health service did not start");
    for (const char* name : kHealthServiceNames) health->SetServingStatus(name, true);
    return front;
}

GrpcFrontEnd::~GrpcFrontEnd() { shutdown(std::chrono::milliseconds(0)); }

void GrpcFrontEnd::shutdown(std::chrono::milliseconds deadline) {
    if (!impl_ || !impl_->server) return;
    if (auto* health = impl_->server->GetHealthCheckService()) health->Shutdown();
    impl_->server->Shutdown(std::chrono::system_clock::now() + deadline);
    impl_->server->Wait();
    impl_->server.reset();
}

}  // namespace vastray::server
