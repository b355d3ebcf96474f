#include "vastray/streamer/PackageBuilder.h"

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>

#include "package/ChunkBuilder.h"
#include "package/Partitioner.h"
#include "package/PackageWriter.h"
#include "vastray/core/ImageFile.h"
#include "vastray/core/ByteSize.h"

namespace vastray {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// A cell deeper than this in the top-level tree means splitting is not converging.
constexpr int kMaxTopDepth = 48;
// A split whose larger side keeps more than this share of the references does not converge.
constexpr double kMaxChildFraction = 0.95;
// First guess of the chunk BVH's bytes per triangle (nodes); a cell whose real footprint turns
// out larger than the chunk size is split again, so this only saves work.
constexpr double kEstimatedBvhBytesPerTriangle = 12.0;

struct BuildNode {
    Aabb cell;
    std::optional<SplitPlane> plane;  // set for interior nodes
    std::unique_ptr<BuildNode> below, above;
    std::optional<BuiltChunk> chunk;  // set for leaves with triangles
    Status status;
};

struct AtomicSeconds {
    std::atomic<uint64_t> nanos{0};
    void add(double seconds) { nanos += uint64_t(seconds * 1e9); }
    double seconds() const { return double(nanos.load()) * 1e-9; }
};

class PackageBuildJob {
public:
    PackageBuildJob(const ChunkSource& source, const PackageBuildOptions& options, double verticesPerTriangle,
                    uint64_t triangles)
        : source_(source),
          options_(options),
          partitioner_(source.positions, source.indices),
          verticesPerTriangle_(verticesPerTriangle),
          progress_("import", triangles, options.progress, options.observer) {}

    std::unique_ptr<BuildNode> run(const std::vector<uint32_t>& triangles, const Aabb& bounds) {
        auto root = std::make_unique<BuildNode>();
        root->cell = bounds;
        processCell(*root, partitioner_.initialRefs(triangles, bounds), 0);
        progress_.finish();
        return root;
    }

    AtomicSeconds encode, decode, bvhBuild, partition;

private:
    uint64_t estimateBytes(size_t refs) const {
        const double perTriangle = std::min(3.0, verticesPerTriangle_ * 1.1 + 0.05) * 12.0 + 16.0 +
                                   (source_.materialIds ? 4.0 : 0.0) + kEstimatedBvhBytesPerTriangle +
                                   std::min(3.0, verticesPerTriangle_ * 1.1 + 0.05) * 4.0 *
                                       double(int(source_.normals != nullptr) + int(source_.colors != nullptr) +
                                              2 * int(source_.uvs != nullptr));
        return uint64_t(double(refs) * perTriangle);
    }

    // Triangles whose centroid lies in the cell (half-open box): counts each triangle about
    // once for progress although straddling ones are referenced by several cells.
    uint64_t ownedTriangles(const std::vector<TriangleRef>& refs, const Aabb& cell) const {
        uint64_t owned = 0;
        for (const TriangleRef& ref : refs) {
            const uint32_t* i = &source_.indices[3 * size_t(ref.triangle)];
            const Vec3f c = (source_.positions[i[0]] + source_.positions[i[1]] + source_.positions[i[2]]) * (1.0f / 3);
            bool inside = true;
            for (int axis = 0; axis < 3; ++axis) inside &= c[axis] >= cell.lo[axis] && c[axis] < cell.hi[axis];
            owned += inside;
        }
        return owned;
    }

    // Tries the cell as one chunk; true when it fits (node becomes a leaf) or failed (status set).
    bool tryLeaf(BuildNode& node, const std::vector<TriangleRef>& refs) {
        auto chunk = buildChunk(source_, refs, node.cell);
        if (!chunk) {
            node.status = chunk.status();
            return true;
        }
        encode.add(chunk->encodeSeconds);
        decode.add(chunk->decodeSeconds);
        bvhBuild.add(chunk->bvhBuildSeconds);
        if (chunk->info.residentBytes > options_.chunkSizeBytes) return false;
        node.chunk = std::move(*chunk);
        progress_.advance(ownedTriangles(refs, node.cell));
        return true;
    }

