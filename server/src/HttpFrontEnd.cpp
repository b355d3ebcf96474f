// HTTP adapters (cpp-httplib): JSON bodies are the proto messages in their canonical JSON
// mapping (field names as in the .proto), errors are {"error": {"code", "message"}}.
//
// Limits against hostile clients (issue 16). cpp-httplib, vendored in third_party/ at 0.29
// (Debian's 0.11 buffered a request line without bound and had no header count limit),
// is built with them (CMakeLists.txt: vastray_httplib): request line and header lines 8 KiB,
// any line 32 KiB, at most 100 headers, at most 1024 ranges with no more than two
// overlapping (coalesced; unsatisfiable ones answer 416), listen backlog 4096. Here: bodies are
// refused from their headers before a byte of them is read, after authentication, above what
// the route takes (bodyLimit); unsupported content types are 415; each read waits at most
// kReadTimeoutSeconds; connections get a thread each from a pool that grows to
// kMaxHttpThreads, so that slow clients holding some threads do not stop the others.
#include <httplib.h>

#include <algorithm>
#include <condition_variable>
#include <deque>
#include <fstream>
#include <mutex>
#include <thread>

#include "JsonMessages.h"
#include "OpenApi.h"
#include "WebPage.h"
#include "vastray/server/FrontEnds.h"

namespace vastray::server {

namespace {

// Connections served at once; an SSE watch holds one for the life of its job. The pool grows
// from kHttpThreads to kMaxHttpThreads when every thread is busy (40 slowloris connections
// held all 32 threads of the old fixed pool: /healthz did not answer for 30 s); beyond that,
// up to kMaxQueuedConnections wait and the rest are closed at once.
constexpr size_t kHttpThreads = 32;
constexpr size_t kMaxHttpThreads = 512;
constexpr size_t kMaxQueuedConnections = 4096;
// A client that sends nothing for this long, within a request or between kept-alive ones,
// loses its connection.
constexpr int kReadTimeoutSeconds = 5;
// Seconds a client told "queue full" (429) should wait before trying again.
constexpr int kRetryAfterSeconds = 5;
const char* kJson = "application/json";

// httplib's TaskQueue: one task per accepted connection.
class ElasticThreadPool final : public httplib::TaskQueue {
public:
    ElasticThreadPool() {
        std::lock_guard<std::mutex> lock(mutex_);
        for (size_t i = 0; i < kHttpThreads; ++i) spawnLocked();
    }
    ~ElasticThreadPool() override { shutdown(); }

    bool enqueue(std::function<void()> task) override {
        std::lock_guard<std::mutex> lock(mutex_);
        if (stopping_) return false;
        if (idle_ <= tasks_.size() && threads_.size() < kMaxHttpThreads) spawnLocked();
        if (tasks_.size() >= kMaxQueuedConnections) return false;  // httplib closes the socket
        tasks_.push_back(std::move(task));
        wake_.notify_one();
        return true;
    }

    void shutdown() override {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stopping_ = true;
        }
        wake_.notify_all();
        for (std::thread& t : threads_)
            if (t.joinable()) t.join();
    }

private:
    void spawnLocked() { threads_.emplace_back([this] { run(); }); }

    void run() {
        std::unique_lock<std::mutex> lock(mutex_);
        while (true) {
            ++idle_;
            wake_.wait(lock, [&] { return stopping_ || !tasks_.empty(); });
            --idle_;
            if (tasks_.empty()) return;  // stopping, nothing left to serve
            std::function<void()> task = std::move(tasks_.front());
            tasks_.pop_front();
            lock.unlock();
            task();
            lock.lock();
        }
    }

