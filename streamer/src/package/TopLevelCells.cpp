#include <utility>

#include "vastray/streamer/ScenePackage.h"

namespace vastray {

std::vector<Cell> topLevelCells(const PackageInfo& info) {
    std::vector<Cell> cells;
    if (info.topTree.empty()) return cells;
    // Explicit stack, below child first, so cells come out in depth-first (chunk id) order.
    std::vector<std::pair<uint32_t, Aabb>> stack{{0u, info.bounds}};
    while (!stack.empty()) {
        auto [index, box] = stack.back();
        stack.pop_back();
        const KdNode& node = info.topTree[index];
        if (node.isLeaf()) {
            cells.push_back({box, node.firstRef()});
            continue;
        }
        Aabb below = box, above = box;
        below.hi[int(node.axis())] = node.split();
        above.lo[int(node.axis())] = node.split();
        stack.push_back({node.aboveChild(), above});
        stack.push_back({index + 1, below});
    }
    return cells;
}

}  // namespace vastray
