#include "Wavefront.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <future>
#include <optional>
#include <vector>

#include "vastray/core/Camera.h"
#include "vastray/core/EnvironmentMap.h"
#include "vastray/core/Microfacet.h"
#include "vastray/core/PathShading.h"
#include "vastray/core/VecMath.h"
#include "ChunkUploader.h"
#include "vastray/gpu/KernelStatistics.h"
#include "vastray/gpu/TileGrid.h"

namespace vastray::gpu {
namespace {

const uint32_t kGenerateSpirv[] =
#include "wf_generate.spv.inc"
    ;
const uint32_t kWalkSpirv[] =
#include "wf_walk.spv.inc"
    ;
const uint32_t kShadeSpirv[] =
#include "wf_shade.spv.inc"
    ;
const uint32_t kAccumulateSpirv[] =
#include "wf_accumulate.spv.inc"
    ;
const uint32_t kAovSpirv[] =
#include "wf_aov.spv.inc"
    ;

static_assert(kWalkNoHit == kEmptyCell && kWavefrontWorkgroupSize == 64);
static_assert(kGeneratePaths == kWaveTiled, "a tile's wave walks and shades with its generate push");

// Indices into StreamingStats::kernelSeconds; kNoKernel: a command no kernel's time includes.
enum Kernel : int {
    kGenerate = StreamingStats::kKernelGenerate,
    kWalk = StreamingStats::kKernelWalk,
    kShade = StreamingStats::kKernelShade,
    kAccumulate = StreamingStats::kKernelAccumulate,
    kAov = StreamingStats::kKernelAov,
    kNoKernel = -1
};
// Walk passes per paging step out of core (with shading between them): enough for paths that
// stay in resident chunks to go on for a few bounces before the host pages again. A step's later
// passes walk only the rays the shading between them started (parked rays wait for the next
// step), so more of them pay only where the wave is large or the steps cost more to start
// (PERF_NOTES 103):
// - 3 by default (the 10M city at 4x over budget, a wave of ~158 k paths: 4 passes 11 % slower);
// - 5 for a step whose chunk table holds chunks absent because their copies still run (partial
//   residency): the step then outlasts those copies instead of ending before them and paging
//   again (the 64M city at 512 MiB, a wave of 983 k paths: 1 % faster on a lease whose bus moved
//   ~42 GB/s; 5 passes in every step 10 % faster on one at ~30 GB/s);
// - 5 with the path state in host memory (a wave of 524 k paths whose steps cost more to start:
//   the 10M city at 16x over budget 9-15 % faster kept open).
constexpr uint32_t kPassesPerPagingStep = 3;
constexpr uint32_t kPassesWhileCopiesRun = 5;
constexpr uint32_t kPassesWithHostState = 5;
// Streamed waves with volume bricks paged and the chunks resident: tiles of a sixteenth of the
// wave's paths at most (Wavefront::render, PERF_NOTES 75).
constexpr uint32_t kFineWindowTiles = 16;
// Timestamps one submission takes at most; commands beyond them go untimed.
constexpr uint32_t kMaxQueries = 16384;

// A timestamp query pool for one render (none when the queue has no timestamps).
class QueryPool {
public:
    explicit QueryPool(VulkanDevice& device) : device_(device) {
        if (device.timestampValidBits() == 0) return;
        VkQueryPoolCreateInfo info{};
        info.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
        info.queryType = VK_QUERY_TYPE_TIMESTAMP;
        info.queryCount = kMaxQueries;
        if (vkCreateQueryPool(device.handle(), &info, nullptr, &pool_) != VK_SUCCESS) pool_ = VK_NULL_HANDLE;
    }
    ~QueryPool() {
        if (pool_) device_.destroyWhenIdle([pool = pool_](VkDevice d) { vkDestroyQueryPool(d, pool, nullptr); });
    }
    QueryPool(const QueryPool&) = delete;
    QueryPool& operator=(const QueryPool&) = delete;
    VkQueryPool handle() const { return pool_; }

private:
    VulkanDevice& device_;
    VkQueryPool pool_ = VK_NULL_HANDLE;
};

// Every kernel's writes are visible to the next kernel's reads, to transfers and to indirect
// dispatches, and fills to kernels.
void barrier(VkCommandBuffer cmd) {
    VkMemoryBarrier b{};
    b.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
    b.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                      VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT;
    const VkPipelineStageFlags stages = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
    vkCmdPipelineBarrier(cmd, stages, stages | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT, 0, 1, &b, 0, nullptr, 0, nullptr);
}

uint32_t groups(uint64_t threads) {
    return uint32_t((threads + kWavefrontWorkgroupSize - 1) / kWavefrontWorkgroupSize);
}

// CameraRays' vectors (core/src/Camera.cpp), so that wf_generate.comp combines the same ones.
void setCamera(WavefrontParams& p, const Camera& camera, uint32_t width, uint32_t height) {
    const CameraRays rays(camera, width, height);
    const Vec3f eye = rays.eye(), forward = rays.forward(), r = rays.right(), u = rays.up();
    p.eyeX = eye.x, p.eyeY = eye.y, p.eyeZ = eye.z;
    p.forwardX = forward.x, p.forwardY = forward.y, p.forwardZ = forward.z;
    p.rightX = r.x, p.rightY = r.y, p.rightZ = r.z;
    p.upX = u.x, p.upY = u.y, p.upZ = u.z;
    p.width = float(width), p.height = float(height);
}

void setEnvironment(WavefrontParams& p, const Environment& e) {
    p.zenithR = e.zenith[0], p.zenithG = e.zenith[1], p.zenithB = e.zenith[2];
    p.horizonR = e.horizon[0], p.horizonG = e.horizon[1], p.horizonB = e.horizon[2];
    p.groundR = e.ground[0], p.groundG = e.ground[1], p.groundB = e.ground[2];
    const Vec3f up = normalize(e.up);
    p.skyUpX = up.x, p.skyUpY = up.y, p.skyUpZ = up.z;
    const Vec3f sun = normalize(e.sunDirection);
    p.sunX = sun.x, p.sunY = sun.y, p.sunZ = sun.z;
    p.sunR = e.sunIrradiance[0], p.sunG = e.sunIrradiance[1], p.sunB = e.sunIrradiance[2];
    p.sunPick = sunPickProbability(e);
    if (e.map) p.envWidth = e.map->width, p.envHeight = e.map->height;
    const Frame frame = environmentFrame(up, e.mapRotationDegrees);
    p.envTangentX = frame.tangent.x, p.envTangentY = frame.tangent.y, p.envTangentZ = frame.tangent.z;
    p.envBitangentX = frame.bitangent.x, p.envBitangentY = frame.bitangent.y, p.envBitangentZ = frame.bitangent.z;
}

}  // namespace

namespace {

// A pipeline being created on a thread of its own: with an empty driver cache a driver compiles
// each kernel (0.3-0.5 s on the H200), so the kernels a render needs are created side by side
// (PERF_NOTES 60).
using PendingPipeline = std::future<Result<std::unique_ptr<ComputePipeline>>>;
PendingPipeline createAsync(VulkanDevice& device, std::span<const uint32_t> spirv, std::vector<uint32_t> constants = {}) {
    return std::async(std::launch::async, [&device, spirv, constants = std::move(constants)] {
        return ComputePipeline::create(device, spirv, sizeof(WavefrontPush), constants);
    });
}

// The texture a material's map names (kNoTexture: none).
uint32_t materialMap(const Material& m, TextureSlot slot) { return m.textures.slots[uint32_t(slot)].texture; }

// The walk variants a render of a scene without cut-outs and without the cost AOV needs: in core
// and out of core (kPaging).
constexpr WalkConstants kWalkInCore{0u, 0u, 0u, 0u, 0u}, kWalkOutOfCore{0u, 1u, 0u, 0u, 0u};
WalkConstants withPackedPositions(WalkConstants c, bool packed) {
    c[4] = packed ? 1u : 0u;
    return c;
}

uint32_t variantKey(std::span<const uint32_t> constants) {
    uint32_t key = 0, bit = 0;
    for (uint32_t c : constants) key |= (c ? 1u : 0u) << bit++;
    return key;
}

}  // namespace

ShadeConstants shadeConstants(std::span<const Material> materials, bool ambientOcclusion, bool sun, bool normals,
                              bool colors, bool environmentMap, uint32_t volumeCodecs, bool lights, bool textures,
                              bool frames, bool emitters, bool hostState) {
    bool emission = false, glossy = false, coated = false, mapped = false, normalMapped = false;
    for (const Material& m : materials) {
        emission = emission || m.emissive[0] > 0 || m.emissive[1] > 0 || m.emissive[2] > 0;
        glossy = glossy || !isLambertian(m);
        coated = coated || m.clearcoat > 0;
        normalMapped = normalMapped || materialMap(m, TextureSlot::Normal) != kNoTexture;
        mapped = mapped || normalMapped || materialMap(m, TextureSlot::BaseColor) != kNoTexture ||
                 materialMap(m, TextureSlot::MetallicRoughness) != kNoTexture ||
                 materialMap(m, TextureSlot::Emissive) != kNoTexture ||
                 (m.clearcoat > 0 && (materialMap(m, TextureSlot::Clearcoat) != kNoTexture ||
                                      materialMap(m, TextureSlot::ClearcoatRoughness) != kNoTexture));
    }
    return {ambientOcclusion, sun, emission, normals, colors, environmentMap, volumeCodecs != 0, glossy, lights, coated,
            textures && mapped, textures && frames && normalMapped, emission && emitters,
            (volumeCodecs >> uint32_t(VolumeCodec::Float)) & 1u, (volumeCodecs >> uint32_t(VolumeCodec::Fp16)) & 1u,
            (volumeCodecs >> uint32_t(VolumeCodec::Fp8)) & 1u, hostState};
}

uint32_t volumeCodecs(std::span<const Volume> volumes) {
    uint32_t codecs = 0;
    for (const Volume& v : volumes) codecs |= 1u << uint32_t(deviceVolumeCodec(v));
    return codecs;
}

Result<std::string> describeKernels(VulkanDevice& device) {
    if (!device.kernelStatistics())
        return device.info().name +
               ": the driver offers no kernel statistics (VK_KHR_pipeline_executable_properties) or the device was"
               " not asked for them\n";
    struct Kernel {
        const char* name;
        std::span<const uint32_t> spirv;
        std::vector<uint32_t> constants;
    };
    // The shade the backend guesses for a scene of default materials under the default sun.
    auto defaultShade = [](bool hostState) {
        return shadeConstants({}, false, true, false, false, false, 0, false, false, false, false, hostState);
    };
    const ShadeConstants shade = defaultShade(false), hostShade = defaultShade(true);
    const Kernel kernels[] = {
        {"wf_walk in core", kWalkSpirv, {kWalkInCore.begin(), kWalkInCore.end()}},
        {"wf_walk out of core", kWalkSpirv, {kWalkOutOfCore.begin(), kWalkOutOfCore.end()}},
        {"wf_walk out of core, cost AOV", kWalkSpirv, {1u, 1u, 0u, 0u, 0u}},  // kWalkOutOfCore and kCountCost
        {"wf_shade (sun, Lambertian)", kShadeSpirv, {shade.begin(), shade.end()}},
        {"wf_shade (sun, Lambertian), state in host memory", kShadeSpirv, {hostShade.begin(), hostShade.end()}},
        {"wf_generate", kGenerateSpirv, {}},
        {"wf_accumulate", kAccumulateSpirv, {}},
        {"wf_aov", kAovSpirv, {}},
    };
    std::string text = device.info().name + "\n";
    for (const Kernel& k : kernels) {
        auto pipeline = ComputePipeline::create(device, k.spirv, sizeof(WavefrontPush), k.constants);
        if (!pipeline) return pipeline.status().withContext(std::string(k.name) + ": ");
        auto figures = (*pipeline)->statistics();
        if (!figures) return figures.status().withContext(std::string(k.name) + ": ");
        text += std::string(k.name) + ": " + *figures + "\n";
    }
    return text;
}

std::unique_ptr<Wavefront> Wavefront::start(VulkanDevice& device, bool inCore, bool packedPositions,
                                            const ShadeConstants& likelyShade) {
    std::unique_ptr<Wavefront> w(new Wavefront(device));
    w->pendingShades_.emplace(variantKey(likelyShade),
                              createAsync(device, kShadeSpirv, std::vector<uint32_t>(likelyShade.begin(), likelyShade.end())));
    w->pendingFixed_[0] = createAsync(device, kGenerateSpirv);
    w->pendingFixed_[1] = createAsync(device, kAccumulateSpirv);
    w->pendingFixed_[2] = createAsync(device, kAovSpirv);
    w->startWalkVariants({withPackedPositions(kWalkOutOfCore, packedPositions)});
    if (inCore) w->startWalkVariants({withPackedPositions(kWalkInCore, packedPositions)});
    return w;
}

Status Wavefront::ready() {
    std::unique_ptr<ComputePipeline>* kernels[] = {&pipelines_.generate, &pipelines_.accumulate, &pipelines_.aov};
    Status status = Status::ok();
    for (int k = 0; k < 3; ++k) {  // every one is waited for, failed or not
        if (!pendingFixed_[k].valid()) continue;
        auto created = pendingFixed_[k].get();
        if (!created && status.isOk()) status = created.status();
        if (created) *kernels[k] = std::move(created).value();
    }
    return status;
}

void Wavefront::startWalkVariants(std::initializer_list<WalkConstants> variants) {
    for (const auto& constants : variants) {
        const uint32_t key = variantKey(constants);
        if (pipelines_.walk.count(key) || pendingWalks_.count(key)) continue;
        pendingWalks_.emplace(key, createAsync(device_, kWalkSpirv, {constants.begin(), constants.end()}));
    }
}

Result<const ComputePipeline*> Wavefront::variant(bool walk, std::span<const uint32_t> constants,
                                                  StreamingStats& stats) {
    const uint32_t key = variantKey(constants);
    auto& cache = walk ? pipelines_.walk : pipelines_.shade;
    if (auto found = cache.find(key); found != cache.end()) return found->second.get();
    const std::vector<uint32_t> values(constants.begin(), constants.end());
    const auto start = std::chrono::steady_clock::now();
    auto& pending = walk ? pendingWalks_ : pendingShades_;
    auto created = [&] {  // the one started for this scene, or a new one
        if (auto started = pending.find(key); started != pending.end()) {
            auto done = started->second.get();
            pending.erase(started);
            return done;
        }
        return ComputePipeline::create(device_, walk ? std::span<const uint32_t>(kWalkSpirv)
                                                     : std::span<const uint32_t>(kShadeSpirv),
                                       sizeof(WavefrontPush), values);
    }();
    stats.pipelineSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!created) return created.status();
    return (cache[key] = std::move(created).value()).get();
}

