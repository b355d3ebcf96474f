// HTTP adapters (cpp-httplib): JSON bodies are the proto messages in their canonical JSON
// mapping (field names as in the .proto), errors are {"error": {"code", "message"}}.
#include <google/protobuf/util/json_util.h>
#include <httplib.h>

#include <fstream>
#include <thread>

#include "OpenApi.h"
#include "vastray/server/FrontEnds.h"

namespace vastray::server {
namespace {

// Connections served at once; an SSE watch holds one for the life of its job.
constexpr size_t kHttpThreads = 32;
// Seconds a client told "queue full" (429) should wait before trying again.
constexpr int kRetryAfterSeconds = 5;
constexpr size_t kMaxJsonBodyBytes = 1u << 20;
const char* kJson = "application/json";

std::string toJson(const google::protobuf::Message& message) {
    google::protobuf::util::JsonPrintOptions options;
    options.always_print_primitive_fields = true;
    options.preserve_proto_field_names = true;
    std::string json;
    (void)google::protobuf::util::MessageToJsonString(message, &json, options);
    return json;
}

ServiceStatus fromJson(const std::string& body, google::protobuf::Message* message) {
    if (body.empty()) return {};
    if (body.size() > kMaxJsonBodyBytes) return invalidArgument("body", "larger than 1 MiB");
    google::protobuf::util::JsonParseOptions options;  // unknown fields are errors
    auto status = google::protobuf::util::JsonStringToMessage(body, message, options);
    if (!status.ok()) return invalidArgument("body", std::string(status.message()));
    return {};
}

std::string escapeJson(const std::string& text) {
    std::string out;
    for (unsigned char c : text) {
        if (c == '"' || c == '\\')
            out += '\\', out += char(c);
        else if (c < 0x20) {
            char buffer[8];
            std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
            out += buffer;
        } else
            out += char(c);
    }
    return out;
}

void writeError(httplib::Response& res, const ServiceStatus& status, int httpStatus = 0) {
    res.status = httpStatus ? httpStatus : httpStatusOf(status.code());
    if (status.code() == StatusCode::ResourceExhausted && res.status == 429)
        res.set_header("Retry-After", std::to_string(kRetryAfterSeconds));
    if (status.code() == StatusCode::Unauthenticated) res.set_header("WWW-Authenticate", "Bearer");
    res.set_content("{\"error\":{\"code\":\"" + std::string(statusCodeName(status.code())) +
                        "\",\"message\":\"" + escapeJson(status.message()) + "\"}}\n",
                    kJson);
}

template <typename T>
void reply(httplib::Response& res, const ServiceResult<T>& result, int okStatus = 200) {
    if (!result) return writeError(res, result.status());
    res.status = okStatus;
    res.set_content(toJson(*result), kJson);
}

ServiceResult<int32_t> intParam(const httplib::Request& req, const char* name) {
    if (!req.has_param(name)) return 0;
    const std::string text = req.get_param_value(name);
    char* end = nullptr;
    const long value = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || value < INT32_MIN || value > INT32_MAX)
        return invalidArgument(name, "'" + text + "' is not an integer");
    return int32_t(value);
}

uint64_t contentLength(const httplib::Request& req) {
    return req.has_header("Content-Length")
               ? std::strtoull(req.get_header_value("Content-Length").c_str(), nullptr, 10)
               : 0;
}

class Routes {
public:
    Routes(Service& service, const FrontEndOptions& options, httplib::Server& server)
        : service_(service), options_(options) {
        server.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
            return authorize(req, res) ? httplib::Server::HandlerResponse::Unhandled
                                       : httplib::Server::HandlerResponse::Handled;
        });
        server.set_error_handler([](const httplib::Request&, httplib::Response& res) {
            if (res.body.empty() && res.status == 404) writeError(res, notFound("no such route"), 404);
        });
        server.set_logger([this](const httplib::Request&, const httplib::Response& res) {
            service_.metrics().countRequest("http", std::to_string(res.status));
        });
        addSceneRoutes(server);
        addJobRoutes(server);
        addOperationalRoutes(server);
    }

