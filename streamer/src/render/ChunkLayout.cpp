// Where each array of a chunk lies in a device slot (vastray::ChunkLayout): what planPool sizes
// slots with and what the Vulkan backend uploads into them.
#include <algorithm>

#include "vastray/core/Bvh4.h"
#include "vastray/streamer/StreamingRenderer.h"

namespace vastray {
namespace {
uint64_t align16(uint64_t bytes) { return (bytes + 15) / 16 * 16; }
}  // namespace

ChunkLayout chunkLayout(uint64_t bvhNodes, uint64_t vertices, uint64_t triangles, bool indexDeltas16,
                        uint64_t longTriangles, const ChunkAttributes& attributes) {
    ChunkLayout l;
    uint64_t at = 0;
    auto section = [&](uint64_t bytes) {
        const uint64_t offset = at;
        at += align16(bytes);
        return offset;
    };
    l.nodes = section(bvhNodes * sizeof(Bvh4Node));
    l.positions = section(devicePositionBytes(vertices, attributes.packedPositions));
    l.indices = section(deviceIndexBytes(triangles, indexDeltas16, longTriangles));
    l.singleSided = section(attributes.singleSided ? (triangles + 3) / 4 * 4 : 0);
    l.primitiveIds = section(attributes.primitiveIds ? triangles * 4 : 0);
    l.materialIds = section(attributes.materialIds ? triangles * 4 : 0);
    l.normals = section(attributes.normals ? vertices * 4 : 0);
    l.colors = section(attributes.colors ? vertices * 4 : 0);
    l.uvs = section(attributes.uvs ? vertices * 8 : 0);
    l.totalBytes = std::max<uint64_t>(at, 16);
    return l;
}

}  // namespace vastray
