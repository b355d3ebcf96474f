#pragma once
// The scene package (.vast): header, materials, top-level KD-tree over cells, chunk
// directory, chunk blobs. docs/PACKAGE_FORMAT.md gives the byte layout. A reader validates
// every field before use; every section and every chunk carries a 64-bit checksum.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "vastray/core/Aabb.h"
#include "vastray/core/Bvh4.h"
#include "vastray/core/KdTree.h"
#include "vastray/core/Emitters.h"
#include "vastray/core/Mesh.h"
#include "vastray/core/Result.h"
#include "vastray/core/Texture.h"
#include "vastray/core/Volume.h"
#include "vastray/core/VolumeLeaf.h"

namespace vastray {

// One scene-wide grid: a triangle referenced by several chunks decodes to the same
// coordinates in each. bits == 0 means lossless float positions.
struct QuantizationGrid {
    uint32_t bits = 20;
    double origin[3] = {0, 0, 0};
    double range = 1;  // the same step on every axis: range / (2^bits - 1)

    // The grid an import snaps a scene to: from 2026-12 (no format change) its step is a power
    // of two and its origin a float on the grid, so that a position can be rebuilt in fp32
    // exactly as dequantize() rounds it (packsPositions). Where that grid would leave the header's
    // limits (coordinates near +-1e18), the earlier grid: origin at the bounds, range = extent.
    static QuantizationGrid forBounds(const Aabb& bounds, uint32_t bits);
    double step() const;
    // Integer grid coordinate of one axis value (bits > 0).
    int32_t quantize(float value, int axis) const;
    float dequantize(int32_t q, int axis) const;
    // The position a chunk stores as three words: grid coordinates, or float bits if lossless.
    Vec3f position(const int32_t* words) const;

    // Whether the device may keep a vertex as packedPosition's 8 bytes instead of 3 floats: at
    // most 20 bits, a power-of-two step (a normal float), origins that are floats on the grid, and
    // the largest coordinate's float spacing at most 2^19 steps (a scene at least about twice as
    // large as the float spacing of its coordinates; the argument needs 2^20). Then every dequantized position p = float(o + q s) is o + m s for
    // an integer m in [0, 2^21) that packedPosition finds exactly, and fp32's o + float(m) * s
    // (a product that is exact, a sum rounded once) gives p again, bit for bit (docs/GEOMETRY.md).
    bool packsPositions() const;
    // A dequantized position's grid coordinates from the origin, 21 bits an axis: x in bits 0-20,
    // y in 21-41, z in 42-62 (with packsPositions).
    uint64_t packedPosition(const Vec3f& p) const;
    void packPositions(const Vec3f* positions, size_t count, uint64_t* out) const;  // the same, for many
    // What the device rebuilds from packed (wf_walk's vertex(): origin + float(m) * step in fp32).
    Vec3f unpackedPosition(uint64_t packed) const;
    // Whether p is a finite position that unpackedPosition(packedPosition(p)) gives back bit for
    // bit: true for every position a chunk of a grid that packsPositions decodes to.
    bool packsExactly(const Vec3f& p) const;
};

// Bits an axis of QuantizationGrid::packedPosition.
inline constexpr uint32_t kPackedPositionBits = 21;

// How chunk geometry is compressed (one codec per package). Draco edgebreaker is the default
// (smallest files); meshoptimizer's index and vertex codecs decode 10-30x faster for about
// 2-6x the bytes (docs/PERFORMANCE.md, "Chunk codec").
enum class GeometryCodec : uint32_t { Draco = 0, Meshopt = 1 };
const char* geometryCodecName(GeometryCodec codec);              // "draco", "meshopt"
Result<GeometryCodec> parseGeometryCodec(const std::string& name);

// The top-level tree uses the chunk tree's node format; a leaf's firstRef() is the chunk id
// of its cell, or kEmptyCell when no triangle touches the cell.
constexpr uint32_t kEmptyCell = 0xFFFFFFFFu;

struct ChunkInfo {
    uint32_t id = 0;
    Aabb cell;                  // the cell's box (cells are disjoint and cover the scene bounds)
    uint64_t offset = 0;        // of the blob in the file
    uint64_t size = 0;          // bytes in the file
    uint64_t checksum = 0;      // XXH64 of the blob
    uint64_t residentBytes = 0; // decoded footprint: positions, indices, ids, attributes, BVH nodes
    uint32_t triangleCount = 0; // references, duplicates included
    uint32_t vertexCount = 0;
    uint32_t bvhNodeCount = 0;  // Bvh4Node
    uint32_t flags = 0;         // kChunkIndexDeltas16 (version 16; 0 before)
    uint32_t longTriangles = 0; // with kChunkIndexDeltas16: triangles whose offsets do not fit
};

// ChunkInfo::flags: the device keeps the chunk's indices in 8 bytes a triangle, its first vertex
// index and the other two's offsets from it in [-32767, 32767], and the `longTriangles` whose
// offsets do not fit in 12 more bytes each (docs/GEOMETRY.md, "Chunk traversal"). Set by the
// importer on every chunk from format 16; the count is checked when the chunk is decoded.
inline constexpr uint32_t kChunkIndexDeltas16 = 1u;
// The largest offset from a triangle's first vertex index that 8-byte indices hold (-32768 marks
// a long triangle on the device).
inline constexpr int32_t kMaxIndexDelta16 = 32767;

// A chunk's indices on the device: 8 bytes a triangle and 12 more for each long one with
// kChunkIndexDeltas16, else 12 a triangle. The one formula slot sizes, uploads and the import's
// cap share.
inline uint64_t deviceIndexBytes(uint64_t triangles, bool indexDeltas16, uint64_t longTriangles) {
    return indexDeltas16 ? triangles * 8 + longTriangles * 12 : triangles * 12;
}

// A chunk's positions on the device: 8 bytes a vertex where the package grid packs them
// (QuantizationGrid::packsPositions), else 3 floats. Shared like deviceIndexBytes.
inline uint64_t devicePositionBytes(uint64_t vertices, bool packed) { return vertices * (packed ? 8 : 12); }

// The triangles (ascending) whose second or third vertex index lies more than kMaxIndexDelta16
// from its first: `indices` holds three per triangle.
std::vector<uint32_t> longTriangles(const std::vector<uint32_t>& indices);

// A volume as the package records it: everything but its voxels (`volume`'s brick table,
// majorants and voxels are empty until PackageReader::openVolumes or readVolumes), and where its
// data lies.
// When writing, `volume` holds the whole volume and the writer fills the rest.
struct PackageVolume {
    Volume volume;
    uint32_t brickCount = 0;
    bool hasEmission = false;  // its data carries an emission grid's voxels
    // Its data (brick table, voxels) in the file, and the XXH64 of the table (version 6: cell table
    // and brick index; before: of the whole data).
    uint64_t offset = 0, size = 0, checksum = 0;

