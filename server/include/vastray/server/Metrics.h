#pragma once
// Counters of the render service, exposed as Prometheus text by Service::metricsText()
// (names in docs/SERVICE.md). Updated from any thread.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace vastray::server {

// A Prometheus histogram with fixed upper bounds (seconds), safe to observe from any thread.
class Histogram {
public:
    explicit Histogram(std::vector<double> upperBounds);
    void observe(double value);
    // The _bucket (cumulative, le="+Inf" last), _sum and _count lines of `name` with `labels`
    // ("state=\"SUCCEEDED\"", or empty); no HELP/TYPE lines.
    std::string samplesText(const std::string& name, const std::string& labels) const;

private:
    const std::vector<double> bounds_;
    mutable std::mutex mutex_;
    std::vector<uint64_t> counts_;  // per bucket, not cumulative; the last one is +Inf
    double sum_ = 0;
    uint64_t count_ = 0;
};

// A gauge whose value is costly to read (a database query): computed at most once per
// `period` however often /metrics is scraped; reads within the period return the last value,
// and concurrent reads wait for the one computation in flight instead of each running one.
// `compute` returns none when it failed: the gauge then reads none (its sample is left out,
// rather than a stale or made-up figure) until the next computation, a period later.
class CachedGauge {
public:
    using Clock = std::chrono::steady_clock;
    CachedGauge(Clock::duration period, std::function<std::optional<uint64_t>()> compute)
        : period_(period), compute_(std::move(compute)) {}
    std::optional<uint64_t> read(Clock::time_point now = Clock::now()) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!computedAt_ || now - *computedAt_ >= period_) {
            value_ = compute_();
            computedAt_ = now;
        }
        return value_;
    }

private:
    const Clock::duration period_;
    const std::function<std::optional<uint64_t>()> compute_;
    std::mutex mutex_;
    std::optional<Clock::time_point> computedAt_;
    std::optional<uint64_t> value_;
};

struct Metrics {
    Metrics();

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

    // Seconds from a job's creation to the start of each of its attempts.
    Histogram queueWait;
    // Seconds from a job's (last) start to its final state, by that state.
    Histogram durationSucceeded, durationFailed, durationCancelled;

    void notePeakDeviceBytes(uint64_t bytes) {
        uint64_t seen = peakDeviceBytes.load();
        while (bytes > seen && !peakDeviceBytes.compare_exchange_weak(seen, bytes)) {
        }
    }

    // Requests answered by a front end ("grpc", "http"), by canonical status code name
    // ("OK", "NOT_FOUND", ...: statusCodeName, or statusCodeNameOfHttp for HTTP responses).
    void countRequest(const std::string& frontEnd, const std::string& code);
    std::string requestsText();
    // vastray_job_queue_wait_seconds and vastray_job_duration_seconds, HELP and TYPE included.
    std::string histogramsText() const;

private:
    std::mutex mutex_;
    std::map<std::pair<std::string, std::string>, uint64_t> requests_;
};

// vastray_build_info (version, build type, compiler, gRPC and protobuf versions) and the
// standard process_* metrics of this process (CPU seconds, resident and virtual memory, open
// and maximum file descriptors, start time), read from /proc/self.
std::string buildInfoText();
std::string processMetricsText();

}  // namespace vastray::server
