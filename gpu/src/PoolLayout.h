#pragma once
// Where the Vulkan backend's small tables lie in its one table buffer: the slot table, the
// package's top-level tree, per chunk its slot, touched flag, demand and look-ahead counters, the
// wavefront's parameters, the material table, the metallic-roughness BSDF's albedo tables, the
// streamed waves' window, the punctual lights and the sampled emissive triangles (byte offsets,
// 16-byte aligned).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "shared/StreamTypes.h"
#include "shared/WavefrontTypes.h"
#include "vastray/core/KdTree.h"
#include "vastray/core/Microfacet.h"
#include "vastray/core/RenderOptions.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray::gpu {

static_assert(kMicrofacetSide == kMicrofacetTableSide);

// Devices round allocations up (to 64 KiB at most on the devices we know); planning with that
// granularity keeps the allocated total under the budget.
constexpr uint64_t kAllocationGranule = 64 * 1024;
inline uint64_t granules(uint64_t bytes) {
    return (std::max<uint64_t>(bytes, 1) + kAllocationGranule - 1) / kAllocationGranule * kAllocationGranule;
}

struct TableLayout {
    uint64_t topNodes = 0, chunkSlots = 0, touched = 0, demand = 0, ahead = 0, queueCounts = 0, queueArgs = 0, params = 0,
             materials = 0, microfacet = 0, stream = 0, lights = 0, emitters = 0;
    uint64_t lightCapacity = 0;  // WavefrontLight records the light section holds (the package's lights)
    uint64_t emitterCapacity = 0;  // WavefrontEmitter records the emitter section holds (the package's)
    uint64_t totalBytes = 0;
};

inline TableLayout tableLayout(uint64_t slots, const PackageInfo& package) {
    auto align = [](uint64_t bytes) { return (bytes + 15) / 16 * 16; };
    const uint64_t chunks = package.chunks.size();
    TableLayout t;
    t.topNodes = align(slots * sizeof(ChunkSlot));
    t.chunkSlots = t.topNodes + align(package.topTree.size() * sizeof(KdNode));
    t.touched = t.chunkSlots + align(chunks * 4);
    t.demand = t.touched + align(chunks * 4);
    t.ahead = t.demand + align((chunks + 2) * 4);
    t.queueCounts = t.ahead + align(chunks * 4);
    t.queueArgs = t.queueCounts + align(kQueueCount * 4);
    t.params = t.queueArgs + align(kQueueCount * 12);
    t.materials = t.params + align(sizeof(WavefrontParams));
    t.microfacet = t.materials + align(std::max<uint64_t>(package.materials.size(), 1) * sizeof(WavefrontMaterial));
    t.stream = t.microfacet + align(kMicrofacetTableFloats * sizeof(float));
    t.lights = t.stream + align(sizeof(StreamWindow));
    t.lightCapacity = package.lights.size();
    t.emitters = t.lights + align(t.lightCapacity * sizeof(WavefrontLight));
    t.emitterCapacity = package.emitters.size();
    t.totalBytes = t.emitters + align(t.emitterCapacity * sizeof(WavefrontEmitter));
    return t;
}

