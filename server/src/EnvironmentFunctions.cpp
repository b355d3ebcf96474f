// Environment maps in the service: uploads (content-addressed by SHA-256, as scenes), decoded on
// upload with readEnvironmentMap, the function `vastray render --environment` reads its file
// with, so that a file the CLI refuses is refused here; listing, deletion, and the map a job
// renders with.
#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>

#include "JobRequest.h"
#include "vastray/core/FilePath.h"
#include "vastray/server/Service.h"

namespace vastray::server {
namespace {

namespace fs = std::filesystem;

// "exr" or "hdr" by the file's magic bytes (OpenEXR's 76 2f 31 01, Radiance's "#?"); empty for
// anything else.
std::string environmentFormat(const fs::path& file) {
    char head[4] = {};
    std::ifstream in(file, std::ios::binary);
    in.read(head, sizeof head);
    if (std::memcmp(head, "\x76\x2f\x31\x01", 4) == 0) return "exr";
    if (std::memcmp(head, "#?", 2) == 0) return "hdr";
    return "";
}

std::string replaceAll(std::string text, const std::string& from, const std::string& to) {
    for (size_t at = 0; (at = text.find(from, at)) != std::string::npos; at += to.size())
        text.replace(at, from.size(), to);
    return text;
}

ServiceStatus checkEnvironmentId(const std::string& id) {
    if (!isSha256Hex(id)) return invalidArgument("id", "expected 64 lowercase hex digits");
    return {};
}

}  // namespace

std::string environmentKey(const v1::Environment& environment) {
    return "environments/" + environment.id() + "." + environment.format();
}

ServiceResult<std::unique_ptr<SceneUpload>> Service::beginEnvironmentUpload(const std::string& name,
                                                                             uint64_t expectedBytes) {
    const uint64_t maxBytes = std::min(options_.maxUploadBytes, kMaxEnvironmentUploadBytes);
    if (ServiceStatus s = checkUploadStart(name, expectedBytes, maxBytes); !s) return s;
    const std::string ext = lowerExtension(name);
    if (ext != ".exr" && ext != ".hdr")
        return invalidArgument("name", "'" + name +
                                           "': an environment map is an OpenEXR (.exr) or Radiance (.hdr) file");
    const fs::path file = objects_->scratchDir() / ("environment-" + randomHex(16) + ".part");
    auto upload = std::unique_ptr<SceneUpload>(new SceneUpload(*this, name, file, maxBytes));
    if (!upload->out_) return internalError(file.string() + ": cannot create");
    return upload;
}

ServiceResult<v1::Environment> SceneUpload::finishEnvironment() {
    if (finished_) return ServiceStatus{StatusCode::FailedPrecondition, "upload already finished"};
    out_.close();
    if (!out_) return internalError(file_.string() + ": write failed");
    if (bytes_ == 0) return invalidArgument("data", name_ + ": the upload is empty");
    auto environment = service_.storeEnvironment(name_, file_, hash_.finishHex(), bytes_);
    std::error_code error;
    fs::remove(file_, error);
    finished_ = true;
    return environment;
}

ServiceResult<v1::Environment> Service::storeEnvironment(const std::string& name, const fs::path& file,
                                                         const std::string& digest, uint64_t bytes) {
    auto known = stores_.environments->getEnvironment(digest);
    if (!known) return internalError(known.message());
    if (*known) return **known;
    v1::Environment environment;
    environment.set_id(digest);
    environment.set_name(name);
    environment.set_format(environmentFormat(file));
    environment.set_upload_bytes(bytes);
    if (environment.format() != lowerExtension(name).substr(1))
        return invalidArgument("data", name + ": not an " +
                                           (lowerExtension(name) == ".exr" ? "OpenEXR" : "Radiance .hdr") +
                                           " file (its first bytes are not that format's magic number)");
    // The image reader picks the format by the extension: the scratch file gets the right one.
    const fs::path image = objects_->scratchDir() / (digest + "-" + randomHex(8) + "." + environment.format());
    std::error_code error;
    fs::rename(file, image, error);
    if (error) return internalError(image.string() + ": " + error.message());
    // One decode at a time, uploads and jobs together: a small file may decode to the texel limit
    // (2^26 texels, about 2.5 GB of host memory while the map is built).
    auto map = [&] {
        std::lock_guard<std::mutex> lock(environmentMutex_);
        return readEnvironmentMap(image.string());
    }();
    if (!map) {
        fs::remove(image, error);
        std::string why = replaceAll(map.message(), image.string(), name);
        if (why.rfind("--environment: ", 0) == 0) why = why.substr(std::strlen("--environment: "));
        if (why.rfind(name, 0) != 0) why = name + ": " + why;
        return invalidArgument("data", why);
    }
    environment.set_width((*map)->width);
    environment.set_height((*map)->height);
    environment.set_device_bytes((*map)->deviceBytes());
    *environment.mutable_create_time() = nowTimestamp();
    if (Status stored = objects_->put(environmentKey(environment), image); !stored) {
        fs::remove(image, error);
        return internalError(stored.message());
    }
    auto inserted = stores_.environments->insertEnvironment(environment);
    if (!inserted) return internalError(inserted.message());
    return *inserted;
}

ServiceResult<v1::Environment> Service::getEnvironment(const v1::GetEnvironmentRequest& request) {
    if (ServiceStatus s = checkEnvironmentId(request.id()); !s) return s;
    auto environment = stores_.environments->getEnvironment(request.id());
    if (!environment) return internalError(environment.message());
    if (!*environment) return notFound("no environment " + request.id());
    return **environment;
}

ServiceResult<v1::ListEnvironmentsResponse> Service::listEnvironments(const v1::ListEnvironmentsRequest& request) {
    auto size = pageSize(request.page_size());
    if (!size) return size.status();
    auto after = parsePageToken(request.page_token());
    if (!after) return after.status();
    auto page = stores_.environments->listEnvironments(*after, *size);
    if (!page) return internalError(page.message());
    v1::ListEnvironmentsResponse response;
    for (auto& environment : page->environments) *response.add_environments() = std::move(environment);
    if (page->more) response.set_next_page_token(std::to_string(page->last));
    return response;
}

ServiceResult<v1::DeleteEnvironmentResponse> Service::deleteEnvironment(const v1::DeleteEnvironmentRequest& request) {
    if (ServiceStatus s = checkEnvironmentId(request.id()); !s) return s;
    // Under mutex_, as submitJob: no job can take the environment between the check and the delete.
    std::lock_guard<std::mutex> lock(mutex_);
    auto environment = stores_.environments->getEnvironment(request.id());
    if (!environment) return internalError(environment.message());
    if (!*environment) return notFound("no environment " + request.id());
    auto unfinished = stores_.jobs->unfinishedJobs();
    if (!unfinished) return internalError(unfinished.message());
    for (const v1::Job& job : *unfinished)
        if (job.request().has_environment() && job.request().environment().id() == request.id())
            return ServiceStatus{StatusCode::FailedPrecondition,
                                 "environment " + request.id() + " is used by " + job.id() + ", a " +
                                     jobStateName(job.state()) + " job"};
    if (Status removed = stores_.environments->deleteEnvironment(request.id()); !removed)
        return internalError(removed.message());
    if (Status removed = objects_->remove(environmentKey(**environment)); !removed)
        return internalError(removed.message());
    return v1::DeleteEnvironmentResponse();
}

ServiceResult<std::shared_ptr<const EnvironmentMap>> Service::jobEnvironmentMap(
    const v1::SubmitJobRequest& request, std::string& name) {
    if (!request.has_environment()) return std::shared_ptr<const EnvironmentMap>();
    const v1::JobEnvironment& wanted = request.environment();
    const std::string key = wanted.id() + " " + std::to_string(std::bit_cast<uint32_t>(wanted.scale()));
    std::lock_guard<std::mutex> lock(environmentMutex_);
    if (key == environmentKey_ && environmentMap_) {
        name = environmentName_;
        return environmentMap_;
    }
    auto environment = stores_.environments->getEnvironment(wanted.id());
    if (!environment) return internalError(environment.message());
    if (!*environment) return notFound("environment.id: environment " + wanted.id() + " is no longer stored");
    auto path = objects_->localPath(environmentKey(**environment));
    if (!path) return notFound("environment.id: environment " + wanted.id() + " is no longer stored");
    auto map = readEnvironmentMap(path->string(), wanted.scale());
    if (!map) return internalError(map.message());
    environmentMap_.reset();  // the old map's memory goes before the next job's render
    environmentKey_ = key;
    environmentMap_ = std::move(map).value();
    environmentName_ = "environment map " + wanted.id() + " (" + (*environment)->name() + ")";
    name = environmentName_;
    return environmentMap_;
}

}  // namespace vastray::server
