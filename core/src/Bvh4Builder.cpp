// Binned-SAH binary BVH over a chunk's triangles, collapsed into 4-wide nodes with 8-bit child
// boxes (core/Bvh4.h): each node opens its largest interior child until it has four, or, when
// that makes the tree deeper than kBvh4MaxDepth, takes exactly two binary levels. Single-threaded and deterministic: chunks are
// built in parallel by the package builder, one chunk per thread.
#include "vastray/core/Bvh4.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>

namespace vastray {
namespace {

// Below this binary depth splits are at the object median: a node of n triangles then has at
// most log2(n / maxLeafSize) + 1 more levels, so the binary depth stays under 22 + 26 and the
// 4-wide depth (half of it, since collapsing takes two levels per node) under kBvh4MaxDepth.
constexpr uint32_t kSahDepth = 22;
static_assert((kSahDepth + 26) / 2 <= kBvh4MaxDepth);

struct BinaryNode {
    Aabb box;
    uint32_t left = 0, right = 0;  // children (interior)
    uint32_t begin = 0, count = 0; // triangle range in the order (leaf)
    bool leaf = false;
};

struct Bin {
    Aabb box;
    uint32_t count = 0;
};

class BinaryBuilder {
public:
    BinaryBuilder(const Vec3f* positions, const uint32_t* indices, uint32_t triangles, const Bvh4BuildOptions& o)
        : options_(o), boxes_(triangles), centroids_(triangles), order_(triangles) {
        options_.maxLeafSize = std::clamp<uint32_t>(options_.maxLeafSize, 1, kBvh4MaxLeafTriangles);
        options_.bins = std::clamp<uint32_t>(options_.bins, 4, 64);
        for (uint32_t t = 0; t < triangles; ++t) {
            Aabb b;
            for (int k = 0; k < 3; ++k) b.extend(positions[indices[3 * size_t(t) + k]]);
            boxes_[t] = b;
            centroids_[t] = (b.lo + b.hi) * 0.5f;
            order_[t] = t;
        }
    }

    void build() {
        nodes_.reserve(order_.size() / 2 + 1);
        buildNode(0, uint32_t(order_.size()), 0);
    }

    const std::vector<BinaryNode>& nodes() const { return nodes_; }
    std::vector<uint32_t>& order() { return order_; }

private:
    uint32_t buildNode(uint32_t begin, uint32_t end, uint32_t depth) {
        const uint32_t index = uint32_t(nodes_.size());
        nodes_.emplace_back();
        Aabb box, centroidBox;
        for (uint32_t i = begin; i < end; ++i) {
            box.extend(boxes_[order_[i]]);
            centroidBox.extend(centroids_[order_[i]]);
        }
        const uint32_t mid = split(begin, end, depth, box, centroidBox);
        if (mid == begin) {
            nodes_[index].box = box, nodes_[index].begin = begin, nodes_[index].count = end - begin;
            nodes_[index].leaf = true;
            return index;
        }
        const uint32_t left = buildNode(begin, mid, depth + 1);
        const uint32_t right = buildNode(mid, end, depth + 1);
        nodes_[index].box = box, nodes_[index].left = left, nodes_[index].right = right;
        return index;
    }

    // Where [begin, end) is split (the order is partitioned there), or begin for a leaf.
    uint32_t split(uint32_t begin, uint32_t end, uint32_t depth, const Aabb& box, const Aabb& centroidBox) {
        const uint32_t n = end - begin;
        if (n <= 1) return begin;
        const Vec3f extent = centroidBox.extent();
        const bool centroidsApart = extent.x > 0 || extent.y > 0 || extent.z > 0;
        if (depth < kSahDepth && centroidsApart) {
            int axis = -1;
            uint32_t bin = 0;
            const double cost = bestSahSplit(begin, end, box, centroidBox, axis, bin);
            if (n <= options_.maxLeafSize && options_.intersectionCost * double(n) <= cost) return begin;
            if (axis >= 0) {
                const uint32_t mid = partitionAtBin(begin, end, centroidBox, axis, bin);
                if (mid != begin && mid != end) return mid;
            }
        } else if (n <= options_.maxLeafSize || (!centroidsApart && n <= kBvh4MaxLeafTriangles)) {
            return begin;
        }
        return medianSplit(begin, end, centroidsApart ? centroidBox.longestAxis() : 0);
    }

    double binScale(const Aabb& centroidBox, int axis) const {
        return double(options_.bins) / (double(centroidBox.hi[axis]) - double(centroidBox.lo[axis]));
    }
    uint32_t binOf(float c, const Aabb& centroidBox, int axis, double scale) const {
        const double b = (double(c) - double(centroidBox.lo[axis])) * scale;
        return std::min(options_.bins - 1, uint32_t(std::max(0.0, b)));
    }