// The wavefront's state buffer (device-local) and output buffer (host-readable), per path and
// per tile pixel: sections in the order of WavefrontParams' addresses.
// Streamed waves' groups (two paths or more each) of a wave of `paths` paths, at most.
inline uint64_t groupCapacity(uint64_t paths) { return (paths + 1) / 2; }
// Queue q's byte offset from StateLayout::queues (common/WavefrontState.glsl's queueOf): the
// three ray queues hold 2 * paths entries, the shade and volume wait queues paths entries, the
// two group queues groupCapacity entries.
inline uint64_t queueOffset(uint32_t q, uint64_t paths) {
    if (q <= kGroupQueue)
        return q < kShadeQueue ? uint64_t(q) * 8 * paths : (8 * kShadeQueue + uint64_t(q - kShadeQueue) * 4) * paths;
    return queueOffset(kGroupQueue, paths) + uint64_t(q - kGroupQueue) * 4 * groupCapacity(paths);
}
// The 16-byte vectors first (per path, rays' directions per ray), then the 8-byte ones, then
// the queues, so that every array is aligned for any count of paths; with `uvs` (the render reads
// the scene's texture coordinates, ChunkAttributes::uvs) the hits' UVs and footprints last (else
// hitUv is 0 and costs nothing), and after them with `frames` (ChunkAttributes::tangents) the
// hits' UV derivatives (kBytesPerPathFrame a path).
struct StateLayout {
    uint64_t rayOrigin, rayDirection, hitPosition, hitNormal, hitIds, throughput, radiance, pendingSun, accum, rayState,
        pathInfo, groupState, queues, hitUv, hitFrame, totalBytes;
};
// With the path state in host memory the paths' walk bits lie apart, a byte a path in whole words
// in device memory (WavefrontParams::walkBits, walkBitsApart: the walk's atomics on them would
// cross the bus); in device memory they lie in the paths' words.
inline uint64_t walkBitsBytes(uint64_t paths) { return (paths + 3) / 4 * 4; }
inline StateLayout stateLayout(uint64_t paths, bool uvs = false, bool frames = false) {
    StateLayout s{};
    const uint64_t perPath = paths * 16;
    s.rayOrigin = 0, s.rayDirection = perPath, s.hitPosition = s.rayDirection + 2 * perPath;
    s.hitNormal = s.hitPosition + perPath, s.hitIds = s.hitNormal + perPath;
    s.throughput = s.hitIds + perPath, s.radiance = s.throughput + perPath, s.pendingSun = s.radiance + perPath;
    s.accum = s.pendingSun + perPath, s.rayState = s.accum + perPath, s.pathInfo = s.rayState + 2 * paths * 8;
    s.groupState = s.pathInfo + paths * 8;
    s.queues = s.groupState + groupCapacity(paths) * 8;
    s.totalBytes = s.queues + queueOffset(kQueueCount, paths);
    if (uvs) s.hitUv = (s.totalBytes + 15) / 16 * 16, s.totalBytes = s.hitUv + kBytesPerPathUv * paths;
    if (uvs && frames)
        s.hitFrame = (s.totalBytes + 15) / 16 * 16, s.totalBytes = s.hitFrame + kBytesPerPathFrame * paths;
    return s;
}
// What a paging step ends with and the host reads: the table's touched flags, demand and
// look-ahead counters and queue counts (they follow one another there, from TableLayout::touched
// to ::queueArgs), then the streamed waves' window head (StreamWindow up to its tiles). The
// device copies them into the output buffer (host-cached memory) at the step's end: read across
// the bus from the table, which is device memory the host maps uncached on a discrete GPU, they
// cost the host a round trip per few bytes.
constexpr uint64_t kWindowHeadBytes = offsetof(StreamWindow, tiles);
inline uint64_t stepCounterBytes(const TableLayout& t) { return t.queueArgs - t.touched + kWindowHeadBytes; }
// The output buffer (host-cached): per tile pixel the colour and the AOVs, then the step's
// counters (stepCounterBytes).
struct OutputLayout {
    uint64_t color, depth, normal, albedo, primId, chunkId, cost, uv, counters, totalBytes;
};
inline OutputLayout outputLayout(uint64_t pixels, uint64_t counterBytes) {
    OutputLayout o{};
    o.color = 0, o.depth = 16 * pixels, o.normal = o.depth + 4 * pixels, o.albedo = o.normal + 12 * pixels;
    o.primId = o.albedo + 12 * pixels, o.chunkId = o.primId + 4 * pixels, o.cost = o.chunkId + 4 * pixels;
    o.uv = o.cost + 8 * pixels;
    o.counters = (o.uv + 8 * pixels + 15) / 16 * 16;
    o.totalBytes = o.counters + counterBytes;
    return o;
}
// The environment map's buffer (core/EnvironmentMap.h's arrays, in this order).
struct EnvironmentLayout {
    uint64_t rgb, density, marginal, conditional, totalBytes;
};
inline EnvironmentLayout environmentLayout(uint64_t width, uint64_t height) {
    EnvironmentLayout e{};
    e.rgb = 0, e.density = 12 * width * height, e.marginal = e.density + 4 * width * height;
    e.conditional = e.marginal + 4 * (height + 1);
    e.totalBytes = e.conditional + 4 * height * (width + 1);
    return e;
}
// The volumes' buffer: WavefrontVolume per volume, then per volume its brick table, majorants,
// density leaves and emission leaves (16-byte aligned; emission 0 when it has no emission grid).
struct VolumeShape {
    uint64_t cells = 0, bricks = 0;
    bool emission = false;
    uint64_t leafBytes = 2064;  // what the device keeps of a brick's leaf in its codec (volumeDeviceLeafBytes)
};
// A paged pool's slot: the largest leaf of the volumes'.
inline uint64_t volumeSlotBytes(std::span<const VolumeShape> volumes) {
    uint64_t bytes = 0;
    for (const VolumeShape& v : volumes) bytes = std::max(bytes, v.leafBytes);
    return bytes;
}
struct VolumeLayout {
    std::vector<uint64_t> brickOf, majorant, voxels, emission;
    uint64_t totalBytes = 0;
};
inline VolumeLayout volumeLayout(std::span<const VolumeShape> volumes) {
    auto align = [](uint64_t x) { return (x + 15) / 16 * 16; };
    VolumeLayout l;
    uint64_t at = align(volumes.size() * sizeof(WavefrontVolume));
    for (const VolumeShape& v : volumes) {
        const uint64_t voxelBytes = v.leafBytes * v.bricks;
        l.brickOf.push_back(at), at = align(at + 4 * v.cells);
        l.majorant.push_back(at), at = align(at + 4 * v.cells);
        l.voxels.push_back(at), at = align(at + voxelBytes);
        l.emission.push_back(v.emission ? at : 0), at = v.emission ? align(at + voxelBytes) : at;
    }
    l.totalBytes = at;
    return l;
}
// Paged volumes (gpu/src/DeviceVolumes.h): WavefrontVolume per volume, per volume its cell table
// (a slot or kBrickAbsent | brick per cell) and majorants, then the pools of `slots` bricks
// (density leaves, and emission leaves when a volume has an emission grid, volumeSlotBytes each; a
// slot holds the same brick in both), the demand counters (per brick of all volumes the parked walks waiting for it, then per
// brick those asking for it ahead, then per slot whether a parked walk keeps it: common/Volume.glsl's
// requestBrick and keepCell), and per path of a wave where its tracking parked (four uvec4,
// VolumePark).
struct PagedVolumeLayout {
    std::vector<uint64_t> brickOf, majorant;
    uint64_t density = 0, emission = 0, demand = 0, park = 0, totalBytes = 0;
};
constexpr uint64_t kVolumeParkBytes = 64;
inline PagedVolumeLayout pagedVolumeLayout(std::span<const VolumeShape> volumes, uint64_t slots, uint64_t paths) {
    auto align = [](uint64_t x) { return (x + 15) / 16 * 16; };
    PagedVolumeLayout l;
    uint64_t at = align(volumes.size() * sizeof(WavefrontVolume)), bricks = 0;
    bool emission = false;
    for (const VolumeShape& v : volumes) {
        l.brickOf.push_back(at), at = align(at + 4 * v.cells);
        l.majorant.push_back(at), at = align(at + 4 * v.cells);
        bricks += v.bricks, emission = emission || v.emission;
    }
    const uint64_t poolBytes = volumeSlotBytes(volumes) * slots;
    l.density = at, at = align(at + poolBytes);
    l.emission = emission ? at : 0, at = emission ? align(at + poolBytes) : at;
    l.demand = at, at = align(at + 8 * bricks + 4 * slots);
    l.park = at, at = align(at + kVolumeParkBytes * paths);
    l.totalBytes = at;
    return l;
}

static_assert(kBytesPerPath == 16 + 2 * (16 + 8) + 3 * 16 + 3 * 16 + 8 + 24 + 8 + 8 && kBytesPerTilePixel == 84);
// A path's word (shared/WavefrontTypes.h): flags, bounce and sample index fit their fields.
static_assert(kPathFlagBits == kPathBounceShift && kPathBounceShift + kPathBounceBits == kPathSampleShift);
// The walk bits lie above the other flags in the word, and fit a byte apart.
static_assert((kPathAlive | kPathShadowPending | kPathCameraHit) < (1u << kPathWalkShift) &&
              ((kWalkClosest | kWalkShadow) << kPathWalkShift) < (1u << kPathFlagBits) && (kWalkClosest | kWalkShadow) < 256u);
static_assert(kMaxDepthLimit + 1 < (1u << kPathBounceBits) && kMaxSamplesPerPixel <= (1u << (32 - kPathSampleShift)));

}  // namespace vastray::gpu
