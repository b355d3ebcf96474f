// Issue 16: the HTTP front end against hostile clients, over raw sockets (a well-behaved
// client library cannot send what these send). Each case names the status it must get.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <sstream>
#include <thread>

#include "ServerTestSupport.h"

namespace vastray::test {
namespace {

// One TCP connection to the server; closes on destruction.
class RawConnection {
public:
    explicit RawConnection(int port) {
        fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in address{};
        address.sin_family = AF_INET;
        address.sin_port = htons(uint16_t(port));
        address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        connected_ = ::connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
    }
    ~RawConnection() {
        if (fd_ >= 0) ::close(fd_);
    }
    bool connected() const { return connected_; }

    // False once the server has closed the connection (or reset it).
    bool send(const std::string& bytes) {
        size_t done = 0;
        while (done < bytes.size()) {
            const ssize_t n = ::send(fd_, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
            if (n <= 0) return false;
            done += size_t(n);
        }
        return true;
    }

    // What the server sends until one whole response is in (headers and Content-Length
    // bytes), it closes, or `seconds` pass.
    std::string receive(double seconds = 10) {
        std::string out;
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
        char buffer[4096];
        while (std::chrono::steady_clock::now() < deadline && !complete(out)) {
            pollfd p{fd_, POLLIN, 0};
            if (::poll(&p, 1, 50) <= 0) continue;
            const ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0);
            if (n <= 0) break;
            out.append(buffer, size_t(n));
        }
        return out;
    }