// One render: records kernels, submits at the points where the host must look (a walk pass
// out of core, a finished tile), and copies finished tiles into the image.
class Wavefront::Run {
public:
    Run(Wavefront& w, const WavefrontBuffers& b, const DeviceRenderJob& job, ChunkPager& pager, RenderImage& image,
        StreamingStats& stats, double& deviceSeconds)
        : w_(w), b_(b), job_(job), options_(*job.options), pager_(pager), image_(image), stats_(stats),
          deviceSeconds_(deviceSeconds), queries_(w.device_) {}
    // A render that fails between a submission and its wait still waits: the buffers outlive it.
    ~Run() { (void)w_.device_.wait(); }

    Status execute() {
        // What this render does not need is not compiled into its kernels (specialization).
        const std::array<float, 3>& sun = options_.environment.sunIrradiance;
        const bool environmentMap = options_.environment.map != nullptr;
        if (environmentMap && !b_.environment) return Status::error("device render: the environment map has no buffer");
        const bool volumes = options_.volumes && !options_.volumes->empty();
        if (volumes && !b_.volumes) return Status::error("device render: the volumes have no buffer");
        const bool lights = options_.lights && !options_.lights->empty();
        if (lights && options_.lights->size() > b_.tables.lightCapacity)
            return Status::error("device render: " + std::to_string(options_.lights->size()) +
                                 " punctual lights, the package's tables hold " + std::to_string(b_.tables.lightCapacity));
        // The walk variants this render will ask for are created beside the shade variant (variant()
        // waits for them when they are first used): the paging one while a chunk is missing, the
        // resident one where every chunk gets a slot.
        const uint32_t cost = (image_.aovs & kAovCost) != 0 ? 1u : 0u;
        const uint64_t mapped = readableTextures();
        auto anyMaterial = [&](bool (*test)(const Material&, uint64_t)) {
            return std::any_of(job_.materials.begin(), job_.materials.end(),
                               [&](const Material& m) { return test(m, mapped); }) ? 1u : 0u;
        };
        cutouts_ = anyMaterial(isAlphaTested);
        blends_ = anyMaterial(isBlended);
        const uint32_t packed = b_.packedPositions ? 1u : 0u;
        if (!pager_.allResident()) w_.startWalkVariants({{cost, 1u, cutouts_, blends_, packed}});
        if (!b_.outOfCore) w_.startWalkVariants({{cost, 0u, cutouts_, blends_, packed}});
        const bool emitters = options_.emitters && !options_.emitters->entries.empty();
        if (emitters && (options_.emitters->entries.size() > b_.tables.emitterCapacity ||
                         options_.emitters->areaDensity.size() != job_.materials.size()))
            return Status::error("device render: " + std::to_string(options_.emitters->entries.size()) +
                                 " emissive triangles over " + std::to_string(options_.emitters->areaDensity.size()) +
                                 " materials, the package's tables hold " + std::to_string(b_.tables.emitterCapacity) +
                                 " over " + std::to_string(job_.materials.size()));
        const ShadeConstants constants =
            shadeConstants(job_.materials, options_.integrator == IntegratorKind::AmbientOcclusion,
                           sun[0] > 0 || sun[1] > 0 || sun[2] > 0, b_.normals, b_.colors, environmentMap,
                           volumes ? volumeCodecs(*options_.volumes) : 0u, lights,
                           b_.textures && b_.uvs, b_.frames, emitters, b_.walkBits != nullptr);
        const bool glossy = constants[7] != 0;
        auto shade = w_.variant(false, constants, stats_);
        if (!shade) return shade.status();
        shade_ = *shade;
        VASTRAY_TRY(uploadParams());
        if (glossy) VASTRAY_TRY(upload(microfacetTables(), b_.tables.microfacet));
        VASTRAY_TRY(upload(std::vector<uint32_t>(b_.chunkCount, 0), b_.tables.touched));
        VASTRAY_TRY(upload(std::vector<uint32_t>(b_.chunkCount + 2, 0), b_.tables.demand));
        std::vector<uint32_t> args;
        for (uint32_t q = 0; q < kQueueCount; ++q) args.insert(args.end(), {0u, 1u, 1u});
        VASTRAY_TRY(upload(args, b_.tables.queueArgs));
        VASTRAY_TRY(uploadResidency());
        if (b_.walkBits)  // no path's rays are being walked (a failed render may have left some)
            record([this](VkCommandBuffer cmd) {
                vkCmdFillBuffer(cmd, b_.walkBits->handle(), 0, VK_WHOLE_SIZE, 0);
                barrier(cmd);
            });
        if (volumes && b_.volumes->paged())  // no path's tracking is parked (a failed render may have left some)
            record([this](VkCommandBuffer cmd) {
                vkCmdFillBuffer(cmd, b_.volumes->buffer()->handle(), b_.volumes->parkOffset(), b_.volumes->parkBytes(), 0);
                barrier(cmd);
            });
        const uint32_t spp = options_.samplesPerPixel;
        const uint32_t samplesPerWave = std::min(spp, b_.pathCapacity);
        // Tiles of the image (the frame, or a region of it); the device sees frame pixels.
        const uint32_t width = image_.width, height = image_.height;
        // Out of core (chunks, volume bricks or texture pages paged), waves are streamed
        // (renderStreamed) when a group of a pixel's samples leaves room for a window of two tiles
        // or more. With volume bricks paged and the chunks resident, a streamed tile holds the
        // pixels of at most a sixteenth of the wave's paths, so that below 16 spp the
        // window still has 16 tiles and a closing tile (which waits for its slowest path) holds
        // back a sixteenth of the wave, not 1/spp of it (PERF_NOTES 75: the 256^3 cloud at 4 spp
        // 226 -> 149 steps; chunks paged the same way took more loads and time, 16x over budget
        // 4,976 -> 7,741 loads: a window of more tiles spreads their demand over more chunks).
        const bool paged = b_.outOfCore || (volumes && b_.volumes->paged()) || pagedTextures();
        const bool streamed = job_.streamWaves && paged && samplesPerWave >= 2;
        const bool fineTiles = streamed && !b_.outOfCore && volumes && b_.volumes->paged();
        const TileGrid grid = planTiles(
            width, height,
            std::max<uint64_t>(1, b_.pathCapacity / (fineTiles ? std::max(samplesPerWave, kFineWindowTiles) : samplesPerWave)));
        if (streamed) {
            VASTRAY_TRY(renderStreamed(grid, samplesPerWave));
        } else {
            for (uint64_t tile = 0; tile < grid.count(); ++tile) {
                VASTRAY_TRY(renderTile(tileAt(grid, tile), samplesPerWave));
                if (job_.progress) job_.progress(tile + 1, grid.count());
            }
        }
        std::vector<uint32_t> touched(b_.chunkCount);
        VASTRAY_TRY(download(touched.data(), touched.size() * 4, *b_.table, b_.tables.touched));
        pager_.streamTouched(touched);
        return Status::ok();
    }

private:
    const Pipelines& kernels() const { return w_.pipelines_; }
    // The textures when they are paged (a shading or an albedo may wait for a page); else null.
    DeviceTextures* pagedTextures() const { return b_.textures && b_.textures->paged() ? b_.textures : nullptr; }

