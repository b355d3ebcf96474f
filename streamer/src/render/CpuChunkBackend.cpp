// The CPU chunk backend (core's KD-tree traversal) and the slot layout every backend shares.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <map>

#include "vastray/core/KdTree.h"
#include "vastray/core/PathShading.h"
#include "vastray/streamer/StreamingRenderer.h"

namespace vastray {
namespace {

uint64_t align16(uint64_t bytes) { return (bytes + 15) & ~uint64_t(15); }

class CpuChunkBackend final : public ChunkBackend {
public:
    CpuChunkBackend(uint32_t slots, const ChunkAttributes& attributes) : slots_(slots), attributes_(attributes) {}

    std::string name() const override { return "cpu"; }
    uint32_t slotCount() const override { return uint32_t(slots_.size()); }
    uint32_t maxBatchRays() const override { return 1u << 18; }

    Status load(uint32_t slot, const DecodedChunk& chunk, std::span<const uint8_t> singleSided) override {
        if (slot >= slots_.size()) return Status::error("slot " + std::to_string(slot) + " does not exist");
        const auto start = std::chrono::steady_clock::now();
        Slot& s = slots_[slot];
        s = Slot{};
        s.chunk = chunk;
        s.singleSided.assign(singleSided.begin(), singleSided.end());
        const ChunkLayout layout = chunkLayout(chunk.kdTree.nodes.size(), chunk.kdTree.leafRefs.size(),
                                               chunk.positions.size(), chunk.indices.size() / 3, attributes_);
        uploaded_ += layout.totalBytes;
        resident_[slot] = layout.totalBytes;
        uint64_t total = 0;
        for (const auto& [k, bytes] : resident_) total += bytes;
        peak_ = std::max(peak_, total);
        uploadSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return Status::ok();
    }

    Status trace(std::span<const Batch> batches) override {
        for (const Batch& b : batches) {
            if (b.slot >= slots_.size() || b.rays.size() != b.hits.size())
                return Status::error("trace: bad batch for slot " + std::to_string(b.slot));
            const Slot& s = slots_[b.slot];
            tbb::parallel_for(tbb::blocked_range<size_t>(0, b.rays.size(), 256), [&](const auto& range) {
                for (size_t i = range.begin(); i != range.end(); ++i) b.hits[i] = traceOne(s, b.rays[i], b.anyHit);
            });
        }
        return Status::ok();
    }

    uint64_t bytesUploaded() const override { return uploaded_; }
    uint64_t peakDeviceBytes() const override { return peak_; }
    double uploadSeconds() const override { return uploadSeconds_; }

private:
    struct Slot {
        DecodedChunk chunk;
        std::vector<uint8_t> singleSided;
    };

    StreamHit traceOne(const Slot& s, const StreamRay& r, bool anyHit) const {
        const DecodedChunk& c = s.chunk;
        const uint8_t* single = s.singleSided.empty() ? nullptr : s.singleSided.data();
        const Ray ray{r.origin, r.direction};
        StreamHit out;
        KdHit kd;
        if (anyHit) {
            if (occludedKdTree(c.kdTree, c.positions.data(), c.indices.data(), single, ray, r.tMin, r.tMax, &kd))
                out.flags = kStreamHitFound;
        } else if (intersectKdTree(c.kdTree, c.positions.data(), c.indices.data(), single, ray, r.tMin, r.tMax,
                                   &kd)) {
            const Vec3f v0 = c.positions[c.indices[3 * kd.triangle]];
            const Vec3f v1 = c.positions[c.indices[3 * kd.triangle + 1]];
            const Vec3f v2 = c.positions[c.indices[3 * kd.triangle + 2]];
            out.t = kd.t;
            out.position = barycentricPosition(v0, v1, v2, kd.u, kd.v);
            out.normal = geometricNormal(v0, v1, v2);
            if (attributes_.primitiveIds) out.primitive = c.primitiveIds[kd.triangle];
            if (attributes_.materialIds && !c.materialIds.empty()) out.material = c.materialIds[kd.triangle];
            out.flags = kStreamHitFound | (kd.frontFacing ? kStreamHitFrontFacing : 0u);
        }
        out.nodesVisited = kd.nodesVisited;
        out.trianglesTested = kd.trianglesTested;
        return out;
    }

    std::vector<Slot> slots_;
    ChunkAttributes attributes_;
    std::map<uint32_t, uint64_t> resident_;
    uint64_t uploaded_ = 0, peak_ = 0;
    double uploadSeconds_ = 0;
};

}  // namespace

ChunkLayout chunkLayout(uint64_t kdNodes, uint64_t kdRefs, uint64_t vertices, uint64_t triangles,
                        const ChunkAttributes& attributes) {
    ChunkLayout l;
    uint64_t at = 0;
    auto section = [&](uint64_t bytes) {
        const uint64_t offset = at;
        at += align16(bytes);
        return offset;
    };
    l.nodes = section(kdNodes * sizeof(KdNode));
    l.leafRefs = section(kdRefs * 4);
    l.positions = section(vertices * 12);
    l.indices = section(triangles * 12);
    l.singleSided = section(attributes.singleSided ? (triangles + 3) / 4 * 4 : 0);
    l.primitiveIds = section(attributes.primitiveIds ? triangles * 4 : 0);
    l.materialIds = section(attributes.materialIds ? triangles * 4 : 0);
    l.totalBytes = std::max<uint64_t>(at, 16);
    return l;
}

Result<std::unique_ptr<ChunkBackend>> createCpuChunkBackend(uint32_t slots, const ChunkAttributes& attributes) {
    if (slots == 0) return Status::error("the CPU chunk backend needs at least one slot");
    return std::unique_ptr<ChunkBackend>(new CpuChunkBackend(slots, attributes));
}

}  // namespace vastray
