#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <memory>
#include <mutex>
#include <new>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>
#include <unistd.h>
#include <vector>

#include "Commands.h"
#include "OutputPath.h"
#include "vastray/core/ByteSize.h"
#include "vastray/core/EnvironmentMap.h"
#include "vastray/core/FilePath.h"
#include "vastray/core/ImageFile.h"
#include "vastray/core/Progress.h"
#include "vastray/core/VecMath.h"
#include "vastray/core/RenderMemory.h"
#include "vastray/core/RenderOptions.h"
#include "vastray/cpu/EmbreeRenderer.h"
#include "vastray/gpu/VulkanChunkBackend.h"
#include "vastray/gpu/VulkanDevice.h"
#include "vastray/streamer/Import.h"
#include "vastray/streamer/PackageBuilder.h"
#include "vastray/streamer/ScenePackage.h"
#include "vastray/streamer/StreamingRenderer.h"

namespace vastray::cli {
namespace {

// --tile when not given.
constexpr int64_t kNoTile = -1;

// Vulkan device indices beyond this name no real machine's device.
constexpr int64_t kMaxGpuDevice = 255;

struct RenderArgs {
    std::string input, output, backend = "vulkan", resolution = "640x480";
    std::string memoryBudget = "1GiB", hostCache = "auto", pathState = "auto";
    int64_t gpuDevice = -1;
    std::string camera, eye, target, up, upAxis = "y", sun, integrator = "path", aovs, statsJson, progress = "auto",
                textureLod = "cone";
    bool noSun = false;
    bool noLights = false;
    std::string environment;  // --environment FILE
    double environmentScale = 1.0, environmentRotate = 0.0;
    std::string region, tiles;  // --region X0,Y0,X1,Y1; --tiles NX,NY (with --tile)
    int64_t tile = kNoTile;
    int64_t spp = 16, maxDepth = 5, seed = 0, threads = 0;
    double fov = 45.0;
    bool stats = false;
};

Result<Vec3f> parseVector(const std::string& flag, const std::string& text) {
    Vec3f v;
    const char* at = text.c_str();
    for (int axis = 0; axis < 3; ++axis) {
        char* end = nullptr;
        v[axis] = std::strtof(at, &end);
        if (end == at || !std::isfinite(v[axis]))
            return Status::error(flag + " '" + text + "': expected three finite numbers x,y,z");
        at = end;
        if (axis < 2 && *at++ != ',') return Status::error(flag + " '" + text + "': expected x,y,z");
    }
    if (*at != '\0') return Status::error(flag + " '" + text + "': unexpected text after x,y,z");
    return v;
}

Status parseResolution(const std::string& text, RenderOptions& options) {
    unsigned long long w = 0, h = 0;
    char x = 0, extra = 0;
    if (text.empty() || text[0] == '-' ||
        std::sscanf(text.c_str(), "%llu%c%llu%c", &w, &x, &h, &extra) != 3 || x != 'x')
        return Status::error("--resolution '" + text + "': expected WxH, e.g. 640x480");
    if (w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide)
        return Status::error("--resolution " + text + ": each side must be in [1, " +
                             std::to_string(kMaxImageSide) + "]");
    options.width = uint32_t(w);
    options.height = uint32_t(h);
    return Status::ok();
}

// Comma-separated unsigned integers, exactly `count` of them.
bool parseUnsignedList(const std::string& text, size_t count, std::vector<uint32_t>& values) {
    values.clear();
    const char* at = text.c_str();
    while (values.size() < count) {
        if (!std::isdigit(static_cast<unsigned char>(*at))) return false;
        char* end = nullptr;
        const unsigned long long v = std::strtoull(at, &end, 10);
        if (v > kMaxImageSide) return false;
        values.push_back(uint32_t(v));
        at = end;
        if (values.size() < count && *at++ != ',') return false;
    }
    return *at == '\0';
}

// --region X0,Y0,X1,Y1: pixels [X0, X1) x [Y0, Y1) of the frame, X1 and Y1 exclusive.
Status parseRegion(const std::string& text, RenderOptions& options) {
    std::vector<uint32_t> v;
    if (!parseUnsignedList(text, 4, v))
        return Status::error("--region '" + text + "': expected X0,Y0,X1,Y1 (pixels; X1 and Y1 exclusive)");
    const PixelBounds r{v[0], v[1], v[2], v[3]};
    const std::string frame =
        " (--resolution " + std::to_string(options.width) + "x" + std::to_string(options.height) + ")";
    if (r.x1 > options.width)
        return Status::error("--region " + text + ": X1 " + std::to_string(r.x1) + " is beyond the image width " +
                             std::to_string(options.width) + frame + "; X1 is exclusive, at most the width");
    if (r.y1 > options.height)
        return Status::error("--region " + text + ": Y1 " + std::to_string(r.y1) + " is beyond the image height " +
                             std::to_string(options.height) + frame + "; Y1 is exclusive, at most the height");
    if (r.x0 >= r.x1 || r.y0 >= r.y1)
        return Status::error("--region " + text + ": empty; needs X0 < X1 and Y0 < Y1 (X1 and Y1 are exclusive)");
    options.region = r;
    return Status::ok();
}

// --tile I --tiles NX,NY: tile I (row by row) of an NX x NY grid whose column c spans
// [c * W / NX, (c + 1) * W / NX) (integer division), rows alike: every pixel in exactly one tile.
Status parseTile(const RenderArgs& args, RenderOptions& options) {
    std::vector<uint32_t> n;
    if (!parseUnsignedList(args.tiles, 2, n))
        return Status::error("--tiles '" + args.tiles + "': expected NX,NY (tiles across and down)");
    if (n[0] < 1 || n[1] < 1 || n[0] > options.width || n[1] > options.height)
        return Status::error("--tiles " + args.tiles + ": NX must be in [1, " + std::to_string(options.width) +
                             "] and NY in [1, " + std::to_string(options.height) + "] (the image is " +
                             std::to_string(options.width) + "x" + std::to_string(options.height) + ")");
    const int64_t count = int64_t(n[0]) * n[1];
    if (args.tile < 0 || args.tile >= count)
        return Status::error("--tile " + std::to_string(args.tile) + " is outside [0, " + std::to_string(count - 1) +
                             "] (--tiles " + args.tiles + ")");
    const uint64_t column = uint64_t(args.tile) % n[0], row = uint64_t(args.tile) / n[0];
    const uint64_t w = options.width, h = options.height;
    options.region = PixelBounds{uint32_t(column * w / n[0]), uint32_t(row * h / n[1]),
                                 uint32_t((column + 1) * w / n[0]), uint32_t((row + 1) * h / n[1])};
    return Status::ok();
}

Status parsePixelSet(const RenderArgs& args, RenderOptions& options) {
    const bool tiled = args.tile != kNoTile || !args.tiles.empty();
    if (tiled && !args.region.empty()) return Status::error("--region and --tile/--tiles exclude each other");
    if (tiled && args.tiles.empty()) return Status::error("--tile needs --tiles NX,NY (the grid of tiles)");
    if (tiled && args.tile == kNoTile) return Status::error("--tiles needs --tile I (which tile to render)");
    if (tiled) return parseTile(args, options);
    if (!args.region.empty()) return parseRegion(args.region, options);
    return Status::ok();
}

Status checkRange(const char* flag, int64_t value, int64_t lo, int64_t hi) {
    if (value >= lo && value <= hi) return Status::ok();
    return Status::error(std::string(flag) + " " + std::to_string(value) + " is outside [" +
                         std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

// --sun X,Y,Z,INTENSITY: towards the sun (world space) and its irradiance, in units of the
// default sun's colour kSunTint (the default sun is 3).
Status parseSun(const RenderArgs& args, RenderOptions& options) {
    if (args.noSun && !args.sun.empty()) return Status::error("--sun and --no-sun exclude each other");
    // An environment map brings its own sun (the bright texels): the default sun goes with the sky.
    if (args.noSun || (!args.environment.empty() && args.sun.empty()))
        options.environment.sunIrradiance = {0.0f, 0.0f, 0.0f};
    if (args.sun.empty()) return Status::ok();
    const size_t comma = args.sun.rfind(',');
    const std::string expected = "--sun '" + args.sun + "': expected X,Y,Z,INTENSITY";
    if (comma == std::string::npos) return Status::error(expected);
    auto direction = parseVector("--sun", args.sun.substr(0, comma));
    if (!direction) return Status::error(expected + " (" + direction.message() + ")");
    char* end = nullptr;
    const float intensity = std::strtof(args.sun.c_str() + comma + 1, &end);
    if (end == args.sun.c_str() + comma + 1 || *end != '\0' || !std::isfinite(intensity))
        return Status::error(expected);
    if (intensity < 0.0f || intensity > kMaxSunIntensity)
        return Status::error("--sun: intensity " + args.sun.substr(comma + 1) + " is outside [0, " +
                             std::to_string(int(kMaxSunIntensity)) + "]");
    if (length(*direction) == 0.0f) return Status::error("--sun: the direction is the zero vector");
    options.environment.sunDirection = *direction;
    for (int c = 0; c < 3; ++c) options.environment.sunIrradiance[c] = kSunTint[c] * intensity;
    return Status::ok();
}

// --up-axis turns sky, sun and framing together; --up then sets the camera's up alone (also
// for automatic framing, which looks down along it); --sun sets the sun in world space.
Status parseCamera(const RenderArgs& args, RenderOptions& options) {
    options.camera.fovYDegrees = float(args.fov);
    if (args.upAxis != "y" && args.upAxis != "z")
        return Status::error("--up-axis '" + args.upAxis + "': expected y or z");
    applyUpAxis(args.upAxis == "z" ? Vec3f{0, 0, 1} : Vec3f{0, 1, 0}, options);
    if (!args.up.empty()) {
        auto up = parseVector("--up", args.up);
        if (!up) return up.status();
        if (length(*up) == 0.0f) return Status::error("--up " + args.up + ": the zero vector has no direction");
        options.camera.up = normalize(*up);
    }
    VASTRAY_TRY(parseSun(args, options));
    if (args.eye.empty() != args.target.empty()) return Status::error("--eye and --target go together");
    if (args.eye.empty()) return Status::ok();
    auto eye = parseVector("--eye", args.eye);
    if (!eye) return eye.status();
    auto target = parseVector("--target", args.target);
    if (!target) return target.status();
    options.frameScene = false;
    options.camera.eye = *eye;
    options.camera.target = *target;
    return Status::ok();
}

Status checkOutput(const RenderArgs& args, const RenderOptions& options) {
    const std::string ext = lowerExtension(args.output);
    if (ext != ".png" && ext != ".exr" && ext != ".pfm")
        return Status::error(args.output + ": output must be .png, .exr or .pfm");
    if (ext != ".exr" && options.aovs != kAovNone) return Status::error("--aovs needs an .exr output");
    if (ext == ".pfm" && options.region)
        return Status::error(args.output + ": a .pfm cannot record where a region lies in its frame; use .exr or .png");
    if (args.progress != "auto" && args.progress != "bar" && args.progress != "openjd" &&
        args.progress != "none")
        return Status::error("--progress '" + args.progress + "': expected auto, bar, openjd or none");
    VASTRAY_TRY(checkWritableOutput("--output", args.output));
    if (!args.statsJson.empty()) VASTRAY_TRY(checkWritableOutput("--stats-json", args.statsJson));
    // The image writer is a module loaded on demand: a broken install fails now, not after the
    // render. A .pfm is written without it.
    if (ext == ".pfm") return Status::ok();
    return loadImageModule().withContext(args.output + ": cannot write: ");
}

// The sizes of --memory-budget and --host-cache (read by the vulkan backend only).
struct StreamingSizes {
    uint64_t memoryBudget = 0, hostCache = 0;
    gpu::PathStateMemory pathState = gpu::PathStateMemory::Auto;  // --path-state
};

// Every flag checked and mapped onto RenderOptions (and *sizes) before any file is read.
Result<RenderOptions> optionsFrom(const RenderArgs& args, StreamingSizes* sizes) {
    if (args.backend != "embree" && args.backend != "vulkan")
        return Status::error("--backend '" + args.backend + "': expected vulkan or embree");
    RenderOptions options;
    VASTRAY_TRY(parseResolution(args.resolution, options));
    VASTRAY_TRY(parsePixelSet(args, options));
    VASTRAY_TRY(checkRange("--spp", args.spp, 1, kMaxSamplesPerPixel));
    VASTRAY_TRY(checkRange("--max-depth", args.maxDepth, 0, kMaxDepthLimit));
    VASTRAY_TRY(checkRange("--seed", args.seed, 0, 0xFFFFFFFFll));
    VASTRAY_TRY(checkRange("--threads", args.threads, 0, 4096));
    if (args.gpuDevice < -1 || args.gpuDevice > kMaxGpuDevice)
        return Status::error("--gpu-device " + std::to_string(args.gpuDevice) +
                             ": expected -1 (first discrete GPU) or a device index in [0, " +
                             std::to_string(kMaxGpuDevice) + "]");
    if (!(args.fov >= kMinFovDegrees && args.fov < 180.0)) {
        char text[96];
        std::snprintf(text, sizeof text, "--fov %g is outside [%g, 180) degrees", args.fov, double(kMinFovDegrees));
        return Status::error(text);
    }
    options.samplesPerPixel = uint32_t(args.spp);
    options.maxDepth = uint32_t(args.maxDepth);
    options.seed = uint32_t(args.seed);
    options.threads = uint32_t(args.threads);
    auto integrator = parseIntegrator(args.integrator);
    if (!integrator) return integrator.status();
    options.integrator = *integrator;
    if (args.textureLod != "cone" && args.textureLod != "finest")
        return Status::error("--texture-lod '" + args.textureLod + "' is not one of cone, finest");
    options.textureLod = args.textureLod == "cone" ? TextureLodMode::Cone : TextureLodMode::Finest;
    auto aovs = parseAovList(args.aovs);
    if (!aovs) return aovs.status();
    options.aovs = *aovs;
    if (args.backend == "embree" && (options.aovs & kAovStreamingOnly))
        return Status::error("--aovs chunkid and cost need --backend vulkan (the Embree reference has no chunks)");
    auto budget = parseByteSize(args.memoryBudget);
    if (!budget) return budget.status().withContext("--memory-budget: ");
    if (args.hostCache == "auto") {
        sizes->hostCache = StreamingOptions::kHostCacheAuto;
    } else {
        auto hostCache = parseByteSize(args.hostCache);
        if (!hostCache) return hostCache.status().withContext("--host-cache: ");
        sizes->hostCache = *hostCache;
    }
    sizes->memoryBudget = *budget;
    auto pathState = gpu::parsePathStateMemory(args.pathState);
    if (!pathState) return pathState.status().withContext("--path-state: ");
    sizes->pathState = *pathState;
    if (!(args.environmentScale >= 0.0 && args.environmentScale <= kMaxEnvironmentRadiance))
        return Status::error("--environment-scale " + std::to_string(args.environmentScale) + " is outside [0, 1e18]");
    if (args.environmentScale != 1.0 && args.environment.empty())
        return Status::error("--environment-scale needs --environment");
    if (!(std::fabs(args.environmentRotate) <= kMaxEnvironmentRotation))
        return Status::error("--environment-rotate " + std::to_string(args.environmentRotate) +
                             " is outside [-360, 360] degrees");
    if (args.environmentRotate != 0.0 && args.environment.empty())
        return Status::error("--environment-rotate needs --environment");
    options.environment.mapRotationDegrees = float(args.environmentRotate);
    if (!args.environment.empty() && options.integrator == IntegratorKind::AmbientOcclusion)
        return Status::error("--environment lights the path integrator; --integrator ao has no lights");
    VASTRAY_TRY(parseCamera(args, options));
    VASTRAY_TRY(checkOutput(args, options));
    VASTRAY_TRY(validateRenderOptions(options));
    return options;
}

// Texture maps are imported and stored (docs/RENDERING.md, "Textures"); both backends render base
// colour, metallic-roughness, emissive and normal maps; occlusion maps are applied by neither, by
// design (a path tracer finds the occlusion itself). Say so rather than leave a user to wonder.
void noteUnrenderedMaps(const std::vector<Material>& materials, const std::string& input) {
    size_t occlusion = 0;
    for (const Material& m : materials)
        occlusion += m.textures.slots[uint32_t(TextureSlot::Occlusion)].texture != kNoTexture;
    if (occlusion > 0)
        std::fprintf(stderr,
                     "vastray render: note: %zu material%s of %s read occlusion maps, which are stored but not "
                     "applied, by design (the path tracer computes occlusion itself; the map would count it "
                     "twice)\n",
                     occlusion, occlusion == 1 ? "" : "s", input.c_str());
}

// Tile progress as the chosen front end shows it; called from worker threads. `openjd` writes
// Open Job Description's action messages ("openjd_progress: N", "openjd_status: TEXT",
// "openjd_fail: TEXT"), one a line on stdout: the specification defines them on stdout (its
// runtime, openjd-sessions, reads the action's stdout with stderr merged into it); the other
// modes write on stderr.
class RenderProgressView {
public:
    explicit RenderProgressView(std::string mode) : mode_(std::move(mode)) {}

    RenderProgress callback() {
        if (mode_ == "none") return {};
        return [this](uint64_t done, uint64_t total) { report(done, total); };
    }
    void finish() {
        if (bar_) bar_->finish();
    }
    // A phase of the command, for OpenJD's task status; other modes show none.
    void status(const std::string& text) { openjdLine("openjd_status", text); }
    // The command fails with `message` (also printed on stderr): OpenJD marks the task failed with it.
    int fail(const std::string& message, int exitCode) {
        std::fprintf(stderr, "vastray render: %s\n", message.c_str());
        openjdLine("openjd_fail", message);
        return exitCode;
    }

private:
    // One message line; a message of several lines is joined into one (OpenJD reads lines).
    void openjdLine(const char* kind, std::string text) {
        if (mode_ != "openjd") return;
        std::replace(text.begin(), text.end(), '\n', ' ');
        std::lock_guard<std::mutex> lock(mutex_);
        std::printf("%s: %s\n", kind, text.c_str());
        std::fflush(stdout);
    }

    void report(uint64_t done, uint64_t total) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (mode_ == "openjd") {
            const int percent = int(100 * done / total);
            if (percent == lastPercent_) return;
            lastPercent_ = percent;
            std::printf("openjd_progress: %d\n", percent);
            std::fflush(stdout);
            return;
        }
        if (!bar_)
            bar_ = std::make_unique<Progress>("render", total,
                                              mode_ == "bar" ? Progress::Mode::Bar : Progress::Mode::Auto);
        bar_->advance(1);
    }

    std::string mode_;
    std::mutex mutex_;
    std::unique_ptr<Progress> bar_;
    int lastPercent_ = -1;
};

void printStats(const RenderStats& s, const RenderOptions& o, const StreamingStats* st) {
    std::printf("render: %s backend, %s integrator, %ux%u, %u spp, max depth %u\n", s.backend.c_str(),
                integratorName(o.integrator), o.width, o.height, o.samplesPerPixel, o.maxDepth);
    std::printf("  triangles            %llu\n", (unsigned long long)s.triangles);
    std::printf("  BVH build            %.3f s\n", s.buildSeconds);
    std::printf("  render               %.3f s\n", s.renderSeconds);
    std::printf("  rays                 %llu (%.2f M rays/s)\n", (unsigned long long)s.rays,
                s.raysPerSecond() / 1e6);
    std::printf("  peak host memory     %s\n", formatBytes(s.peakHostBytes).c_str());
    if (!st) return;
    std::printf("  memory budget        %s (%u chunk slots), peak device %s\n",
                formatBytes(st->memoryBudgetBytes).c_str(), st->slots, formatBytes(st->peakDeviceBytes).c_str());
    if (st->wavePaths > 0)
        std::printf("  wave                 %u paths, path state in %s\n", st->wavePaths,
                    st->pathStateHostBytes > 0 ? ("host memory (" + formatBytes(st->pathStateHostBytes) + ")").c_str()
                                               : "device memory");
    std::printf("  chunks               %llu touched of %llu, %llu loads, %llu decodes\n",
                (unsigned long long)st->chunksTouched, (unsigned long long)st->chunksTotal,
                (unsigned long long)st->chunkLoads, (unsigned long long)st->decodes);
    std::printf("  bytes                %s read, %s uploaded\n", formatBytes(st->bytesRead).c_str(),
                formatBytes(st->bytesUploaded).c_str());
    std::printf("  seconds              device %.3f (kernels: walk %.3f, shade %.3f), decode %.3f (workers; waited %.3f), upload %.3f, "
                "pipelines %.3f\n",
                st->deviceSeconds, st->kernelSeconds[StreamingStats::kKernelWalk],
                st->kernelSeconds[StreamingStats::kKernelShade], st->decodeSeconds, st->decodeWaitSeconds,
                st->uploadSeconds, st->pipelineSeconds);
    std::printf("  device               %llu submits, %llu walk passes, %s up, %s down (besides chunks)\n",
                (unsigned long long)st->submits, (unsigned long long)st->walkPasses,
                formatBytes(st->hostToDeviceBytes).c_str(), formatBytes(st->deviceToHostBytes).c_str());
    if (st->volumeBrickSlots > 0 || st->volumeBricksRead > 0)
        std::printf("  volume bricks        %llu slots, %llu loads, %llu read from the package\n",
                    (unsigned long long)st->volumeBrickSlots, (unsigned long long)st->volumeBrickLoads,
                    (unsigned long long)st->volumeBricksRead);
    if (st->texturePageSlots > 0 || st->texturePagesRead > 0)
        std::printf("  texture pages        %llu slots, %llu loads, %llu read from the package\n",
                    (unsigned long long)st->texturePageSlots, (unsigned long long)st->texturePageLoads,
                    (unsigned long long)st->texturePagesRead);
}

// Where a `vastray render --backend vulkan` command's time goes besides the render itself
// (--stats-json; docs/RENDERING.md): a cold render's wall time is mostly these.
struct CommandTimings {
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    double deviceStartSeconds = 0;  // device_start_seconds: creating the Vulkan device (beside the package's opening)
    double deviceWaitSeconds = 0;   // device_wait_seconds: the backend factory waiting for it
    double backendSeconds = 0;      // backend_seconds: creating the backend (pools, staging area, first kernels)
    double openSeconds = 0;         // open_seconds: the command's start to the backend being ready
    double closeSeconds = 0;        // close_seconds: after the backend was ready, besides render_seconds (teardown)
    double writeSeconds = 0;        // write_seconds: writing the image file
};

double secondsBetween(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}

Status writeStatsJson(const std::string& path, const RenderStats& s, const StreamingStats* st,
                      const CommandTimings* timings) {
    nlohmann::json j{{"backend", s.backend},
                           {"render_seconds", s.renderSeconds},
                           {"build_seconds", s.buildSeconds},
                           {"rays", s.rays},
                           {"rays_per_second", s.raysPerSecond()},
                           {"triangles", s.triangles},
                           {"peak_host_bytes", s.peakHostBytes}};
    if (st) {
        j["chunks_total"] = st->chunksTotal;
        j["chunks_touched"] = st->chunksTouched;
        j["chunk_loads"] = st->chunkLoads;
        j["chunk_decodes"] = st->decodes;
        j["stream_chunks_touched"] = st->streamChunksTouched;
        j["stream_reloads"] = st->streamReloads;
        j["idle_load_steps"] = st->idleLoadSteps;
        j["late_chunks"] = st->lateChunks;
        j["host_gap_seconds"] = st->hostGapSeconds;
        j["device_idle_seconds"] = st->deviceIdleSeconds;
        j["chunk_slots"] = st->slots;
        j["wave_paths"] = st->wavePaths;
        j["path_state_host_bytes"] = st->pathStateHostBytes;
        j["bytes_read"] = st->bytesRead;
        j["bytes_uploaded"] = st->bytesUploaded;
        j["decode_seconds"] = st->decodeSeconds;
        j["decode_wait_seconds"] = st->decodeWaitSeconds;
        j["upload_seconds"] = st->uploadSeconds;
        j["device_seconds"] = st->deviceSeconds;
        j["walked_rays"] = st->walkedRays;
        j["submits"] = st->submits;
        j["walk_passes"] = st->walkPasses;
        j["pipeline_seconds"] = st->pipelineSeconds;
        j["streamed_tiles"] = st->streamedTiles;
        j["stream_window_tiles"] = st->streamWindowTiles;
        j["volume_brick_slots"] = st->volumeBrickSlots;
        j["volume_brick_loads"] = st->volumeBrickLoads;
        j["volume_bricks_read"] = st->volumeBricksRead;
        j["texture_page_slots"] = st->texturePageSlots;
        j["texture_page_loads"] = st->texturePageLoads;
        j["texture_pages_read"] = st->texturePagesRead;
        j["host_to_device_bytes"] = st->hostToDeviceBytes;
        j["device_to_host_bytes"] = st->deviceToHostBytes;
        for (int k = 0; k < StreamingStats::kKernels; ++k)
            j["kernel_seconds"][StreamingStats::kKernelNames[k]] = st->kernelSeconds[k];
        j["peak_device_bytes"] = st->peakDeviceBytes;
        j["memory_budget_bytes"] = st->memoryBudgetBytes;
    }
    if (timings) {
        j["device_start_seconds"] = timings->deviceStartSeconds;
        j["device_wait_seconds"] = timings->deviceWaitSeconds;
        j["backend_seconds"] = timings->backendSeconds;
        j["open_seconds"] = timings->openSeconds;
        j["close_seconds"] = timings->closeSeconds;
        j["write_seconds"] = timings->writeSeconds;
    }
    std::ofstream out(path);
    out << j.dump(2) << "\n";
    if (!out) return Status::error(path + ": cannot write stats");
    return Status::ok();
}

// A mesh file given to the streaming backend is imported into a temporary package first
// (chunks of a quarter of the budget, at most 16 MiB); the package is removed afterwards.
class TemporaryPackage {
public:
    ~TemporaryPackage() {
        if (!path_.empty()) std::filesystem::remove(path_);
    }
    Result<std::string> import(const std::string& mesh, uint64_t budget) {
        auto imported = importMesh(mesh);
        if (!imported) return imported.status();
        PackageBuildOptions build;
        build.chunkSizeBytes = std::max<uint64_t>(kMinChunkSizeBytes, std::min<uint64_t>(16ull << 20, budget / 4));
        build.progress = Progress::Mode::None;
        build.degenerateDropped = imported->report.degenerateDropped;
        path_ = (std::filesystem::temp_directory_path() /
                 ("vastray-render-" + std::to_string(::getpid()) + ".vast")).string();
        auto report = buildPackage(std::move(imported->mesh), path_, build);
        if (!report) return report.status().withContext(mesh + ": importing for --backend vulkan: ");
        return path_;
    }

private:
    std::string path_;
};

Result<RenderImage> renderVulkan(const RenderArgs& args, RenderOptions options, const StreamingSizes& sizes,
                                 RenderStats& stats, StreamingStats& streaming, const RenderProgress& progress,
                                 CommandTimings& timings) {
    const uint64_t budget = sizes.memoryBudget;
    // The device starts up (~0.3 s on a discrete GPU) while the package opens and its chunks
    // decode (StreamingOptions::decodeOnOpen); the backend factory waits for it.
    gpu::VulkanDeviceOptions deviceOptions;
    deviceOptions.deviceIndex = int(args.gpuDevice);
    // An early return waits for it in the future's destructor (std::async).
    auto starting = std::async(std::launch::async, [deviceOptions, &timings] {
        const auto start = std::chrono::steady_clock::now();
        auto device = gpu::VulkanDevice::create(deviceOptions);
        timings.deviceStartSeconds = secondsBetween(start, std::chrono::steady_clock::now());
        return device;
    });
    std::optional<decltype(starting.get())> device;
    TemporaryPackage temporary;
    std::string path = args.input;
    if (!isPackagePath(path)) {
        auto imported = temporary.import(path, budget);
        if (!imported) return imported.status();
        path = *imported;
    }
    auto reader = PackageReader::open(path);
    if (!reader) return reader.status();
    VASTRAY_TRY(applySceneCamera((*reader)->info().cameras, args.camera, options));
    if (!args.noLights) applySceneLights((*reader)->info().lights, (*reader)->info().bounds, options);
    applySceneEmitters((*reader)->info().emitters, (*reader)->info().materials, options);
    noteUnrenderedMaps((*reader)->info().materials, args.input);
    if (!(*reader)->info().volumes.empty()) {  // brick tables now, each brick when a ray needs it
        auto volumes = (*reader)->openVolumes();
        if (!volumes) return volumes.status();
        options.volumes = std::move(volumes).value();
    }
    StreamingOptions streamingOptions;
    streamingOptions.hostCacheBytes = sizes.hostCache;
    streamingOptions.decodeThreads = options.threads;  // 0: all cores
    streamingOptions.decodeOnOpen = true;
    streaming.memoryBudgetBytes = budget;
    const ChunkBackendFactory factory =
        [&](const PackageInfo& info, const ChunkAttributes& attributes) -> Result<std::unique_ptr<ChunkBackend>> {
        const auto waiting = std::chrono::steady_clock::now();
        if (!device) device.emplace(starting.get());
        if (!*device) return device->status();
        const auto creating = std::chrono::steady_clock::now();
        timings.deviceWaitSeconds = secondsBetween(waiting, creating);
        auto backend = gpu::createVulkanChunkBackend(***device, info, attributes, budget, gpu::kWaveShareOutOfCore, {},
                                                     gpu::environmentBytes(options.environment) +
                                                         gpu::volumeReserveBytes(info, budget),
                                                     {sizes.pathState});
        const auto ready = std::chrono::steady_clock::now();
        timings.backendSeconds = secondsBetween(creating, ready);
        timings.openSeconds = secondsBetween(timings.start, ready);
        return backend;
    };
    auto image = renderStreaming(**reader, options, streamingOptions, factory, &stats, &streaming, progress);
    timings.closeSeconds = std::max(
        0.0, secondsBetween(timings.start, std::chrono::steady_clock::now()) - timings.openSeconds - stats.renderSeconds);
    return image;
}

// "pixels 16,0,33,19 of 50x37" or "50x37".
std::string describePixels(const RenderOptions& options) {
    const std::string frame = std::to_string(options.width) + "x" + std::to_string(options.height);
    if (!options.region) return frame;
    const PixelBounds& r = *options.region;
    return "pixels " + std::to_string(r.x0) + "," + std::to_string(r.y0) + "," + std::to_string(r.x1) + "," +
           std::to_string(r.y1) + " of " + frame;
}

int runRenderChecked(const RenderArgs& args, RenderProgressView& progress) {
    StreamingSizes sizes;
    auto options = optionsFrom(args, &sizes);
    if (!options) return progress.fail(options.message(), 2);
    const std::string ext = lowerExtension(args.output);
    if (Status memory = checkRenderHostMemory(*options, ext == ".exr"); !memory)
        return progress.fail(memory.message(), 1);
    if (!args.environment.empty()) {
        progress.status("reading " + args.environment);
        auto map = readEnvironmentMap(args.environment, float(args.environmentScale));
        if (!map) return progress.fail(map.message(), 1);
        options->environment.map = std::move(map).value();
    }
    RenderStats stats;
    StreamingStats streaming;
    CommandTimings timings;
    const bool vulkan = args.backend == "vulkan";
    progress.status("rendering " + describePixels(*options) + " of " + args.input + " (" + args.backend + ", " +
                    std::to_string(options->samplesPerPixel) + " spp)");
    Result<RenderImage> image = Status::error("no image");
    if (vulkan) {
        image = renderVulkan(args, *options, sizes, stats, streaming, progress.callback(), timings);
    } else {
        auto scene = loadRenderScene(args.input);
        if (!scene) return progress.fail(scene.message(), 1);
        if (Status camera = applySceneCamera(scene->mesh.cameras, args.camera, *options); !camera)
            return progress.fail(camera.message(), 2);
        options->volumes = scene->volumes;
        if (!args.noLights) applySceneLights(scene->mesh.lights, scene->bounds, *options);
        applySceneEmitters(scene->emitters, scene->mesh.materials, *options);
        noteUnrenderedMaps(scene->mesh.materials, args.input);
        image = renderWithEmbree(*scene, *options, &stats, progress.callback());
    }
    if (!image) return progress.fail(image.message(), 1);
    progress.finish();
    progress.status("writing " + args.output);
    const auto writing = std::chrono::steady_clock::now();
    Status written = writeImageFile(args.output, *image);
    timings.writeSeconds = secondsBetween(writing, std::chrono::steady_clock::now());
    if (written && !args.statsJson.empty())
        written = writeStatsJson(args.statsJson, stats, vulkan ? &streaming : nullptr, vulkan ? &timings : nullptr);
    if (!written) return progress.fail(written.message(), 1);
    if (args.stats) printStats(stats, *options, vulkan ? &streaming : nullptr);
    progress.status("wrote " + args.output);
    return 0;
}

// The estimate covers the image; an allocation that still fails (another process took the
// memory meanwhile, a scene larger than the host) ends the command with a message, not abort().
int runRender(const RenderArgs& args) {
    RenderProgressView progress(args.progress);
    try {
        return runRenderChecked(args, progress);
    } catch (const std::bad_alloc&) {
        return progress.fail(
            "out of host memory (resolution " + args.resolution + ", " + args.backend + " backend)", 1);
    }
}

}  // namespace

CommandRun addRenderCommand(CLI::App& app) {
    auto args = std::make_shared<RenderArgs>();
    CLI::App* cmd = app.add_subcommand(
        "render", "Render a mesh file or a scene package to .png (tone mapped), .exr (linear) or .pfm (linear RGB floats).");
    cmd->add_option("input", args->input,
                    "mesh file (.obj, .ply, .gltf, .glb, or a format of `vastray import --help`: rendered whole, in core) or package (.vast)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("-o,--output", args->output, "image to write (.png, .exr or .pfm; AOVs need .exr; .pfm: beauty only, written without the OpenImageIO module)")->required();
    cmd->add_option("--backend", args->backend,
                    "vulkan (streaming path tracer on the GPU; a mesh file is imported to a temporary package first) | "
                    "embree (CPU reference, whole scene in core)")
        ->capture_default_str();
    cmd->add_option("--memory-budget", args->memoryBudget,
                    "vulkan: device memory for chunk slots, the path state of a wave, tables and volumes, all of it (KiB/MiB/GiB); "
                    "volumes bigger than half of it page their bricks through a pool of that half, plus what the wave and the chunk slots leave")
        ->capture_default_str();
    cmd->add_option("--path-state", args->pathState,
                    "vulkan, out of core: where a wave's path state lives: device (in the budget, beside the chunk slots), "
                    "host (pinned host memory off the budget: a wave of 524288 paths and the budget for slots but for the "
                    "paths' walk bits, a byte a path; "
                    "kernels read the state across the bus; no volumes), or auto (host on a discrete GPU when the "
                    "scene's chunks exceed 6 budgets and it has no volumes, else device)")
        ->capture_default_str();
    cmd->add_option("--host-cache", args->hostCache, "vulkan: decoded chunks kept in host memory (KiB/MiB/GiB; 0 = none; auto = the whole decoded scene, up to a quarter of this machine's memory)")
        ->capture_default_str();
    cmd->add_option("--gpu-device", args->gpuDevice,
                    "vulkan: index of the Vulkan device to use, -1..255 (-1: the first discrete GPU, else the first device)")
        ->capture_default_str();
    cmd->add_option("--spp", args->spp, "samples per pixel, 1..65536")->capture_default_str();
    cmd->add_option("--resolution", args->resolution, "WxH, each side 1..16384")->capture_default_str();
    cmd->add_option("--camera", args->camera,
                    "a camera of the scene (glTF, Collada, FBX... cameras, kept in the package) by name or 0-based index; "
                    "default: the scene's first camera if it has one and --eye is not given, else framing");
    cmd->add_option("--eye", args->eye,
                    "camera position x,y,z (with --target; default: the scene's first camera, else frame the scene)");
    cmd->add_option("--target", args->target, "point the camera looks at, x,y,z");
    cmd->add_option("--up", args->up,
                    "camera up vector x,y,z (default: the --up-axis); automatic framing looks down along it too");
    cmd->add_option("--up-axis", args->upAxis, "y | z: the world's up for the sky, the default sun and framing")
        ->capture_default_str();
    cmd->add_option("--sun", args->sun,
                    "X,Y,Z,INTENSITY: direction towards the sun (world space) and its strength (default: 3, from "
                    "0.4,0.8,0.3 turned to the --up-axis)");
    cmd->add_flag("--no-sun", args->noSun, "sky light only");
    cmd->add_flag("--no-lights", args->noLights,
                  "ignore the scene's punctual lights (glTF KHR_lights_punctual, and those assimp reads from Collada, FBX, "
                  "...; kept in the package)");
    cmd->add_option("--environment", args->environment,
                    "FILE (.exr, .hdr, .pfm, ...): a latitude-longitude environment map that replaces the sky (its top "
                    "row towards the --up-axis), importance sampled; the default sun is off with it (--sun adds one)")
        ->check(CLI::ExistingFile);
    cmd->add_option("--environment-scale", args->environmentScale,
                    "multiplies the --environment map's radiance, [0, 1e18]")
        ->capture_default_str();
    cmd->add_option("--environment-rotate", args->environmentRotate,
                    "turns the --environment map about the up axis by DEGREES, [-360, 360] (positive: the map's "
                    "first column moves from the frame's tangent towards its bitangent; docs/RENDERING.md)")
        ->capture_default_str();
    cmd->add_option("--fov", args->fov, "vertical field of view in degrees, [0.001, 180)")->capture_default_str();
    cmd->add_option("--integrator", args->integrator, "path | ao (ambient occlusion)")->capture_default_str();
    cmd->add_option("--texture-lod", args->textureLod,
                    "cone | finest: the level textures are sampled at; cone: the ray cone's footprint (trilinear, "
                    "fewer pages read out of core); finest: level 0 (the pixel samples alone filter, as Mitsuba 3's "
                    "bitmap does)")
        ->capture_default_str();
    cmd->add_option("--max-depth", args->maxDepth, "scattering events per path, 0..1024")
        ->capture_default_str();
    cmd->add_option("--seed", args->seed, "random seed, 0..4294967295; same seed, same image")
        ->capture_default_str();
    cmd->add_option("--aovs", args->aovs, "extra EXR channels: any of depth,normal,albedo,primid,uv,chunkid,cost (uv: the hit's texture "
                    "coordinates, 0 in a scene without them; the last two: vulkan only)");
    cmd->add_option("--threads", args->threads,
                    "worker threads (0 = all cores); the image does not depend on it")
        ->capture_default_str();
    cmd->add_flag("--stats", args->stats, "print rays, timings and memory");
    cmd->add_option("--stats-json", args->statsJson, "write the figures as JSON to this file");
    cmd->add_option("--region", args->region,
                    "render only pixels X0,Y0,X1,Y1 of the --resolution frame (X1, Y1 exclusive, like pbrt's "
                    "--pixelbounds): same camera, pixels equal to the whole frame's bit for bit; the image is the "
                    "region's size and records its place in the frame (EXR data window, PNG text chunk "
                    "vastray:region); join tiles with `vastray assemble`");
    cmd->add_option("--tile", args->tile, "with --tiles: render tile I (0-based, row by row) of the grid, as --region");
    cmd->add_option("--tiles", args->tiles,
                    "NX,NY: a grid of tiles over the frame; column c spans pixels [c*W/NX, (c+1)*W/NX), rows alike");
    cmd->add_option("--progress", args->progress,
                    "auto | bar | openjd | none; bar and lines on stderr; openjd: Open Job Description's "
                    "openjd_progress/openjd_status/openjd_fail lines on stdout")
        ->capture_default_str();
    return [args]() { return runRender(*args); };
}

}  // namespace vastray::cli