    // The cheapest split over all axes and bin boundaries; axis stays -1 when none exists.
    double bestSahSplit(uint32_t begin, uint32_t end, const Aabb& box, const Aabb& centroidBox, int& axis,
                        uint32_t& bin) const {
        const double area = box.surfaceArea();
        const double inverseArea = area > 0 ? 1.0 / area : 1.0;
        double best = std::numeric_limits<double>::infinity();
        const uint32_t bins = options_.bins;
        for (int a = 0; a < 3; ++a) {
            if (!(centroidBox.hi[a] > centroidBox.lo[a])) continue;
            std::array<Bin, 64> b{};
            const double scale = binScale(centroidBox, a);
            for (uint32_t i = begin; i < end; ++i) {
                Bin& target = b[binOf(centroids_[order_[i]][a], centroidBox, a, scale)];
                target.box.extend(boxes_[order_[i]]);
                ++target.count;
            }
            std::array<double, 64> rightCost{};
            Aabb right;
            uint32_t rightCount = 0;
            for (uint32_t k = bins - 1; k > 0; --k) {
                right.extend(b[k].box), rightCount += b[k].count;
                rightCost[k] = right.surfaceArea() * rightCount;
            }
            Aabb left;
            uint32_t leftCount = 0;
            for (uint32_t k = 0; k + 1 < bins; ++k) {
                left.extend(b[k].box), leftCount += b[k].count;
                if (leftCount == 0 || leftCount == end - begin) continue;
                const double c = options_.traversalCost +
                                 options_.intersectionCost * (left.surfaceArea() * leftCount + rightCost[k + 1]) * inverseArea;
                if (c < best) best = c, axis = a, bin = k;
            }
        }
        return best;
    }

    uint32_t partitionAtBin(uint32_t begin, uint32_t end, const Aabb& centroidBox, int axis, uint32_t bin) {
        const double scale = binScale(centroidBox, axis);
        auto it = std::partition(order_.begin() + begin, order_.begin() + end, [&](uint32_t t) {
            return binOf(centroids_[t][axis], centroidBox, axis, scale) <= bin;
        });
        return uint32_t(it - order_.begin());
    }

    // Halves the range by centroid along `axis`, ties broken by triangle index (deterministic).
    uint32_t medianSplit(uint32_t begin, uint32_t end, int axis) {
        const uint32_t mid = begin + (end - begin) / 2;
        std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                         [&](uint32_t a, uint32_t b) {
                             const float ca = centroids_[a][axis], cb = centroids_[b][axis];
                             return ca < cb || (ca == cb && a < b);
                         });
        return mid;
    }

    Bvh4BuildOptions options_;
    std::vector<Aabb> boxes_;
    std::vector<Vec3f> centroids_;
    std::vector<uint32_t> order_;
    std::vector<BinaryNode> nodes_;
};

// Smallest e in [-126, 127] with 255 * 2^e >= extent.
int quantizationExponent(double extent) {
    if (!(extent > 0)) return -126;
    int e = std::clamp(int(std::ceil(std::log2(extent / 255.0))), -126, 127);
    while (e < 127 && std::ldexp(255.0, e) < extent) ++e;
    while (e > -126 && std::ldexp(255.0, e - 1) >= extent) --e;
    return e;
}

void quantize(Bvh4Node& node, const Aabb& box, const std::array<Aabb, 4>& children, int count) {
    node.exponents = 0;
    for (int a = 0; a < 3; ++a) {
        const double lo = box.lo[a];
        const int e = quantizationExponent(double(box.hi[a]) - lo);
        node.origin[a] = box.lo[a];
        node.exponents |= uint32_t(e + 127) << (8 * a);
        node.qlo[a] = node.qhi[a] = 0;
        for (int i = 0; i < 4; ++i) {
            uint32_t qlo = 255, qhi = 0;  // an empty slot's box is inverted
            if (i < count) {
                qlo = uint32_t(std::clamp(std::floor(std::ldexp(double(children[i].lo[a]) - lo, -e)), 0.0, 255.0));
                qhi = uint32_t(std::clamp(std::ceil(std::ldexp(double(children[i].hi[a]) - lo, -e)), 0.0, 255.0));
            }
            node.qlo[a] |= qlo << (8 * i);
            node.qhi[a] |= qhi << (8 * i);
        }
    }
}

class Collapser {
public:
    Collapser(const std::vector<BinaryNode>& binary, bool greedy, Bvh4& out)
        : binary_(binary), greedy_(greedy), out_(out) {}

