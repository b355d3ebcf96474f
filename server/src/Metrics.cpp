#include "vastray/server/Metrics.h"

#include <algorithm>
#include <cstdio>

namespace vastray::server {
namespace {

// Renders take from well under a second (tests) to hours (large scenes out of core); waits
// in the queue alike.
const std::vector<double> kSecondsBuckets = {0.01, 0.05, 0.1, 0.25, 0.5, 1,   2.5,  5,    10,
                                             30,   60,   120, 300,  600, 1800, 3600, 14400};

std::string number(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.17g", value);
    return buffer;
}

}  // namespace

Histogram::Histogram(std::vector<double> upperBounds)
    : bounds_(std::move(upperBounds)), counts_(bounds_.size() + 1, 0) {}

void Histogram::observe(double value) {
    const size_t bucket = size_t(std::lower_bound(bounds_.begin(), bounds_.end(), value) - bounds_.begin());
    std::lock_guard<std::mutex> lock(mutex_);
    ++counts_[bucket];
    sum_ += value;
    ++count_;
}

std::string Histogram::samplesText(const std::string& name, const std::string& labels) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::string prefix = labels.empty() ? "" : labels + ",";
    std::string text;
    uint64_t cumulative = 0;
    for (size_t i = 0; i <= bounds_.size(); ++i) {
        cumulative += counts_[i];
        const std::string le = i < bounds_.size() ? number(bounds_[i]) : "+Inf";
        text += name + "_bucket{" + prefix + "le=\"" + le + "\"} " + std::to_string(cumulative) + "\n";
    }
    const std::string braces = labels.empty() ? "" : "{" + labels + "}";
    text += name + "_sum" + braces + " " + number(sum_) + "\n";
    text += name + "_count" + braces + " " + std::to_string(count_) + "\n";
    return text;
}

Metrics::Metrics()
    : queueWait(kSecondsBuckets),
      durationSucceeded(kSecondsBuckets),
      durationFailed(kSecondsBuckets),
      durationCancelled(kSecondsBuckets) {}

void Metrics::countRequest(const std::string& frontEnd, const std::string& code) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++requests_[{frontEnd, code}];
}

std::string Metrics::requestsText() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::string text =
        "# HELP vastray_requests_total Requests answered, by front end and canonical status code name (HTTP "
        "statuses mapped as docs/SERVICE.md says).\n"
        "# TYPE vastray_requests_total counter\n";
    for (const auto& [key, count] : requests_)
        text += "vastray_requests_total{frontend=\"" + key.first + "\",code=\"" + key.second + "\"} " +
                std::to_string(count) + "\n";
    return text;
}

std::string Metrics::histogramsText() const {
    std::string text =
        "# HELP vastray_job_queue_wait_seconds Time from a job's submission to the start of each of its "
        "attempts.\n"
        "# TYPE vastray_job_queue_wait_seconds histogram\n";
    text += queueWait.samplesText("vastray_job_queue_wait_seconds", "");
    text +=
        "# HELP vastray_job_duration_seconds Time from a job's start to its final state, by that state.\n"
        "# TYPE vastray_job_duration_seconds histogram\n";
    text += durationSucceeded.samplesText("vastray_job_duration_seconds", "state=\"SUCCEEDED\"");
    text += durationFailed.samplesText("vastray_job_duration_seconds", "state=\"FAILED\"");
    text += durationCancelled.samplesText("vastray_job_duration_seconds", "state=\"CANCELLED\"");
    return text;
}

}  // namespace vastray::server
