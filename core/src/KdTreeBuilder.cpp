#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstring>
#include <memory>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "vastray/core/KdTree.h"

namespace vastray {
namespace {

constexpr uint32_t kNoParent = ~0u;
constexpr uint32_t kMaxBins = 64;
constexpr uint32_t kTwoCopiesMin = 64;  // binRefs: nodes with this many references or more use
constexpr uint32_t kFourCopiesMin = 256;  // two / four histogram copies
constexpr size_t kPrefetchAhead = 8;  // partition: straddlers whose vertices are prefetched ahead

// A triangle reference with its AABB clipped to the current node box. Plain float arrays
// (not Vec3f) because the per-axis inner loops index them by a runtime axis. 32 bytes, aligned:
// the binning loop loads lo (+ triangle) and hi (+ pad) as two aligned 4-float vectors.
struct alignas(16) Ref {
    float lo[3];
    uint32_t triangle;
    float hi[3];
    uint32_t pad;
};
static_assert(sizeof(Ref) == 32);

// A triangle's three vertices, padded for aligned 4-float loads (one cache-line pair per
// straddler instead of an index and three vertex lookups).
struct alignas(16) TriangleVertices {
    float p[3][4];
};

// Growable array of references without value-initialisation of new elements (Ref is trivial).
class RefBuffer {
public:
    Ref* data() { return data_.get(); }
    // Makes room for [0, size) keeping the first `keep` elements.
    void reserve(size_t size, size_t keep) {
        if (size <= capacity_) return;
        const size_t capacity = std::max(size, capacity_ + capacity_ / 2);
        std::unique_ptr<Ref[]> grown(new Ref[capacity]);
        if (keep) std::memcpy(grown.get(), data_.get(), keep * sizeof(Ref));
        data_ = std::move(grown);
        capacity_ = capacity;
    }

private:
    std::unique_ptr<Ref[]> data_;
    size_t capacity_ = 0;
};

// A node waiting to be built. Its references are refs[begin, end); when the item is popped,
// nothing above `end` is in use any more (depth-first order keeps the buffer a stack, with gaps
// where a parent's references were).
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
        refs_.reserve(size_t(count_) * 3, 0);
        Ref* refs = refs_.data();
#if defined(__SSE2__)
        vertices_.reset(new TriangleVertices[count_]);
#endif
        for (uint32_t i = 0; i < count_; ++i) {
            Aabb box;
            for (int k = 0; k < 3; ++k) box.extend(positions_[indices_[3 * i + k]]);
#if defined(__SSE2__)
            for (int k = 0; k < 3; ++k) {
                const Vec3f p = positions_[indices_[3 * i + k]];
                vertices_[i].p[k][0] = p.x, vertices_[i].p[k][1] = p.y, vertices_[i].p[k][2] = p.z;
                vertices_[i].p[k][3] = 0.0f;
            }
#endif
            Ref& r = refs[i];
            for (int a = 0; a < 3; ++a) r.lo[a] = box.lo[a], r.hi[a] = box.hi[a];
            r.triangle = i;
            r.pad = 0;
            tree_.bounds.extend(box);
        }
    }

    // Every item still on the work stack has its references below item.end of the item being
    // processed, so [item.end, ...) is free: partition writes the below child's references there.
    void processNode(const WorkItem& item) {
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
        const Ref* refs = refs_.data();
        const size_t first = tree_.leafRefs.size();
        tree_.leafRefs.resize(first + (item.end - item.begin));
        uint32_t* out = tree_.leafRefs.data() + first;
        for (uint32_t i = item.begin; i < item.end; ++i) *out++ = refs[i].triangle;
    }

