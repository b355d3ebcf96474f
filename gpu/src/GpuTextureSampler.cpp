#include "vastray/gpu/GpuTextureSampler.h"

#include <cstring>

namespace vastray::gpu {
namespace {

const uint32_t kTextureProbeSpirv[] =
#include "texture_probe.spv.inc"
    ;

static_assert(kGpuTexturePageSide == kTexturePageSide && kGpuTexturePageTexels == kTexturePageTexels &&
                  kGpuTexturePageWords * 4 == kTexturePageBytes,
              "common/Texture.glsl reads pages as core/Texture.h lays them out");
static_assert(kMaxGpuTextureLevels >= kMaxTextureLevels);
static_assert(uint32_t(TextureWrap::Repeat) == 0 && uint32_t(TextureWrap::Clamp) == 1 &&
              uint32_t(TextureWrap::Mirror) == 2, "common/Texture.glsl's wrap numbers");

constexpr uint64_t kMaxQueriesPerDispatch = 65535ull * 64;

Result<GpuBuffer> uploaded(VulkanDevice& device, const void* data, uint64_t bytes) {
    auto buffer = device.createBuffer(std::max<uint64_t>(bytes, 16));
    if (!buffer) return buffer.status();
    if (bytes) VASTRAY_TRY(buffer->upload(data, bytes));
    return std::move(buffer).value();
}

}  // namespace

Result<std::unique_ptr<GpuTextureSampler>> GpuTextureSampler::create(VulkanDevice& device) {
    std::unique_ptr<GpuTextureSampler> sampler(new GpuTextureSampler(device));
    auto pipeline = ComputePipeline::create(device, kTextureProbeSpirv, sizeof(TextureProbePushConstants));
    if (!pipeline) return pipeline.status();
    sampler->pipeline_ = std::move(pipeline).value();
    return sampler;
}

Status GpuTextureSampler::upload(std::span<const TextureUpload> textures,
                                 const std::function<bool(uint32_t, uint32_t)>& resident) {
    textures_ = GpuBuffer(), pageTable_ = GpuBuffer(), pool_ = GpuBuffer();
    firstEntry_.clear();
    residentPages_ = 0;
    std::vector<GpuTexture> records;
    std::vector<uint32_t> table;
    std::vector<uint8_t> pool;
    for (uint32_t t = 0; t < textures.size(); ++t) {
        const TextureUpload& u = textures[t];
        GpuTexture g{};
        g.width = u.layout.width;
        g.height = u.layout.height;
        g.levelCount = u.layout.levelCount;
        g.flags = uint32_t(u.wrapS) | (uint32_t(u.wrapT) << 2) |
                  (u.encoding == TextureEncoding::Linear ? kTextureFlagLinear : 0u);
        g.pageTable = uint32_t(table.size());
        for (uint32_t l = 0; l < u.layout.levelCount; ++l) g.levelFirstPage[l] = u.layout.levels[l].firstPage;
        firstEntry_.push_back(g.pageTable);
        for (uint32_t p = 0; p < u.layout.pageCount; ++p) {
            if (!resident(t, p)) {
                table.push_back(kTexturePageAbsent);
                continue;
            }
            table.push_back(residentPages_++);
            pool.insert(pool.end(), u.pages + size_t(p) * kTexturePageBytes, u.pages + size_t(p + 1) * kTexturePageBytes);
        }
        records.push_back(g);
    }
    auto r = uploaded(device_, records.data(), records.size() * sizeof(GpuTexture));
    if (!r) return r.status();
    auto pt = uploaded(device_, table.data(), table.size() * sizeof(uint32_t));
    if (!pt) return pt.status();
    auto pl = uploaded(device_, pool.data(), pool.size());
    if (!pl) return pl.status();
    textures_ = std::move(r).value(), pageTable_ = std::move(pt).value(), pool_ = std::move(pl).value();
    return Status::ok();
}

Result<std::vector<TextureSampleResult>> GpuTextureSampler::sample(std::span<const TextureQuery> queries) {
    if (!textures_.isValid()) return Status::error("texture sampling: no textures uploaded");
    for (const TextureQuery& q : queries)
        if (q.texture >= firstEntry_.size())
            return Status::error("texture sampling: texture " + std::to_string(q.texture) + " of " +
                                 std::to_string(firstEntry_.size()));
    std::vector<TextureSampleResult> out(queries.size());
    if (queries.empty()) return out;
    auto in = uploaded(device_, queries.data(), queries.size_bytes());
    if (!in) return in.status();
    auto results = device_.createBuffer(queries.size() * 16, VulkanDevice::MemoryUse::Readback);
    if (!results) return results.status();
    auto missing = device_.createBuffer(queries.size() * 4, VulkanDevice::MemoryUse::Readback);
    if (!missing) return missing.status();
    VASTRAY_TRY(device_.submit([&](VkCommandBuffer cmd) {
        for (uint64_t first = 0; first < queries.size(); first += kMaxQueriesPerDispatch) {
            const uint64_t count = std::min<uint64_t>(kMaxQueriesPerDispatch, queries.size() - first);
            TextureProbePushConstants pc{};
            pc.textures = textures_.address(), pc.pageTable = pageTable_.address(), pc.pool = pool_.address();
            pc.queries = in->address() + first * sizeof(TextureQuery);
            pc.results = results->address() + first * 16;
            pc.missing = missing->address() + first * 4;
            pc.queryCount = uint32_t(count);
            pipeline_->record(cmd, &pc, uint32_t((count + 63) / 64));
        }
    }));
    std::vector<float> values(queries.size() * 4);
    std::vector<uint32_t> absent(queries.size());
    VASTRAY_TRY(results->download(values.data(), values.size() * 4));
    VASTRAY_TRY(missing->download(absent.data(), absent.size() * 4));
    for (size_t i = 0; i < out.size(); ++i)
        out[i] = {values[4 * i], values[4 * i + 1], values[4 * i + 2], values[4 * i + 3], absent[i]};
    return out;
}

}  // namespace vastray::gpu
