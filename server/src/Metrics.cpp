#include "vastray/server/Metrics.h"

namespace vastray::server {

void Metrics::countRequest(const std::string& frontEnd, const std::string& code) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++requests_[{frontEnd, code}];
}

std::string Metrics::requestsText() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::string text =
        "# HELP vastray_requests_total Requests answered, by front end and status code.\n"
        "# TYPE vastray_requests_total counter\n";
    for (const auto& [key, count] : requests_)
        text += "vastray_requests_total{frontend=\"" + key.first + "\",code=\"" + key.second + "\"} " +
                std::to_string(count) + "\n";
    return text;
}

}  // namespace vastray::server
