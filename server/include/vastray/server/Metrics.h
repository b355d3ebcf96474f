#pragma once
// Counters of the render service, exposed as Prometheus text by Service::metricsText()
// (names in docs/SERVICE.md). Updated from any thread.
#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>

namespace vastray::server {

struct Metrics {
    std::atomic<uint64_t> jobsSubmitted{0};     // new jobs accepted
    std::atomic<uint64_t> jobsRejectedFull{0};  // refused with RESOURCE_EXHAUSTED (queue full)
    std::atomic<uint64_t> jobsSucceeded{0}, jobsFailed{0}, jobsCancelled{0};
    std::atomic<uint64_t> jobsRequeued{0};    // found QUEUED or RUNNING at start
    std::atomic<uint64_t> scenesUploaded{0};  // new scenes stored
    std::atomic<uint64_t> uploadBytes{0};     // bytes received in uploads
    std::atomic<uint64_t> rays{0};
    std::atomic<uint64_t> chunkLoads{0};
    std::atomic<uint64_t> renderMicroseconds{0};
    std::atomic<uint64_t> peakDeviceBytes{0};  // the largest JobStats.peak_device_bytes so far
    // Device time per wavefront kernel over finished jobs (StreamingStats::kKernelNames order).
    static constexpr int kKernels = 5;
    std::atomic<uint64_t> kernelMicroseconds[kKernels] = {};

    void notePeakDeviceBytes(uint64_t bytes) {
        uint64_t seen = peakDeviceBytes.load();
        while (bytes > seen && !peakDeviceBytes.compare_exchange_weak(seen, bytes)) {
        }
    }

    // Requests answered by a front end ("grpc", "http"), by status code name.
    void countRequest(const std::string& frontEnd, const std::string& code);
    std::string requestsText();

private:
    std::mutex mutex_;
    std::map<std::pair<std::string, std::string>, uint64_t> requests_;
};

}  // namespace vastray::server
