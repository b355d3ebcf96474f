#include "DeviceTextures.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <numeric>
#include <string>

#include "PoolLayout.h"
#include "vastray/core/ByteSize.h"
#include "vastray/core/PathShading.h"

namespace vastray::gpu {
namespace {

static_assert(kGpuTexturePageWords * 4 == kTexturePageBytes, "a pool slot holds one page as core/Texture.h lays it out");
static_assert(kNoGpuTexture == kNoTexture);

uint64_t align256(uint64_t bytes) { return (bytes + 255) / 256 * 256; }

uint64_t pagesOf(std::span<const PackageTexture> textures) {
    uint64_t pages = 0;
    for (const PackageTexture& t : textures) pages += t.layout.pageCount;
    return pages;
}

// Where the arrays lie in the buffer: the records, the page table, the demand counters (paged
// only), the pool.
struct TextureBufferLayout {
    uint64_t pageTable = 0, demand = 0, pool = 0, totalBytes = 0;
};
TextureBufferLayout textureBufferLayout(uint64_t textures, uint64_t pages, uint64_t slots, bool paged) {
    TextureBufferLayout l;
    l.pageTable = align256(textures * sizeof(GpuTexture));
    l.demand = l.pageTable + align256(pages * 4);
    l.pool = l.demand + (paged ? align256(pages * 4) : 0);
    l.totalBytes = l.pool + slots * kTexturePageBytes;
    return l;
}

GpuTexture gpuTexture(const PackageTexture& t, uint32_t firstEntry) {
    GpuTexture g{};
    g.width = t.layout.width, g.height = t.layout.height, g.levelCount = t.layout.levelCount;
    g.flags = uint32_t(t.wrapS) | (uint32_t(t.wrapT) << 2) |
              (t.encoding == TextureEncoding::Linear ? kTextureFlagLinear : 0u);
    g.pageTable = firstEntry;
    for (uint32_t l = 0; l < t.layout.levelCount && l < kMaxGpuTextureLevels; ++l)
        g.levelFirstPage[l] = t.layout.levels[l].firstPage;
    return g;
}

}  // namespace

std::vector<uint32_t> cutoutTextures(std::span<const Material> materials, uint64_t textureCount) {
    std::vector<uint32_t> pinned;
    for (const Material& m : materials)
        if (isAlphaTested(m, textureCount) && m.textures.slots[uint32_t(TextureSlot::BaseColor)].texture < textureCount)
            pinned.push_back(m.textures.slots[uint32_t(TextureSlot::BaseColor)].texture);
    std::sort(pinned.begin(), pinned.end());
    pinned.erase(std::unique(pinned.begin(), pinned.end()), pinned.end());
    return pinned;
}

uint64_t pinnedPages(std::span<const PackageTexture> textures, std::span<const uint32_t> pinned) {
    uint64_t pages = 0;
    for (uint32_t t : pinned)
        if (t < textures.size()) pages += textures[t].layout.levels[0].pagesX * textures[t].layout.levels[0].pagesY;
    return pages;
}

uint64_t inCoreTextureBytes(std::span<const PackageTexture> textures) {
    if (textures.empty()) return 0;
    const uint64_t pages = pagesOf(textures);
    return granules(textureBufferLayout(textures.size(), pages, pages, false).totalBytes);
}

uint64_t pagedTextureBytes(std::span<const PackageTexture> textures, uint64_t slots) {
    if (textures.empty()) return 0;
    const uint64_t pages = pagesOf(textures);
    return granules(textureBufferLayout(textures.size(), pages, slots, true).totalBytes) + granules(pages * 4);
}

Status DeviceTextures::prepare(std::span<const PackageTexture> textures, const TexturePageReader& read,
                               uint64_t bytes, StreamingStats& stats, std::span<const uint32_t> pinned) {
    const bool same = textures.data() == textures_.data() && textures.size() == textures_.size() && present() &&
                      std::equal(pinned.begin(), pinned.end(), pinned_.begin(), pinned_.end());
    if (same && allocatedBytes() <= bytes) {
        stats.texturePageSlots = paged() ? slots_ : 0;
        return Status::ok();
    }
    buffer_ = GpuBuffer(), readback_ = GpuBuffer();
    records_.clear(), textures_ = {};
    if (textures.empty()) return Status::ok();
    read_ = read;
    pinned_.assign(pinned.begin(), pinned.end());
    const uint64_t pages = pagesOf(textures), fewest = kMinTexturePageSlots + pinnedPages(textures, pinned);
    if (pages >= kTexturePageAbsent) return Status::error("textures: " + std::to_string(pages) + " pages, too many to page");
    uint64_t slots = pages;
    if (inCoreTextureBytes(textures) > bytes) {
        // From above: the tables' allocation granules overlap the pool's, so bytes less the
        // tables' own allocation would undercount.
        slots = std::min<uint64_t>(bytes / kTexturePageBytes, pages - 1);
        while (slots > 0 && pagedTextureBytes(textures, slots) > bytes) --slots;
        if (slots < fewest)
            return Status::error("the textures need " + formatBytes(inCoreTextureBytes(textures)) +
                                 " of device memory in core, or " + formatBytes(pagedTextureBytes(textures, fewest)) +
                                 " paged through the fewest page slots (" + std::to_string(kMinTexturePageSlots) +
                                 (fewest > kMinTexturePageSlots
                                      ? " and " + std::to_string(fewest - kMinTexturePageSlots) + " cut-out pages kept"
                                      : std::string()) +
                                 "); the pool kept " + formatBytes(bytes) + " for them");
    }
    Status built = build(textures, uint32_t(slots), stats);
    if (!built) {
        buffer_ = GpuBuffer(), readback_ = GpuBuffer();
        records_.clear();
        return built;
    }
    textures_ = textures;
    stats.texturePageSlots = paged() ? slots_ : 0;
    return Status::ok();
}

Status DeviceTextures::build(std::span<const PackageTexture> textures, uint32_t slots, StreamingStats& stats) {
    pageCount_ = pagesOf(textures);
    slots_ = slots;
    const bool isPaged = slots < pageCount_;
    const TextureBufferLayout layout = textureBufferLayout(textures.size(), pageCount_, slots, isPaged);
    pageTableOffset_ = layout.pageTable, demandOffset_ = layout.demand, poolOffset_ = layout.pool;
    auto buffer = device_.createBuffer(layout.totalBytes);
    if (!buffer) return buffer.status().withContext("textures: ");
    buffer_ = std::move(buffer).value();
    if (isPaged) {
        auto readback = device_.createBuffer(pageCount_ * 4, VulkanDevice::MemoryUse::Readback);
        if (!readback) return readback.status().withContext("textures' demand readback: ");
        readback_ = std::move(readback).value();
    }
    entryTexture_.clear(), entryPage_.clear();
    for (uint32_t t = 0; t < textures.size(); ++t) {
        records_.push_back(gpuTexture(textures[t], uint32_t(entryTexture_.size())));
        for (uint32_t p = 0; p < textures[t].layout.pageCount; ++p) entryTexture_.push_back(t), entryPage_.push_back(p);
    }
    VASTRAY_TRY(buffer_.upload(records_.data(), records_.size() * sizeof(GpuTexture), 0));
    table_.assign(pageCount_, kTexturePageAbsent);
    slotEntry_.assign(slots, kTexturePageAbsent);
    slotUsed_.assign(slots, 0);
    step_ = 0;
    cached_.assign(isPaged ? pageCount_ : 0, {});
    cachedUse_.assign(cached_.size(), 0);
    cacheOrder_.clear(), cachedBytes_ = 0;
    pinnedSlots_ = 0;
    if (isPaged) {  // pages come in when asked for, but the cut-outs' level 0, which stays
        VASTRAY_TRY(buffer_.upload(table_.data(), table_.size() * 4, pageTableOffset_));
        const std::vector<uint32_t> zeros(pageCount_, 0);
        VASTRAY_TRY(buffer_.upload(zeros.data(), zeros.size() * 4, demandOffset_));
        const std::vector<uint32_t> pins = pinnedEntries(textures);
        if (pins.size() > slots) return Status::error("textures: the cut-outs' pages exceed the page slots");
        std::vector<uint32_t> first(pins.size());
        std::iota(first.begin(), first.end(), 0u);
        VASTRAY_TRY(load(pins, first, stats));
        pinnedSlots_ = uint32_t(pins.size());
        return Status::ok();
    }
    std::vector<uint32_t> all(pageCount_);
    std::iota(all.begin(), all.end(), 0u);
    return load(all, all, stats);  // in core: page p in slot p
}

Result<uint64_t> DeviceTextures::page(std::span<const uint32_t> demand, StreamingStats& stats) {
    if (!paged() || demand.size() != pageCount_) return Status::error("texture paging: demand counters of the wrong size");
    ++step_;
    // The pages read, most read first: the first slots_ of them should be resident.
    std::vector<uint32_t> read;
    for (uint32_t e = 0; e < pageCount_; ++e)
        if (demand[e] > 0) read.push_back(e);
    std::stable_sort(read.begin(), read.end(), [&](uint32_t a, uint32_t b) { return demand[a] > demand[b]; });
    std::vector<uint32_t> wanted;  // absent pages among them
    std::vector<bool> inTarget(slots_, false);
    for (size_t i = 0; i < read.size(); ++i) {
        const uint32_t e = read[i];
        if (table_[e] != kTexturePageAbsent) {
            if (i < slots_) inTarget[table_[e]] = true;
            slotUsed_[table_[e]] = step_;
        } else if (i < slots_ || wanted.empty()) {  // the most read absent page comes in whatever its rank
            wanted.push_back(e);
        }
    }
    if (wanted.empty()) return uint64_t(0);
    // Slots: empty ones, then those of pages outside the target, least recently used first, then
    // (when the target holds every slot) those of its least read pages; never a pinned one.
    std::vector<uint32_t> order(slots_ - pinnedSlots_);
    std::iota(order.begin(), order.end(), pinnedSlots_);
    auto rank = [&](uint32_t s) {
        const uint32_t e = slotEntry_[s];
        return std::tuple(e == kTexturePageAbsent ? 0 : inTarget[s] ? 2 : 1, inTarget[s] ? demand[e] : 0u, slotUsed_[s]);
    };
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return rank(a) < rank(b); });
    const size_t loads = std::min(wanted.size(), order.size());
    if (Status s = load(std::span(wanted).first(loads), std::span(order).first(loads), stats); !s) return s;
    return uint64_t(loads);
}