    // True once the server has closed the connection (within `seconds`).
    bool closedWithin(double seconds) {
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
        char buffer[4096];
        while (std::chrono::steady_clock::now() < deadline) {
            pollfd p{fd_, POLLIN, 0};
            if (::poll(&p, 1, 50) <= 0) continue;
            if (::recv(fd_, buffer, sizeof buffer, 0) <= 0) return true;
        }
        return false;
    }

private:
    static bool complete(const std::string& response) {
        const size_t end = response.find("\r\n\r\n");
        if (end == std::string::npos) return false;
        const size_t at = response.find("Content-Length: ");
        const size_t length = at < end ? std::strtoull(response.c_str() + at + 16, nullptr, 10) : 0;
        return response.size() >= end + 4 + length;
    }

public:

private:
    int fd_ = -1;
    bool connected_ = false;
};

// "HTTP/1.1 413 Payload Too Large\r\n..." -> 413; 0 when nothing came back.
int statusOf(const std::string& response) {
    if (response.rfind("HTTP/1.1 ", 0) != 0) return 0;
    return std::atoi(response.c_str() + 9);
}

class HttpHostileClient : public ServerTest {
protected:
    std::string exchange(const std::string& request, double seconds = 10) {
        RawConnection c(server_.httpPort());
        EXPECT_TRUE(c.connected());
        c.send(request);
        return c.receive(seconds);
    }
};

// 256 MiB without a line end grew the server by 450 MiB, no token needed.
TEST_F(HttpHostileClient, RequestLineWithoutLineEndIsCutOff) {
    startServer();
    RawConnection c(server_.httpPort());
    ASSERT_TRUE(c.connected());
    const std::string chunk(1 << 20, 'A');
    bool accepted = true;
    for (int i = 0; i < 64 && accepted; ++i) accepted = c.send(chunk);
    EXPECT_FALSE(accepted) << "64 MiB of request line were all read";
    EXPECT_EQ(http().Get("/healthz")->status, 200);
}

// 20,000 headers were accepted. The server stops reading at the 101st and closes: the client
// sees 400, or a reset when the rest of its headers were still unread.
TEST_F(HttpHostileClient, TooManyHeadersAreRefused) {
    startServer();
    std::string request = "GET /healthz HTTP/1.1\r\nHost: x\r\n";
    for (int i = 0; i < 20000; ++i) request += "X-H" + std::to_string(i) + ": v\r\n";
    request += "\r\n";
    RawConnection c(server_.httpPort());
    c.send(request);
    const int status = statusOf(c.receive());
    EXPECT_TRUE(status == 400 || status == 0) << status;
    EXPECT_EQ(http().Get("/healthz")->status, 200);
}

TEST_F(HttpHostileClient, HeadersAtTheCountLimitAreServed) {
    startServer();
    std::string request = "GET /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\n";
    for (int i = 0; i < 90; ++i) request += "X-H" + std::to_string(i) + ": v\r\n";
    EXPECT_EQ(statusOf(exchange(request + "\r\n")), 200);
}

// A 2 GiB body announced without a token: 401 at once, from the headers. (The server then
// reads at most one line limit, 32 KiB, of what follows before it closes the connection.)
TEST_F(HttpHostileClient, UnauthenticatedBodyIsRefusedBeforeItIsRead) {
    const auto tokenFile = dir_ / "token";
    std::ofstream(tokenFile) << "s3cret-token\n";
    startServer({"--auth-token-file", tokenFile.string()});
    const auto start = std::chrono::steady_clock::now();
    const std::string response = exchange(
        "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nContent-Length: 2147483648\r\n\r\n");
    EXPECT_EQ(statusOf(response), 401) << response;
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
}

TEST_F(HttpHostileClient, JsonBodyAboveTheRouteLimitIs413FromItsHeaders) {
    startServer();
    const std::string response = exchange(
        "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nContent-Length: 1048577\r\n\r\n");
    EXPECT_EQ(statusOf(response), 413) << response;
    EXPECT_NE(response.find("exceeds the 1048576-byte limit of POST /v1/jobs"), std::string::npos) << response;
}

TEST_F(HttpHostileClient, BodyOnARouteThatTakesNoneIs413) {
    startServer();
    const std::string response = exchange("GET /healthz HTTP/1.1\r\nHost: x\r\nContent-Length: 1000000\r\n\r\n");
    EXPECT_EQ(statusOf(response), 413) << response;
    EXPECT_NE(response.find("GET /healthz takes no request body"), std::string::npos) << response;
}

TEST_F(HttpHostileClient, ChunkedJsonBodyIs411) {
    startServer();
    const std::string response = exchange("POST /v1/jobs HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n");
    EXPECT_EQ(statusOf(response), 411) << response;
}

// multipart/form-data got a 500 with an empty body. Judged from the headers: the body is
// never sent here (unread bytes would make the server's close a reset).
TEST_F(HttpHostileClient, UnsupportedContentTypesAre415) {
    startServer();
    const struct {
        const char* route;
        const char* type;
    } cases[] = {{"PUT /v1/scenes?name=a.ply", "multipart/form-data; boundary=b"},
                 {"POST /v1/jobs", "multipart/form-data; boundary=b"},
                 {"POST /v1/jobs", "application/xml"}};
    for (const auto& c : cases) {
        const std::string response = exchange(std::string(c.route) + " HTTP/1.1\r\nHost: x\r\nContent-Type: " +
                                              c.type + "\r\nContent-Length: 100\r\n\r\n");
        EXPECT_EQ(statusOf(response), 415) << c.route << ": " << response;
        EXPECT_NE(response.find("is not accepted by"), std::string::npos) << response;
    }
}

class HttpRanges : public HttpHostileClient {
protected:
    // A finished 32x32 job; its result's path.
    std::string finishedResult() {
        startServer();
        const json scene = uploadSphere();
        auto res = submit(smallJob(scene["id"]));
        EXPECT_TRUE(res && res->status == 202);
        const std::string id = json::parse(res->body)["id"];
        waitForState(id, "JOB_STATE_SUCCEEDED");
        image_ = result(id);
        return "/v1/jobs/" + id + "/result";
    }
    std::string image_;
};

// Answered 206 with a wrapped 64-bit Content-Length.
TEST_F(HttpRanges, UnsatisfiableRangeIs416) {
    const std::string path = finishedResult();
    auto res = http().Get(path.c_str(), httplib::Headers{{"Range", "bytes=99999999-"}});
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 416);
    EXPECT_TRUE(res->body.empty());
}

// 2,000 overlapping ranges returned 100 times the file.
TEST_F(HttpRanges, ManyOverlappingRangesAre416) {
    const std::string path = finishedResult();
    std::string ranges = "bytes=0-1";  // 2,000 ranges in one header line below its 8 KiB limit
    for (int i = 0; i < 1999; ++i) ranges += ",0-1";
    auto res = http().Get(path.c_str(), httplib::Headers{{"Range", ranges}});
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 416);
    EXPECT_LT(res->body.size(), image_.size());
    // Within the count, more than two overlapping ranges are refused as well.
    res = http().Get(path.c_str(), httplib::Headers{{"Range", "bytes=0-100,10-200,20-300,30-400"}});
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 416);
}