    // What a render keeps of it in device memory: brick table and majorants (4 bytes each per
    // cell) and the bricks' leaves in its codec as the device keeps them (volumeDeviceLeafBytes;
    // twice with an emission grid).
    uint64_t deviceBytes() const {
        return 8 * volume.cellCount() + uint64_t(brickCount) * volumeDeviceLeafBytes(volume.codec) * (hasEmission ? 2 : 1);
    }
};

// A texture of the package (version 10; docs/PACKAGE_FORMAT.md "Textures"): what it is and
// where its pages' entries start in PackageInfo::texturePages.
struct PackageTexture {
    std::string name;
    TextureLayout layout;
    TextureWrap wrapS = TextureWrap::Repeat, wrapT = TextureWrap::Repeat;
    TextureEncoding encoding = TextureEncoding::Srgb;
    uint32_t firstEntry = 0;  // its level 0 page's entry
};

// Where one page's zstd frame lies in the page data, and its XXH64.
struct TexturePageEntry {
    uint64_t offset = 0;  // from the start of the page data
    uint64_t checksum = 0;
    uint32_t size = 0;
};

struct PackageInfo {
    uint32_t formatVersion = 0;
    uint64_t fileBytes = 0;
    uint64_t triangleCount = 0;        // distinct triangles in the package
    uint64_t referenceCount = 0;       // sum over chunks; minus triangleCount = duplicated refs
    uint64_t chunkSizeBytes = 0;       // the budget each chunk was cut to
    uint64_t maxChunkResidentBytes = 0;
    uint64_t degenerateDropped = 0;    // by the importer
    uint64_t collapsedDropped = 0;     // by quantization
    bool defaultDoubleSided = true;
    bool hasNormals = false;           // every chunk carries per-vertex shading normals
    bool hasColors = false;            // every chunk carries per-vertex colours
    bool hasUvs = false;               // every chunk carries per-vertex texture coordinates (version 9)
    GeometryCodec codec = GeometryCodec::Draco;
    Aabb bounds;
    QuantizationGrid grid;
    std::vector<Material> materials;
    std::vector<SceneCamera> cameras;  // the imported file's cameras (glTF), in its order
    std::vector<PunctualLight> lights;  // the imported file's placed lights (version 7), in its order
    // The emissive triangles next-event estimation samples (version 12; core/Emitters.h), in
    // primitive-id order, their corners as the chunks decode them.
    std::vector<EmissiveTriangle> emitters;
    std::vector<KdNode> topTree;
    std::vector<ChunkInfo> chunks;
    std::vector<PackageVolume> volumes;  // density grids (version 4), in import order
    std::vector<PackageTexture> textures;       // the materials' maps' textures (version 10)
    std::vector<TexturePageEntry> texturePages;  // every texture's pages, texture by texture
    uint64_t textureDataOffset = 0, textureDataBytes = 0;  // the page data (after the volumes' data)