    // Emits the 4-wide node for binary node b (and its subtree); returns its index.
    uint32_t emit(uint32_t b, uint32_t depth) {
        if (depth > kBvh4MaxDepth) {  // the greedy pass went too deep: buildBvh4 starts again
            tooDeep_ = true;
            return kBvh4EmptyChild;
        }
        out_.maxDepth = std::max(out_.maxDepth, depth);
        std::array<uint32_t, 4> picked{};
        int count = 0;
        const BinaryNode& node = binary_[b];
        if (node.leaf) {
            picked[count++] = b;  // a root that is a leaf: one child
        } else if (greedy_) {
            // Open the interior child of largest area until there are four (fuller nodes).
            picked[count++] = node.left, picked[count++] = node.right;
            while (count < 4) {
                int open = -1;
                for (int i = 0; i < count; ++i)
                    if (!binary_[picked[i]].leaf &&
                        (open < 0 || binary_[picked[i]].box.surfaceArea() > binary_[picked[open]].box.surfaceArea()))
                        open = i;
                if (open < 0) break;
                const BinaryNode& c = binary_[picked[open]];
                picked[open] = c.left;
                for (int i = count; i > open + 1; --i) picked[i] = picked[i - 1];
                picked[open + 1] = c.right, ++count;
            }
        } else {
            // Two binary levels per node: the 4-wide depth is half the binary one.
            for (uint32_t c : {node.left, node.right}) {
                if (binary_[c].leaf) {
                    picked[count++] = c;
                } else {
                    picked[count++] = binary_[c].left;
                    picked[count++] = binary_[c].right;
                }
            }
        }
        const uint32_t index = uint32_t(out_.nodes.size());
        out_.nodes.emplace_back();
        std::array<Aabb, 4> boxes;
        std::array<uint32_t, 4> words;
        words.fill(kBvh4EmptyChild);
        for (int i = 0; i < count; ++i) {
            const BinaryNode& c = binary_[picked[i]];
            boxes[i] = c.box;
            words[i] = c.leaf ? bvh4LeafWord(c.begin, c.count) : emit(picked[i], depth + 1);
        }
        Bvh4Node& n = out_.nodes[index];
        quantize(n, node.box, boxes, count);
        for (int i = 0; i < 4; ++i) n.child[i] = words[i];
        return index;
    }

    bool tooDeep() const { return tooDeep_; }

private:
    const std::vector<BinaryNode>& binary_;
    bool greedy_;
    bool tooDeep_ = false;
    Bvh4& out_;
};

}  // namespace

Bvh4 buildBvh4(const Vec3f* positions, const uint32_t* indices, uint32_t triangleCount,
               const Bvh4BuildOptions& options) {
    assert(triangleCount <= kBvh4MaxTriangles);
    Bvh4 tree;
    if (triangleCount == 0) return tree;
    BinaryBuilder builder(positions, indices, triangleCount, options);
    builder.build();
    tree.bounds = builder.nodes().front().box;
    tree.nodes.reserve(builder.nodes().size() / 3 + 1);
    Collapser greedy(builder.nodes(), true, tree);
    greedy.emit(0, 0);
    if (greedy.tooDeep()) {  // rare (very unbalanced trees): two levels per node
        tree.nodes.clear(), tree.maxDepth = 0;
        Collapser(builder.nodes(), false, tree).emit(0, 0);
    }
    tree.order = std::move(builder.order());
    return tree;
}

Aabb bvh4ChildBox(const Bvh4Node& node, int i) {
    Aabb box;
    for (int a = 0; a < 3; ++a) {
        const float scale = std::ldexp(1.0f, int((node.exponents >> (8 * a)) & 255u) - 127);
        const float qlo = float((node.qlo[a] >> (8 * i)) & 255u), qhi = float((node.qhi[a] >> (8 * i)) & 255u);
        box.lo[a] = node.origin[a] + qlo * scale;
        box.hi[a] = node.origin[a] + qhi * scale;
    }
    return box;
}

std::string validateBvh4Nodes(const std::vector<Bvh4Node>& nodes, uint32_t triangleCount) {
    std::vector<uint8_t> depth(nodes.size(), 0);
    for (size_t i = 0; i < nodes.size(); ++i) {
        const Bvh4Node& n = nodes[i];
        const std::string where = "BVH node " + std::to_string(i) + ": ";
        for (int a = 0; a < 3; ++a) {
            const uint32_t e = (n.exponents >> (8 * a)) & 255u;
            if (e < 1 || e > 254) return where + "exponent byte " + std::to_string(e) + " outside [1, 254]";
            if (!std::isfinite(n.origin[a])) return where + "origin is not finite";
        }
        if ((n.exponents >> 24) != 0) return where + "unused exponent bits set";
        for (uint32_t w : n.child) {
            if (w == kBvh4EmptyChild) continue;
            if (bvh4IsLeaf(w)) {
                if (uint64_t(bvh4LeafFirst(w)) + bvh4LeafCount(w) > triangleCount)
                    return where + "leaf triangles past the chunk's " + std::to_string(triangleCount);
                continue;
            }
            if (w <= i || w >= nodes.size())
                return where + "child " + std::to_string(w) + " is not a later node of the " +
                       std::to_string(nodes.size());
            if (depth[i] + 1u > kBvh4MaxDepth)
                return where + "deeper than the limit of " + std::to_string(kBvh4MaxDepth) + " levels";
            depth[w] = uint8_t(std::max<uint32_t>(depth[w], depth[i] + 1u));
        }
    }
    return {};
}

}  // namespace vastray