    // A rectangle of the image, which lies at (originX, originY) in a frame frameWidth wide; its
    // pixel i (row by row) is the image's pixel at(i) and the frame's pixel first() + ...
    struct Tile {
        uint32_t x = 0, y = 0, width = 0, height = 0, imageWidth = 0;
        uint32_t originX = 0, originY = 0, frameWidth = 0;
        uint32_t first() const { return (originY + y) * frameWidth + originX + x; }
        uint32_t count() const { return width * height; }
        uint64_t at(uint64_t i) const { return uint64_t(y + i / width) * imageWidth + x + i % width; }
    };

    Tile tileAt(const TileGrid& grid, uint64_t index) const {
        Tile t;
        t.x = uint32_t(index % grid.columns) * grid.tileWidth, t.y = uint32_t(index / grid.columns) * grid.tileHeight;
        t.width = std::min(grid.tileWidth, image_.width - t.x), t.height = std::min(grid.tileHeight, image_.height - t.y);
        t.imageWidth = image_.width;
        t.originX = image_.originX, t.originY = image_.originY, t.frameWidth = options_.width;
        return t;
    }

    // Where the output buffer (b_.outputPixels pixels) keeps each output and the step's counters.
    OutputLayout outputs() const { return outputLayout(b_.outputPixels, stepCounterBytes(b_.tables)); }

