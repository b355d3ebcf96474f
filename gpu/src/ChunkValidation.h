#pragma once
// Checks that a chunk's arrays reference only what they hold, before they reach the device:
// an out-of-range index or reference would make a kernel read outside its buffers.
#include <cstdint>
#include <span>

#include "vastray/core/Bvh4.h"
#include "vastray/core/KdTree.h"
#include "vastray/core/Result.h"

namespace vastray::gpu {

// Index count a multiple of 3, every index < vertexCount, every leaf reference < the triangle
// count, every node inside the tree (children after their parent) and no deeper than the
// kernels' stack (kMaxKdDepth).
Status validateChunkGeometry(const KdTree& tree, uint64_t vertexCount, std::span<const uint32_t> indices);
// The same for a BVH chunk (validateBvh4Nodes: nodes, leaves, depth <= kBvh4MaxDepth).
Status validateChunkGeometry(const Bvh4& tree, uint64_t vertexCount, std::span<const uint32_t> indices);

}  // namespace vastray::gpu