    std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<std::function<void()>> tasks_;
    std::vector<std::thread> threads_;
    size_t idle_ = 0;
    bool stopping_ = false;
};

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

// ?state=: a JobState's name (JOB_STATE_QUEUED), or the name without its prefix (QUEUED), as
// the states were called before the protos followed buf's lint rules; absent: every state.
ServiceResult<v1::JobState> stateParam(const httplib::Request& req) {
    v1::JobState state = v1::JOB_STATE_UNSPECIFIED;
    if (!req.has_param("state")) return state;
    const std::string text = req.get_param_value("state");
    if (v1::JobState_Parse(text, &state) || v1::JobState_Parse("JOB_STATE_" + text, &state)) return state;
    return invalidArgument("state",
                           "'" + text +
                               "': expected JOB_STATE_QUEUED, JOB_STATE_RUNNING, JOB_STATE_SUCCEEDED, "
                               "JOB_STATE_FAILED or JOB_STATE_CANCELLED (or the same without JOB_STATE_)");
}

uint64_t contentLength(const httplib::Request& req) {
    return req.has_header("Content-Length")
               ? std::strtoull(req.get_header_value("Content-Length").c_str(), nullptr, 10)
               : 0;
}

// The media type without parameters, lower case ("Application/JSON; charset=utf-8" -> "application/json").
std::string mediaType(const httplib::Request& req) {
    std::string type = req.get_header_value("Content-Type");
    type = type.substr(0, type.find(';'));
    while (!type.empty() && type.back() == ' ') type.pop_back();
    std::transform(type.begin(), type.end(), type.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return type;
}

bool isCancelPath(const std::string& path) {
    return path.rfind("/v1/jobs/", 0) == 0 && path.size() > 16 && path.compare(path.size() - 7, 7, ":cancel") == 0;
}

// What a route takes as its body; the pre-routing handler refuses the rest from the headers.
struct BodyRule {
    uint64_t maxBytes = 0;  // 0: the route takes no body
    bool json = false;      // application/json (or curl -d's default form type, or none)
};

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
            service_.metrics().countRequest("http", statusCodeNameOfHttp(res.status));
        });
        addSceneRoutes(server);
        addEnvironmentRoutes(server);
        addJobRoutes(server);
        addOperationalRoutes(server);
        addWebPageRoutes(server);
    }

