#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>

#include "vastray/core/KdTree.h"

namespace vastray {
namespace {

constexpr uint32_t kNoParent = ~0u;
constexpr uint32_t kMaxBins = 64;

// A triangle reference with its AABB clipped to the current node box. Plain float arrays
// (not Vec3f) because the per-axis inner loops index them by a runtime axis.
struct Ref {
    float lo[3];
    float hi[3];
    uint32_t triangle;
};

// A node waiting to be built. Its references are refs[begin, end), always the top of the
// ref stack when the item is popped (depth-first order keeps the buffer a stack).
struct WorkItem {
    float lo[3];
    float hi[3];
    uint32_t begin;
    uint32_t end;
    uint32_t depth;
    uint32_t parent;  // interior node whose aboveChild must point here, or kNoParent
};

struct Split {
    int axis = -1;
    float position = 0;
};

uint32_t defaultMaxDepth(uint32_t triangleCount, uint32_t requested) {
    if (requested != 0) return std::min(requested, kMaxKdDepth);
    const double depth = 8.0 + 1.3 * std::log2(double(std::max(triangleCount, 1u)));
    return std::min(uint32_t(depth), kMaxKdDepth);
}

float boxArea(const float* lo, const float* hi) {
    const float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    return 2.0f * (dx * dy + dy * dz + dz * dx);
}

class KdBuilder {
public:
    KdBuilder(const Vec3f* positions, const uint32_t* indices, uint32_t triangleCount,
              const KdBuildOptions& options)
        : positions_(positions), indices_(indices), count_(triangleCount), options_(options) {
        bins_ = std::clamp(options.bins, 4u, kMaxBins);
        maxDepth_ = defaultMaxDepth(triangleCount, options.maxDepth);
    }

    KdTree build() {
        initRefs();
        if (count_ == 0) {
            tree_.nodes.push_back(KdNode::leaf(0, 0));  // a root always exists; bounds are empty
            return std::move(tree_);
        }
        tree_.nodes.reserve(size_t(count_) * 2);
        tree_.leafRefs.reserve(size_t(count_) * 2);
        WorkItem root{};
        for (int a = 0; a < 3; ++a) root.lo[a] = tree_.bounds.lo[a], root.hi[a] = tree_.bounds.hi[a];
        root.begin = 0;
        root.end = count_;
        root.parent = kNoParent;
        stack_.push_back(root);
        while (!stack_.empty()) {
            const WorkItem item = stack_.back();
            stack_.pop_back();
            processNode(item);
        }
        return std::move(tree_);
    }

private:
    void initRefs() {
        refs_.resize(count_);
        for (uint32_t i = 0; i < count_; ++i) {
            Aabb box;
            for (int k = 0; k < 3; ++k) box.extend(positions_[indices_[3 * i + k]]);
            Ref& r = refs_[i];
            for (int a = 0; a < 3; ++a) r.lo[a] = box.lo[a], r.hi[a] = box.hi[a];
            r.triangle = i;
            tree_.bounds.extend(box);
        }
    }

    void processNode(const WorkItem& item) {
        assert(item.end == refs_.size());
        const uint32_t index = uint32_t(tree_.nodes.size());
        assert(index < (1u << 30));
        if (item.parent != kNoParent) tree_.nodes[item.parent] = KdNode::interior(
            tree_.nodes[item.parent].axis(), tree_.nodes[item.parent].split(), index);
        tree_.maxDepth = std::max(tree_.maxDepth, item.depth);
        const Split split = findSplit(item);
        if (split.axis < 0) {
            makeLeaf(item);
            return;
        }
        tree_.nodes.push_back(KdNode::interior(uint32_t(split.axis), split.position, 0));
        partition(item, split, index);
    }

    void makeLeaf(const WorkItem& item) {
        tree_.nodes.push_back(KdNode::leaf(uint32_t(tree_.leafRefs.size()), item.end - item.begin));
        for (uint32_t i = item.begin; i < item.end; ++i) tree_.leafRefs.push_back(refs_[i].triangle);
        refs_.resize(item.begin);
    }