    // One pass over the references fills the start/end bin histograms of all three axes (rows
    // 0-2: starts of x, y, z; rows 3-5: ends; each row `bins + 1` counters). A reference lies
    // inside the node box, so its bin is never negative; rounding can put a coordinate equal to
    // the box's upper end into bin `bins`, which is folded into the last bin afterwards instead
    // of clamping in the loop. Consecutive references often fall into the same bins, so larger
    // nodes count references round-robin into two or four copies that are summed afterwards (no
    // store-to-load forwarding chain through one counter).
    void binRefs(const WorkItem& item, const float* scale, uint32_t bins) {
        const uint32_t stride = bins + 1, rows = 6 * stride, n = item.end - item.begin;
        // Small nodes: merging the copies would cost more than the chains.
        const uint32_t copies = n >= kFourCopiesMin ? 4 : (n >= kTwoCopiesMin ? 2 : 1);
        uint32_t* const h0 = hist_;
        std::memset(hist_, 0, copies * rows * sizeof(uint32_t));
        const Ref* r = refs_.data() + item.begin;
        const Ref* const end = refs_.data() + item.end;
#if defined(__SSE2__)
        // The same float operations as the scalar formula uint32_t((x - lo) * scale), lane by
        // lane, so the bins are bit-identical; lane 3 (triangle / pad) is ignored. The triangle
        // index is masked off first: as a float it is usually a denormal, and arithmetic on
        // denormals can take a slow microcode path.
        const __m128 lo = _mm_setr_ps(item.lo[0], item.lo[1], item.lo[2], 0.0f);
        const __m128 sc = _mm_setr_ps(scale[0], scale[1], scale[2], 0.0f);
        const int s = int(stride);
        const __m128i offLo = _mm_setr_epi32(0, s, 2 * s, 0), offHi = _mm_setr_epi32(3 * s, 4 * s, 5 * s, 0);
        const __m128 xyzMask = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
        alignas(16) int32_t idx[8];
        auto binOne = [&](const Ref* ref, uint32_t* h) {
            const __m128 vlo = _mm_and_ps(_mm_load_ps(ref->lo), xyzMask), vhi = _mm_load_ps(ref->hi);
            _mm_store_si128(reinterpret_cast<__m128i*>(idx),
                            _mm_add_epi32(_mm_cvttps_epi32(_mm_mul_ps(_mm_sub_ps(vlo, lo), sc)), offLo));
            _mm_store_si128(reinterpret_cast<__m128i*>(idx + 4),
                            _mm_add_epi32(_mm_cvttps_epi32(_mm_mul_ps(_mm_sub_ps(vhi, lo), sc)), offHi));
            ++h[idx[0]], ++h[idx[1]], ++h[idx[2]], ++h[idx[4]], ++h[idx[5]], ++h[idx[6]];
        };
#else
        const float lo[3] = {item.lo[0], item.lo[1], item.lo[2]};
        const float sc[3] = {scale[0], scale[1], scale[2]};
        auto binOne = [&](const Ref* ref, uint32_t* h) {
            for (int a = 0; a < 3; ++a) {
                ++h[a * stride + uint32_t((ref->lo[a] - lo[a]) * sc[a])];
                ++h[(3 + a) * stride + uint32_t((ref->hi[a] - lo[a]) * sc[a])];
            }
        };
#endif
        if (copies == 4) {
            for (; end - r >= 4; r += 4) {
                binOne(r, h0);
                binOne(r + 1, h0 + rows);
                binOne(r + 2, h0 + 2 * rows);
                binOne(r + 3, h0 + 3 * rows);
            }
        } else if (copies == 2) {
            for (; end - r >= 2; r += 2) {
                binOne(r, h0);
                binOne(r + 1, h0 + rows);
            }
        }
        for (; r != end; ++r) binOne(r, h0);
        for (uint32_t c = 1; c < copies; ++c) {
            const uint32_t* hc = h0 + c * rows;
            uint32_t i = 0;
#if defined(__SSE2__)
            for (; i + 4 <= rows; i += 4) {
                const __m128i sum = _mm_add_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(h0 + i)),
                                                  _mm_loadu_si128(reinterpret_cast<const __m128i*>(hc + i)));
                _mm_storeu_si128(reinterpret_cast<__m128i*>(h0 + i), sum);
            }
#endif
            for (; i < rows; ++i) h0[i] += hc[i];
        }
        for (int row = 0; row < 6; ++row) h0[row * stride + bins - 1] += h0[row * stride + bins];
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
        Split best;
        float bestCost = options_.intersectionCost * float(n);  // cost of staying a leaf
        binRefs(item, scale, bins);
        for (int a = 0; a < 3; ++a)
            if (scale[a] > 0.0f)
                sweepAxis(item, a, n, bins, hist_ + a * (bins + 1), hist_ + (3 + a) * (bins + 1), 1.0f / area,
                          &best, &bestCost);
        return best;
    }

    // Evaluates the SAH at the bins-1 inner bin boundaries of one axis. Works on locals only:
    // stores through pointers in the loop would make the compiler reload the histograms.
    void sweepAxis(const WorkItem& item, int a, uint32_t n, uint32_t bins, const uint32_t* starts,
                   const uint32_t* ends, float invArea, Split* best, float* bestCost) const {
        const int o1 = (a + 1) % 3, o2 = (a + 2) % 3;
        const float d1 = item.hi[o1] - item.lo[o1], d2 = item.hi[o2] - item.lo[o2];
        const float lo = item.lo[a], hi = item.hi[a], extent = hi - lo, step = 1.0f / float(bins);
        const float side = 2.0f * (d1 + d2) * invArea, cap = 2.0f * d1 * d2 * invArea;
        const float ct = options_.traversalCost, ci = options_.intersectionCost;
        const float emptyFactor = 1.0f - options_.emptyBonus;
        float bestLocal = *bestCost;
        int bestK = -1;
#if defined(__SSE2__)
        // The scalar recurrence (counts, empty bonus) first, then the cost of every boundary with
        // the same float operations in the same order as the scalar formula below, four lanes at
        // a time, so the chosen split is bit-identical. Boundaries outside (lo, hi) cost +inf.
        alignas(16) float countBelow[kMaxBins + 4], countAbove[kMaxBins + 4], bonus[kMaxBins + 4];
        alignas(16) float costs[kMaxBins + 4];
        const uint32_t m = bins - 1;  // boundaries k = 1 .. bins-1 at index k-1
        {
            uint32_t below = 0, above = n;
            for (uint32_t k = 1; k < bins; ++k) {
                below += starts[k - 1];
                above -= ends[k - 1];
                countBelow[k - 1] = float(below);
                countAbove[k - 1] = float(above);
                bonus[k - 1] = (below == 0 || above == 0) ? emptyFactor : 1.0f;
            }
        }
        for (uint32_t j = m; j < m + 4; ++j) countBelow[j] = countAbove[j] = bonus[j] = 0.0f;  // tail lanes
        const __m128 vlo = _mm_set1_ps(lo), vhi = _mm_set1_ps(hi), vextent = _mm_set1_ps(extent);
        const __m128 vstep = _mm_set1_ps(step), vside = _mm_set1_ps(side), vcap = _mm_set1_ps(cap);
        const __m128 vct = _mm_set1_ps(ct), vci = _mm_set1_ps(ci), vinf = _mm_set1_ps(INFINITY);
        for (uint32_t j = 0; j < m; j += 4) {
            const __m128 k = _mm_cvtepi32_ps(_mm_setr_epi32(int(j + 1), int(j + 2), int(j + 3), int(j + 4)));
            const __m128 position = _mm_add_ps(vlo, _mm_mul_ps(vextent, _mm_mul_ps(k, vstep)));
            const __m128 pBelow = _mm_add_ps(_mm_mul_ps(_mm_sub_ps(position, vlo), vside), vcap);
            const __m128 pAbove = _mm_add_ps(_mm_mul_ps(_mm_sub_ps(vhi, position), vside), vcap);
            const __m128 weighted = _mm_add_ps(_mm_mul_ps(pBelow, _mm_load_ps(countBelow + j)),
                                               _mm_mul_ps(pAbove, _mm_load_ps(countAbove + j)));
            const __m128 cost =
                _mm_add_ps(vct, _mm_mul_ps(_mm_mul_ps(vci, _mm_load_ps(bonus + j)), weighted));
            const __m128 inside = _mm_and_ps(_mm_cmpgt_ps(position, vlo), _mm_cmplt_ps(position, vhi));
            _mm_store_ps(costs + j, _mm_or_ps(_mm_and_ps(inside, cost), _mm_andnot_ps(inside, vinf)));
        }
        for (uint32_t j = 0; j < m; ++j)
            if (costs[j] < bestLocal) bestLocal = costs[j], bestK = int(j + 1);
#else
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
#endif
        if (bestK < 0) return;
        *bestCost = bestLocal;
        *best = {a, lo + extent * (float(bestK) * step)};
    }

    // Which children a reference goes to. A reference touching the plane from one side stays on
    // that side; one lying in the plane goes above (the traversal visits both children of a plane
    // the ray meets, with a margin, so either side would be found; above matches the binning).
    static void classify(const Ref& r, int a, float s, bool* below, bool* above) {
        const float lo = r.lo[a], hi = r.hi[a];
        *below = lo < s;
        *above = (hi > s) | ((lo == s) & (hi == s));  // | and &: no branches
    }

    // Tightens the bounds of a reference that straddles the plane x[a] = s to the bounds of the
    // triangle's part on each side (vertices on that side plus the edge/plane crossings), so
    // later splits duplicate it less. The part bounds are padded by 2^-20 of the triangle's
    // magnitude because the crossings are rounded: bounds must stay conservative.