TEST_F(HttpRanges, SatisfiableRangesStillWork) {
    const std::string path = finishedResult();
    auto res = http().Get(path.c_str(), httplib::Headers{{"Range", "bytes=-4"}});
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 206);
    EXPECT_EQ(res->body, image_.substr(image_.size() - 4));
}

// 40 slow-header connections held every thread of the old pool: /healthz stalled for 30 s.
TEST_F(HttpHostileClient, SlowHeaderClientsDoNotStopOthers) {
    startServer();
    std::vector<std::unique_ptr<RawConnection>> slow;
    for (int i = 0; i < 60; ++i) {
        slow.push_back(std::make_unique<RawConnection>(server_.httpPort()));
        slow.back()->send("GET /healthz HTTP/1.1\r\nHost: x\r\n");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const auto start = std::chrono::steady_clock::now();
    auto res = http().Get("/healthz");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 200);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 2.0);
}

// A client that stops sending mid-header is answered 400 after the read timeout (5 s) and
// loses its connection at the latest one keep-alive timeout (5 s) later.
TEST_F(HttpHostileClient, StalledHeaderIsDroppedAfterTheReadTimeout) {
    startServer();
    RawConnection c(server_.httpPort());
    c.send("GET /healthz HTTP/1.1\r\nHost: x\r\n");
    const auto start = std::chrono::steady_clock::now();
    const std::string response = c.receive(15);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(statusOf(response), 400) << response;
    EXPECT_GE(seconds, 4.0);
    EXPECT_LT(seconds, 7.0);
    EXPECT_TRUE(c.closedWithin(7.0)) << "the connection stayed open";
}

// A backlog of 5 reset 41-103 of 200 concurrent submissions. For a listening socket `ss`
// reports the backlog in its Send-Q column.
TEST_F(HttpHostileClient, ListenBacklogIsLikeGrpcs) {
    startServer();
    const CommandResult ss = runShell("ss -ltnH 'sport = :" + std::to_string(server_.httpPort()) + "'");
    ASSERT_EQ(ss.exitCode, 0) << ss.output;
    std::istringstream fields(ss.output);
    std::string state, receiveQueue, sendQueue;
    fields >> state >> receiveQueue >> sendQueue;
    EXPECT_EQ(state, "LISTEN") << ss.output;
    // The kernel caps a backlog at net.core.somaxconn (4096 by default since Linux 5.4).
    int somaxconn = 4096;
    std::ifstream("/proc/sys/net/core/somaxconn") >> somaxconn;
    EXPECT_EQ(sendQueue, std::to_string(std::min(4096, somaxconn))) << ss.output;
    EXPECT_GT(std::min(4096, somaxconn), 5);
}

// Every connection of a burst gets an answer.
TEST_F(HttpHostileClient, BurstOfConcurrentConnectionsAllGetAnAnswer) {
    startServer();
    std::vector<std::unique_ptr<RawConnection>> burst;
    for (int i = 0; i < 300; ++i) burst.push_back(std::make_unique<RawConnection>(server_.httpPort()));
    int answered = 0;
    for (auto& c : burst) {
        ASSERT_TRUE(c->connected());
        if (c->send("GET /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n") && statusOf(c->receive(10)) == 200)
            ++answered;
    }
    EXPECT_EQ(answered, 300);
}

}  // namespace
}  // namespace vastray::test