    // One pass over the references fills the start/end bin histograms of all three axes. A
    // reference lies inside the node box, so its bin is never negative; rounding can put a
    // coordinate equal to the box's upper end into bin `bins`, which is folded into the last bin
    // afterwards instead of clamping in the loop.
    void binRefs(const WorkItem& item, const float* scale, uint32_t bins) {
        for (int a = 0; a < 3; ++a) {
            std::memset(starts_[a], 0, (bins + 1) * sizeof(uint32_t));
            std::memset(ends_[a], 0, (bins + 1) * sizeof(uint32_t));
        }
        // Locals: the histograms are uint32_t like WorkItem::end, so the compiler would
        // otherwise reload the box and the loop bound after every increment.
        const float lo[3] = {item.lo[0], item.lo[1], item.lo[2]};
        const float sc[3] = {scale[0], scale[1], scale[2]};
        const Ref* r = refs_.data() + item.begin;
        const Ref* const end = refs_.data() + item.end;
        for (; r != end; ++r) {
            for (int a = 0; a < 3; ++a) {
                ++starts_[a][uint32_t((r->lo[a] - lo[a]) * sc[a])];
                ++ends_[a][uint32_t((r->hi[a] - lo[a]) * sc[a])];
            }
        }
        for (int a = 0; a < 3; ++a) {
            starts_[a][bins - 1] += starts_[a][bins];
            ends_[a][bins - 1] += ends_[a][bins];
        }
    }

    Split findSplit(const WorkItem& item) {
        const uint32_t n = item.end - item.begin;
        const float area = boxArea(item.lo, item.hi);
        if (n <= options_.maxLeafSize || item.depth >= maxDepth_ || !(area > 0.0f)) return {};
        // Small nodes get fewer bins: the sweep over empty bins would dominate the build time
        // (most nodes are small); n/2 bins (at least 8) still place a plane between most pairs.
        const uint32_t bins = std::min(bins_, std::max(8u, n / 2));
        float scale[3];
        for (int a = 0; a < 3; ++a) {
            const float extent = item.hi[a] - item.lo[a];
            scale[a] = extent > 0.0f ? float(bins) / extent : 0.0f;
        }
        binRefs(item, scale, bins);
        Split best;
        float bestCost = options_.intersectionCost * float(n);  // cost of staying a leaf
        for (int a = 0; a < 3; ++a)
            if (scale[a] > 0.0f) sweepAxis(item, a, n, bins, 1.0f / area, &best, &bestCost);
        return best;
    }

    // Evaluates the SAH at the bins-1 inner bin boundaries of one axis. Works on locals only:
    // stores through pointers in the loop would make the compiler reload the histograms.
    void sweepAxis(const WorkItem& item, int a, uint32_t n, uint32_t bins, float invArea, Split* best,
                   float* bestCost) const {
        const int o1 = (a + 1) % 3, o2 = (a + 2) % 3;
        const float d1 = item.hi[o1] - item.lo[o1], d2 = item.hi[o2] - item.lo[o2];
        const float lo = item.lo[a], hi = item.hi[a], extent = hi - lo, step = 1.0f / float(bins);
        const float side = 2.0f * (d1 + d2) * invArea, cap = 2.0f * d1 * d2 * invArea;
        const float ct = options_.traversalCost, ci = options_.intersectionCost;
        const float emptyFactor = 1.0f - options_.emptyBonus;
        const uint32_t* starts = starts_[a];
        const uint32_t* ends = ends_[a];
        float bestLocal = *bestCost;
        int bestK = -1;
        uint32_t below = 0, above = n;
        for (uint32_t k = 1; k < bins; ++k) {
            below += starts[k - 1];
            above -= ends[k - 1];
            const float position = lo + extent * (float(k) * step);
            const float pBelow = (position - lo) * side + cap, pAbove = (hi - position) * side + cap;
            const float bonus = (below == 0 || above == 0) ? emptyFactor : 1.0f;
            const float cost = ct + ci * bonus * (pBelow * float(below) + pAbove * float(above));
            const bool inside = position > lo && position < hi;
            if (inside && cost < bestLocal) bestLocal = cost, bestK = int(k);
        }
        if (bestK < 0) return;
        *bestCost = bestLocal;
        *best = {a, lo + extent * (float(bestK) * step)};
    }

    // Which children a reference goes to. A reference touching the plane from one side stays on
    // that side; one lying in the plane goes above (the traversal visits both children of a plane
    // the ray meets, with a margin, so either side would be found; above matches the binning).
    static void classify(const Ref& r, int a, float s, bool* below, bool* above) {
        const bool planar = r.lo[a] == s && r.hi[a] == s;
        *below = r.lo[a] < s;
        *above = r.hi[a] > s || planar;
    }

