#pragma once
// Submit requests: defaults, validation (each error names the field) and the mapping onto
// the RenderOptions every backend takes.
#include <google/protobuf/timestamp.pb.h>

#include <cstdint>
#include <string>

#include "vastray/core/RenderOptions.h"
#include "vastray/server/ServiceStatus.h"
#include "vastray/v1/render_service.pb.h"
#include "vastray/v1/scene_service.pb.h"

namespace vastray::server {

// The request with every default filled in, or INVALID_ARGUMENT naming the field.
ServiceResult<v1::SubmitJobRequest> normalizeSubmitRequest(const v1::SubmitJobRequest& request,
                                                           uint64_t serverMemoryBudget);
// From a normalized request.
Result<RenderOptions> renderOptionsOf(const v1::SubmitJobRequest& request);

// "scenes/ID.vast" and "results/JOB.png|exr": object keys.
std::string sceneKey(const std::string& sceneId);
// "environments/ID.exr|hdr".
std::string environmentKey(const v1::Environment& environment);
std::string resultKey(const v1::Job& job);
const char* resultContentType(const v1::SubmitJobRequest& request);

const char* jobStateName(v1::JobState state);
// The wall clock now, to the microsecond.
google::protobuf::Timestamp nowTimestamp();
// Seconds from `from` to `to` (0 when `from` is unset or later).
double secondsBetween(const google::protobuf::Timestamp& from, const google::protobuf::Timestamp& to);

// Random lowercase hex digits (not for secrets).
std::string randomHex(size_t digits);
// "job-" and 32 hex digits.
std::string newJobId();
// List paging: page_size 0 means 100, at most 1000; a page token is a decimal position.
ServiceResult<uint32_t> pageSize(int32_t requested);
ServiceResult<uint64_t> parsePageToken(const std::string& token);
bool isFinal(v1::JobState state);
// Tiles of a job (SubmitJobRequest.tiles; 1 when none) and tile i's pixels (row by row), as
// `vastray render --tiles NX,NY --tile I` splits the frame.
constexpr uint32_t kMaxTiles = 1024;
uint32_t tileCount(const v1::SubmitJobRequest& request);
PixelBounds tileBounds(const v1::SubmitJobRequest& request, uint32_t tile);
// The error of a job whose failed attempts reached --max-attempts: every attempt's reason
// (Job.attempt_errors), oldest first.
std::string failedAttemptsMessage(const v1::Job& job, uint32_t maxAttempts);
// RFC 3339, for messages.
std::string timestampText(const google::protobuf::Timestamp& time);

}  // namespace vastray::server
