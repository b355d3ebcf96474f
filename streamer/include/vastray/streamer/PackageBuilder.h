#pragma once
// Turns an imported mesh into a scene package: quantize on one grid, partition with a
// top-level KD-tree until every chunk fits the chunk size, encode each chunk (Draco or meshopt), decode
// it again and build its KD-tree on the decoder's output, write the .vast atomically.
#include <cstdint>
#include <string>
#include <vector>

#include "vastray/core/Mesh.h"
#include "vastray/core/Progress.h"
#include "vastray/core/Result.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {

struct PackageBuildOptions {
    uint64_t chunkSizeBytes = 16ull << 20;  // resident footprint limit of one chunk
    uint32_t quantizeBits = 20;             // grid precision over the scene extent; 0 = lossless
    uint32_t threads = 0;                   // 0 = all cores
    GeometryCodec codec = GeometryCodec::Draco;  // chunk geometry codec
    int dracoSpeed = 7;                     // Draco's 0 (smallest, slowest) … 10 (fastest, largest); 7: the
                                            // bytes of 5, faster (docs/PERF_NOTES.md, import item 8)
    // Cap on a chunk's device footprint per triangle (BVH nodes, positions, indices): a chunk
    // over it gets its BVH rebuilt with larger leaves (up to 16 triangles; ChunkBuilder.cpp's
    // ladder), and keeps the last if none fits. Hits are unchanged; rays test more triangles.
    // 0: no cap (leaves of about 2 triangles). Default 32 bytes per triangle.
    double residentBytesPerTriangle = 32;
    // The most emissive triangles stored for next-event estimation (core/Emitters.h); a scene with
    // more stores none (warned). At most kMaxEmitters, what a reader accepts.
    uint32_t maxEmitters = kMaxEmitters;
    bool defaultDoubleSided = true;         // recorded in the header for tools
    Progress::Mode progress = Progress::Mode::Auto;
    Progress::Observer observer;            // told the triangles placed, from worker threads
    uint64_t degenerateDropped = 0;         // from the importer's report, recorded in the header
    std::vector<Volume> volumes;            // density grids stored beside the mesh (VolumeImport.h)
};

// Smallest chunk size accepted: below it the per-chunk overheads dominate.
constexpr uint64_t kMinChunkSizeBytes = 16ull << 10;
constexpr uint32_t kMaxQuantizeBits = 30;

struct PackageBuildReport {
    uint64_t triangles = 0;          // in the package
    uint64_t collapsedDropped = 0;   // triangles quantization reduced to zero area
    uint64_t references = 0;
    uint32_t chunks = 0;
    uint32_t emptyCells = 0;
    uint64_t fileBytes = 0;
    uint64_t maxChunkResidentBytes = 0;
    // The textures stored (decoded, mip-mapped and paged during the write): how many, their
    // pages and the pages' compressed bytes.
    uint32_t textures = 0;
    uint64_t texturePages = 0, textureBytes = 0;
    // The emissive triangles stored for next-event estimation (core/Emitters.h), and those left
    // out because there were more than kMaxEmitters (all of them then: they are hit by chance only).
    uint64_t emitters = 0, emittersLeftOut = 0;
    // What the build left out that the renders would have used (each says what and why).
    std::vector<std::string> warnings;
    double quantizeSeconds = 0, partitionSeconds = 0, encodeSeconds = 0, decodeSeconds = 0,
           bvhBuildSeconds = 0, writeSeconds = 0, totalSeconds = 0;
};

// A texture source (an importer's encoded image) decoded and made into the pages the package
// stores (docs/PACKAGE_FORMAT.md, "Textures"): what import writes, and what the Embree reference
// samples when it renders a file without a package. Errors name the image.
Result<DecodedTexture> decodeTexture(const TextureSource& source);

// `mesh` is consumed (positions are replaced by their quantized values).
Result<PackageBuildReport> buildPackage(TriangleMesh mesh, const std::string& outPath,
                                        const PackageBuildOptions& options);

}  // namespace vastray
