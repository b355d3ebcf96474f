#pragma once
// Runs an embarrassingly parallel generator one batch ahead of a sequential consumer: TBB
// threads fill batch k+1 while the calling thread streams batch k into the sink. Memory is
// two batches, whatever the mesh size. Items must depend only on their index, so the output
// does not depend on the thread count or the batch size.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "vastray/core/Result.h"

namespace vastray::gen {

// fill(first, count, out): writes items [first, first + count) to out; called concurrently
// on disjoint ranges. emit(items, count): consumes one batch in order on the calling thread;
// its first error stops the run and is returned.
template <typename Item, typename Fill, typename Emit>
Status runBatchPipeline(uint64_t itemCount, uint64_t batchSize, const Fill& fill, Emit emit) {
    std::vector<Item> current(std::min(itemCount, batchSize)), next(current.size());
    auto fillBatch = [&fill](uint64_t first, uint64_t count, std::vector<Item>& out) {
        tbb::parallel_for(tbb::blocked_range<uint64_t>(0, count, 1024),
                          [&](const tbb::blocked_range<uint64_t>& r) {
                              fill(first + r.begin(), r.end() - r.begin(), out.data() + r.begin());
                          });
    };
    fillBatch(0, current.size(), current);
    tbb::task_group ahead;
    for (uint64_t first = 0; first < itemCount; first += batchSize) {
        const uint64_t count = std::min(batchSize, itemCount - first);
        const uint64_t nextFirst = first + count;
        const uint64_t nextCount = std::min(batchSize, itemCount - nextFirst);
        if (nextCount > 0) ahead.run([&, nextFirst, nextCount] { fillBatch(nextFirst, nextCount, next); });
        Status status = emit(static_cast<const Item*>(current.data()), count);
        ahead.wait();
        if (!status.isOk()) return status;
        std::swap(current, next);
    }
    return Status::ok();
}

}  // namespace vastray::gen
