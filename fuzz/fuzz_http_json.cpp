// Fuzzes the JSON bodies of the HTTP front end (POST /v1/jobs, /v1/jobs/{id}:cancel,
// /v1/scenes:findMissing) through what the server does with them: the proto's JSON parser with
// the server's options and size limit (server/src/JsonMessages.h), then, for a job, the
// request's normalization and its render options, and the JSON reply.
#include <cstdint>
#include <string>

#include "JobRequest.h"
#include "JsonMessages.h"
#include "vastray/v1/render_service.pb.h"
#include "vastray/v1/scene_service.pb.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace vastray::server;
    const std::string body(reinterpret_cast<const char*>(data), size);
    vastray::v1::SubmitJobRequest submit;
    if (fromJson(body, &submit)) {
        auto normalized = normalizeSubmitRequest(submit, 4ull << 30);
        if (normalized) (void)renderOptionsOf(*normalized);
        (void)toJson(submit);
    }
    vastray::v1::CancelJobRequest cancel;
    (void)fromJson(body, &cancel);
    vastray::v1::FindMissingRequest missing;
    if (fromJson(body, &missing)) (void)toJson(missing);
    return 0;
}