    Status cannotSplit(size_t triangles) const {
        return Status::error("a cell of " + std::to_string(triangles) +
                             " triangles cannot be split to fit the chunk size of " +
                             formatBytes(options_.chunkSizeBytes) +
                             " (too many triangles overlap one place); use a larger --chunk-size");
    }

    void processCell(BuildNode& node, std::vector<TriangleRef> refs, int depth) {
        if (refs.empty()) return;
        const bool triedLeaf = estimateBytes(refs.size()) <= options_.chunkSizeBytes;
        if (triedLeaf && tryLeaf(node, refs)) return;
        auto start = Clock::now();
        const std::optional<SplitPlane> plane = depth < kMaxTopDepth ? partitioner_.findSplit(refs, node.cell)
                                                                     : std::nullopt;
        if (!plane) {
            if (!triedLeaf && tryLeaf(node, refs)) return;
            node.status = cannotSplit(refs.size());
            return;
        }
        const size_t count = refs.size();
        std::vector<TriangleRef> below, above;
        partitioner_.split(refs, node.cell, *plane, below, above);
        partition.add(secondsSince(start));
        if (double(std::max(below.size(), above.size())) > kMaxChildFraction * double(count)) {
            node.status = cannotSplit(count);
            return;
        }
        node.plane = plane;
        node.below = std::make_unique<BuildNode>();
        node.above = std::make_unique<BuildNode>();
        node.below->cell = Partitioner::childBox(node.cell, *plane, false);
        node.above->cell = Partitioner::childBox(node.cell, *plane, true);
        tbb::task_group group;
        group.run([&] { processCell(*node.below, std::move(below), depth + 1); });  // `below` outlives wait()
        processCell(*node.above, std::move(above), depth + 1);
        group.wait();
    }

