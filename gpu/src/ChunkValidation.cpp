#include "ChunkValidation.h"

#include <string>
#include <vector>

namespace vastray::gpu {

namespace {
Status validateIndices(uint64_t vertexCount, std::span<const uint32_t> indices) {
    if (indices.size() % 3 != 0) return Status::error("index count is not a multiple of 3");
    for (size_t i = 0; i < indices.size(); ++i)
        if (indices[i] >= vertexCount)
            return Status::error("index " + std::to_string(i) + " = " + std::to_string(indices[i]) +
                                 " exceeds the vertex count " + std::to_string(vertexCount));
    return Status::ok();
}
}  // namespace

Status validateChunkGeometry(const Bvh4& tree, uint64_t vertexCount, std::span<const uint32_t> indices) {
    VASTRAY_TRY(validateIndices(vertexCount, indices));
    if (indices.size() / 3 > kBvh4MaxTriangles) return Status::error("more triangles than a BVH chunk can hold");
    const std::string bad = validateBvh4Nodes(tree.nodes, uint32_t(indices.size() / 3));
    return bad.empty() ? Status::ok() : Status::error(bad);
}

Status validateChunkGeometry(const KdTree& t, uint64_t vertexCount, std::span<const uint32_t> indices) {
    VASTRAY_TRY(validateIndices(vertexCount, indices));
    const uint64_t triangles = indices.size() / 3;
    for (size_t i = 0; i < t.leafRefs.size(); ++i)
        if (t.leafRefs[i] >= triangles)
            return Status::error("KD-tree reference " + std::to_string(i) + " exceeds the triangle count");
    // Children lie after their parent (depth-first order), so one forward pass finds every
    // node's depth.
    std::vector<uint32_t> depth(t.nodes.size(), 0);
    for (size_t i = 0; i < t.nodes.size(); ++i) {
        const KdNode n = t.nodes[i];
        const bool bad = n.isLeaf() ? uint64_t(n.firstRef()) + n.primitiveCount() > t.leafRefs.size()
                                    : n.aboveChild() <= i || n.aboveChild() >= t.nodes.size() ||
                                          i + 1 >= t.nodes.size() || depth[i] >= kMaxKdDepth;
        if (bad) return Status::error("KD-tree node " + std::to_string(i) + " points outside the tree or is too deep");
        if (!n.isLeaf()) depth[i + 1] = depth[n.aboveChild()] = depth[i] + 1;
    }
    return Status::ok();
}

}  // namespace vastray::gpu