    uint64_t duplicatedReferences() const { return referenceCount - triangleCount; }
    // The decoded size of every chunk together: what a host cache holding the scene needs.
    uint64_t decodedBytes() const {
        uint64_t sum = 0;
        for (const ChunkInfo& c : chunks) sum += c.residentBytes;
        return sum;
    }
};

// A leaf of the top-level tree: its box and its chunk (kEmptyCell when empty).
struct Cell {
    Aabb box;
    uint32_t chunk = kEmptyCell;
};
// Every leaf cell, in depth-first order (the scene bounds split at each node's plane).
std::vector<Cell> topLevelCells(const PackageInfo& info);

// A chunk as the renderer uses it, in the order edgebreaker decoded it.
struct DecodedChunk {
    uint32_t id = 0;
    std::vector<Vec3f> positions;
    std::vector<uint32_t> indices;      // 3 per triangle, into positions, in the BVH's leaf order
    std::vector<uint32_t> primitiveIds; // per triangle: its index in the imported mesh
    std::vector<uint32_t> materialIds;  // per triangle, or empty: material 0
    std::vector<uint32_t> normals;      // per vertex, or empty: octahedral codes (core/VertexAttributes.h)
    std::vector<uint32_t> colors;       // per vertex, or empty: packed sRGB8
    std::vector<std::array<float, 2>> uvs;  // per vertex, or empty: texture coordinates (u, v)
    Bvh4 bvh;                           // over this chunk's triangles (bvh.order is not kept)
    // Set by the package reader once every index and BVH node is checked to lie in
    // range (backends then skip their own pass over the arrays); false for a hand-made chunk.
    bool validated = false;
    // kChunkIndexDeltas16 of its directory entry: the device keeps its indices in 8 bytes a
    // triangle, the long ones (longTriangles(indices), which the reader finds and checks against
    // the directory's count) in 12 more. False for a hand-made chunk.
    bool indexDeltas16 = false;
    std::vector<uint32_t> longTriangles;
    uint64_t residentBytes() const;
};

struct PackageFile;

// Whether a path names a scene package by its extension (.vast, any case).
bool isPackagePath(const std::string& path);

class PackageReader {
public:
    // Reads and validates header, materials, top-level tree and directory (not the chunks).
    static Result<std::unique_ptr<PackageReader>> open(const std::string& path);
    ~PackageReader();

    const PackageInfo& info() const { return info_; }
    const std::string& path() const { return path_; }

    // Reads one blob and checks its checksum ("scene.vast: chunk 17: checksum mismatch").
    Result<std::vector<uint8_t>> readChunkBlob(uint32_t id) const;
    Result<DecodedChunk> readChunk(uint32_t id) const;
    // Page `page` of texture `texture` (version 10), checked against its checksum and inflated
    // into `out` (kTexturePageBytes bytes, core/Texture.h). Errors name the file, texture and page.
    Status readTexturePage(uint32_t texture, uint32_t page, uint8_t* out) const;
    // Every chunk's checksum and structure, every volume brick and every texture page; one
    // message per damaged chunk, the first damaged volume, each damaged page; empty when sound.
    std::vector<std::string> verify() const;
    // Every volume's brick table and majorants, checked, without its voxels: each brick is read
    // and checked when a render asks for it (Volume::bricks, readVolumeBrick; the source keeps the
    // file open). Packages before version 6 store no per-brick checksums: their volumes come whole,
    // as readVolumes gives them. Empty when the package has none.
    Result<std::shared_ptr<const std::vector<Volume>>> openVolumes() const;
    // Every volume's data, checked (checksums, checkVolume) and with its majorants computed;
    // empty when the package has none. ("scene.vast: volume 0 'density': ...")
    Result<std::shared_ptr<const std::vector<Volume>>> readVolumes() const;

private:
    PackageReader() = default;
    Result<std::vector<Volume>> readWholeVolumes() const;  // before version 6
    std::string path_;
    PackageInfo info_;
    std::shared_ptr<PackageFile> file_;
};

// Decodes a blob read from a package (checksum already checked) and validates every count
// and every KD node against the blob's size.
// `importedTriangles` bounds the primitive ids (the package's triangles plus those that
// quantization collapsed).
Result<DecodedChunk> decodeChunkBlob(const std::vector<uint8_t>& blob, const ChunkInfo& info,
                                     const QuantizationGrid& grid, uint32_t materialCount,
                                     uint64_t importedTriangles);

}  // namespace vastray
