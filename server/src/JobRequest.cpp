#include "JobRequest.h"

#include <google/protobuf/util/time_util.h>

#include <chrono>
#include <cmath>
#include <optional>
#include <random>
#include <set>

#include "vastray/core/Camera.h"
#include "vastray/core/EnvironmentMap.h"
#include "vastray/core/RayCone.h"
#include "vastray/server/Sha256.h"

namespace vastray::server {
namespace {

constexpr uint32_t kDefaultPriority = 50, kMaxPriority = 100;
constexpr uint32_t kDefaultMaxDepth = 5;
constexpr size_t kMaxRequestIdLength = 128, kMaxLabels = 32, kMaxLabelKey = 63, kMaxLabelValue = 255;

ServiceStatus checkRange(const char* field, uint64_t value, uint64_t lo, uint64_t hi) {
    if (value >= lo && value <= hi) return {};
    return invalidArgument(field, std::to_string(value) + " is outside [" + std::to_string(lo) + ", " +
                                      std::to_string(hi) + "]");
}

ServiceStatus checkVector(const std::string& field, const google::protobuf::RepeatedField<float>& v) {
    if (v.size() != 3)
        return invalidArgument(field, "expected 3 numbers x, y, z, got " + std::to_string(v.size()));
    for (float x : v)
        if (!std::isfinite(x)) return invalidArgument(field, "expected finite numbers");
    return {};
}

ServiceStatus normalizeCamera(v1::Camera& camera, bool zUp) {
    if (auto s = checkVector("camera.eye", camera.eye()); !s) return s;
    if (auto s = checkVector("camera.target", camera.target()); !s) return s;
    if (camera.up().empty()) {
        camera.add_up(0);
        camera.add_up(zUp ? 0 : 1);
        camera.add_up(zUp ? 1 : 0);
    }
    if (auto s = checkVector("camera.up", camera.up()); !s) return s;
    if (camera.fov_y_degrees() == 0) camera.set_fov_y_degrees(45);
    if (Status fov = checkFov(camera.fov_y_degrees()); !fov) return invalidArgument("camera.fov_y_degrees", fov.message());
    return {};
}

ServiceStatus normalizeOutput(v1::SubmitJobRequest& r) {
    std::set<std::string> seen;
    for (const std::string& aov : r.aovs()) {
        if (!parseAovList(aov))
            return invalidArgument("aovs", "'" + aov + "': expected depth, normal, albedo, primid, chunkid, cost or uv");
        if (!seen.insert(aov).second) return invalidArgument("aovs", "'" + aov + "' given twice");
    }
    if (r.output_format().empty()) r.set_output_format(r.aovs().empty() ? "png" : "exr");
    if (r.output_format() != "png" && r.output_format() != "exr")
        return invalidArgument("output_format", "'" + r.output_format() + "': expected png or exr");
    if (r.output_format() == "png" && !r.aovs().empty())
        return invalidArgument("output_format", "aovs need exr");
    return {};
}

ServiceStatus normalizeLabels(const v1::SubmitJobRequest& r) {
    if (r.labels_size() > int(kMaxLabels))
        return invalidArgument("labels", "more than " + std::to_string(kMaxLabels));
    for (const auto& [key, value] : r.labels()) {
        if (key.empty() || key.size() > kMaxLabelKey)
            return invalidArgument(
                "labels", "key '" + key + "' must have 1.." + std::to_string(kMaxLabelKey) + " characters");
        if (value.size() > kMaxLabelValue)
            return invalidArgument("labels",
                                   "value of '" + key + "' is longer than " + std::to_string(kMaxLabelValue));
    }
    return {};
}

// The environment map's fields, with the ranges of `vastray render --environment-scale` and
// `--environment-rotate`; absent scale means 1.
ServiceStatus normalizeEnvironment(v1::SubmitJobRequest& r) {
    if (!r.has_environment()) return {};
    v1::JobEnvironment& e = *r.mutable_environment();
    if (e.id().empty()) return invalidArgument("environment.id", "required (an environment's id, from UploadEnvironment)");
    if (!isSha256Hex(e.id())) return invalidArgument("environment.id", "expected 64 lowercase hex digits");
    if (!e.has_scale()) e.set_scale(1);
    if (!(e.scale() >= 0 && e.scale() <= kMaxEnvironmentRadiance))
        return invalidArgument("environment.scale", std::to_string(e.scale()) + " is outside [0, 1e18]");
    if (!(std::fabs(e.rotation_degrees()) <= kMaxEnvironmentRotation))
        return invalidArgument("environment.rotation_degrees",
                               std::to_string(e.rotation_degrees()) + " is outside [-360, 360] degrees");
    if (r.integrator() == "ao")
        return invalidArgument("environment", "an environment map lights the path integrator; integrator ao has no lights");
    return {};
}

// SubmitJobRequest.texture_lod, as `vastray render --texture-lod` names the modes. "" is cone:
// requests stored before the field existed render as they did then (cones were the default).
std::optional<TextureLodMode> parseTextureLod(const std::string& name) {
    if (name.empty() || name == textureLodModeName(TextureLodMode::Cone)) return TextureLodMode::Cone;
    if (name == textureLodModeName(TextureLodMode::Finest)) return TextureLodMode::Finest;
    return std::nullopt;
}

ServiceStatus normalizeRender(v1::SubmitJobRequest& r) {
    if (r.scene_id().empty()) return invalidArgument("scene_id", "required");
    if (!isSha256Hex(r.scene_id())) return invalidArgument("scene_id", "expected 64 lowercase hex digits");
    if (auto s = checkRange("width", r.width(), 1, kMaxImageSide); !s) return s;
    if (auto s = checkRange("height", r.height(), 1, kMaxImageSide); !s) return s;
    if (auto s = checkRange("spp", r.spp(), 1, kMaxSamplesPerPixel); !s) return s;
    if (r.integrator().empty()) r.set_integrator("path");
    if (!parseIntegrator(r.integrator()))
        return invalidArgument("integrator", "'" + r.integrator() + "': expected path or ao");
    if (!r.has_max_depth()) r.set_max_depth(kDefaultMaxDepth);
    if (auto s = checkRange("max_depth", r.max_depth(), 0, kMaxDepthLimit); !s) return s;
    if (!parseTextureLod(r.texture_lod()))
        return invalidArgument("texture_lod", "'" + r.texture_lod() + "': expected cone or finest");
    if (r.texture_lod().empty()) r.set_texture_lod(textureLodModeName(TextureLodMode::Cone));
    if (r.up_axis().empty()) r.set_up_axis("y");
    if (r.up_axis() != "y" && r.up_axis() != "z")
        return invalidArgument("up_axis", "'" + r.up_axis() + "': expected y or z");
    if (r.has_sun()) {
        if (auto s = checkVector("sun.direction", r.sun().direction()); !s) return s;
        const auto& d = r.sun().direction();
        if (d[0] == 0 && d[1] == 0 && d[2] == 0) return invalidArgument("sun.direction", "the zero vector");
        if (!std::isfinite(r.sun().intensity()) || r.sun().intensity() < 0 || r.sun().intensity() > kMaxSunIntensity)
            return invalidArgument("sun.intensity", "expected a number in [0, 1000000]");
    }
    if (r.scene_camera().size() > kMaxSceneCameraNameBytes)
        return invalidArgument("scene_camera", "is " + std::to_string(r.scene_camera().size()) + " bytes long (at most " +
                                                   std::to_string(kMaxSceneCameraNameBytes) +
                                                   ", the longest camera name a package keeps: give the name "
                                                   "`vastray info` lists, or the camera's index)");
    if (r.has_camera() && !r.scene_camera().empty())
        return invalidArgument("scene_camera", "and camera exclude each other");
    if (auto s = normalizeEnvironment(r); !s) return s;
    if (r.has_camera()) return normalizeCamera(*r.mutable_camera(), r.up_axis() == "z");
    return {};
}

}  // namespace

ServiceResult<v1::SubmitJobRequest> normalizeSubmitRequest(const v1::SubmitJobRequest& request,
                                                           uint64_t serverMemoryBudget) {
    v1::SubmitJobRequest r = request;
    if (auto s = normalizeRender(r); !s) return s;
    if (auto s = normalizeOutput(r); !s) return s;
    if (auto s = normalizeLabels(r); !s) return s;
    if (r.memory_budget_bytes() == 0) r.set_memory_budget_bytes(serverMemoryBudget);
    if (r.memory_budget_bytes() > serverMemoryBudget)
        return invalidArgument("memory_budget_bytes", std::to_string(r.memory_budget_bytes()) +
                                                          " exceeds the server's --memory-budget of " +
                                                          std::to_string(serverMemoryBudget));
    if (!r.has_priority()) r.set_priority(kDefaultPriority);
    if (auto s = checkRange("priority", r.priority(), 0, kMaxPriority); !s) return s;
    if (r.request_id().size() > kMaxRequestIdLength)
        return invalidArgument("request_id",
                               "longer than " + std::to_string(kMaxRequestIdLength) + " characters");
    if (r.tiles_size() != 0) {
        if (r.tiles_size() != 2) return invalidArgument("tiles", "expected [nx, ny]");
        if (r.tiles(0) < 1 || r.tiles(1) < 1 || r.tiles(0) > r.width() || r.tiles(1) > r.height())
            return invalidArgument("tiles",
                                   "each count must be at least 1 and at most the image's width or height");
        if (uint64_t(r.tiles(0)) * r.tiles(1) > kMaxTiles)
            return invalidArgument("tiles", "more than " + std::to_string(kMaxTiles) + " tiles");
    }
    auto options = renderOptionsOf(r);
    if (!options) return invalidArgument("request", options.message());
    return r;
}

uint32_t tileCount(const v1::SubmitJobRequest& r) {
    return r.tiles_size() == 2 ? r.tiles(0) * r.tiles(1) : 1;
}

PixelBounds tileBounds(const v1::SubmitJobRequest& r, uint32_t tile) {
    const uint32_t nx = r.tiles_size() == 2 ? r.tiles(0) : 1, ny = r.tiles_size() == 2 ? r.tiles(1) : 1;
    const uint32_t column = tile % nx, row = tile / nx;
    return {uint32_t(uint64_t(column) * r.width() / nx), uint32_t(uint64_t(row) * r.height() / ny),
            uint32_t(uint64_t(column + 1) * r.width() / nx), uint32_t(uint64_t(row + 1) * r.height() / ny)};
}

Result<RenderOptions> renderOptionsOf(const v1::SubmitJobRequest& r) {
    RenderOptions options;
    options.width = r.width();
    options.height = r.height();
    options.samplesPerPixel = r.spp();
    auto integrator = parseIntegrator(r.integrator());
    if (!integrator) return integrator.status();
    options.integrator = *integrator;
    options.maxDepth = r.max_depth();
    options.seed = r.seed();
    auto textureLod = parseTextureLod(r.texture_lod());
    if (!textureLod) return Status::error("texture_lod: '" + r.texture_lod() + "': expected cone or finest");
    options.textureLod = *textureLod;
    std::string aovs;
    for (const std::string& aov : r.aovs()) aovs += (aovs.empty() ? "" : ",") + aov;
    auto flags = parseAovList(aovs);
    if (!flags) return flags.status();
    options.aovs = *flags;
    applyUpAxis(r.up_axis() == "z" ? Vec3f{0, 0, 1} : Vec3f{0, 1, 0}, options);  // stored requests: ""
    // As `vastray render --environment` without --sun: the map's bright texels are its sun. The
    // map itself is read when the job runs (Service::jobEnvironmentMap).
    if (r.has_environment() && !r.has_sun()) options.environment.sunIrradiance = {0.0f, 0.0f, 0.0f};
    if (r.has_environment()) options.environment.mapRotationDegrees = r.environment().rotation_degrees();
    if (r.has_sun() && r.sun().direction_size() == 3) {
        const auto& d = r.sun().direction();
        options.environment.sunDirection = {d[0], d[1], d[2]};
        for (int c = 0; c < 3; ++c) options.environment.sunIrradiance[c] = kSunTint[c] * r.sun().intensity();
    }
    if (r.has_camera()) {
        const v1::Camera& c = r.camera();
        options.frameScene = false;
        options.camera.eye = {c.eye(0), c.eye(1), c.eye(2)};
        options.camera.target = {c.target(0), c.target(1), c.target(2)};
        options.camera.up = {c.up(0), c.up(1), c.up(2)};
        options.camera.fovYDegrees = c.fov_y_degrees();
    }
    VASTRAY_TRY(validateRenderOptions(options));
    return options;
}

std::string sceneKey(const std::string& sceneId) { return "scenes/" + sceneId + ".vast"; }

std::string resultKey(const v1::Job& job) {
    return "results/" + job.id() + "." + job.request().output_format();
}

const char* resultContentType(const v1::SubmitJobRequest& request) {
    return request.output_format() == "exr" ? "image/x-exr" : "image/png";
}

const char* jobStateName(v1::JobState state) { return v1::JobState_Name(state).c_str(); }

std::string randomHex(size_t digits) {
    static thread_local std::mt19937_64 random{std::random_device{}()};
    static const char* kHex = "0123456789abcdef";
    std::string text;
    for (size_t i = 0; i < digits; ++i) text += kHex[random() & 15];
    return text;
}

google::protobuf::Timestamp nowTimestamp() {
    const auto micros = std::chrono::duration_cast<std::chrono::microseconds>(
                            std::chrono::system_clock::now().time_since_epoch())
                            .count();
    google::protobuf::Timestamp t;
    t.set_seconds(micros / 1000000);
    t.set_nanos(int32_t(micros % 1000000) * 1000);
    return t;
}

double secondsBetween(const google::protobuf::Timestamp& from, const google::protobuf::Timestamp& to) {
    if (from.seconds() == 0 && from.nanos() == 0) return 0;
    const double seconds = double(to.seconds() - from.seconds()) + 1e-9 * double(to.nanos() - from.nanos());
    return seconds > 0 ? seconds : 0;
}

std::string newJobId() { return "job-" + randomHex(32); }

ServiceResult<uint32_t> pageSize(int32_t requested) {
    constexpr uint32_t kDefaultPageSize = 100, kMaxPageSize = 1000;
    if (requested == 0) return kDefaultPageSize;
    if (requested < 0 || uint32_t(requested) > kMaxPageSize)
        return invalidArgument(
            "page_size", std::to_string(requested) + " is outside [1, " + std::to_string(kMaxPageSize) + "]");
    return uint32_t(requested);
}

ServiceResult<uint64_t> parsePageToken(const std::string& token) {
    if (token.empty()) return uint64_t(0);
    uint64_t value = 0;
    for (char c : token) {
        if (c < '0' || c > '9' || value > (UINT64_MAX - 9) / 10)
            return invalidArgument("page_token", "not a token this server issued");
        value = value * 10 + uint64_t(c - '0');
    }
    return value;
}

bool isFinal(v1::JobState state) {
    return state == v1::JOB_STATE_SUCCEEDED || state == v1::JOB_STATE_FAILED ||
           state == v1::JOB_STATE_CANCELLED;
}

std::string timestampText(const google::protobuf::Timestamp& time) {
    return google::protobuf::util::TimeUtil::ToString(time);
}

std::string failedAttemptsMessage(const v1::Job& job, uint32_t maxAttempts) {
    std::string text = "failed " + std::to_string(job.attempt_errors_size()) + " times (--max-attempts " +
                       std::to_string(maxAttempts) + "); not run again: ";
    for (int i = 0; i < job.attempt_errors_size(); ++i) text += (i ? "; " : "") + job.attempt_errors(i);
    return text;
}

}  // namespace vastray::server
