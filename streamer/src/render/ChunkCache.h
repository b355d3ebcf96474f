#pragma once
// Decoded chunks on the host: read + decode on worker threads (so decoding overlaps the GPU's
// tracing), kept in an LRU cache bounded in bytes so that a chunk evicted from the device and
// needed again in the same job is not decoded twice while it fits. Two queues: chunks asked for
// now (prefetch, get) are decoded before speculative ones (prefetchBackground), and a get() of a
// chunk still waiting in the background queue moves it to the front.
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <span>
#include <thread>
#include <unordered_map>
#include <vector>

#include "vastray/core/Result.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {

using ChunkHandle = std::shared_ptr<const DecodedChunk>;

// The speculative queue's order once `first` is asked for ahead of it: the ids of `first` that
// are `waiting`, in `first`'s order (each once), then the other waiting ids in their order.
std::vector<uint32_t> speculativeOrder(std::span<const uint32_t> waiting, std::span<const uint32_t> first);

class ChunkCache {
public:
    // workers >= 1 decode threads; capacityBytes bounds the decoded chunks kept after use.
    ChunkCache(const PackageReader& reader, uint64_t capacityBytes, uint32_t workers);
    ~ChunkCache();
    ChunkCache(const ChunkCache&) = delete;
    ChunkCache& operator=(const ChunkCache&) = delete;

    // Starts decoding the chunk on a worker unless it is cached or in flight.
    void prefetch(uint32_t id);
    // The same, behind every chunk asked for by prefetch() or get(): for chunks a render will
    // probably need later. Speculative chunks are kept until their first get(), so the caller
    // bounds their bytes (see prefetchForRender).
    void prefetchBackground(uint32_t id);
    // The same for `ids`, in this order ahead of every other speculative chunk: those already
    // waiting in the background queue move there (a render's order replaces the order the
    // scene's chunks were queued in as it opened, StreamingOptions::decodeOnOpen).
    void prefetchBackground(std::span<const uint32_t> ids);
    // Runs `hook` on the decoding thread for each chunk decoded from now on, before get() returns
    // it, and on the workers for the chunks decoded already (after the chunks asked for by
    // prefetch() or get(), before the speculative ones): ChunkBackend::stage, which prepares loads
    // off the render thread. The hook must be safe to call from several threads at once.
    using DecodedHook = std::function<void(const DecodedChunk&)>;
    void setDecodedHook(DecodedHook hook);
    // Bytes of the chunks decoded or in flight that no get() has used yet.
    uint64_t unusedBytes() const;
    // The decoded chunk (waits for its decode; decodes it now when nobody asked before).
    // A corrupt chunk is an error naming the package and the chunk.
    Result<ChunkHandle> get(uint32_t id);

    uint64_t capacity() const { return capacity_; }
    uint64_t bytesRead() const;
    uint64_t decodes() const;
    double decodeSeconds() const;
    // Time get() spent on chunks not yet decoded when asked for, until they were (the render
    // thread's wait for decodes: a cold start's loads).
    double waitSeconds() const;

private:
    using Decoded = std::shared_future<Result<ChunkHandle>>;
    struct Entry {
        Decoded decoded;
        uint64_t bytes = 0;  // once decoded
        uint64_t lastUse = 0;
        bool used = false;  // prefetched chunks are kept until their first get()
        bool background = false;  // waiting in background_, not started
    };
    using Job = std::pair<uint32_t, std::shared_ptr<std::promise<Result<ChunkHandle>>>>;
    Decoded startLocked(uint32_t id, bool background);
    void workerLoop();
    void trimLocked();

    const PackageReader& reader_;
    const uint64_t capacity_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<Job> queue_;       // asked for now
    std::deque<Job> background_;  // speculative: taken when queue_ is empty
    std::shared_ptr<const DecodedHook> hook_;  // setDecodedHook
    std::deque<ChunkHandle> hookBacklog_;      // decoded before the hook was set: it runs on them
    std::unordered_map<uint32_t, Entry> entries_;
    std::vector<std::thread> threads_;
    bool stopping_ = false;
    uint64_t tick_ = 0;
    uint64_t bytesRead_ = 0;
    uint64_t decodes_ = 0;
    double decodeSeconds_ = 0;
    double waitSeconds_ = 0;
};

}  // namespace vastray
