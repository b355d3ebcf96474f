// `vastray serve` start-up: the Vulkan device opens before the server reports ready, so a
// --gpu-device that does not exist stops the start at once with a message naming the devices;
// --backend embree opens no Vulkan device at all.
#include <chrono>
#include <regex>

#include "ServerTestSupport.h"

namespace vastray::test {
namespace {

// More devices than any machine has.
constexpr int kMissingDevice = 1000;

TEST_F(ServerTest, MissingGpuDeviceFailsAtStartNamingTheDevices) {
    // The device a default start picks, as the ready log names it.
    startServer({"--backend", "vulkan"});
    std::smatch m;
    const std::string readyLog = server_.log();
    ASSERT_TRUE(std::regex_search(readyLog, m, std::regex("backend vulkan on Vulkan device ([^\n]+)\n")))
        << readyLog;
    const std::string deviceName = m[1];
    server_.kill(SIGTERM);

    const auto start = std::chrono::steady_clock::now();
    // Under `timeout`: a server that started anyway is killed and the test fails, not hangs.
    const CommandResult run = runShell("timeout 60 " + std::string(VASTRAY_BINARY) + " serve --data-dir " +
                                         (dir_ / "bad").string() +
                                         " --grpc 127.0.0.1:0 --http 127.0.0.1:0 --backend vulkan --gpu-device " +
                                         std::to_string(kMissingDevice));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_NE(run.exitCode, 0) << run.output;
    EXPECT_NE(run.exitCode, 124) << "still running after 60 s: " << run.output;
    EXPECT_LT(seconds, 20.0) << "fails at start, not at the first job";
    EXPECT_EQ(run.output.find("ready"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("--gpu-device " + std::to_string(kMissingDevice) + ": Vulkan: there is no device " +
                              std::to_string(kMissingDevice)),
              std::string::npos)
        << run.output;
    EXPECT_NE(run.output.find("[0] "), std::string::npos) << "lists the devices: " << run.output;
    EXPECT_NE(run.output.find(deviceName), std::string::npos) << "names " << deviceName << ": " << run.output;
}

TEST_F(ServerTest, EmbreeBackendOpensNoVulkanDevice) {
    // A device index that does not exist is not even looked at.
    startServer({"--backend", "embree", "--gpu-device", std::to_string(kMissingDevice)});
    EXPECT_NE(server_.log().find("backend embree\n"), std::string::npos) << server_.log();
    EXPECT_EQ(server_.log().find("Vulkan device"), std::string::npos) << server_.log();
}

}  // namespace
}  // namespace vastray::test