#if defined(__SSE2__)
    void prefetchVertices(uint32_t triangle) const {
        const char* p = reinterpret_cast<const char*>(&vertices_[triangle]);
        __builtin_prefetch(p);
        __builtin_prefetch(p + sizeof(TriangleVertices) - 1);
    }
#endif

#if defined(__SSE2__)
    // The same float operations as the scalar version below, three lanes at a time, so the
    // bounds are bit-identical: std::min(x, y) is (y < x ? y : x), which is _mm_min_ps(y, x),
    // and std::max(x, y) is (x < y ? y : x), which is _mm_max_ps(y, x).
    void splitStraddler(int a, float s, Ref* below, Ref* above) const {
        const TriangleVertices& tv = vertices_[below->triangle];
        const __m128 p[3] = {_mm_load_ps(tv.p[0]), _mm_load_ps(tv.p[1]), _mm_load_ps(tv.p[2])};
        const float pa[3] = {tv.p[0][a], tv.p[1][a], tv.p[2][a]};
        const __m128 inf = _mm_set1_ps(INFINITY), minusInf = _mm_set1_ps(-INFINITY);
        __m128 belowLo = inf, belowHi = minusInf, aboveLo = inf, aboveHi = minusInf;
        alignas(16) static constexpr uint32_t kLaneMasks[3][4] = {
            {~0u, 0, 0, 0}, {0, ~0u, 0, 0}, {0, 0, ~0u, 0}};
        const __m128 laneA = _mm_load_ps(reinterpret_cast<const float*>(kLaneMasks[a]));
        const __m128 planeS = _mm_and_ps(laneA, _mm_set1_ps(s));
        for (int i = 0; i < 3; ++i) {
            const int j = i == 2 ? 0 : i + 1;
            const __m128 p0 = p[i];
            const float a0 = pa[i], a1 = pa[j];
            if (a0 <= s) belowLo = _mm_min_ps(p0, belowLo), belowHi = _mm_max_ps(p0, belowHi);
            if (a0 >= s) aboveLo = _mm_min_ps(p0, aboveLo), aboveHi = _mm_max_ps(p0, aboveHi);
            if ((a0 < s && a1 > s) || (a0 > s && a1 < s)) {
                const __m128 t = _mm_set1_ps((s - a0) / (a1 - a0));
                __m128 q = _mm_add_ps(p0, _mm_mul_ps(_mm_sub_ps(p[j], p0), t));
                q = _mm_or_ps(_mm_andnot_ps(laneA, q), planeS);
                belowLo = _mm_min_ps(q, belowLo), belowHi = _mm_max_ps(q, belowHi);
                aboveLo = _mm_min_ps(q, aboveLo), aboveHi = _mm_max_ps(q, aboveHi);
            }
        }
        const __m128 absMask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
        __m128 magnitude = _mm_and_ps(p[0], absMask);
        magnitude = _mm_max_ps(_mm_and_ps(p[1], absMask), magnitude);
        magnitude = _mm_max_ps(_mm_and_ps(p[2], absMask), magnitude);
        const __m128 pad = _mm_mul_ps(magnitude, _mm_set1_ps(1.0f / 1048576.0f));
        alignas(16) float out[4][4];
        _mm_store_ps(out[0], _mm_max_ps(_mm_sub_ps(belowLo, pad), _mm_load_ps(below->lo)));
        _mm_store_ps(out[1], _mm_min_ps(_mm_add_ps(belowHi, pad), _mm_load_ps(below->hi)));
        _mm_store_ps(out[2], _mm_max_ps(_mm_sub_ps(aboveLo, pad), _mm_load_ps(above->lo)));
        _mm_store_ps(out[3], _mm_min_ps(_mm_add_ps(aboveHi, pad), _mm_load_ps(above->hi)));
        for (int k = 0; k < 3; ++k) {
            below->lo[k] = out[0][k];
            below->hi[k] = out[1][k];
            above->lo[k] = out[2][k];
            above->hi[k] = out[3][k];
        }
        below->hi[a] = std::min(below->hi[a], s);
        above->lo[a] = std::max(above->lo[a], s);
    }
