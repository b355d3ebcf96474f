// vastray_build_info and the process_* metrics that Prometheus client libraries export by
// convention (same names and units), read from /proc/self on each scrape.
#include <google/protobuf/stubs/common.h>
#include <grpcpp/grpcpp.h>
#include <sys/resource.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "vastray/server/Metrics.h"

namespace vastray::server {
namespace {

std::string metric(const char* name, const char* type, const char* help, const std::string& value) {
    return std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n" + name + " " +
           value + "\n";
}

std::string compilerName() {
#if defined(__clang__)
    return "clang " __clang_version__;
#elif defined(__GNUC__)
    return "gcc " __VERSION__;
#else
    return "unknown";
#endif
}

// Fields of /proc/self/stat after the command name (which may hold spaces): [0] is the state
// (field 3 of proc(5)), so field N of proc(5) is at [N - 3].
std::vector<std::string> statFields() {
    std::ifstream in("/proc/self/stat");
    const std::string line((std::istreambuf_iterator<char>(in)), {});
    std::vector<std::string> fields;
    const size_t close = line.rfind(')');
    if (close == std::string::npos) return fields;
    std::istringstream rest(line.substr(close + 1));
    for (std::string field; rest >> field;) fields.push_back(field);
    return fields;
}

double bootTimeSeconds() {
    std::ifstream in("/proc/stat");
    for (std::string key; in >> key;) {
        if (key == "btime") {
            double seconds = 0;
            in >> seconds;
            return seconds;
        }
        in.ignore(1 << 20, '\n');
    }
    return 0;
}

}  // namespace

std::string buildInfoText() {
    const std::string labels = std::string("version=\"") + VASTRAY_VERSION + "\",build_type=\"" +
                               VASTRAY_BUILD_TYPE + "\",compiler=\"" + compilerName() + "\",grpc=\"" +
                               grpc::Version() + "\",protobuf=\"" +
                               google::protobuf::internal::VersionString(GOOGLE_PROTOBUF_VERSION) + "\"";
    return "# HELP vastray_build_info The build of this server (value 1).\n"
           "# TYPE vastray_build_info gauge\n"
           "vastray_build_info{" +
           labels + "} 1\n";
}

std::string processMetricsText() {
    const std::vector<std::string> f = statFields();
    if (f.size() < 22) return "";  // not Linux: no /proc
    const double ticks = double(::sysconf(_SC_CLK_TCK));
    const double cpuSeconds = (std::stod(f[14 - 3]) + std::stod(f[15 - 3])) / ticks;
    const double startSeconds = bootTimeSeconds() + std::stod(f[22 - 3]) / ticks;
    const uint64_t virtualBytes = std::stoull(f[23 - 3]);
    const uint64_t residentBytes = std::stoull(f[24 - 3]) * uint64_t(::sysconf(_SC_PAGESIZE));
    std::error_code error;
    uint64_t openFds = 0;
    for (auto it = std::filesystem::directory_iterator("/proc/self/fd", error);
         !error && it != std::filesystem::directory_iterator(); it.increment(error))
        ++openFds;
    rlimit limit{};
    ::getrlimit(RLIMIT_NOFILE, &limit);
    return metric("process_cpu_seconds_total", "counter", "User and system CPU time spent in seconds.",
                  std::to_string(cpuSeconds)) +
           metric("process_resident_memory_bytes", "gauge", "Resident memory size in bytes.",
                  std::to_string(residentBytes)) +
           metric("process_virtual_memory_bytes", "gauge", "Virtual memory size in bytes.",
                  std::to_string(virtualBytes)) +
           metric("process_open_fds", "gauge", "Number of open file descriptors.", std::to_string(openFds)) +
           metric("process_max_fds", "gauge", "Maximum number of open file descriptors.",
                  std::to_string(uint64_t(limit.rlim_cur))) +
           metric("process_start_time_seconds", "gauge", "Start time of the process since unix epoch in seconds.",
                  std::to_string(startSeconds));
}

}  // namespace vastray::server
