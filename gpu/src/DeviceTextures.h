#pragma once
// A scene's textures on the device (core/Texture.h's paged layout; the kernels read them through
// common/Texture.glsl and common/MaterialMaps.glsl): one buffer holding the GpuTexture records,
// the page table (a pool slot, or kTexturePageAbsent, per page of every texture), the demand
// counters (paged) and the pool of page slots. In core the pool holds every page. When the bytes
// the budget kept for textures cannot, the pool holds as many pages as fit and page() turns the
// kernels' per-page demand (the pages waiting paths read) into loads between paging steps, as
// DeviceVolumes does for bricks. docs/RENDERING.md, "Textures out of core".
#include <cstdint>
#include <functional>
#include <set>
#include <span>
#include <utility>
#include <vector>

#include "shared/TextureTypes.h"
#include "vastray/core/Result.h"
#include "vastray/gpu/VulkanChunkBackend.h"
#include "vastray/gpu/VulkanDevice.h"
#include "vastray/streamer/ScenePackage.h"
#include "vastray/streamer/StreamingRenderer.h"

namespace vastray::gpu {

// The device bytes of `textures` (PackageInfo::textures): in core (every page), and paged through
// `slots` page slots (with the demand counters and their readback). 0 without textures.
uint64_t inCoreTextureBytes(std::span<const PackageTexture> textures);
uint64_t pagedTextureBytes(std::span<const PackageTexture> textures, uint64_t slots);

// Cut-outs (docs/RENDERING.md, "Cut-outs"): the walk tests a cut-out's base colour map at level 0
// and cannot wait for a page, so those pages stay resident (pinned) while the others are paged.
// The textures that are some cut-out or blended material's base colour map (ascending), and their
// level-0 pages.
std::vector<uint32_t> cutoutTextures(std::span<const Material> materials, uint64_t textureCount);
uint64_t pinnedPages(std::span<const PackageTexture> textures, std::span<const uint32_t> pinned);

// Reads page `page` of texture `texture` (kTexturePageBytes bytes, checked and inflated: the
// package reader's readTexturePage). Called from worker threads.
using TexturePageReader = std::function<Status(uint32_t texture, uint32_t page, uint8_t* out)>;

// Paged textures keep the pages they read, inflated, in a host cache of at most this many bytes,
// so that a page paged in again is copied, not read and inflated again; least recently used out.
constexpr uint64_t kTextureHostCacheBytes = 1ull << 30;

class DeviceTextures {
public:
    explicit DeviceTextures(VulkanDevice& device, uint64_t hostCacheBytes = kTextureHostCacheBytes)
        : device_(device), hostCacheBytes_(hostCacheBytes) {}

    // Puts `textures` on the device in at most `bytes`: every page when they fit, else a pool of
    // as many page slots as fit, the level-0 pages of the `pinned` textures (cutoutTextures)
    // resident in the first of them for good (an error below those and kMinTexturePageSlots more,
    // naming both sizes). Kept while the next render asks for the same textures.
    Status prepare(std::span<const PackageTexture> textures, const TexturePageReader& read, uint64_t bytes,
                   StreamingStats& stats, std::span<const uint32_t> pinned = {});

    bool present() const { return !records_.empty(); }
    bool paged() const { return present() && slots_ < pageCount_; }
    uint64_t allocatedBytes() const { return buffer_.allocatedBytes() + readback_.allocatedBytes(); }
    uint64_t recordsAddress() const { return buffer_.address(); }
    uint64_t pageTableAddress() const { return buffer_.address() + pageTableOffset_; }
    uint64_t poolAddress() const { return buffer_.address() + poolOffset_; }
    // Paged: the demand counters (uint per page) in buffer(), and host-cached memory they are
    // copied into after each paging step.
    uint64_t demandAddress() const { return paged() ? buffer_.address() + demandOffset_ : 0; }
    const GpuBuffer& buffer() const { return buffer_; }
    const GpuBuffer& readback() const { return readback_; }
    uint64_t demandOffset() const { return demandOffset_; }
    uint64_t pageCount() const { return pageCount_; }
    uint32_t slotCount() const { return slots_; }

    // Paged, between steps while the device is idle: loads the absent pages waiting paths asked
    // for (`demand`: a counter per page). The pages read most stay or come in (as many as there
    // are slots); slots of pages nobody read are taken first, the least recently used first.
    // Returns the pages loaded (at least one when an absent page is asked for).
    Result<uint64_t> page(std::span<const uint32_t> demand, StreamingStats& stats);

private:
    Status build(std::span<const PackageTexture> textures, uint32_t slots, StreamingStats& stats);
    // The page-table entries of the pinned textures' level-0 pages.
    std::vector<uint32_t> pinnedEntries(std::span<const PackageTexture> textures) const;
    // Copies `pages` (page-table entries) into `slots`: from the host cache, or read and inflated
    // on worker threads (then kept in the cache when paged).
    Status load(std::span<const uint32_t> pages, std::span<const uint32_t> slots, StreamingStats& stats);
    // Keeps page `entry`'s bytes in the host cache, dropping the least recently used beyond its
    // bound (never a page used this step: then this one is not kept).
    void keepInHost(uint32_t entry, const uint8_t* bytes);

    VulkanDevice& device_;
    TexturePageReader read_;
    std::span<const PackageTexture> textures_;  // the textures in buffer_ (the package's)
    std::vector<GpuTexture> records_;
    GpuBuffer buffer_, readback_;
    uint64_t pageCount_ = 0, pageTableOffset_ = 0, demandOffset_ = 0, poolOffset_ = 0;
    uint32_t slots_ = 0;
    // Per page-table entry its texture and page, its slot (kTexturePageAbsent: none); per slot its
    // entry and the last step that loaded it or found it read.
    std::vector<uint32_t> entryTexture_, entryPage_, table_, slotEntry_;
    std::vector<uint64_t> slotUsed_;
    uint64_t step_ = 0;
    std::vector<uint32_t> pinned_;  // textures whose level-0 pages stay resident (slots [0, pinnedSlots_))
    uint32_t pinnedSlots_ = 0;
    // The host cache (paged): per entry its inflated bytes (empty: not kept) and last use; by use.
    uint64_t hostCacheBytes_, cachedBytes_ = 0;
    std::vector<std::vector<uint8_t>> cached_;
    std::vector<uint64_t> cachedUse_;
    std::set<std::pair<uint64_t, uint32_t>> cacheOrder_;
};

}  // namespace vastray::gpu