    const ChunkSource& source_;
    const PackageBuildOptions& options_;
    Partitioner partitioner_;
    double verticesPerTriangle_;
    Progress progress_;
};

// Depth-first: top-level nodes (below child next, above child later) and chunks in leaf order.
struct Flattened {
    std::vector<KdNode> nodes;
    std::vector<ChunkInfo> chunks;
    std::vector<std::vector<uint8_t>> blobs;
    Status status;
};

void flatten(BuildNode& node, Flattened& out) {
    if (!node.status.isOk() && out.status.isOk()) out.status = node.status;
    const size_t index = out.nodes.size();
    out.nodes.push_back({});
    if (!node.plane) {
        uint32_t chunkId = kEmptyCell;
        if (node.chunk) {
            chunkId = uint32_t(out.chunks.size());
            node.chunk->info.id = chunkId;
            out.chunks.push_back(node.chunk->info);
            out.blobs.push_back(std::move(node.chunk->blob));
            node.chunk.reset();
        }
        out.nodes[index] = KdNode::leaf(chunkId, chunkId != kEmptyCell ? 1 : 0);
        return;
    }
    flatten(*node.below, out);
    const uint32_t above = uint32_t(out.nodes.size());
    flatten(*node.above, out);
    out.nodes[index] = KdNode::interior(node.plane->axis, node.plane->position, above);
}

struct QuantizedScene {
    std::vector<int32_t> words;       // 3 per vertex
    std::vector<uint32_t> triangles;  // kept triangle ids
    uint64_t collapsed = 0;
    Aabb bounds;
};

bool isDegenerate(Vec3f a, Vec3f b, Vec3f c) {
    if (a == b || b == c || a == c) return true;
    const double ux = double(b.x) - a.x, uy = double(b.y) - a.y, uz = double(b.z) - a.z;
    const double vx = double(c.x) - a.x, vy = double(c.y) - a.y, vz = double(c.z) - a.z;
    return uy * vz - uz * vy == 0 && uz * vx - ux * vz == 0 && ux * vy - uy * vx == 0;
}

// Snaps every vertex to the scene grid (positions become what the renderer will see) and
// drops the triangles that the snapping collapsed.
QuantizedScene quantizeScene(TriangleMesh& mesh, const QuantizationGrid& grid) {
    QuantizedScene scene;
    scene.words.resize(mesh.positions.size() * 3);
    tbb::parallel_for(size_t(0), mesh.positions.size(), [&](size_t v) {
        int32_t* w = &scene.words[3 * v];
        for (int axis = 0; axis < 3; ++axis)
            w[axis] = grid.bits == 0 ? std::bit_cast<int32_t>(mesh.positions[v][axis])
                                     : grid.quantize(mesh.positions[v][axis], axis);
        mesh.positions[v] = grid.position(w);
    });
    const uint64_t n = mesh.triangleCount();
    scene.triangles.reserve(n);
    for (uint64_t t = 0; t < n; ++t) {
        const uint32_t* i = &mesh.indices[3 * t];
        const Vec3f a = mesh.positions[i[0]], b = mesh.positions[i[1]], c = mesh.positions[i[2]];
        if (isDegenerate(a, b, c)) {
            scene.collapsed++;
            continue;
        }
        scene.triangles.push_back(uint32_t(t));
        scene.bounds.extend(a);
        scene.bounds.extend(b);
        scene.bounds.extend(c);
    }
    return scene;
}

Status validateOptions(const PackageBuildOptions& options, const TriangleMesh& mesh) {
    if (options.chunkSizeBytes < kMinChunkSizeBytes)
        return Status::error("chunk size " + formatBytes(options.chunkSizeBytes) + " is below the minimum of " +
                             formatBytes(kMinChunkSizeBytes));
    if (options.quantizeBits > kMaxQuantizeBits)
        return Status::error("--quantize-bits " + std::to_string(options.quantizeBits) + " is above the maximum of " +
                             std::to_string(kMaxQuantizeBits) + " (0 = lossless)");
    if (!(options.residentBytesPerTriangle >= 0) || options.residentBytesPerTriangle > 1e6)
        return Status::error("resident bytes per triangle must be 0 (no cap) or a positive number");
    if (options.dracoSpeed < 0 || options.dracoSpeed > 10)
        return Status::error("Draco speed " + std::to_string(options.dracoSpeed) + " is outside 0..10");
    if (mesh.triangleCount() == 0) return Status::error("the mesh has no triangles");
    if (mesh.triangleCount() >= kEmptyCell) return Status::error("more than 2^32-1 triangles");
    if (mesh.materials.empty()) return Status::error("the mesh has no material");
    if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
        return Status::error("the mesh has " + std::to_string(mesh.normals.size()) + " normals for " +
                             std::to_string(mesh.positions.size()) + " vertices");
    if (!mesh.colors.empty() && mesh.colors.size() != mesh.positions.size())
        return Status::error("the mesh has " + std::to_string(mesh.colors.size()) + " colours for " +
                             std::to_string(mesh.positions.size()) + " vertices");
    if (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size())
        return Status::error("the mesh has " + std::to_string(mesh.uvs.size()) + " texture coordinates for " +
                             std::to_string(mesh.positions.size()) + " vertices");
    return Status::ok();
}

}  // namespace

Result<DecodedTexture> decodeTexture(const TextureSource& source) {
    auto image = decodeRgba8Image(source.name, source.extension, source.bytes, uint64_t(kMaxTextureSide) * kMaxTextureSide);
    if (!image) return image.status();
    auto pyramid = buildTexturePyramid(*image, source.wrapS, source.wrapT, source.encoding);
    if (!pyramid) return pyramid.status().withContext(source.name + ": ");
    return pyramid;
}