void DeviceTextures::keepInHost(uint32_t entry, const uint8_t* bytes) {
    while (cachedBytes_ + kTexturePageBytes > hostCacheBytes_) {
        // Pages this load copies from the cache (used this step) stay: then this one is not kept.
        if (cacheOrder_.empty() || cacheOrder_.begin()->first == step_) return;
        const uint32_t oldest = cacheOrder_.begin()->second;
        cacheOrder_.erase(cacheOrder_.begin());
        std::vector<uint8_t>().swap(cached_[oldest]);
        cachedBytes_ -= kTexturePageBytes;
    }
    cached_[entry].assign(bytes, bytes + kTexturePageBytes);
    cachedUse_[entry] = step_;
    cacheOrder_.insert({step_, entry});
    cachedBytes_ += kTexturePageBytes;
}

std::vector<uint32_t> DeviceTextures::pinnedEntries(std::span<const PackageTexture> textures) const {
    std::vector<uint32_t> entries;
    for (uint32_t t : pinned_) {
        if (t >= records_.size()) continue;
        const TextureLevel& level = textures[t].layout.levels[0];
        for (uint32_t p = 0; p < level.pagesX * level.pagesY; ++p)
            entries.push_back(records_[t].pageTable + level.firstPage + p);
    }
    return entries;
}