#else
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
#endif

    // One pass: above references are compacted in place (the write index never passes the read
    // index), below ones are written to the free space after the item, so the below child's
    // references end up on top of the stack. A reference entirely on one side of the plane is
    // copied unchanged: clamping it to the plane would be a no-op.
    void partition(const WorkItem& item, const Split& split, uint32_t index) {
        const int a = split.axis;
        const float s = split.position;
        const uint32_t n = item.end - item.begin;
        refs_.reserve(size_t(item.end) + n, item.end);
        Ref* const refs = refs_.data();
        Ref* aboveOut = refs + item.begin;
        Ref* const belowBegin = refs + item.end;
        Ref* belowOut = belowBegin;
        // Branch-free: every reference is written to both outputs and each output advances only
        // if the reference belongs there (aboveOut never passes the read position, belowOut stays
        // within the n free slots). Straddlers are only recorded here and clipped afterwards (a
        // branch on them mispredicts often); when both children are at the depth cap they become
        // leaves whose reference bounds are never used, so they are not clipped at all.
        if (straddlers_.size() < 2 * size_t(n)) straddlers_.resize(2 * size_t(n));
        uint32_t* straddlerOut = straddlers_.data();
        for (const Ref* in = refs + item.begin, *end = refs + item.end; in != end; ++in) {
            const Ref r = *in;
            bool below, above;
            classify(r, a, s, &below, &above);
            *belowOut = r;
            *aboveOut = r;
            straddlerOut[0] = uint32_t(belowOut - refs);
            straddlerOut[1] = uint32_t(aboveOut - refs);
            straddlerOut += 2 * size_t(below & above);
            belowOut += below;
            aboveOut += above;
        }
        if (item.depth + 1 < maxDepth_) {
            const uint32_t* const list = straddlers_.data();
            const size_t count = size_t(straddlerOut - list) / 2;
            // A straddler's vertices are usually far away in memory (a cache miss on unordered
            // meshes): prefetch them a few straddlers ahead.
            for (size_t k = 0; k < count; ++k) {
#if defined(__SSE2__)
                if (k + kPrefetchAhead < count) prefetchVertices(refs[list[2 * (k + kPrefetchAhead)]].triangle);
#endif
                splitStraddler(a, s, refs + list[2 * k], refs + list[2 * k + 1]);
            }
        }
        const uint32_t nAbove = uint32_t(aboveOut - (refs + item.begin));
        const uint32_t nBelow = uint32_t(belowOut - belowBegin);
        WorkItem above = item, below = item;
        above.lo[a] = s;
        above.end = item.begin + nAbove;
        above.depth = below.depth = item.depth + 1;
        above.parent = index;
        below.hi[a] = s;
        below.begin = item.end;
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
    RefBuffer refs_;
#if defined(__SSE2__)
    std::unique_ptr<TriangleVertices[]> vertices_;  // splitStraddler's copy of the vertices
#endif
    std::vector<uint32_t> straddlers_;  // partition scratch: (below, above) slots of straddlers
    std::vector<WorkItem> stack_;
    uint32_t hist_[4 * 6 * (kMaxBins + 1)];  // up to four copies of 6 rows of bins + 1 counters
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

KdBuildOptions compactKdBuildOptions(uint32_t triangleCount) {
    KdBuildOptions options;
    options.maxLeafSize = 4;
    options.intersectionCost = 2.0f;
    options.bins = 16;
    options.maxDepth = std::clamp(uint32_t(std::bit_width(triangleCount)) + 3u, 8u, kMaxKdDepth);
    return options;
}

}  // namespace vastray