Result<PackageBuildReport> buildPackage(TriangleMesh mesh, const std::string& outPath,
                                        const PackageBuildOptions& options) {
    VASTRAY_TRY(validateOptions(options, mesh));
    const auto totalStart = Clock::now();
    std::optional<tbb::global_control> threadLimit;
    if (options.threads > 0) threadLimit.emplace(tbb::global_control::max_allowed_parallelism, options.threads);
    PackageBuildReport report;

    auto start = Clock::now();
    const QuantizationGrid grid = QuantizationGrid::forBounds(mesh.bounds(), options.quantizeBits);
    QuantizedScene scene = quantizeScene(mesh, grid);
    report.quantizeSeconds = secondsSince(start);
    report.collapsedDropped = scene.collapsed;
    if (scene.triangles.empty())
        return Status::error("every triangle collapsed at " + std::to_string(options.quantizeBits) +
                             " quantization bits; use more bits");

    ChunkSource source{mesh.positions.data(), scene.words.data(), mesh.indices.data(),
                       mesh.materials.size() > 1 && !mesh.materialIds.empty() ? mesh.materialIds.data() : nullptr,
                       &grid, options.dracoSpeed, options.codec, options.residentBytesPerTriangle,
                       mesh.normals.empty() ? nullptr : mesh.normals.data(),
                       mesh.colors.empty() ? nullptr : mesh.colors.data(),
                       mesh.uvs.empty() ? nullptr : mesh.uvs.data()};
    PackageBuildJob job(source, options, double(mesh.positions.size()) / double(mesh.triangleCount()),
                        scene.triangles.size());
    std::unique_ptr<BuildNode> root = job.run(scene.triangles, scene.bounds);
    Flattened flat;
    flatten(*root, flat);
    root.reset();
    if (!flat.status.isOk()) return flat.status;

    PackageInfo info;
    info.triangleCount = scene.triangles.size();
    info.chunkSizeBytes = options.chunkSizeBytes;
    info.degenerateDropped = options.degenerateDropped;
    info.collapsedDropped = scene.collapsed;
    info.defaultDoubleSided = options.defaultDoubleSided;
    info.codec = options.codec;
    info.hasNormals = !mesh.normals.empty();
    info.hasColors = !mesh.colors.empty();
    info.hasUvs = !mesh.uvs.empty();
    info.bounds = scene.bounds;
    info.grid = grid;
    info.materials = mesh.materials;
    info.cameras = mesh.cameras;
    info.lights = mesh.lights;
    // The emissive triangles next-event estimation samples, at the positions quantization left.
    info.emitters = collectEmitters(mesh, mesh.textures.size(), scene.triangles);
    if (info.emitters.size() > std::min(options.maxEmitters, kMaxEmitters)) {
        report.emittersLeftOut = info.emitters.size();
        report.warnings.push_back(std::to_string(info.emitters.size()) + " emissive triangles are more than the " +
                                  std::to_string(std::min(options.maxEmitters, kMaxEmitters)) +
                                  " next-event estimation samples: none is sampled, they light the scene only where "
                                  "paths hit them (right, but slower to converge)");
        info.emitters.clear();
    }
    report.emitters = info.emitters.size();
    for (const Volume& volume : options.volumes) info.volumes.push_back({volume});
    info.topTree = std::move(flat.nodes);
    info.chunks = std::move(flat.chunks);
    for (const ChunkInfo& chunk : info.chunks) {
        info.referenceCount += chunk.triangleCount;
        info.maxChunkResidentBytes = std::max(info.maxChunkResidentBytes, chunk.residentBytes);
    }
    start = Clock::now();
    // Each texture is decoded and made into pages when the writer comes to it: one at a time.
    std::vector<TextureInput> textures;
    for (const TextureSource& source : mesh.textures)
        textures.push_back({source.name, [&source] { return decodeTexture(source); }});
    VASTRAY_TRY(writePackage(outPath, info, flat.blobs, textures));
    report.writeSeconds = secondsSince(start);

    report.triangles = info.triangleCount;
    report.references = info.referenceCount;
    report.chunks = uint32_t(info.chunks.size());
    for (const KdNode& node : info.topTree) report.emptyCells += node.isLeaf() && node.firstRef() == kEmptyCell;
    report.fileBytes = info.fileBytes;
    report.textures = uint32_t(info.textures.size());
    report.texturePages = info.texturePages.size();
    report.textureBytes = info.textureDataBytes;
    report.maxChunkResidentBytes = info.maxChunkResidentBytes;
    report.partitionSeconds = job.partition.seconds();
    report.encodeSeconds = job.encode.seconds();
    report.decodeSeconds = job.decode.seconds();
    report.bvhBuildSeconds = job.bvhBuild.seconds();
    report.totalSeconds = secondsSince(totalStart);
    return report;
}

}  // namespace vastray
