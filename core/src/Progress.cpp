#include "vastray/core/Progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace vastray {

Progress::Progress(std::string label, uint64_t total, Mode mode, Observer observer)
    : label_(std::move(label)), total_(total), mode_(mode), observer_(std::move(observer)) {
    if (mode_ == Mode::Auto) mode_ = isatty(STDERR_FILENO) ? Mode::Bar : Mode::Lines;
    start_ = lastPrint_ = std::chrono::steady_clock::now();
}

Progress::~Progress() { end(false); }

void Progress::advance(uint64_t amount) {
    const uint64_t done = done_.fetch_add(amount) + amount;
    if (observer_) observer_(std::min(done, total_), total_);
    if (mode_ == Mode::None) return;
    const auto now = std::chrono::steady_clock::now();
    const int decile = total_ ? int(std::min<uint64_t>(done * 10 / total_, 10)) : 10;
    std::unique_lock lock(printMutex_, std::try_to_lock);
    if (!lock.owns_lock() || finished_) return;
    const bool due = mode_ == Mode::Bar ? now - lastPrint_ > std::chrono::milliseconds(100)
                                        : decile != lastDecile_ && decile < 10;
    if (!due) return;
    lastPrint_ = now;
    lastDecile_ = decile;
    print(done, false);
}

void Progress::finish() {
    if (observer_) observer_(total_, total_);
    end(true);
}

void Progress::end(bool complete) {
    std::lock_guard lock(printMutex_);
    if (finished_) return;
    finished_ = true;
    if (mode_ != Mode::None) print(complete ? total_ : done_.load(), true);
}

void Progress::print(uint64_t done, bool final) {
    done = std::min(done, total_);  // work units may be estimates (e.g. duplicated references)
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double fraction = total_ ? std::min(1.0, double(done) / double(total_)) : 1.0;
    if (mode_ == Mode::Bar) {
        constexpr int kWidth = 30;
        const int filled = int(fraction * kWidth);
        std::string bar(filled, '#');
        bar.resize(kWidth, '.');
        std::fprintf(stderr, "\r%s [%s] %5.1f%% %.1fs%s", label_.c_str(), bar.c_str(),
                     100.0 * fraction, seconds, final ? "\n" : "");
    } else {
        std::fprintf(stderr, "%s: %3.0f%% (%llu/%llu) %.1fs\n", label_.c_str(), 100.0 * fraction,
                     (unsigned long long)done, (unsigned long long)total_, seconds);
    }
    std::fflush(stderr);
}

}  // namespace vastray