    // Tightens the bounds of a reference that straddles the plane x[a] = s to the bounds of the
    // triangle's part on each side (vertices on that side plus the edge/plane crossings), so
    // later splits duplicate it less. The part bounds are padded by 2^-20 of the triangle's
    // magnitude because the crossings are rounded: bounds must stay conservative.
    void splitStraddler(int a, float s, Ref* below, Ref* above) const {
        const uint32_t* v = indices_ + 3 * size_t(below->triangle);
        const Vec3f p[3] = {positions_[v[0]], positions_[v[1]], positions_[v[2]]};
        Aabb partBelow, partAbove;
        for (int i = 0; i < 3; ++i) {
            const Vec3f& p0 = p[i];
            const Vec3f& p1 = p[(i + 1) % 3];
            if (p0[a] <= s) partBelow.extend(p0);
            if (p0[a] >= s) partAbove.extend(p0);
            if ((p0[a] < s && p1[a] > s) || (p0[a] > s && p1[a] < s)) {
                Vec3f q = p0 + (p1 - p0) * ((s - p0[a]) / (p1[a] - p0[a]));
                q[a] = s;
                partBelow.extend(q);
                partAbove.extend(q);
            }
        }
        for (int k = 0; k < 3; ++k) {
            const float magnitude = std::max({std::abs(p[0][k]), std::abs(p[1][k]), std::abs(p[2][k])});
            const float pad = magnitude * (1.0f / 1048576.0f);
            below->lo[k] = std::max(below->lo[k], partBelow.lo[k] - pad);
            below->hi[k] = std::min(below->hi[k], partBelow.hi[k] + pad);
            above->lo[k] = std::max(above->lo[k], partAbove.lo[k] - pad);
            above->hi[k] = std::min(above->hi[k], partAbove.hi[k] + pad);
        }
        below->hi[a] = std::min(below->hi[a], s);
        above->lo[a] = std::max(above->lo[a], s);
    }

    // One pass: above references are compacted in place (the write index never passes the read
    // index), below ones go to the scratch buffer and are appended after them, so the below
    // child's references end up on top of the stack.
    void partition(const WorkItem& item, const Split& split, uint32_t index) {
        const int a = split.axis;
        const float s = split.position;
        if (scratch_.size() < item.end - item.begin) scratch_.resize(item.end - item.begin);
        Ref* aboveOut = refs_.data() + item.begin;
        Ref* belowOut = scratch_.data();
        for (uint32_t i = item.begin; i < item.end; ++i) {
            const Ref r = refs_[i];
            bool b, ab;
            classify(r, a, s, &b, &ab);
            if (b && ab) {
                *belowOut = r;
                *aboveOut = r;
                splitStraddler(a, s, belowOut++, aboveOut++);
                continue;
            }
            if (b) *belowOut = r, belowOut->hi[a] = std::min(r.hi[a], s), ++belowOut;
            if (ab) *aboveOut = r, aboveOut->lo[a] = std::max(r.lo[a], s), ++aboveOut;
        }
        const uint32_t nAbove = uint32_t(aboveOut - (refs_.data() + item.begin));
        const uint32_t nBelow = uint32_t(belowOut - scratch_.data());
        refs_.resize(size_t(item.begin) + nAbove);
        refs_.insert(refs_.end(), scratch_.data(), belowOut);
        WorkItem above = item, below = item;
        above.lo[a] = s;
        above.end = item.begin + nAbove;
        above.depth = below.depth = item.depth + 1;
        above.parent = index;
        below.hi[a] = s;
        below.begin = item.begin + nAbove;
        below.end = below.begin + nBelow;
        below.parent = kNoParent;
        stack_.push_back(above);  // below is popped first, so it becomes node index + 1
        stack_.push_back(below);
    }

    const Vec3f* positions_;
    const uint32_t* indices_;
    uint32_t count_;
    KdBuildOptions options_;
    uint32_t bins_ = 32;
    uint32_t maxDepth_ = 0;
    KdTree tree_;
    std::vector<Ref> refs_;
    std::vector<Ref> scratch_;
    std::vector<WorkItem> stack_;
    uint32_t starts_[3][kMaxBins + 1];
    uint32_t ends_[3][kMaxBins + 1];
};

}  // namespace

KdTree buildKdTree(const Vec3f* positions, const uint32_t* indices, uint32_t triangleCount,
                   const KdBuildOptions& options) {
    return KdBuilder(positions, indices, triangleCount, options).build();
}

KdTreeStats computeKdTreeStats(const KdTree& tree) {
    KdTreeStats stats;
    stats.nodes = tree.nodes.size();
    stats.maxDepth = tree.maxDepth;
    for (const KdNode& node : tree.nodes) {
        if (!node.isLeaf()) continue;
        ++stats.leaves;
        stats.emptyLeaves += node.primitiveCount() == 0;
        stats.references += node.primitiveCount();
    }
    const uint64_t filled = stats.leaves - stats.emptyLeaves;
    stats.meanLeafSize = filled ? double(stats.references) / double(filled) : 0.0;
    return stats;
}

}  // namespace vastray
