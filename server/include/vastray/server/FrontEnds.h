#pragma once
// The two front ends of the render service, both thin adapters over Service: they check the
// bearer token, translate messages (HTTP: JSON mapped from the proto messages), call one
// Service function and map its ServiceStatus to a gRPC status or an HTTP status.
#include <chrono>
#include <memory>
#include <string>

#include "vastray/core/Result.h"
#include "vastray/server/Service.h"

namespace vastray::server {

struct FrontEndOptions {
    std::string authToken;  // empty: no authentication; else "authorization: Bearer TOKEN" required
    std::string tlsCertFile, tlsKeyFile;  // both empty: plain text
};

// Largest `data` of one UploadSceneRequest and of one GetResultResponse.
constexpr size_t kMaxStreamChunkBytes = 1u << 20;

// gRPC: SceneService, RenderService, grpc.health.v1.Health and server reflection.
class GrpcFrontEnd {
public:
    // `address` is HOST:PORT; port 0 picks a free port (see port()).
    static Result<std::unique_ptr<GrpcFrontEnd>> start(Service& service, const std::string& address,
                                                       const FrontEndOptions& options);
    ~GrpcFrontEnd();
    int port() const { return port_; }
    // Health turns NOT_SERVING, new calls are refused, calls in flight get `deadline`.
    void shutdown(std::chrono::milliseconds deadline);

private:
    GrpcFrontEnd() = default;
    struct Impl;
    std::unique_ptr<Impl> impl_;
    int port_ = 0;
};

// HTTP/1.1 (cpp-httplib) on its own thread; routes in docs/SERVICE.md.
class HttpFrontEnd {
public:
    static Result<std::unique_ptr<HttpFrontEnd>> start(Service& service, const std::string& address,
                                                       const FrontEndOptions& options);
    ~HttpFrontEnd();
    int port() const { return port_; }
    void stop();

private:
    HttpFrontEnd() = default;
    struct Impl;
    std::unique_ptr<Impl> impl_;
    int port_ = 0;
};

// "HOST:PORT" (IPv6 as "[::1]:PORT") into host and port; port 0..65535.
Result<std::pair<std::string, int>> splitHostPort(const std::string& address);
// Constant-time check of an "authorization" header value against "Bearer TOKEN".
bool bearerMatches(const std::string& header, const std::string& token);

}  // namespace vastray::server