private:
    bool authorize(const httplib::Request& req, httplib::Response& res) {
        if (options_.authToken.empty() || req.path == "/healthz" || req.path == "/readyz") return true;
        if (bearerMatches(req.get_header_value("Authorization"), options_.authToken)) return true;
        writeError(res, {StatusCode::Unauthenticated,
                         "missing or wrong bearer token (header 'Authorization: Bearer TOKEN')"});
        return false;
    }

    void addSceneRoutes(httplib::Server& server) {
        server.Put("/v1/scenes",
                   [this](const httplib::Request& req, httplib::Response& res,
                          const httplib::ContentReader& content) { upload(req, res, content); });
        server.Get("/v1/scenes", [this](const httplib::Request& req, httplib::Response& res) {
            v1::ListScenesRequest request;
            auto size = intParam(req, "page_size");
            if (!size) return writeError(res, size.status());
            request.set_page_size(*size);
            request.set_page_token(req.get_param_value("page_token"));
            reply(res, service_.listScenes(request));
        });
        server.Post("/v1/scenes:findMissing", [this](const httplib::Request& req, httplib::Response& res) {
            v1::FindMissingRequest request;
            if (auto s = fromJson(req.body, &request); !s) return writeError(res, s);
            reply(res, service_.findMissing(request));
        });
        server.Get(R"(/v1/scenes/([^/:]+))", [this](const httplib::Request& req, httplib::Response& res) {
            v1::GetSceneRequest request;
            request.set_id(req.matches[1]);
            reply(res, service_.getScene(request));
        });
        server.Delete(R"(/v1/scenes/([^/:]+))", [this](const httplib::Request& req, httplib::Response& res) {
            v1::DeleteSceneRequest request;
            request.set_id(req.matches[1]);
            reply(res, service_.deleteScene(request));
        });
    }

    void upload(const httplib::Request& req, httplib::Response& res, const httplib::ContentReader& content) {
        auto upload = service_.beginUpload(req.get_param_value("name"), contentLength(req));
        // An upload refused for its size is 413 (payload too large), not 429.
        if (!upload)
            return writeError(res, upload.status(),
                              upload.status().code() == StatusCode::ResourceExhausted ? 413 : 0);
        ServiceStatus status;
        content([&](const char* data, size_t size) {
            status = (*upload)->append(data, size);
            return status.isOk();
        });
        if (!status) return writeError(res, status, status.code() == StatusCode::ResourceExhausted ? 413 : 0);
        reply(res, (*upload)->finish());
    }

    void addJobRoutes(httplib::Server& server) {
        server.Post("/v1/jobs",
                    [this](const httplib::Request& req, httplib::Response& res) { submit(req, res); });
        server.Get("/v1/jobs", [this](const httplib::Request& req, httplib::Response& res) {
            v1::ListJobsRequest request;
            auto size = intParam(req, "page_size");
            if (!size) return writeError(res, size.status());
            request.set_page_size(*size);
            request.set_page_token(req.get_param_value("page_token"));
            v1::JobState state = v1::JOB_STATE_UNSPECIFIED;
            if (req.has_param("state") && !v1::JobState_Parse(req.get_param_value("state"), &state))
                return writeError(
                    res, invalidArgument("state",
                                         "'" + req.get_param_value("state") +
                                             "': expected QUEUED, RUNNING, SUCCEEDED, FAILED or CANCELLED"));
            request.set_state(state);
            reply(res, service_.listJobs(request));
        });
        server.Get(R"(/v1/jobs/([^/:]+))", [this](const httplib::Request& req, httplib::Response& res) {
            v1::GetJobRequest request;
            request.set_id(req.matches[1]);
            reply(res, service_.getJob(request));
        });
        // The body is optional. A POST without Content-Length (plain `curl -X POST`) has none:
        // reading it anyway would wait for the connection's read timeout (5 s), then fail.
        server.Post(R"(/v1/jobs/([^/:]+):cancel)",
                    [this](const httplib::Request& req, httplib::Response& res,
                           const httplib::ContentReader& reader) {
                        std::string body;
                        if (req.has_header("Content-Length") || req.has_header("Transfer-Encoding"))
                            reader([&body](const char* data, size_t n) {
                                body.append(data, n);
                                return true;
                            });
                        v1::CancelJobRequest request;
                        if (auto s = fromJson(body, &request); !s) return writeError(res, s);
                        request.set_id(req.matches[1]);
                        reply(res, service_.cancelJob(request));
                    });
        server.Get(
            R"(/v1/jobs/([^/:]+)/events)",
            [this](const httplib::Request& req, httplib::Response& res) { events(req.matches[1], res); });
        server.Get(
            R"(/v1/jobs/([^/:]+)/result)",
            [this](const httplib::Request& req, httplib::Response& res) { result(req.matches[1], res); });
    }

    void submit(const httplib::Request& req, httplib::Response& res) {
        v1::SubmitJobRequest request;
        if (auto s = fromJson(req.body, &request); !s) return writeError(res, s);
        const std::string key = req.get_header_value("Idempotency-Key");
        if (!key.empty() && !request.request_id().empty() && key != request.request_id())
            return writeError(res, invalidArgument("request_id", "differs from the Idempotency-Key header"));
        if (!key.empty()) request.set_request_id(key);
        auto outcome = service_.submitJob(request);
        if (!outcome) return writeError(res, outcome.status());
        res.status = outcome->created ? 202 : 200;
        res.set_header("Location", "/v1/jobs/" + outcome->job.id());
        res.set_content(toJson(outcome->job), kJson);
    }

    // Server-Sent Events: one "event: KIND" + "data: JSON" block per JobEvent; after a final
    // state the stream ends. A failed watch ends with an "error" event.
    void events(const std::string& id, httplib::Response& res) {
        v1::GetJobRequest get;
        get.set_id(id);
        if (auto job = service_.getJob(get); !job) return writeError(res, job.status());
        res.set_header("Cache-Control", "no-cache");
        res.set_chunked_content_provider("text/event-stream", [this, id](size_t, httplib::DataSink& sink) {
            v1::WatchJobRequest request;
            request.set_id(id);
            auto write = [&sink](const std::string& kind, const std::string& data) {
                const std::string block = "event: " + kind + "\ndata: " + data + "\n\n";
                return sink.write(block.data(), block.size());
            };
            ServiceStatus status = service_.watchJob(
                request,
                [&](const v1::JobEvent& event) {
                    return write(v1::JobEvent::Kind_Name(event.kind()), toJson(event));
                },
                [&] { return !sink.is_writable(); });
            if (!status && status.code() != StatusCode::Cancelled)
                write("error", "{\"code\":\"" + std::string(statusCodeName(status.code())) +
                                   "\",\"message\":\"" + escapeJson(status.message()) + "\"}");
            sink.done();
            return true;
        });
    }

    // The image; httplib answers Range requests (206 + Content-Range, 416) from the provider.
    void result(const std::string& id, httplib::Response& res) {
        auto file = service_.resultFile(id);
        if (!file) return writeError(res, file.status());
        res.set_header("Accept-Ranges", "bytes");
        const std::filesystem::path path = file->path;
        res.set_content_provider(
            file->bytes, file->contentType, [path](size_t offset, size_t length, httplib::DataSink& sink) {
                std::ifstream in(path, std::ios::binary);
                in.seekg(std::streamoff(offset));
                std::vector<char> buffer(std::min<size_t>(length, 64u << 10));
                while (length > 0) {
                    const size_t n = std::min(length, buffer.size());
                    if (!in.read(buffer.data(), std::streamsize(n)) || !sink.write(buffer.data(), n))
                        return false;
                    length -= n;
                }
                return true;
            });
    }

    void addOperationalRoutes(httplib::Server& server) {
        server.Get("/healthz", [](const httplib::Request&, httplib::Response& res) {
            res.set_content("ok\n", "text/plain");
        });
        server.Get("/readyz", [this](const httplib::Request&, httplib::Response& res) {
            const bool ready = service_.ready();
            res.status = ready ? 200 : 503;
            res.set_content(ready ? "ready\n" : "not ready\n", "text/plain");
        });
        server.Get("/metrics", [this](const httplib::Request&, httplib::Response& res) {
            res.set_content(service_.metricsText(), "text/plain; version=0.0.4");
        });
        server.Get("/openapi.json", [](const httplib::Request&, httplib::Response& res) {
            res.set_content(openApiDocument(), kJson);
        });
    }

    Service& service_;
    FrontEndOptions options_;
};

}  // namespace

