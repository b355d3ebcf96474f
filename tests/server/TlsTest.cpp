// --tls-cert/--tls-key: both front ends serve TLS with a self-signed certificate made by the
// `openssl` command, and clients that trust it connect.
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>

#include <future>

#include "ServerTestSupport.h"
#include "vastray/v1/render_service.grpc.pb.h"

namespace vastray::test {
namespace {

TEST_F(ServerTest, TlsOnBothFrontEnds) {
    const auto cert = dir_ / "cert.pem", key = dir_ / "key.pem";
    const std::string command =
        "openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj /CN=localhost "
        "-addext subjectAltName=IP:127.0.0.1 -keyout " +
        key.string() + " -out " + cert.string() + " > /dev/null 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << "openssl could not make a certificate";
    startServer({"--tls-cert", cert.string(), "--tls-key", key.string()});

    httplib::SSLClient https("127.0.0.1", server_.httpPort());
    https.set_ca_cert_path(cert.c_str());
    https.enable_server_certificate_verification(true);
    auto res = https.Get("/v1/jobs");
    ASSERT_TRUE(res) << "TLS handshake failed: " << httplib::to_string(res.error());
    EXPECT_EQ(res->status, 200);
    EXPECT_FALSE(http().Get("/healthz")) << "plain HTTP is not served";

    grpc::SslCredentialsOptions ssl;
    ssl.pem_root_certs = readBytes(cert);
    auto channel = grpc::CreateChannel(server_.grpcAddress(), grpc::SslCredentials(ssl));
    auto stub = v1::RenderService::NewStub(channel);
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(30));
    v1::ListJobsResponse jobs;
    const grpc::Status status = stub->ListJobs(&context, {}, &jobs);
    EXPECT_TRUE(status.ok()) << status.error_message();
}

}  // namespace
}  // namespace vastray::test