Status DeviceTextures::load(std::span<const uint32_t> pages, std::span<const uint32_t> slots, StreamingStats& stats) {
    if (pages.empty()) return Status::ok();
    // Pages the host cache lacks are read and inflated on worker threads, a batch at a time (a
    // page is 65 KiB), then every page is copied.
    constexpr size_t kBatch = 256;
    const bool caching = !cached_.empty();
    std::vector<uint8_t> data(std::min(pages.size(), kBatch) * kTexturePageBytes);
    for (size_t first = 0; first < pages.size(); first += kBatch) {
        const size_t count = std::min(kBatch, pages.size() - first);
        std::vector<size_t> reads;  // batch positions not in the host cache
        std::vector<bool> hits(count, false);
        for (size_t i = 0; i < count; ++i) {
            const uint32_t e = pages[first + i];
            hits[i] = caching && !cached_[e].empty();
            if (!hits[i]) {
                reads.push_back(i);
                continue;
            }
            // Used again: the most recent, so that keeping this batch's reads never drops it.
            cacheOrder_.erase({cachedUse_[e], e});
            cachedUse_[e] = step_;
            cacheOrder_.insert({step_, e});
        }
        std::vector<Status> failures(reads.size(), Status::ok());
        std::atomic<bool> failed{false};
        tbb::parallel_for(size_t(0), reads.size(), [&](size_t k) {
            const size_t i = reads[k];
            const uint32_t e = pages[first + i];
            Status s = read_(entryTexture_[e], entryPage_[e], data.data() + i * kTexturePageBytes);
            if (!s) failures[k] = std::move(s), failed = true;
        });
        if (failed)
            for (const Status& s : failures)
                if (!s) return s;
        stats.texturePagesRead += reads.size();
        for (size_t i = 0; i < count; ++i) {
            const uint32_t e = pages[first + i], slot = slots[first + i];
            const uint8_t* bytes = hits[i] ? cached_[e].data() : data.data() + i * kTexturePageBytes;
            if (slotEntry_[slot] != kTexturePageAbsent) table_[slotEntry_[slot]] = kTexturePageAbsent;
            slotEntry_[slot] = e, table_[e] = slot, slotUsed_[slot] = step_;
            VASTRAY_TRY(buffer_.upload(bytes, kTexturePageBytes, poolOffset_ + uint64_t(slot) * kTexturePageBytes));
            if (!hits[i] && caching) keepInHost(e, bytes);
        }
        stats.hostToDeviceBytes += count * kTexturePageBytes;
    }
    if (paged()) stats.texturePageLoads += pages.size();
    stats.hostToDeviceBytes += table_.size() * 4;
    return buffer_.upload(table_.data(), table_.size() * 4, pageTableOffset_);
}

}  // namespace vastray::gpu