struct HttpFrontEnd::Impl {
    std::unique_ptr<httplib::Server> server;
    std::unique_ptr<Routes> routes;
    std::thread thread;
};

Result<std::unique_ptr<HttpFrontEnd>> HttpFrontEnd::start(Service& service, const std::string& address,
                                                          const FrontEndOptions& options) {
    auto hostPort = splitHostPort(address);
    if (!hostPort) return hostPort.status();
    std::unique_ptr<HttpFrontEnd> front(new HttpFrontEnd());
    front->impl_ = std::make_unique<Impl>();
    auto& server = front->impl_->server;
    if (options.tlsCertFile.empty()) {
        server = std::make_unique<httplib::Server>();
    } else {
        server =
            std::make_unique<httplib::SSLServer>(options.tlsCertFile.c_str(), options.tlsKeyFile.c_str());
        if (!server->is_valid()) return Status::error("HTTP: cannot load --tls-cert/--tls-key");
    }
    server->new_task_queue = [] { return new httplib::ThreadPool(kHttpThreads); };
    // Small responses on a kept-alive connection otherwise wait ~40 ms for Nagle's algorithm
    // to meet the client's delayed ACK (measured by bench/load: HTTP p50 43 ms against gRPC 2 ms).
    server->set_tcp_nodelay(true);
    // The largest body is an upload; JSON bodies are bounded again (1 MiB) when parsed.
    server->set_payload_max_length(service.options().maxUploadBytes);
    front->impl_->routes = std::make_unique<Routes>(service, options, *server);
    const auto& [host, port] = *hostPort;
    front->port_ =
        port == 0 ? server->bind_to_any_port(host) : (server->bind_to_port(host, port) ? port : -1);
    if (front->port_ <= 0) return Status::error("HTTP: cannot listen on " + address);
    front->impl_->thread = std::thread([s = server.get()] { s->listen_after_bind(); });
    return front;
}

HttpFrontEnd::~HttpFrontEnd() { stop(); }

void HttpFrontEnd::stop() {
    if (!impl_ || !impl_->server) return;
    impl_->server->stop();
    if (impl_->thread.joinable()) impl_->thread.join();
    impl_->server.reset();
}

}  // namespace vastray::server