private:
    bool authorize(const httplib::Request& req, httplib::Response& res) {
        if (options_.authToken.empty() || req.path == "/healthz" || req.path == "/readyz" || isWebPagePath(req.path))
            return admitBody(req, res);
        if (bearerMatches(req.get_header_value("Authorization"), options_.authToken)) return admitBody(req, res);
        writeError(res, {StatusCode::Unauthenticated,
                         "missing or wrong bearer token (header 'Authorization: Bearer TOKEN')"});
        return false;
    }

    BodyRule bodyRule(const httplib::Request& req) const {
        if (req.method == "PUT" && req.path == "/v1/scenes") return {service_.options().maxUploadBytes, false};
        if (req.method == "PUT" && req.path == "/v1/environments")
            return {std::min(service_.options().maxUploadBytes, kMaxEnvironmentUploadBytes), false};
        if (req.method == "POST" &&
            (req.path == "/v1/jobs" || req.path == "/v1/scenes:findMissing" || isCancelPath(req.path)))
            return {kMaxJsonBodyBytes, true};
        return {};
    }

    // Runs before httplib reads any of the body: its size and type are judged from the
    // headers, so an oversized or unwanted body costs the server next to nothing (after an
    // error response httplib reads what follows as the next request line: at most 32 KiB,
    // then it closes the connection).
    bool admitBody(const httplib::Request& req, httplib::Response& res) {
        const bool chunked = req.has_header("Transfer-Encoding");
        const bool hasLength = req.has_header("Content-Length");
        const std::string lengthText = req.get_header_value("Content-Length");
        if (hasLength && (lengthText.empty() || lengthText.find_first_not_of("0123456789") != std::string::npos ||
                          lengthText.size() > 19)) {
            writeError(res, invalidArgument("Content-Length", "'" + lengthText + "' is not a byte count"), 400);
            return false;
        }
        const uint64_t length = hasLength ? std::strtoull(lengthText.c_str(), nullptr, 10) : 0;
        if (!chunked && length == 0) return true;
        const BodyRule rule = bodyRule(req);
        const std::string route = req.method + " " + req.path;
        if (rule.maxBytes == 0) {
            writeError(res, {StatusCode::InvalidArgument, route + " takes no request body"}, 413);
            return false;
        }
        if (length > rule.maxBytes) {
            writeError(res,
                       {StatusCode::ResourceExhausted, "a body of " + std::to_string(length) + " bytes exceeds the " +
                                                           std::to_string(rule.maxBytes) + "-byte limit of " + route},
                       413);
            return false;
        }
        if (chunked && rule.json) {
            writeError(res, {StatusCode::InvalidArgument, route + " needs a Content-Length (no chunked JSON bodies)"},
                       411);
            return false;
        }
        const std::string type = mediaType(req);
        const bool accepted = rule.json ? (type.empty() || type == "application/json" ||
                                           type == "application/x-www-form-urlencoded")
                                        : type.rfind("multipart/", 0) != 0;
        if (!accepted) {
            writeError(res,
                       {StatusCode::InvalidArgument,
                        "Content-Type '" + type + "' is not accepted by " + route +
                            (rule.json ? " (send application/json)" : " (send the file's bytes as the body)")},
                       415);
            return false;
        }
        return true;
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
        server.Get(R"(/v1/scenes/([^:/]+))", [this](const httplib::Request& req, httplib::Response& res) {
            v1::GetSceneRequest request;
            request.set_id(req.matches[1]);
            reply(res, service_.getScene(request));
        });
        server.Delete(R"(/v1/scenes/([^:/]+))", [this](const httplib::Request& req, httplib::Response& res) {
            v1::DeleteSceneRequest request;
            request.set_id(req.matches[1]);
            reply(res, service_.deleteScene(request));
        });
    }

    void addEnvironmentRoutes(httplib::Server& server) {
        server.Put("/v1/environments",
                   [this](const httplib::Request& req, httplib::Response& res,
                          const httplib::ContentReader& content) { uploadEnvironment(req, res, content); });
        server.Get("/v1/environments", [this](const httplib::Request& req, httplib::Response& res) {
            v1::ListEnvironmentsRequest request;
            auto size = intParam(req, "page_size");
            if (!size) return writeError(res, size.status());
            request.set_page_size(*size);
            request.set_page_token(req.get_param_value("page_token"));
            reply(res, service_.listEnvironments(request));
        });
        server.Get(R"(/v1/environments/([^:/]+))", [this](const httplib::Request& req, httplib::Response& res) {
            v1::GetEnvironmentRequest request;
            request.set_id(req.matches[1]);
            reply(res, service_.getEnvironment(request));
        });
        server.Delete(R"(/v1/environments/([^:/]+))", [this](const httplib::Request& req, httplib::Response& res) {
            v1::DeleteEnvironmentRequest request;
            request.set_id(req.matches[1]);
            reply(res, service_.deleteEnvironment(request));
        });
    }

    // The body into `upload` as it arrives. httplib stops a chunked body (no Content-Length to
    // judge first) before it passes the server's payload limit and reports it only by the
    // reader's false: such a body, or one whose connection broke, was not read to its end and
    // is refused, never stored cut short.
    ServiceStatus receiveBody(const httplib::Request& req, const httplib::ContentReader& content, SceneUpload& upload) {
        ServiceStatus status;
        const bool whole = content([&](const char* data, size_t size) {
            status = upload.append(data, size);
            return status.isOk();
        });
        if (!status || whole) return status;
        return {StatusCode::ResourceExhausted,
                req.get_param_value("name") + ": the upload was cut off before its end (a chunked body over the " +
                    std::to_string(bodyRule(req).maxBytes) + "-byte limit of " + req.method + " " + req.path +
                    ", or a connection that broke)"};
    }

    void uploadEnvironment(const httplib::Request& req, httplib::Response& res,
                           const httplib::ContentReader& content) {
        auto upload = service_.beginEnvironmentUpload(req.get_param_value("name"), contentLength(req));
        if (!upload)
            return writeError(res, upload.status(),
                              upload.status().code() == StatusCode::ResourceExhausted ? 413 : 0);
        const ServiceStatus status = receiveBody(req, content, **upload);
        if (!status) return writeError(res, status, status.code() == StatusCode::ResourceExhausted ? 413 : 0);
        reply(res, (*upload)->finishEnvironment());
    }

    void upload(const httplib::Request& req, httplib::Response& res, const httplib::ContentReader& content) {
        const std::string async = req.get_param_value("async");
        if (async != "" && async != "true" && async != "false")
            return writeError(res, invalidArgument("async", "'" + async + "': expected true or false"));
        auto upload = service_.beginUpload(req.get_param_value("name"), contentLength(req));
        // An upload refused for its size is 413 (payload too large), not 429.
        if (!upload)
            return writeError(res, upload.status(),
                              upload.status().code() == StatusCode::ResourceExhausted ? 413 : 0);
        const ServiceStatus status = receiveBody(req, content, **upload);
        if (!status) return writeError(res, status, status.code() == StatusCode::ResourceExhausted ? 413 : 0);
        auto scene = (*upload)->finish(async == "true");
        // A queued import: 202, the job to watch in Location.
        if (scene && !scene->import_job_id().empty()) res.set_header("Location", "/v1/jobs/" + scene->import_job_id());
        reply(res, scene, scene && !scene->import_job_id().empty() ? 202 : 200);
    }

    // Route patterns: cpp-httplib takes any pattern containing "/:" for a path-parameter
    // pattern ("/users/:id"), so character classes list ':' before '/'.
    void addJobRoutes(httplib::Server& server) {
        server.Post("/v1/jobs",
                    [this](const httplib::Request& req, httplib::Response& res) { submit(req, res); });
        server.Get("/v1/jobs", [this](const httplib::Request& req, httplib::Response& res) {
            v1::ListJobsRequest request;
            auto size = intParam(req, "page_size");
            if (!size) return writeError(res, size.status());
            request.set_page_size(*size);
            request.set_page_token(req.get_param_value("page_token"));
            auto state = stateParam(req);
            if (!state) return writeError(res, state.status());
            request.set_state(*state);
            reply(res, service_.listJobs(request));
        });
        server.Get(R"(/v1/jobs/([^:/]+))", [this](const httplib::Request& req, httplib::Response& res) {
            v1::GetJobRequest request;
            request.set_id(req.matches[1]);
            reply(res, service_.getJob(request));
        });
        // The body is optional. A POST without Content-Length (plain `curl -X POST`) has none:
        // reading it anyway would wait for the connection's read timeout (5 s), then fail.
        server.Post(R"(/v1/jobs/([^:/]+):cancel)",
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
            R"(/v1/jobs/([^:/]+)/events)",
            [this](const httplib::Request& req, httplib::Response& res) { events(req.matches[1], res); });
        server.Get(
            R"(/v1/jobs/([^:/]+)/result)",
            [this](const httplib::Request& req, httplib::Response& res) { result(req.matches[1], req, res); });
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

    // Server-Sent Events: one "event: KIND" + "data: JSON" block per JobEvent (KIND as its
    // `kind` field: KIND_SNAPSHOT, KIND_STATE_CHANGED, KIND_PROGRESS); after a final state the
    // stream ends. A failed watch ends with an "error" event.
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
    // With `aov` or `format=png`: a PNG preview of one channel group (Service::resultPreviewPng).
    void result(const std::string& id, const httplib::Request& req, httplib::Response& res) {
        const std::string format = req.get_param_value("format");
        if (req.has_param("format") && format != "png")
            return writeError(res, invalidArgument("format", "'" + format + "': expected png (leave it out for the file as stored)"));
        if (req.has_param("format") || req.has_param("aov")) {
            auto png = service_.resultPreviewPng(id, req.has_param("aov") ? req.get_param_value("aov") : "beauty");
            if (!png) return writeError(res, png.status());
            res.set_header("Cache-Control", "private, max-age=3600");  // a job's result never changes
            return res.set_content(*png, "image/png");
        }
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
        server.Get("/openapi.json", [this](const httplib::Request&, httplib::Response& res) {
            res.set_content(openApiDocument(!options_.authToken.empty()), kJson);
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
    server->new_task_queue = [] { return new ElasticThreadPool(); };
    server->set_read_timeout(kReadTimeoutSeconds, 0);
    server->set_keep_alive_timeout(kReadTimeoutSeconds);
    // Small responses on a kept-alive connection otherwise wait ~40 ms for Nagle's algorithm
    // to meet the client's delayed ACK (measured by bench/load: HTTP p50 43 ms against gRPC 2 ms).
    server->set_tcp_nodelay(true);
    // The largest body is an upload; every route's own limit is applied before reading (admitBody).
    server->set_payload_max_length(service.options().maxUploadBytes);
    front->impl_->routes = std::make_unique<Routes>(service, options, *server);
    const auto& [host, port] = *hostPort;
    front->port_ =
        port == 0 ? server->bind_to_any_port(host) : (server->bind_to_port(host, port) ? port : -1);
    if (front->port_ <= 0) return Status::error("HTTP: cannot listen on " + address);
    front->impl_->thread = std::thread([s = server.get()] { s->listen_after_bind(); });
    // httplib's stop() does nothing until the listen loop runs: a SIGTERM right after start
    // left the thread in accept() for ever and the join in stop() hung (seen under load).
    server->wait_until_ready();
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
