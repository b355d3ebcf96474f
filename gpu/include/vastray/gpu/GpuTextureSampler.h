#pragma once
// Textures' pages in a device pool, sampled in batches by texture_probe.comp through
// common/Texture.glsl: the GPU twin of core/Texture.h's sampleTexture, before the renderer's
// texture pool uses it, held by tests against the CPU sampling (same footprint, same page, same
// texels; results within float rounding), and against its page table (a sample whose page the
// pool lacks names that page and returns zero, never another level's texels).
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "shared/TextureTypes.h"
#include "vastray/core/Result.h"
#include "vastray/core/Texture.h"
#include "vastray/gpu/ComputePipeline.h"
#include "vastray/gpu/VulkanDevice.h"

namespace vastray::gpu {

// One texture's pages as the package stores them decoded (layout.pageCount * kTexturePageBytes
// bytes of RGBA8 rows, core/Texture.h).
struct TextureUpload {
    TextureLayout layout;
    TextureWrap wrapS = TextureWrap::Repeat, wrapT = TextureWrap::Repeat;
    TextureEncoding encoding = TextureEncoding::Srgb;
    const uint8_t* pages = nullptr;
};

struct TextureSampleResult {
    float r = 0, g = 0, b = 0, a = 0;
    uint32_t missingEntry = kTexturePageAbsent;  // the page-table entry of an absent page
};

class GpuTextureSampler {
public:
    static Result<std::unique_ptr<GpuTextureSampler>> create(VulkanDevice& device);

    // Replaces the textures: the pages `resident(texture, page)` accepts get a pool slot each,
    // the others are absent in the page table. An upload larger than the device allows fails.
    Status upload(std::span<const TextureUpload> textures,
                  const std::function<bool(uint32_t texture, uint32_t page)>& resident);
    // The page-table entry of a texture's page (what TextureSampleResult::missingEntry names).
    uint32_t pageTableEntry(uint32_t texture, uint32_t page) const { return firstEntry_[texture] + page; }
    uint32_t residentPages() const { return residentPages_; }

    Result<std::vector<TextureSampleResult>> sample(std::span<const TextureQuery> queries);

private:
    explicit GpuTextureSampler(VulkanDevice& device) : device_(device) {}

    VulkanDevice& device_;
    std::unique_ptr<ComputePipeline> pipeline_;
    GpuBuffer textures_, pageTable_, pool_;
    std::vector<uint32_t> firstEntry_;
    uint32_t residentPages_ = 0;
};

}  // namespace vastray::gpu
