#include "render/ChunkCache.h"

#include <algorithm>
#include <chrono>

namespace vastray {

ChunkCache::ChunkCache(const PackageReader& reader, uint64_t capacityBytes, uint32_t workers)
    : reader_(reader), capacity_(capacityBytes) {
    for (uint32_t i = 0; i < std::max(1u, workers); ++i) threads_.emplace_back([this] { workerLoop(); });
}

ChunkCache::~ChunkCache() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : threads_) t.join();
}

void ChunkCache::workerLoop() {
    for (;;) {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [this] {
            return stopping_ || !queue_.empty() || !background_.empty() || !hookBacklog_.empty();
        });
        if (stopping_) return;  // speculative or not, nobody waits for the rest once the cache goes
        if (queue_.empty() && !hookBacklog_.empty()) {
            const ChunkHandle chunk = std::move(hookBacklog_.front());
            hookBacklog_.pop_front();
            const std::shared_ptr<const DecodedHook> hook = hook_;
            lock.unlock();
            (*hook)(*chunk);
            continue;
        }
        std::deque<Job>& from = !queue_.empty() ? queue_ : background_;
        auto [id, promise] = std::move(from.front());
        from.pop_front();
        if (auto it = entries_.find(id); it != entries_.end()) it->second.background = false;
        lock.unlock();

        const auto start = std::chrono::steady_clock::now();
        Result<ChunkHandle> out = Status::error("");
        uint64_t blobBytes = 0;
        auto blob = reader_.readChunkBlob(id);
        if (!blob) {
            out = blob.status();
        } else {
            blobBytes = blob->size();
            const PackageInfo& info = reader_.info();
            auto chunk = decodeChunkBlob(*blob, info.chunks[id], info.grid, uint32_t(info.materials.size()),
                                         info.triangleCount + info.collapsedDropped);
            if (chunk)
                out = ChunkHandle(std::make_shared<const DecodedChunk>(std::move(chunk).value()));
            else
                out = chunk.status().withContext(reader_.path() + ": chunk " + std::to_string(id) + ": ");
        }
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

        lock.lock();
        bytesRead_ += blobBytes;
        decodeSeconds_ += seconds;
        ++decodes_;
        auto it = entries_.find(id);
        if (it != entries_.end() && out) it->second.bytes = (*out)->residentBytes();
        const std::shared_ptr<const DecodedHook> hook = hook_;
        lock.unlock();
        if (hook && out) (*hook)(**out);  // before get() has the chunk: no load of it runs meanwhile
        promise->set_value(std::move(out));
    }
}

ChunkCache::Decoded ChunkCache::startLocked(uint32_t id, bool background) {
    auto it = entries_.find(id);
    if (it != entries_.end()) {
        it->second.lastUse = ++tick_;
        if (it->second.background && !background) {  // wanted now: to the front of the queue
            auto job = std::find_if(background_.begin(), background_.end(), [&](const Job& j) { return j.first == id; });
            if (job != background_.end()) {
                queue_.push_front(std::move(*job));
                background_.erase(job);
                wake_.notify_one();
            }
            it->second.background = false;
        }
        return it->second.decoded;
    }
    auto promise = std::make_shared<std::promise<Result<ChunkHandle>>>();
    Entry entry;
    entry.decoded = promise->get_future().share();
    entry.lastUse = ++tick_;
    entry.background = background;
    entries_.emplace(id, entry);
    (background ? background_ : queue_).emplace_back(id, std::move(promise));
    wake_.notify_one();
    return entry.decoded;
}

void ChunkCache::prefetch(uint32_t id) {
    if (id >= reader_.info().chunks.size()) return;
    std::lock_guard<std::mutex> lock(mutex_);
    startLocked(id, false);
}

void ChunkCache::prefetchBackground(uint32_t id) {
    if (id >= reader_.info().chunks.size()) return;
    std::lock_guard<std::mutex> lock(mutex_);
    startLocked(id, true);
}

