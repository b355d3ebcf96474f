#pragma once
// A density volume (a fog, smoke or scanned-density grid) as vastray stores and renders it
// (docs/RENDERING.md, "Volumes"): voxels of a sparse grid in its own index space, grouped in
// bricks of kVolumeBrickSize^3 on a regular brick grid, each brick cell with a majorant (the
// largest density its points can take), placed in the world by an affine map. The density at
// an index-space point is the trilinear interpolation of the voxels around it (voxel ijk sits
// at the point ijk; voxels in no stored brick are 0), times the material's densityScale: the
// extinction coefficient per world unit.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "vastray/core/Aabb.h"
#include "vastray/core/Random.h"
#include "vastray/core/Result.h"
#include "vastray/core/Vec3.h"

namespace vastray {

constexpr uint32_t kVolumeBrickSize = 8;
constexpr uint32_t kVolumeBrickVoxels = kVolumeBrickSize * kVolumeBrickSize * kVolumeBrickSize;
constexpr uint32_t kNoBrick = 0xFFFFFFFFu;

// Limits on a volume, checked at import and again by the package reader.
constexpr uint64_t kMaxVolumeBrickCells = uint64_t(1) << 24;   // brick grid cells (x * y * z)
constexpr uint64_t kMaxVolumeBricks = uint64_t(1) << 22;       // stored bricks (8 GiB of voxels)
constexpr uint32_t kMaxVolumes = 64;                           // volumes per scene
constexpr float kMaxVolumeDensity = 1e18f;                     // voxel values are in [0, this]

// How a volume's bricks are stored in its package and held in the device's brick pool: NanoVDB
// leaf nodes of float values (exact), or NanoVDB's quantized Fp16 and Fp8 leaves (a minimum and a
// quantum per brick, a 16- or 8-bit code per voxel; core/VolumeLeaf.h). The voxels a render
// reads are the ones the leaves decode to.
enum class VolumeCodec : uint32_t { Float = 0, Fp16 = 1, Fp8 = 2 };
constexpr uint32_t kVolumeCodecCount = 3;

// How a volume scatters: extinction = densityScale * density; of what is extinguished, the
// fraction `albedo` (per channel) scatters with the Henyey-Greenstein phase function of
// `anisotropy` g (0: isotropic; > 0 forward), the rest is absorbed. With an emission grid, the
// absorbing part glows: emitted radiance = emission (per channel) * the emission grid's value;
// with `temperature`, the grid holds kelvin in [0, kMaxTemperature] and the emitted radiance is
// emission (per channel) * the blackbody's colour at the grid's value (core/Blackbody.h).
struct VolumeMaterial {
    std::array<float, 3> albedo{0.8f, 0.8f, 0.8f};  // each in [0, 1]
    float densityScale = 1.0f;                       // finite, >= 0
    float anisotropy = 0.0f;                         // in (-1, 1)
    std::array<float, 3> emission{1.0f, 1.0f, 1.0f};  // each in [0, 1e18]; used with an emission grid
    bool temperature = false;                          // the emission grid is a temperature in kelvin
};

// Where the bricks of volumes whose voxels stay in their file come from: a package's volume
// data, read one brick at a time (streamer/PackageReader::openVolumes). Called from any thread.
class VolumeBrickSource {
public:
    virtual ~VolumeBrickSource() = default;
    // Reads stored brick `brick` of the source's volume `volume`, checks it (checksum, every voxel
    // finite in [0, 1e18], its largest density the one the brick table recorded) and writes its
    // kVolumeBrickVoxels densities, and as many emission values when the volume has an emission
    // grid (else `emission` is not written). Errors name the file, the volume and the brick.
    // A source that stores its bricks as leaves (a version 14 package: leafCodec says their codec)
    // also writes them to `leaves` when it is not null: the density's leaf, then the emission
    // grid's (volumeLeafBytes each), the values written being what they decode to.
    virtual Status readBrick(uint32_t volume, uint32_t brick, float* density, float* emission,
                             uint8_t* leaves) const = 0;
    virtual std::optional<VolumeCodec> leafCodec(uint32_t /*volume*/) const { return std::nullopt; }
};

struct Volume {
    std::string name;  // the grid's name in its file (UTF-8)
    // Affine maps, row-major 3 x 4 ([r][0..2] linear, [r][3] translation): index space to world
    // and world to index space (its inverse).
    std::array<float, 12> indexToWorld{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    std::array<float, 12> worldToIndex{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    // The index of brick cell (0, 0, 0)'s first voxel (each a multiple of kVolumeBrickSize) and
    // the brick grid's size in cells. Brick cell c covers the index-space points p with
    // floor((p - origin) / kVolumeBrickSize) == c; every point of nonzero density lies in a cell.
    std::array<int32_t, 3> origin{0, 0, 0};
    std::array<uint32_t, 3> brickCells{0, 0, 0};
    // Per brick cell, x fastest: the stored brick holding its voxels (kNoBrick: all 0), and a
    // bound on the density (unscaled) of any point in the cell: the largest voxel of its brick
    // and of the 7 cells after it on some axes (trilinear interpolation reads one voxel past the
    // cell's last on each axis); 0: the cell is empty and rays skip it.
    std::vector<uint32_t> brickOf;
    std::vector<float> majorant;
    // kVolumeBrickVoxels per stored brick, x fastest then y then z; empty while the bricks stay in
    // their file (`bricks` set).
    std::vector<float> voxels;
    // An emission grid's voxels in the same bricks (its values where the density has no brick
    // are dropped: nothing absorbs there, so nothing glows), or empty: no emission.
    std::vector<float> emissionVoxels;
    VolumeMaterial material;
    // The codec of its bricks' leaves: what a package writer stores (quantizing the voxels it
    // reads), and for a volume whose bricks stay in their source what the device's pool holds
    // (deviceVolumeCodec). A quantized volume read into memory is decoded: codec Float.
    VolumeCodec codec = VolumeCodec::Float;
    Aabb worldBounds;  // the brick grid's box mapped to the world
    // Set when the voxels stay in their file: brickOf and majorant are here, `voxels` and
    // `emissionVoxels` empty, and each brick is read on demand (readVolumeBrick). The CPU
    // functions below (volumeVoxel, tracking) need the voxels in memory.
    struct StoredBricks {
        std::shared_ptr<const VolumeBrickSource> source;
        uint32_t volume = 0;   // the volume's number in `source`
        uint64_t count = 0;    // stored bricks
        bool emission = false; // they carry an emission grid's voxels
    } bricks;

    uint64_t cellCount() const { return uint64_t(brickCells[0]) * brickCells[1] * brickCells[2]; }
    uint64_t brickCount() const { return bricks.source ? bricks.count : voxels.size() / kVolumeBrickVoxels; }
    bool hasEmission() const { return bricks.source ? bricks.emission : !emissionVoxels.empty(); }
};

// Stored brick `brick`'s densities (kVolumeBrickVoxels) and, with an emission grid, its emission
// values: copied from the voxels in memory, or read through the volume's brick source.
Status readVolumeBrick(const Volume& volume, uint64_t brick, float* density, float* emission);
// The same values and the brick's leaves in `codec` (the density's, then with an emission grid
// the emission's; volumeLeafBytes each; core/VolumeLeaf.h): given verbatim by a source that
// stores leaves of that codec, else encoded from the values read, which are then replaced by the
// values the leaves decode to. `origin`: the index of the brick's first voxel (its cell's).
Status readVolumeLeaves(const Volume& volume, VolumeCodec codec, uint64_t brick, std::array<int32_t, 3> origin,
                        float* density, float* emission, uint8_t* leaves);
// The codec of the leaves the device holds for a volume: its own when its bricks stay in their
// source (a package's leaves go to the device as they are stored), float when its voxels are in
// memory (held exactly, the values the CPU functions read).
inline VolumeCodec deviceVolumeCodec(const Volume& volume) {
    return volume.bricks.source ? volume.codec : VolumeCodec::Float;
}
// The index of brick cell `cell`'s first voxel, and per stored brick its cell's (from brickOf).
std::array<int32_t, 3> volumeCellOrigin(const Volume& volume, uint64_t cell);
std::vector<std::array<int32_t, 3>> volumeBrickOrigins(const Volume& volume);

// The voxel at index ijk (0 outside the stored bricks).
float volumeVoxel(const Volume& volume, int32_t i, int32_t j, int32_t k);
// Trilinear density (unscaled) at an index-space point.
float volumeDensity(const Volume& volume, Vec3f indexPoint);
// The radiance the volume emits at a world point: material.emission times the emission grid's
// trilinear value (a temperature grid: times blackbodyRadiance of it); 0 without an emission grid.
Vec3f volumeEmission(const Volume& volume, Vec3f worldPoint);

// The world box of the brick grid under indexToWorld, and worldToIndex from indexToWorld.
// Returns false when the map is not invertible (or not finite).
bool finishVolumeTransform(Volume& volume);
// `bounds` grown by every volume's world box: what automatic framing frames (the mesh and its
// volumes).
Aabb boundsWithVolumes(Aabb bounds, const std::vector<Volume>* volumes);
// Per-cell majorants from the voxels (brickOf and voxels set).
void computeVolumeMajorants(Volume& volume);
// Per-cell majorants from each stored brick's largest voxel (brickOf set; `brickMaximum` holds one
// value per stored brick): the same values computeVolumeMajorants finds from the voxels.
void computeVolumeMajorants(Volume& volume, std::span<const float> brickMaximum);
// Consistency of a volume read from a file: sizes, limits, brick indices, finite non-negative
// voxels, a finite map, a valid material. Returns an empty string when sound, else what is
// wrong. Majorants and worldToIndex are not checked: readers compute them
// (computeVolumeMajorants, finishVolumeTransform, which refuses a map it cannot invert).
std::string checkVolume(const Volume& volume);
// A brick table's entries (brickOf, one per cell): each names one of `bricks` stored bricks or
// none (kNoBrick), and no brick belongs to two cells (the paged pool keeps a brick where its one
// cell is). Returns an empty string when sound, else the first cell that is wrong.
std::string checkBrickTable(std::span<const uint32_t> brickOf, uint64_t bricks);

// A ray in the world (unit direction) against every volume: delta tracking (free-flight
// sampling, Woodcock) with the brick cells' majorants, empty cells skipped. Random numbers come
// from `key` at dimensions kDimVolumeBase + n, n counting up from *counter (advanced).
struct VolumeCollision {
    float t = 0.0f;          // world distance of the real collision
    uint32_t volume = 0;     // which volume
};
// The first real collision before tMax, if any (the nearest among the volumes).
bool sampleVolumeCollision(const std::vector<Volume>& volumes, Vec3f origin, Vec3f direction, float tMax,
                           RandomKey key, uint32_t seed, uint32_t* counter, VolumeCollision* collision);
// Transmittance along the ray up to tMax, estimated by ratio tracking (unbiased).
float volumeTransmittance(const std::vector<Volume>& volumes, Vec3f origin, Vec3f direction, float tMax,
                          RandomKey key, uint32_t seed, uint32_t* counter);

// Henyey-Greenstein phase function of anisotropy g for light travelling along unit `travel`
// (the ray's direction) and scattered towards unit `scattered`: its density (per steradian),
// and a direction drawn from it with u1, u2 in [0, 1) (perfect importance sampling: the
// phase function over the density is 1).
float henyeyGreenstein(float g, Vec3f travel, Vec3f scattered);
Vec3f sampleHenyeyGreenstein(float g, Vec3f travel, float u1, float u2);

// Tentative collisions one tracking call takes at most: beyond, free flight stops (a
// collision where it stands) and transmittance is 0, so a hostile density cannot hang a render.
constexpr uint32_t kMaxVolumeSteps = 65536;

}  // namespace vastray