    // Zeroes the cost AOV of `count` output pixels from `first` (a tile's, or a window slot's).
    void clearCost(uint64_t first, uint64_t count) {
        if (!(image_.aovs & kAovCost)) return;
        const uint64_t at = outputs().cost + 8 * first;
        recordFill([=, this](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, b_.output->handle(), at, count * 8, 0); });
    }

    // The AOVs of a tile's pixels: one walk of pixel-centre rays, which belong to no path.
    Status walkAovs(const Tile& tile) {
        WavefrontPush push = makePush(tile, 0, 1, kGenerateAov);
        clearQueue(push.queue);
        dispatch(*kernels().generate, kGenerate, push, tile.count());
        push.mode = kWaveTiled;  // for the walk
        VASTRAY_TRY(walkWave(push, false));
        DeviceTextures* textures = (image_.aovs & (kAovAlbedo | kAovNormal)) ? pagedTextures() : nullptr;
        if (textures) {
            clearQueue(kShadeWaitQueue);
            clearTextureCounters(*textures);
        }
        push.mode = kAovPixels;
        dispatch(*kernels().aov, kAov, push, tile.count());
        return textures ? retryAovs(push, *textures) : Status::ok();
    }

    // Paged textures: the pixels whose albedo waited for a page (kShadeWaitQueue), until none
    // waits: the pages they asked for are loaded and wf_aov.comp runs again over those pixels.
    Status retryAovs(WavefrontPush push, DeviceTextures& textures) {
        std::vector<uint32_t> demand(textures.pageCount());
        for (;;) {
            copyTextureCounters(textures);
            VASTRAY_TRY(flush());
            uint32_t waiting = 0;
            VASTRAY_TRY(download(&waiting, 4, *b_.table, b_.tables.queueCounts + 4ull * kShadeWaitQueue));
            if (waiting == 0) return Status::ok();
            VASTRAY_TRY(download(demand.data(), demand.size() * 4, textures.readback(), 0));
            auto loaded = textures.page(demand, stats_);
            if (!loaded) return loaded.status();
            if (*loaded == 0) return nothingLoaded(waiting, nullptr, &textures);
            moveWaitingToShadeQueue();
            clearTextureCounters(textures);
            push.mode = kAovRetry;
            dispatchQueue(*kernels().aov, kAov, push, kShadeQueue);
            clearQueue(kShadeQueue);
        }
    }

    // The error of a paging step that loaded nothing while `waiting` paths (or AOV pixels) wait.
    Status nothingLoaded(uint32_t waiting, const DeviceVolumes* volumes, const DeviceTextures* textures) const {
        std::string pools;
        if (volumes) pools = "the pool of " + std::to_string(volumes->slotCount()) + " brick slots";
        if (textures)
            pools += (pools.empty() ? "" : " and ") + std::string("the pool of ") +
                     std::to_string(textures->slotCount()) + " texture page slots";
        return Status::error(std::to_string(waiting) + " paths wait for " +
                             (volumes && textures ? "volume bricks or texture pages"
                              : volumes           ? "volume bricks"
                                                  : "texture pages") +
                             ", but " + pools + " loaded none");
    }

    Status renderTile(const Tile& tile, uint32_t samplesPerWave) {
        const uint32_t count = tile.count();
        const StateLayout state = stateLayout(b_.pathCapacity, b_.uvs, b_.frames);
        record([=, this](VkCommandBuffer cmd) {
            vkCmdFillBuffer(cmd, b_.state->handle(), state.accum, uint64_t(count) * 16, 0);
            barrier(cmd);
        });
        clearCost(0, count);
        if (image_.aovs & ~kAovCost) VASTRAY_TRY(walkAovs(tile));
        for (uint32_t s0 = 0; s0 < options_.samplesPerPixel; s0 += samplesPerWave) {
            if (job_.cancel && job_.cancel->load()) return Status::error("render cancelled");
            const uint32_t samples = std::min(samplesPerWave, options_.samplesPerPixel - s0);
            WavefrontPush push = makePush(tile, s0, samples, kGeneratePaths);
            clearQueue(push.queue);
            dispatch(*kernels().generate, kGenerate, push, uint64_t(count) * samples);
            VASTRAY_TRY(walkWave(push, true));
            push.mode = s0 + samples == options_.samplesPerPixel ? 1u : 0u;
            dispatch(*kernels().accumulate, kAccumulate, push, count);
        }
        VASTRAY_TRY(flush());
        return readTile(tile);
    }

    // Empties queue q (its count) before kernels append to it; `besideNext`: the op recorded next
    // does not touch q, so no barrier between them.
    void clearQueue(uint32_t q, bool besideNext = false) {
        recordFill([this, q](VkCommandBuffer cmd) {
            vkCmdFillBuffer(cmd, b_.table->handle(), b_.tables.queueCounts + 4ull * q, 4, 0);
            vkCmdFillBuffer(cmd, b_.table->handle(), b_.tables.queueArgs + 12ull * q, 4, 0);
        }, besideNext);
    }

    WavefrontPush makePush(const Tile& tile, uint32_t firstSample, uint32_t samples, uint32_t mode) {
        WavefrontPush p{};
        p.params = b_.table->address() + b_.tables.params;
        p.firstPixel = tile.first(), p.pixelCount = tile.count(), p.tileWidth = tile.width;
        p.firstSample = firstSample, p.sampleCount = samples;
        p.mode = mode, p.queue = kWalkQueue, p.parkQueue = kParkQueue;
        putGrid(p);
        return p;
    }

    // The grid wf_walk's kPackedPositions rebuilds vertices with (zeros without it).
    void putGrid(WavefrontPush& p) const {
        p.gridOriginX = b_.grid[0], p.gridOriginY = b_.grid[1], p.gridOriginZ = b_.grid[2], p.gridStep = b_.grid[3];
    }

    // One walk pass over the walk queue (the rays generate and shade started; emptied after it),
    // in a paging step's first pass (`parked`) beside a walk of the rays the step before parked
    // (the park queue other than push.parkQueue, which the rays parked now join; the two walks
    // share a barrier), then, when shading, the shading of the paths it finished (their new rays
    // join the walk queue).
    void walkRound(WavefrontPush& push, bool shade, bool parked) {
        if (parked) {
            WavefrontPush p = push;
            p.queue = otherParkQueue(push.parkQueue);
            dispatchQueue(*walk_, kWalk, p, p.queue, true);
        }
        dispatchQueue(*walk_, kWalk, push, kWalkQueue);
        ++stats_.walkPasses;
        clearQueue(kWalkQueue);
        if (shade) shadeReady(push);
    }
    static uint32_t otherParkQueue(uint32_t q) { return q == kParkQueue ? kParkQueue + 1 : kParkQueue; }
    // A paging step's start: the park queues trade places (the rays the last step parked walk in
    // this step's first pass, beside the walk queue's), the rays this step parks go to the other
    // one, emptied, and the demand (with its total) and look-ahead counters start from zero: a
    // ray parks at most once a step, so after the step they count every parked ray once.
    void beginPagingStep(WavefrontPush& push) {
        push.parkQueue = otherParkQueue(push.parkQueue);
        clearQueue(push.parkQueue);
        recordFill([this](VkCommandBuffer cmd) {
            vkCmdFillBuffer(cmd, b_.table->handle(), b_.tables.demand, (uint64_t(b_.chunkCount) + 1) * 4, 0);
            vkCmdFillBuffer(cmd, b_.table->handle(), b_.tables.ahead, uint64_t(b_.chunkCount) * 4, 0);
        });
    }
    // Streamed waves restart the groups the shading ends in the shading itself
    // (StreamingOptions::restartInShade): a generate kernel after each shading cost ~30 us of
    // device time a dispatch at 10M over 4x, ~1,800 of them a frame (PERF_NOTES 106, 107).
    bool restartInShade() const { return streamed_ && job_.restartInShade; }
    void shadeReady(WavefrontPush& push) {
        WavefrontPush s = push;
        s.kernelFlags = restartInShade() ? kKernelRestartGroups : 0u;
        dispatchQueue(*shade_, kShade, s, kShadeQueue);
        // Streamed, restarted by a generate kernel: that kernel touches the group and walk queues,
        // not this one, so the clear runs beside it, behind the same barrier.
        const bool generate = streamed_ && !restartInShade();
        clearQueue(kShadeQueue, generate);
        if (generate) regenerate(push, 0);
    }
    // Streamed waves: the groups of queue push.groupQueue (those whose block the shading just
    // finished, and idle ones), or with allGroups > 0 the groups 0..allGroups-1, add their block
    // to their pixel and start the next one (wf_generate.comp, kGenerateStream).
    void regenerate(WavefrontPush& push, uint32_t allGroups) {
        WavefrontPush g = push;
        g.mode = kGenerateStream, g.pixelCount = allGroups;
        if (allGroups > 0)
            dispatch(*kernels().generate, kGenerate, g, allGroups);
        else
            dispatchQueue(*kernels().generate, kGenerate, g, push.groupQueue);
        clearQueue(push.groupQueue);
        push.groupQueue = 2 * kGroupQueue + 1 - push.groupQueue;  // the other one (kGroupQueue is odd)
    }
    // Paged volumes or textures: the paths of the wait queue move to the (empty) shade queue and
    // shade again; those that still miss a brick or page join the wait queue again.
    void retryWaiting(WavefrontPush& push) {
        moveWaitingToShadeQueue();
        shadeReady(push);
    }
    // The wait queue becomes the shade queue, and is emptied. The whole queue is copied: the
    // shading just before may have added paths the host has not counted.
    void moveWaitingToShadeQueue() {
        record([this](VkCommandBuffer cmd) {
            const uint64_t queues = stateLayout(b_.pathCapacity, b_.uvs, b_.frames).queues, capacity = b_.pathCapacity;
            const VkBufferCopy paths{queues + queueOffset(kShadeWaitQueue, capacity),
                                     queues + queueOffset(kShadeQueue, capacity), 4 * capacity};
            vkCmdCopyBuffer(cmd, b_.state->handle(), b_.state->handle(), 1, &paths);
            const VkBufferCopy counters[] = {
                {b_.tables.queueCounts + 4ull * kShadeWaitQueue, b_.tables.queueCounts + 4ull * kShadeQueue, 4},
                {b_.tables.queueArgs + 12ull * kShadeWaitQueue, b_.tables.queueArgs + 12ull * kShadeQueue, 12}};
            vkCmdCopyBuffer(cmd, b_.table->handle(), b_.table->handle(), 2, counters);
            barrier(cmd);
        });
        clearQueue(kShadeWaitQueue);
    }
    // Paged textures: the step's demand counters into host-cached memory, and their clearing.
    void copyTextureCounters(const DeviceTextures& textures) {
        record([&textures](VkCommandBuffer cmd) {
            const VkBufferCopy region{textures.demandOffset(), 0, textures.pageCount() * 4};
            vkCmdCopyBuffer(cmd, textures.buffer().handle(), textures.readback().handle(), 1, &region);
            barrier(cmd);
        });
    }
    void clearTextureCounters(const DeviceTextures& textures) {
        recordFill([&textures](VkCommandBuffer cmd) {
            vkCmdFillBuffer(cmd, textures.buffer().handle(), textures.demandOffset(), textures.pageCount() * 4, 0);
        });
    }
    // Paged volumes: the step's demand counters into host-cached memory.
    void copyVolumeCounters(const DeviceVolumes& volumes) {
        if (volumes.brickCount() == 0) return;
        record([&volumes](VkCommandBuffer cmd) {
            const VkBufferCopy region{volumes.demandOffset(), 0, volumes.demandCount() * 4};
            vkCmdCopyBuffer(cmd, volumes.buffer()->handle(), volumes.readback()->handle(), 1, &region);
            barrier(cmd);
        });
    }
    // Where copyStepCounters puts the table's bytes at `tableOffset` (from TableLayout::touched
    // to ::queueArgs, or the window head at ::stream) in the output buffer.
    uint64_t stepCopyOf(uint64_t tableOffset) const {
        const TableLayout& t = b_.tables;
        const uint64_t at = outputs().counters;
        return tableOffset >= t.stream ? at + (t.queueArgs - t.touched) + (tableOffset - t.stream)
                                       : at + (tableOffset - t.touched);
    }
    // The step's counters and window head into the output buffer (stepCounterBytes), where the
    // host reads them after the step from host-cached memory.
    void copyStepCounters() {
        record([this](VkCommandBuffer cmd) {
            const TableLayout& t = b_.tables;
            const VkBufferCopy regions[2] = {{t.touched, stepCopyOf(t.touched), t.queueArgs - t.touched},
                                             {t.stream, stepCopyOf(t.stream), kWindowHeadBytes}};
            vkCmdCopyBuffer(cmd, b_.table->handle(), b_.output->handle(), 2, regions);
            VkMemoryBarrier b{};
            b.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
            b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            b.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &b, 0, nullptr, 0,
                                 nullptr);
        });
    }
    // Paged volumes: no brick is asked for yet.
    void clearVolumeCounters(const DeviceVolumes& volumes) {
        recordFill([&volumes](VkCommandBuffer cmd) {
            if (volumes.brickCount() > 0)
                vkCmdFillBuffer(cmd, volumes.buffer()->handle(), volumes.demandOffset(), volumes.demandCount() * 4, 0);
        });
    }

    // Runs the wave's rays (and, when shading, its paths to their ends) from queue push.queue.
    // In core: one walk pass and one shading per scattering event, recorded behind the previous
    // kernels. Out of core: paging steps; each submits a few walk passes with shading between
    // them (a path goes on at once while its chunks are resident), reads the per-chunk demand
    // of the rays parked by the last one and the queue sizes, and lets the pager page in the
    // chunks the parked rays wait for. Paths at different bounces share the steps, so a chunk's
    // residency serves every bounce that needs it.
    // With job.overlapLoads the pager only plans between steps (evicting the victims, which the
    // next step then sees empty) and loads while the device walks that step: uploads and decoding
    // overlap the device's work, and a chunk serves rays one step later than it would otherwise.
    // When the next step would have nothing to do without the planned chunks, they are loaded
    // before it instead.
    Status walkWave(WavefrontPush& push, bool shade) {
        const bool ao = options_.integrator == IntegratorKind::AmbientOcclusion;
        const uint32_t events = !shade ? 1u : ao ? 2u : options_.maxDepth + 1u;
        clearQueue(kShadeQueue);
        clearQueue(kShadeWaitQueue);
        // In core no ray parks: the walk without the paging code.
        auto walk = w_.variant(true, WalkConstants{(image_.aovs & kAovCost) != 0, !pager_.allResident(), cutouts_, blends_,
                                                            b_.packedPositions}, stats_);
        if (!walk) return walk.status();
        walk_ = *walk;
        DeviceVolumes* volumes = shade && b_.volumes && b_.volumes->paged() ? b_.volumes : nullptr;
        DeviceTextures* textures = shade ? pagedTextures() : nullptr;
        if (pager_.allResident() && !volumes && !textures) {
            for (uint32_t e = 0; e < events; ++e) walkRound(push, shade, false);
            return Status::ok();
        }
        clearQueue(kParkQueue);
        clearQueue(kParkQueue + 1);
        pager_.beginStream();
        Paging st(b_.chunkCount, volumes, textures);
        const std::vector<uint32_t>& counts = st.counts;
        // Paging bricks or pages: a step's passes take every path it resumes to its end or its
        // next park (for bricks, pages or chunks; a pass over an empty queue costs an empty
        // dispatch), so that no path needs the step's region in a later step. Paging chunks
        // only: a few passes, then the host pages again; one without shading (no pass after the
        // first has rays to walk).
        for (uint64_t step = 0;; ++step) {
            const uint32_t passes = !shade ? 1u : volumes || textures ? events : chunkPagingPasses();
            if (job_.cancel && job_.cancel->load()) return Status::error("render cancelled");
            beginPagingStep(push);
            if (volumes) clearVolumeCounters(*volumes);
            if (textures) clearTextureCounters(*textures);
            if (step > 0 && shade) shadeReady(push);  // the paths the last step's final pass finished
            if ((volumes || textures) && counts[kShadeWaitQueue] > 0) retryWaiting(push);
            recordFill([this](VkCommandBuffer cmd) {
                vkCmdFillBuffer(cmd, b_.table->handle(), b_.tables.touched, uint64_t(b_.chunkCount) * 4, 0);
            });
            for (uint32_t r = 0; r < passes; ++r) walkRound(push, shade && r + 1 < passes, r == 0);
            VASTRAY_TRY(runStep(st, volumes, textures));
            if (counts[push.parkQueue] == 0 && counts[kShadeQueue] == 0 && counts[kShadeWaitQueue] == 0)
                return finishPaging(st);
            VASTRAY_TRY(pageChunks(st, counts[kShadeQueue]));
        }
    }

    // A paging step's counters, and the chunks planned for the next step.
    struct Paging {
        Paging(uint32_t chunks, const DeviceVolumes* volumes, const DeviceTextures* textures)
            : demand(chunks + 2), ahead(chunks), counts(kQueueCount), touched(chunks), waveTouched(chunks, 0),
              brickDemand(volumes ? volumes->demandCount() : 0), pageDemand(textures ? textures->pageCount() : 0) {}
        std::vector<uint32_t> demand, ahead, counts, touched, waveTouched, brickDemand, pageDemand;
        bool planned = false;  // loads planned for the step about to run
        size_t loaded = 0;     // chunks loaded during the last step
    };

    // The last step: chunks it loaded become resident on the device too; the stream's chunks.
    Status finishPaging(const Paging& st) {
        if (st.loaded > 0 || residencyMasked_) VASTRAY_TRY(uploadResidency());
        pager_.streamTouched(st.waveTouched);
        return Status::ok();
    }

    // Submits the step recorded, loads the chunks planned after the last one and does the host's
    // `alongside` work (streamed waves: reading the tiles closed after the last step) while the
    // device works, waits, reads the counters (demand and look-ahead, queue sizes, touched flags)
    // and, when paths wait for volume bricks or texture pages, pages in what they wait for
    // (DeviceVolumes::page, DeviceTextures::page: every such step loads at least one).
    Status runStep(Paging& st, DeviceVolumes* volumes, DeviceTextures* textures,
                   const std::function<Status()>& alongside = {}) {
        if (volumes) copyVolumeCounters(*volumes);
        if (textures) copyTextureCounters(*textures);
        copyStepCounters();
        VASTRAY_TRY(beginSubmit());
        st.loaded = 0;
        if (st.planned) {
            auto done = pager_.loadPlanned();  // while the device walks
            if (!done) return done.status();
            st.loaded = done->size(), st.planned = false;
        }
        if (alongside) {
            const Status s = alongside();
            if (!s.isOk()) {
                (void)finishSubmit();
                return s;
            }
        }
        VASTRAY_TRY(finishSubmit());
        stepEnded_ = std::chrono::steady_clock::now();
        const TableLayout& t = b_.tables;
        VASTRAY_TRY(download(st.demand.data(), st.demand.size() * 4, *b_.output, stepCopyOf(t.demand)));
        VASTRAY_TRY(download(st.ahead.data(), st.ahead.size() * 4, *b_.output, stepCopyOf(t.ahead)));
        VASTRAY_TRY(download(st.counts.data(), st.counts.size() * 4, *b_.output, stepCopyOf(t.queueCounts)));
        VASTRAY_TRY(download(st.touched.data(), st.touched.size() * 4, *b_.output, stepCopyOf(t.touched)));
        for (size_t c = 0; c < st.touched.size(); ++c) st.waveTouched[c] |= st.touched[c];
        pager_.markUsed(st.touched);
        const uint32_t waiting = st.counts[kShadeWaitQueue];
        if (!(volumes || textures) || waiting == 0) return Status::ok();
        uint64_t loads = 0;
        if (volumes) {
            VASTRAY_TRY(download(st.brickDemand.data(), st.brickDemand.size() * 4, *volumes->readback(), 0));
            auto paged = volumes->page(st.brickDemand, stats_);
            if (!paged) return paged.status();
            loads += *paged;
        }
        if (textures) {
            VASTRAY_TRY(download(st.pageDemand.data(), st.pageDemand.size() * 4, textures->readback(), 0));
            auto paged = textures->page(st.pageDemand, stats_);
            if (!paged) return paged.status();
            loads += *paged;
        }
        return loads > 0 ? Status::ok() : nothingLoaded(waiting, volumes, textures);
    }

    // After a step that did not finish: plans the chunks the parked rays wait for. With overlap
    // they load while the device walks the next step, when it has work without them (`ready`:
    // paths to shade or groups to start, plus parked rays that wait for chunks resident now),
    // else now. With partial residency the next step sees the chunks whose copies still run as
    // absent, and does not wait for them, when it has work without them too (`arrived`).
    Status pageChunks(Paging& st, uint64_t ready) {
        const bool partial = job_.partialResidency && job_.overlapLoads && b_.uploader;
        uint64_t completed = kAllCopies;  // the copies done by now (all without partial residency)
        if (partial) {
            auto done = b_.uploader->completed();
            if (!done) return done.status();
            completed = *done;
        }
        if (st.demand[b_.chunkCount] == 0)  // nobody waits: the paths go on
            return st.loaded > 0 || residencyMasked_ ? uploadResidency(completed) : Status::ok();
        const auto plan = pager_.planLoads(std::span<const uint32_t>(st.demand).first(b_.chunkCount), st.ahead);
        st.planned = !plan.empty();
        const std::span<const uint32_t> slots = pager_.chunkSlots();
        uint64_t arrived = ready, arriving = 0;
        for (uint32_t c = 0; c < b_.chunkCount; ++c)
            if (slots[c] != kEmptyCell)
                (copyRunning(c, completed) ? arriving : arrived) += uint64_t(st.demand[c]) + st.ahead[c];
        if (st.planned && (!job_.overlapLoads || arrived + arriving == 0)) {
            auto done = pager_.loadPlanned();
            if (!done) return done.status();
            st.loaded += done->size(), st.planned = false;
            ++stats_.idleLoadSteps;
        }
        // Chunks the step just run saw absent while their copies ran are on their way.
        if (plan.empty() && st.loaded == 0 && !residencyMasked_)
            return Status::error("rays wait for chunks, but the pager loaded none (no evictable slot)");
        return uploadResidency(arrived > 0 ? completed : kAllCopies);
    }

    // Walk passes of the next paging step when it pages chunks only (kPassesPerPagingStep).
    uint32_t chunkPagingPasses() const {
        return b_.walkBits ? kPassesWithHostState : residencyMasked_ ? kPassesWhileCopiesRun : kPassesPerPagingStep;
    }

    // Whether chunk c's copy into its slot (DMA) was still running at timeline value `completed`.
    bool copyRunning(uint32_t c, uint64_t completed) const {
        return b_.uploader && b_.uploader->copyValue(c) > completed;
    }

    // Streamed waves (out of core; docs/RENDERING.md, "Streamed waves"). The wave's paths form
    // groups of `groupSize` (a pixel's block of samples); a group whose block is done adds it to
    // its pixel's sum and starts the pixel's next block, or the next pixel of a window of open
    // tiles, at once (in the shading that ended it, common/StreamGroups.glsl, or with
    // restartInShade off in wf_generate.comp after every shading), so the wave stays full while the
    // last paths of a tile wait for their chunks, instead of a tile's wave running down to its
    // last path before the next tile starts. A tile's outputs lie in a ring slot of the output
    // buffer; the host closes a tile when the device has counted all its pixels done, reads it
    // and opens the next. A tile holds about as many pixels as the wave has groups, so the window
    // is as wide as the output buffer holds tiles (PoolPlan::outputPixels: out of core with the
    // outputs in host memory twice the wave's pixels, ~32 tiles), at most kMaxWindowTiles. The
    // AOVs come first, tile by tile, as in renderTile.
    Status renderStreamed(const TileGrid& grid, uint32_t groupSize) {
        const uint64_t tiles = grid.count();
        const uint32_t tilePixels = grid.tileWidth * grid.tileHeight;
        const uint32_t groupCount = b_.pathCapacity / groupSize;
        uint32_t ringSlots = uint32_t(std::min<uint64_t>(kMaxWindowTiles, b_.outputPixels / tilePixels));
        if (job_.windowTiles > 0) ringSlots = std::min(ringSlots, job_.windowTiles);
        stats_.streamWindowTiles = std::min<uint64_t>(ringSlots, tiles);
        if (image_.aovs & ~kAovCost)
            for (uint64_t tile = 0; tile < tiles; ++tile) {
                const Tile t = tileAt(grid, tile);
                clearCost(0, t.count());
                VASTRAY_TRY(walkAovs(t));
                VASTRAY_TRY(flush());
                VASTRAY_TRY(readAovs(t, 0, image_.aovs, false));
                VASTRAY_TRY(readWalkedRays());
            }
        VASTRAY_TRY(uploadBytes(&tilePixels, 4, b_.tables.params + offsetof(WavefrontParams, tilePixels)));
        auto walk = w_.variant(true, WalkConstants{(image_.aovs & kAovCost) != 0, 1u, cutouts_, blends_, b_.packedPositions}, stats_);
        if (!walk) return walk.status();
        walk_ = *walk;
        streamed_ = true;
        DeviceVolumes* volumes = b_.volumes && b_.volumes->paged() ? b_.volumes : nullptr;
        DeviceTextures* textures = pagedTextures();
        // Paging bricks or pages: every path a step resumes runs to its end or its next park (walkWave).
        const uint32_t events = options_.integrator == IntegratorKind::AmbientOcclusion ? 2u : options_.maxDepth + 1u;
        const StateLayout state = stateLayout(b_.pathCapacity, b_.uvs, b_.frames);
        record([=, this](VkCommandBuffer cmd) {  // every group idle
            vkCmdFillBuffer(cmd, b_.state->handle(), state.groupState, uint64_t(groupCount) * 8, kGroupIdle);
            barrier(cmd);
        });
        for (uint32_t q = 0; q < kQueueCount; ++q) clearQueue(q);
        WavefrontPush push{};
        push.params = b_.table->address() + b_.tables.params;
        push.sampleCount = groupSize, push.mode = kWaveStreamed, push.queue = kWalkQueue, push.groupQueue = kGroupQueue;
        push.parkQueue = kParkQueue;
        putGrid(push);

        struct Open {
            uint64_t tile;
            uint32_t slot, pixels;
        };
        std::vector<Open> window;  // oldest first
        // Tiles closed after a step: their slots stay busy until the host has read them, which it
        // does while the device runs the next step (the device no longer writes them: they left
        // the window; reading ~34 tiles of a 1080p frame took 0.011-0.014 s of the host's time
        // between steps, PERF_NOTES 100), or at once after the last step or when the window has
        // no pixel left to start.
        std::vector<Open> closing;
        std::vector<bool> slotBusy(ringSlots, false);
        uint64_t nextTile = 0, closed = 0;
        uint32_t cursor = 0;  // the device's window cursor, rewound to the window's end after a step
        const uint64_t streamOffset = b_.tables.stream;
        pager_.beginStream();
        Paging st(b_.chunkCount, volumes, textures);
        const std::vector<uint32_t>& counts = st.counts;
        std::vector<uint32_t> windowHead(kWindowHeadBytes / 4);  // cursor, tile count, padding, done[]
        uint64_t readTiles = 0;
        const auto readClosed = [&]() -> Status {
            for (const Open& o : closing) {
                const Tile t = tileAt(grid, o.tile);
                VASTRAY_TRY(readColor(t, uint64_t(o.slot) * tilePixels));
                if (image_.aovs & kAovCost)
                    VASTRAY_TRY(readAovs(t, uint64_t(o.slot) * tilePixels, kAovCost, (image_.aovs & ~kAovCost) != 0));
                slotBusy[o.slot] = false;
                ++stats_.streamedTiles;
                if (job_.progress) job_.progress(++readTiles, tiles);
            }
            closing.clear();
            return Status::ok();
        };
        for (uint64_t step = 0;; ++step) {
            const uint32_t passes = volumes || textures ? events : chunkPagingPasses();
            if (job_.cancel && job_.cancel->load()) return Status::error("render cancelled");
            // Open tiles in the free slots, and write the window.
            // (A slot whose tile closed after the last step is free once the host has read it.)
            for (auto idle = std::find(slotBusy.begin(), slotBusy.end(), false); idle != slotBusy.end() && nextTile < tiles;
                 idle = std::find(idle, slotBusy.end(), false)) {
                const uint32_t slot = uint32_t(idle - slotBusy.begin());
                *idle = true;
                window.push_back({nextTile, slot, tileAt(grid, nextTile).count()});
                ++nextTile;
                clearCost(uint64_t(slot) * tilePixels, tilePixels);
                recordFill([this, streamOffset, slot](VkCommandBuffer cmd) {
                    vkCmdFillBuffer(cmd, b_.table->handle(), streamOffset + offsetof(StreamWindow, done) + 4ull * slot, 4, 0);
                });
            }
            std::vector<uint32_t> head(4 + 4 * kMaxWindowTiles, 0);
            head[0] = cursor, head[1] = uint32_t(window.size());
            for (size_t i = 0; i < window.size(); ++i) {
                const Tile t = tileAt(grid, window[i].tile);
                uint32_t* entry = &head[4 + 4 * i];
                entry[0] = t.first(), entry[1] = t.width, entry[2] = window[i].pixels, entry[3] = window[i].slot;
            }
            stats_.hostToDeviceBytes += 16 + 16 * window.size();
            recordFill([this, streamOffset, head](VkCommandBuffer cmd) {
                vkCmdUpdateBuffer(cmd, b_.table->handle(), streamOffset, 8, head.data());
                vkCmdUpdateBuffer(cmd, b_.table->handle(), streamOffset + offsetof(StreamWindow, tiles),
                                  16 * kMaxWindowTiles, head.data() + 4);
                vkCmdFillBuffer(cmd, b_.table->handle(), b_.tables.demand + 4ull * (b_.chunkCount + 1), 4, 0);
                vkCmdFillBuffer(cmd, b_.table->handle(), b_.tables.touched, uint64_t(b_.chunkCount) * 4, 0);
            });
            beginPagingStep(push);
            if (volumes) clearVolumeCounters(*volumes);
            if (textures) clearTextureCounters(*textures);
            if (step == 0) {
                regenerate(push, groupCount);
            } else {
                // Groups left idle (the window had no pixel for them) take the pixels of the tiles
                // just opened; with restarts in the shading nothing else restarts them.
                if (restartInShade() && counts[push.groupQueue] > 0) regenerate(push, 0);
                shadeReady(push);  // the paths the last step's final pass finished (and the groups after them)
            }
            if ((volumes || textures) && counts[kShadeWaitQueue] > 0) retryWaiting(push);
            for (uint32_t r = 0; r < passes; ++r) walkRound(push, r + 1 < passes, r == 0);
            VASTRAY_TRY(runStep(st, volumes, textures, readClosed));
            // The head the step's end copied (copyStepCounters).
            VASTRAY_TRY(download(windowHead.data(), windowHead.size() * 4, *b_.output, stepCopyOf(streamOffset)));
            stats_.walkedRays += st.demand[b_.chunkCount + 1];
            // Close the tiles whose pixels are all done (all started: they lie before the
            // cursor), and rewind the cursor past them to the window's end at most.
            uint32_t windowPixels = 0;
            for (const Open& o : window) windowPixels += o.pixels;
            cursor = std::min(windowHead[0], windowPixels);
            for (size_t i = 0; i < window.size();) {
                const Open o = window[i];
                if (windowHead[4 + o.slot] < o.pixels) {
                    ++i;
                    continue;
                }
                cursor -= o.pixels, windowPixels -= o.pixels;
                closing.push_back(o);
                window.erase(window.begin() + long(i));
                ++closed;
                pager_.streamTouched(st.waveTouched);  // a stream: the steps between two closed tiles
                std::fill(st.waveTouched.begin(), st.waveTouched.end(), 0);
                pager_.beginStream();
            }
            if (closed == tiles) {
                VASTRAY_TRY(readClosed());
                break;
            }
            // A window whose every pixel has started (a narrow window) needs the closed tiles'
            // slots in the next step, or its idle groups would wait a step for pixels.
            if (cursor >= windowPixels && nextTile < tiles) VASTRAY_TRY(readClosed());
            const bool groupsWork = cursor < windowPixels || nextTile < tiles;  // idle groups get pixels next step
            VASTRAY_TRY(pageChunks(st, counts[kShadeQueue] + (groupsWork ? counts[push.groupQueue] : 0)));
        }
        streamed_ = false;
        return finishPaging(st);
    }

    Status readTile(const Tile& tile) {
        VASTRAY_TRY(readColor(tile, 0));
        VASTRAY_TRY(readAovs(tile, 0, image_.aovs, false));
        return readWalkedRays();
    }

    // The rays walked since the counter last restarted (a tile's streams), which restarts.
    Status readWalkedRays() {
        uint32_t rays = 0;
        VASTRAY_TRY(download(&rays, 4, *b_.table, b_.tables.demand + 4ull * (b_.chunkCount + 1)));
        stats_.walkedRays += rays;
        return upload(std::vector<uint32_t>(1, 0), b_.tables.demand + 4ull * (b_.chunkCount + 1));
    }

    // The tile's colour and alpha from the output pixels at `first` on.
    Status readColor(const Tile& tile, uint64_t first) {
        const OutputLayout o = outputs();
        const uint64_t count = tile.count();
        // RGBA in blocks on all cores: a 1080p tile is 33 MB, and one core copying and splitting
        // it (and faulting in the image's fresh pages) took longer than the device's 1 spp render.
        std::atomic<bool> failed{false};
        tbb::parallel_for(tbb::blocked_range<uint64_t>(0, count, 1 << 15), [&](const tbb::blocked_range<uint64_t>& r) {
            std::vector<float> block(4 * (r.end() - r.begin()));
            if (!b_.output->download(block.data(), block.size() * 4, o.color + 16 * (first + r.begin()))) {
                failed = true;
                return;
            }
            for (uint64_t i = r.begin(); i != r.end(); ++i) {
                const uint64_t p = tile.at(i), k = 4 * (i - r.begin());
                for (int c = 0; c < 3; ++c) image_.rgb[3 * p + c] = block[k + c];
                image_.alpha[p] = block[k + 3];
            }
        });
        if (failed) return Status::error("reading the rendered tile back from the device failed");
        stats_.deviceToHostBytes += 16ull * count;
        return Status::ok();
    }

    // The tile's AOVs among `aovs` from the output pixels at `first` on; the cost AOV is added to
    // the image's with addCost (streamed waves: the AOV walk's cost, then the paths').
    Status readAovs(const Tile& tile, uint64_t first, uint32_t aovs, bool addCost) {
        const OutputLayout o = outputs();
        if (aovs & kAovDepth) VASTRAY_TRY(readRows<float>(tile, 1, o.depth + 4 * first, image_.depth, false));
        if (aovs & kAovNormal) VASTRAY_TRY(readRows<float>(tile, 3, o.normal + 12 * first, image_.normal, false));
        if (aovs & kAovAlbedo) VASTRAY_TRY(readRows<float>(tile, 3, o.albedo + 12 * first, image_.albedo, false));
        if (aovs & kAovPrimId) VASTRAY_TRY(readRows<uint32_t>(tile, 1, o.primId + 4 * first, image_.primId, false));
        if (aovs & kAovChunkId) VASTRAY_TRY(readRows<uint32_t>(tile, 1, o.chunkId + 4 * first, image_.chunkId, false));
        if (aovs & kAovCost) VASTRAY_TRY(readRows<uint32_t>(tile, 2, o.cost + 8 * first, image_.cost, addCost));
        if (aovs & kAovUv) VASTRAY_TRY(readRows<float>(tile, 2, o.uv + 8 * first, image_.uv, false));
        return Status::ok();
    }

    // An output array of the tile (`channels` values of T per pixel, at `offset` in the output
    // buffer) into the image's array `to` (element type To), row by row; added to it with `add`.
    template <typename T, typename To>
    Status readRows(const Tile& tile, uint32_t channels, uint64_t offset, std::vector<To>& to, bool add) {
        std::vector<T> rows(uint64_t(channels) * tile.count());
        VASTRAY_TRY(download(rows.data(), rows.size() * sizeof(T), *b_.output, offset));
        const uint64_t rowValues = uint64_t(channels) * tile.width;
        for (uint32_t r = 0; r < tile.height; ++r) {
            const auto from = rows.begin() + r * rowValues;
            const auto at = to.begin() + tile.at(uint64_t(r) * tile.width) * channels;
            if (add)
                std::transform(from, from + rowValues, at, at, [](T a, To b) { return To(b + a); });
            else
                std::copy_n(from, rowValues, at);
        }
        return Status::ok();
    }

    Status uploadParams() {
        WavefrontParams p{};
        const uint64_t table = b_.table->address(), state = b_.state->address(), out = b_.output->address();
        const TableLayout& t = b_.tables;
        p.slotTable = table, p.topNodes = table + t.topNodes, p.chunkSlots = table + t.chunkSlots;
        p.touched = table + t.touched, p.demand = table + t.demand, p.ahead = table + t.ahead;
        p.materials = table + t.materials, p.microfacet = table + t.microfacet, p.lights = table + t.lights;
        p.emitters = table + t.emitters;
        const StateLayout s = stateLayout(b_.pathCapacity, b_.uvs, b_.frames);
        p.rayOrigin = state + s.rayOrigin, p.rayDirection = state + s.rayDirection;
        p.rayState = state + s.rayState;
        p.hitPosition = state + s.hitPosition, p.hitNormal = state + s.hitNormal, p.hitIds = state + s.hitIds;
        p.throughput = state + s.throughput, p.radiance = state + s.radiance, p.pendingSun = state + s.pendingSun;
        p.pathInfo = state + s.pathInfo, p.accum = state + s.accum, p.queues = state + s.queues;
        p.walkBits = b_.walkBits ? b_.walkBits->address() : p.pathInfo;  // apart, or in the path words
        p.walkBitsApart = b_.walkBits ? 1u : 0u;
        p.groupState = state + s.groupState, p.stream = table + t.stream;
        p.queueCounts = table + t.queueCounts, p.queueArgs = table + t.queueArgs;
        const OutputLayout o = outputs();
        p.outColor = out + o.color, p.outDepth = out + o.depth, p.outNormal = out + o.normal;
        p.outAlbedo = out + o.albedo, p.outPrimId = out + o.primId, p.outChunkId = out + o.chunkId;
        p.outCost = out + o.cost, p.outUv = out + o.uv;
        p.hitUv = b_.uvs ? state + s.hitUv : 0;
        p.hitFrame = b_.frames ? state + s.hitFrame : 0;
        setCamera(p, job_.camera, options_.width, options_.height);
        // Ray cones pick the maps' levels (core/RayCone.h); zero spreads sample level 0.
        if (options_.textureLod == TextureLodMode::Cone) {
            p.cameraSpread = CameraRays(job_.camera, options_.width, options_.height).coneSpread();
            p.scatterSpread = kConeScatterSpread;
        }
        setEnvironment(p, options_.environment);
        if (b_.environment) {
            const uint64_t base = b_.environment->address();
            const EnvironmentLayout e = environmentLayout(p.envWidth, p.envHeight);
            p.envRgb = base + e.rgb, p.envDensity = base + e.density;
            p.envMarginal = base + e.marginal, p.envConditional = base + e.conditional;
        }
        if (b_.volumes && options_.volumes) {
            const uint64_t base = b_.volumes->buffer()->address();
            p.volumes = base;  // the WavefrontVolume records come first
            p.volumeCount = uint32_t(options_.volumes->size());
            if (b_.volumes->paged()) {
                p.volumeDemand = base + b_.volumes->demandOffset();
                p.volumePark = base + b_.volumes->parkOffset();
                p.volumeBrickCount = uint32_t(b_.volumes->brickCount());
            }
        }
        if (b_.textures) {
            p.textures = b_.textures->recordsAddress(), p.texturePages = b_.textures->pageTableAddress();
            p.texturePool = b_.textures->poolAddress(), p.textureDemand = b_.textures->demandAddress();
        }
        p.aoDistance = options_.aoDistance;
        p.boundsLoX = b_.bounds.lo.x, p.boundsLoY = b_.bounds.lo.y, p.boundsLoZ = b_.bounds.lo.z;
        p.boundsHiX = b_.bounds.hi.x, p.boundsHiY = b_.bounds.hi.y, p.boundsHiZ = b_.bounds.hi.z;
        p.imageWidth = options_.width;
        p.materialCount = uint32_t(job_.materials.size());
        p.seed = options_.seed, p.samplesPerPixel = options_.samplesPerPixel, p.maxDepth = options_.maxDepth;
        p.aovs = image_.aovs, p.pathCapacity = b_.pathCapacity;
        p.chunkCount = b_.chunkCount, p.topNodeCount = b_.topNodeCount;
        std::vector<WavefrontMaterial> materials;
        for (const Material& m : job_.materials) {
            WavefrontMaterial& r = materials.emplace_back();
            r.baseR = m.baseColor[0], r.baseG = m.baseColor[1], r.baseB = m.baseColor[2];
            r.emitR = m.emissive[0], r.emitG = m.emissive[1], r.emitB = m.emissive[2];
            r.doubleSided = m.doubleSided ? 1u : 0u;
            r.metallic = m.metallic, r.roughness = m.roughness, r.specular = m.specular;
            r.specularColorR = m.specularColor[0], r.specularColorG = m.specularColor[1];
            r.specularColorB = m.specularColor[2];
            r.clearcoat = m.clearcoat, r.clearcoatRoughness = m.clearcoatRoughness;
            r.dielectricF0 = iorF0(m.ior);
            setMaps(m, r);
        }
        VASTRAY_TRY(uploadEmitters(p, materials));
        VASTRAY_TRY(upload(materials, b_.tables.materials));
        VASTRAY_TRY(uploadLights(p));
        return uploadBytes(&p, sizeof(p), b_.tables.params);
    }

    // The textures the maps can read: the package's when the device holds them and the hits' UVs; else none.
    uint64_t readableTextures() const { return b_.textures && b_.uvs ? job_.textures.size() : 0; }
    // The render's punctual lights (none: empty).
    std::span<const LightEntry> lights() const {
        return options_.lights ? std::span<const LightEntry>(*options_.lights) : std::span<const LightEntry>();
    }

    // The material's maps in its record: each map's texture (kNoGpuTexture without textures on the
    // device, the hits' UVs or a texture the package has) and UV transform.
    void setMaps(const Material& m, WavefrontMaterial& r) const {
        const uint64_t textures = readableTextures();
        auto set = [&](TextureSlot slot, uint32_t& texture, float* uv) {
            const TextureBinding& binding = m.textures.slots[uint32_t(slot)];
            texture = binding.texture < textures ? binding.texture : kNoGpuTexture;
            std::copy(binding.transform.begin(), binding.transform.end(), uv);
        };
        set(TextureSlot::BaseColor, r.baseColorMap, r.baseColorUv);
        set(TextureSlot::MetallicRoughness, r.metallicRoughnessMap, r.metallicRoughnessUv);
        set(TextureSlot::Emissive, r.emissiveMap, r.emissiveUv);
        set(TextureSlot::Normal, r.normalMap, r.normalUv);
        set(TextureSlot::Clearcoat, r.clearcoatMap, r.clearcoatUv);
        set(TextureSlot::ClearcoatRoughness, r.clearcoatRoughnessMap, r.clearcoatRoughnessUv);
        if (!(m.clearcoat > 0)) r.clearcoatMap = r.clearcoatRoughnessMap = kNoGpuTexture;
        if (!b_.frames) r.normalMap = kNoGpuTexture;
        r.normalScale = m.textures.normalScale;
        r.alphaCutoff = r.baseColorMap != kNoGpuTexture ? m.alphaCutoff : 0.0f;
        r.baseAlpha = m.baseColor[3];
        r.alphaBlend = isBlended(m, textures) ? 1u : 0u;
    }

    // The render's punctual lights (core/Light.h's table, the same floats the Embree reference
    // reads) into the table buffer's light section, which the package's light count sized.
    Status uploadLights(WavefrontParams& p) {
        if (!options_.lights || options_.lights->empty()) return Status::ok();
        p.lightCount = uint32_t(options_.lights->size());
        const std::span<const LightEntry> entries = lights();
        p.punctualPick = punctualPickProbability(options_.environment, entries);
        std::vector<WavefrontLight> lights;
        for (const LightEntry& e : entries)
            lights.push_back({e.position.x, e.position.y, e.position.z, uint32_t(e.type), e.direction.x, e.direction.y,
                              e.direction.z, e.cdf, e.radiant.x, e.radiant.y, e.radiant.z, e.pick, e.coneScale,
                              e.coneOffset, 0u, 0u});
        return upload(lights, b_.tables.lights);
    }

    // The render's emissive triangles (core/Emitters.h's table, the same floats the Embree
    // reference reads) into the table buffer's emitter section, which the package's emitter count
    // sized, and each material's density.
    Status uploadEmitters(WavefrontParams& p, std::vector<WavefrontMaterial>& materials) {
        if (!options_.emitters || options_.emitters->entries.empty()) return Status::ok();
        const EmitterTable& table = *options_.emitters;
        p.emitterCount = uint32_t(table.entries.size());
        p.emitterPick = emitterPickProbability(options_.environment, lights(), &table);
        for (size_t m = 0; m < materials.size(); ++m) materials[m].emitterDensity = table.areaDensity[m];
        Wavefront::UploadedEmitters& uploaded = w_.uploadedEmitters_;
        if (uploaded.table == options_.emitters && uploaded.buffer == b_.table && uploaded.offset == b_.tables.emitters)
            return Status::ok();
        uploaded = {};
        std::vector<WavefrontEmitter> emitters;
        emitters.reserve(table.entries.size());
        for (const EmitterEntry& e : table.entries)
            emitters.push_back({e.v0.x, e.v0.y, e.v0.z, e.material, e.v1.x, e.v1.y, e.v1.z, e.keep, e.v2.x, e.v2.y,
                                e.v2.z, e.alias, e.t0[0], e.t0[1], e.t1[0], e.t1[1], e.t2[0], e.t2[1], 0.0f, 0.0f});
        VASTRAY_TRY(upload(emitters, b_.tables.emitters));
        uploaded = {options_.emitters, b_.table, b_.tables.emitters};
        return Status::ok();
    }

    // The pager's chunk slots into the device's table. With `completed` below kAllCopies (out of
    // core, DMA uploads: the timeline value of the copies done), chunks whose copies still run
    // are written absent, and the next submission waits only for the copies done
    // (copiesWaitUpTo_): its kernels do not read the others' slots.
    static constexpr uint64_t kAllCopies = ~0ull;
    Status uploadResidency(uint64_t completed = kAllCopies) {
        const std::span<const uint32_t> slots = pager_.chunkSlots();
        residencyMasked_ = false;
        if (completed == kAllCopies || !b_.uploader)
            return uploadBytes(slots.data(), slots.size_bytes(), b_.tables.chunkSlots);
        std::vector<uint32_t> table(slots.begin(), slots.end());
        for (uint32_t c = 0; c < table.size(); ++c)
            if (table[c] != kEmptyCell && copyRunning(c, completed)) {
                table[c] = kEmptyCell, residencyMasked_ = true;
                ++stats_.lateChunks;
            }
        if (residencyMasked_) copiesWaitUpTo_ = completed;
        return upload(table, b_.tables.chunkSlots);
    }

    template <typename T>
    Status upload(const std::vector<T>& data, uint64_t offset) {
        return uploadBytes(data.data(), data.size() * sizeof(T), offset);
    }
    Status uploadBytes(const void* data, uint64_t bytes, uint64_t offset) {
        stats_.hostToDeviceBytes += bytes;
        return b_.table->upload(data, bytes, offset);
    }
    Status download(void* data, uint64_t bytes, const GpuBuffer& from, uint64_t offset) {
        stats_.deviceToHostBytes += bytes;
        return from.download(data, bytes, offset);
    }

    // An op that records its own barrier.
    void record(std::function<void(VkCommandBuffer)> op) { ops_.push_back({kNoKernel, std::move(op), false, false, true}); }
    // An op of fills and buffer updates only, each to its own range (no two adjacent ones touch
    // the same bytes): adjacent ones share one barrier, after the last (the queue clears and
    // counter fills between two kernels, ~6 barriers a paging step fewer). `besideNext`: the op
    // recorded next does not touch these bytes either, and shares that barrier too.
    void recordFill(std::function<void(VkCommandBuffer)> op, bool besideNext = false) {
        ops_.push_back({kNoKernel, std::move(op), true, besideNext, false});
    }
    void dispatch(const ComputePipeline& pipeline, Kernel kernel, const WavefrontPush& push, uint64_t threads) {
        if (threads == 0) return;
        ops_.push_back({kernel, [&pipeline, push, threads](VkCommandBuffer cmd) { pipeline.record(cmd, &push, groups(threads)); },
                        false, false, false});
    }
    // One thread per entry of queue q (an indirect dispatch: the count is on the device).
    // `besideNext`: the op recorded next touches nothing this kernel does but through atomics
    // (appends to the same queues, counters), and shares its barrier.
    void dispatchQueue(const ComputePipeline& pipeline, Kernel kernel, const WavefrontPush& push, uint32_t q,
                       bool besideNext = false) {
        ops_.push_back({kernel,
                        [this, &pipeline, push, q](VkCommandBuffer cmd) {
                            pipeline.recordIndirect(cmd, &push, b_.table->handle(), b_.tables.queueArgs + 12ull * q);
                        },
                        false, besideNext, false});
    }
    // Submits what was recorded and waits. With timestamps, one before the first command and
    // one after each barrier (after every kernel, and after the last of adjacent fills): the
    // difference is the device time of the commands between (barriers serialize them), added to
    // the figure of the kernel among them (a fill beside a kernel counts in that kernel's).
    Status flush() {
        VASTRAY_TRY(beginSubmit());
        return finishSubmit();
    }
    // Whether a barrier follows op i (every op but one that shares the next op's barrier).
    bool barrierAfter(size_t i) const {
        const Op& op = ops_[i];
        return op.ownBarrier || !(i + 1 < ops_.size() && (op.besideNext || (op.fill && ops_[i + 1].fill)));
    }
    // flush in two halves: the host may work between them (on what the submission does not read).
    Status beginSubmit() {
        if (ops_.empty()) return Status::ok();
        const VkQueryPool pool = queries_.handle();
        // The timestamp after each op (0: none; 1..: the query), as long as the pool has queries.
        stamps_.assign(ops_.size(), 0);
        uint32_t queries = pool ? 1 : 0;
        for (size_t i = 0; i < ops_.size() && pool && queries < kMaxQueries; ++i)
            if (barrierAfter(i)) stamps_[i] = queries++;
        submittedQueries_ = queries;
        const auto start = std::chrono::steady_clock::now();
        // Chunks loaded since the last submission are copied on the transfer queue: the kernels
        // wait for those copies on the device, the host does not.
        SubmitWait copies;
        if (b_.uploader) {
            auto pending = b_.uploader->pending(std::exchange(copiesWaitUpTo_, kAllCopies));
            if (!pending) {
                ops_.clear();
                return pending.status();
            }
            copies = *pending;
        }
        const Status s = w_.device_.begin([&](VkCommandBuffer cmd) {
            if (queries > 0) {
                vkCmdResetQueryPool(cmd, pool, 0, queries);
                vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, pool, 0);
            }
            for (size_t i = 0; i < ops_.size(); ++i) {
                ops_[i].record(cmd);
                if (!ops_[i].ownBarrier && barrierAfter(i)) barrier(cmd);
                if (stamps_[i] > 0) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool, stamps_[i]);
            }
        }, copies.semaphore ? &copies : nullptr);
        const auto submitted = std::chrono::steady_clock::now();
        deviceSeconds_ += std::chrono::duration<double>(submitted - start).count();
        if (stepEnded_) stats_.hostGapSeconds += std::chrono::duration<double>(submitted - *stepEnded_).count();
        stepEnded_.reset();
        ++stats_.submits;
        if (!s.isOk()) ops_.clear();
        return s;
    }
    // Waits for the submission (the time waited counts as device time) and adds its kernel times.
    Status finishSubmit() {
        if (!w_.device_.running()) return Status::ok();
        const auto start = std::chrono::steady_clock::now();
        const Status s = w_.device_.wait();
        deviceSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (s.isOk() && submittedQueries_ > 1) addKernelTimes(queries_.handle(), submittedQueries_);
        ops_.clear();
        return s;
    }
    void addKernelTimes(VkQueryPool pool, uint32_t queries) {
        std::vector<uint64_t> ticks(queries);
        if (vkGetQueryPoolResults(w_.device_.handle(), pool, 0, queries, ticks.size() * 8, ticks.data(), 8,
                                  VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT) != VK_SUCCESS)
            return;
        const uint32_t bits = w_.device_.timestampValidBits();
        const uint64_t mask = bits >= 64 ? ~0ull : (1ull << bits) - 1;
        const double seconds = w_.device_.timestampPeriodNs() * 1e-9;
        uint32_t before = 0;  // the query before the op's group
        for (size_t i = 0; i < ops_.size(); ++i) {
            if (stamps_[i] == 0) continue;
            const uint64_t delta = (ticks[stamps_[i]] - ticks[before]) & mask;
            if (ops_[i].kernel != kNoKernel) stats_.kernelSeconds[ops_[i].kernel] += double(delta) * seconds;
            before = stamps_[i];
        }
        // The device idle since the last submission's last command (its timestamp follows that
        // command only when the pool had a query left for it).
        if (lastTick_) stats_.deviceIdleSeconds += double((ticks[0] - *lastTick_) & mask) * seconds;
        lastTick_.reset();
        if (stamps_.back() != 0) lastTick_ = ticks[stamps_.back()];
    }

    struct Op {
        int kernel;
        std::function<void(VkCommandBuffer)> record;
        bool fill;        // recordFill: the barrier follows the last of adjacent fills
        bool besideNext;  // the next op does not touch what this one does: the barrier follows that op
        bool ownBarrier;  // record: it records its barrier itself
    };

    Wavefront& w_;
    const WavefrontBuffers& b_;
    const DeviceRenderJob& job_;
    const RenderOptions& options_;
    ChunkPager& pager_;
    RenderImage& image_;
    StreamingStats& stats_;
    double& deviceSeconds_;
    std::vector<Op> ops_;  // recorded, or submitted and not yet finished
    uint32_t submittedQueries_ = 0;
    std::vector<uint32_t> stamps_;      // the submitted ops' timestamps (beginSubmit)
    std::optional<uint64_t> lastTick_;  // the last submission's timestamp after its last command
    QueryPool queries_;
    const ComputePipeline* shade_ = nullptr;  // this render's specialization
    const ComputePipeline* walk_ = nullptr;   // this wave's (paging or not)
    uint32_t cutouts_ = 0;                    // the walk's kCutouts: some material is a cut-out or a blend
    uint32_t blends_ = 0;                     // the walk's kBlends: some material is a blend
    bool streamed_ = false;                   // renderStreamed runs: shading regenerates groups
    // Partial residency (uploadResidency): the device's table shows some resident chunks absent,
    // and the timeline value of the copies the next submission waits for (~0: all).
    bool residencyMasked_ = false;
    uint64_t copiesWaitUpTo_ = kAllCopies;
    // When the last paging step's wait returned (host_gap_seconds counts from it to the next submission).
    std::optional<std::chrono::steady_clock::time_point> stepEnded_;
};

Status Wavefront::render(const WavefrontBuffers& buffers, const DeviceRenderJob& job, ChunkPager& pager,
                         RenderImage& image, StreamingStats& stats, double& deviceSeconds) {
    if (!job.options || job.materials.empty()) return Status::error("device render: no options or no material");
    Run run(*this, buffers, job, pager, image, stats, deviceSeconds);
    return run.execute();
}

}  // namespace vastray::gpu