namespace {
// Sorts `items` (whose ids `idOf` gives) so that those `first` names come first, in its order
// (an id's first place in it), the others after them in their own order.
template <typename Items, typename IdOf>
void putFirst(Items& items, std::span<const uint32_t> first, IdOf idOf) {
    std::unordered_map<uint32_t, size_t> rank;
    for (uint32_t id : first) rank.emplace(id, rank.size());
    auto rankOf = [&](const auto& item) {
        auto it = rank.find(idOf(item));
        return it == rank.end() ? rank.size() : it->second;
    };
    std::stable_sort(items.begin(), items.end(), [&](const auto& a, const auto& b) { return rankOf(a) < rankOf(b); });
}
}  // namespace

std::vector<uint32_t> speculativeOrder(std::span<const uint32_t> waiting, std::span<const uint32_t> first) {
    std::vector<uint32_t> order(waiting.begin(), waiting.end());
    putFirst(order, first, [](uint32_t id) { return id; });
    return order;
}

void ChunkCache::prefetchBackground(std::span<const uint32_t> ids) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (uint32_t id : ids)
        if (id < reader_.info().chunks.size()) startLocked(id, true);  // new ones join the queue's end
    putFirst(background_, ids, [](const Job& job) { return job.first; });
}

void ChunkCache::setDecodedHook(DecodedHook hook) {
    std::lock_guard<std::mutex> lock(mutex_);
    hook_ = hook ? std::make_shared<const DecodedHook>(std::move(hook)) : nullptr;
    hookBacklog_.clear();
    if (!hook_) return;
    for (const auto& [id, e] : entries_)
        if (e.decoded.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
            const Result<ChunkHandle>& decoded = e.decoded.get();
            if (decoded) hookBacklog_.push_back(*decoded);
        }
    if (!hookBacklog_.empty()) wake_.notify_all();
}

uint64_t ChunkCache::unusedBytes() const {
    std::lock_guard<std::mutex> lock(mutex_);
    uint64_t total = 0;
    for (const auto& [id, e] : entries_)
        if (!e.used) total += reader_.info().chunks[id].residentBytes;
    return total;
}

Result<ChunkHandle> ChunkCache::get(uint32_t id) {
    if (id >= reader_.info().chunks.size())
        return Status::error(reader_.path() + ": chunk " + std::to_string(id) + " does not exist");
    const auto start = std::chrono::steady_clock::now();
    Decoded decoded;
    bool waits = false;  // the chunk was not decoded when asked for: the time until it is counts
    {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = entries_.find(id);
        waits = it == entries_.end() || it->second.decoded.wait_for(std::chrono::seconds(0)) != std::future_status::ready;
        decoded = startLocked(id, false);
    }
    Result<ChunkHandle> out = decoded.get();
    std::lock_guard<std::mutex> lock(mutex_);
    if (waits) waitSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!out) {
        entries_.erase(id);  // a failed read is not cached: the next get reports it again
        return out;
    }
    entries_[id].used = true;
    trimLocked();
    return out;
}

// Drops least recently used decoded chunks until the cache fits; chunks in flight stay.
void ChunkCache::trimLocked() {
    uint64_t total = 0;
    for (const auto& [id, e] : entries_)
        if (e.used) total += e.bytes;
    while (total > capacity_) {
        auto victim = entries_.end();
        for (auto it = entries_.begin(); it != entries_.end(); ++it)
            if (it->second.used && it->second.bytes > 0 && (victim == entries_.end() || it->second.lastUse < victim->second.lastUse))
                victim = it;
        if (victim == entries_.end()) break;
        total -= victim->second.bytes;
        entries_.erase(victim);
    }
}

uint64_t ChunkCache::bytesRead() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return bytesRead_;
}
uint64_t ChunkCache::decodes() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return decodes_;
}
double ChunkCache::decodeSeconds() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return decodeSeconds_;
}
double ChunkCache::waitSeconds() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return waitSeconds_;
}

}  // namespace vastray
