#include <algorithm>

#include "vastray/core/KdTree.h"

namespace vastray {
namespace {

class Truncator {
public:
    Truncator(const KdTree& tree, uint32_t maxDepth) : in_(tree), maxDepth_(maxDepth) {}

    KdTree run() {
        out_.bounds = in_.bounds;
        if (!in_.nodes.empty()) emit(0, 0);
        return std::move(out_);
    }

private:
    // Copies the subtree at `index` (at `depth`) into out_, below child right after its parent.
    // Recursion depth is bounded by the tree's (<= kMaxKdDepth).
    void emit(uint32_t index, uint32_t depth) {
        const KdNode node = in_.nodes[index];
        out_.maxDepth = std::max(out_.maxDepth, depth);
        if (node.isLeaf() || depth >= maxDepth_) {
            gathered_.clear();
            gather(index);
            if (!node.isLeaf()) {
                std::sort(gathered_.begin(), gathered_.end());
                gathered_.erase(std::unique(gathered_.begin(), gathered_.end()), gathered_.end());
            }
            out_.nodes.push_back(KdNode::leaf(uint32_t(out_.leafRefs.size()), uint32_t(gathered_.size())));
            out_.leafRefs.insert(out_.leafRefs.end(), gathered_.begin(), gathered_.end());
            return;
        }
        const size_t at = out_.nodes.size();
        out_.nodes.push_back(node);
        emit(index + 1, depth + 1);
        out_.nodes[at] = KdNode::interior(node.axis(), node.split(), uint32_t(out_.nodes.size()));
        emit(node.aboveChild(), depth + 1);
    }

    // The references of every leaf of the subtree at `index`, in tree order.
    void gather(uint32_t index) {
        const KdNode node = in_.nodes[index];
        if (node.isLeaf()) {
            const uint32_t* refs = in_.leafRefs.data() + node.firstRef();
            gathered_.insert(gathered_.end(), refs, refs + node.primitiveCount());
            return;
        }
        gather(index + 1);
        gather(node.aboveChild());
    }

    const KdTree& in_;
    const uint32_t maxDepth_;
    KdTree out_;
    std::vector<uint32_t> gathered_;
};

}  // namespace

KdTree truncateKdTree(const KdTree& tree, uint32_t maxDepth) { return Truncator(tree, maxDepth).run(); }

}  // namespace vastray
