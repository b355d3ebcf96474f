#pragma once
// The device wavefront: a whole render as compute kernels over path state in device memory
// (wf_generate, wf_walk, wf_shade, wf_accumulate, wf_aov). The host records one command buffer
// per tile when every chunk is resident; otherwise it submits paging steps (a few walk passes
// with shading between them), reads the per-chunk demand counters of the parked rays, and lets
// the pager page chunks in before the next step; paged volumes page their bricks at the same
// points (paths that read an absent brick wait and shade again). Only the counters and the
// finished tile's pixels come back.
#include <array>
#include <future>
#include <initializer_list>
#include <map>
#include <memory>
#include <span>

#include "DeviceTextures.h"
#include "DeviceVolumes.h"
#include "PoolLayout.h"
#include "vastray/gpu/ComputePipeline.h"
#include "vastray/gpu/VulkanDevice.h"
#include "vastray/streamer/StreamingRenderer.h"

namespace vastray::gpu {

class ChunkUploader;

// The backend's buffers the wavefront works in.
struct WavefrontBuffers {
    GpuBuffer* table = nullptr;  // TableLayout
    TableLayout tables;
    GpuBuffer* state = nullptr;  // StateLayout for pathCapacity paths
    GpuBuffer* output = nullptr; // OutputLayout for pathCapacity pixels
    // The paths' walk bits apart (walkBitsBytes): set exactly when the path state lies in host
    // memory (PoolPlan::stateInHostMemory, which also picks the shade variant: ShadeConstants); else
    // they lie in the path words.
    GpuBuffer* walkBits = nullptr;
    uint32_t pathCapacity = 0;
    uint64_t outputPixels = 0;  // the output buffer's pixels (PoolPlan::outputPixels, >= pathCapacity)
    bool outOfCore = false;  // fewer slots than chunks: waves are streamed (Wavefront.cpp, renderStreamed)
    Aabb bounds;  // the package's
    uint32_t topNodeCount = 0, chunkCount = 0;
    bool normals = false, colors = false;  // slots hold shading normals, colours (ChunkAttributes)
    bool uvs = false;  // slots hold texture coordinates and the state buffer the hits' (StateLayout::hitUv)
    bool frames = false;  // the state buffer holds the hits' UV derivatives (StateLayout::hitFrame)
    // Slots hold positions in 8 bytes a vertex (ChunkAttributes::packedPositions): the walk's
    // kPackedPositions, with the grid's origin and step (exact floats) in its push constants.
    bool packedPositions = false;
    std::array<float, 4> grid{};  // origin x, y, z, step
    ChunkUploader* uploader = nullptr;  // DMA uploads: every submission waits for the copies before it
    GpuBuffer* environment = nullptr;   // EnvironmentLayout of the render's environment map; none without
    DeviceVolumes* volumes = nullptr;   // the render's volumes (RenderOptions::volumes), in core or paged; none without
    DeviceTextures* textures = nullptr; // the package's textures (DeviceRenderJob::textures), in core or paged; none without
};

// wf_shade.comp's specialization constants (constant_id 0-16, in that order): what a render's
// shading needs; kVolumes says the render has volumes (`volumeCodecs`, a bit per VolumeCodec its
// volumes use: 0 none), kClearcoat that some material has a clear coat, kTextures that some
// material has maps and the render has textures and the hits' UVs (`textures`), kNormalMaps that
// some material has a normal map and the hits keep their UV derivatives (`frames`), kEmitters
// that next-event estimation samples emissive triangles (`emitters`), the next three
// (common/Volume.glsl) which of the float, Fp16 and Fp8 leaf reads the volumes need; constant
// 16 (kStateInHostMemory) that the path state lies in host memory (`hostState`,
// PoolPlan::stateInHostMemory: the shading then takes a workgroup's ended paths off each group's
// count with one atomic).
using ShadeConstants = std::array<uint32_t, 17>;
// wf_walk.comp's specialization: the cost AOV, paging, cut-outs (or blends), blends, packed positions.
using WalkConstants = std::array<uint32_t, 5>;
ShadeConstants shadeConstants(std::span<const Material> materials, bool ambientOcclusion, bool sun, bool normals,
                              bool colors, bool environmentMap, uint32_t volumeCodecs, bool lights, bool textures = false,
                              bool frames = false, bool emitters = false, bool hostState = false);

// The bits of volumeCodecs for shadeConstants: a bit per VolumeCodec the volumes use.
uint32_t volumeCodecs(std::span<const Volume> volumes);

class Wavefront {
public:
    // Starts creating its kernels on threads of their own (a driver compiles each, 0.1-0.4 s on
    // the H200 with an empty cache): the three every render uses, the walk variants a render
    // without the cost AOV asks for (the paging one; with inCore, every chunk having a slot, the
    // resident one too; packedPositions: ChunkAttributes::packedPositions) and the shade variant `likelyShade` (the scene's with the default
    // options), so that they compile while the backend allocates its pools. ready() waits for
    // the three; a render waits for the variants it uses (a render that needs another shade
    // variant creates its own).
    static std::unique_ptr<Wavefront> start(VulkanDevice& device, bool inCore, bool packedPositions,
                                            const ShadeConstants& likelyShade);
    Status ready();

    // deviceSeconds: time spent waiting for submissions.
    Status render(const WavefrontBuffers& buffers, const DeviceRenderJob& job, ChunkPager& pager, RenderImage& image,
                  StreamingStats& stats, double& deviceSeconds);

private:
    explicit Wavefront(VulkanDevice& device) : device_(device) {}
    struct Pipelines {
        std::unique_ptr<ComputePipeline> generate, accumulate, aov;
        // Specialized on what a render needs (wf_walk.comp, wf_shade.comp: constant_id 0, 1, ...),
        // built when first asked for; key: the constants as bits.
        std::map<uint32_t, std::unique_ptr<ComputePipeline>> walk, shade;
    };
    class Run;
    // The walk or shade kernel with these specialization constants (each 0 or 1): made before,
    // or the one started for them (waited for), or created now. The time waiting for or creating
    // one (a driver compilation on its first use in a process) is added to stats.pipelineSeconds.
    Result<const ComputePipeline*> variant(bool walk, std::span<const uint32_t> constants, StreamingStats& stats);
    // Starts creating these walk variants (kCountCost, kPaging) on threads of their own, while
    // the render thread goes on; variant() takes them when a render first asks for them.
    void startWalkVariants(std::initializer_list<WalkConstants> variants);

    VulkanDevice& device_;
    Pipelines pipelines_;
    std::map<uint32_t, std::future<Result<std::unique_ptr<ComputePipeline>>>> pendingWalks_;
    std::map<uint32_t, std::future<Result<std::unique_ptr<ComputePipeline>>>> pendingShades_;
    std::future<Result<std::unique_ptr<ComputePipeline>>> pendingFixed_[3];  // generate, accumulate, aov
    // The emitter table last uploaded, and where: a render of the same table (a kept-open scene's,
    // RenderOptions::emitters shared between its renders) into the same buffer uploads none.
    struct UploadedEmitters {
        std::shared_ptr<const EmitterTable> table;
        const GpuBuffer* buffer = nullptr;
        uint64_t offset = 0;
    } uploadedEmitters_;
};

}  // namespace vastray::gpu
