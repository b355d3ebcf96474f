#pragma once
// Density volumes from OpenVDB files (.vdb): one float grid, read into vastray's bricked
// Volume (core/Volume.h). Like the mesh importers it returns a checked volume or an error that
// names the file, the grid and the limit or value at fault ("smoke.vdb: grid 'density': voxel
// (3, 4, 5) has density nan; ..."); it never throws. docs/HARDENING.md, "Volumes (.vdb)",
// lists what it refuses.
#include <cstdint>
#include <string>
#include <vector>

#include "vastray/core/Result.h"
#include "vastray/core/Volume.h"

namespace vastray {

// Files above this size are refused before OpenVDB reads a byte of them.
constexpr uint64_t kMaxVdbFileBytes = uint64_t(16) << 30;
// Every point of nonzero density (the active values' index box grown by one voxel, which
// trilinear interpolation reaches) lies within +-kMaxVdbIndex on each axis: the renderer maps
// world points to index space in float, which holds whole voxels exactly only up to 2^24.
constexpr int64_t kMaxVdbIndex = int64_t(1) << 24;

// Reads the float grid `gridName` of the .vdb file at `path` (empty: the file's first float
// grid). Active voxels and active tiles are read, inactive values count as 0; the grid must be
// a fog volume (background 0) with values in [0, kMaxVolumeDensity] and a linear (affine)
// transform. Volume::name is the grid's name; `material` is stored as given (checked).
// `emissionGrid` (empty: none) names a float grid of the same file with the density's transform
// whose values, times material.emission, are the radiance the volume emits (Volume::
// emissionVoxels: read in the density's bricks only); with material.temperature, a temperature
// grid in kelvin, each voxel in [0, kMaxTemperature] (core/Blackbody.h).
Result<Volume> readVdbVolume(const std::string& path, const std::string& gridName,
                             const VolumeMaterial& material, const std::string& emissionGrid = {});

// readVdbVolume with the voxels left in the file: the same checks and the same volume, less
// Volume::voxels and emissionVoxels; Volume::bricks.source fills each brick from the file when
// asked for (readVolumeBrick), one at a time, and holds the file open. What stays in memory is
// the cell table, the majorants and 8 bytes per brick and grid; while the grids are scanned,
// also OpenVDB's tree without its voxel buffers (about 100 bytes per 8^3 leaf). A file written
// to a stream (no grid offsets) or of format 221 or older is read whole (docs/HARDENING.md).
// The file must not change while the volume is in use: a brick read again is checked again
// (every value in range) but not against the first pass.
Result<Volume> openVdbVolume(const std::string& path, const std::string& gridName,
                             const VolumeMaterial& material, const std::string& emissionGrid = {});

// Reads every brick of a volume whose bricks stay in their source into Volume::voxels (and
// emissionVoxels), and drops the source: what the CPU functions of core/Volume.h need.
Status readVolumeIntoMemory(Volume& volume);

// What messages call a volume's material fields: a front end's own names for them, e.g. the
// CLI's options ("--volume-density") or an upload manifest's keys ("vastray-volumes.json:
// volumes[1].density").
struct VolumeFieldNames {
    std::string albedo, density, anisotropy, emissionScale;
};

// One volume to import, as a front end read it from its own syntax (`vastray import --volume
// FILE.vdb[:GRID] --volume-...`, an upload's vastray-volumes.json).
struct VolumeSource {
    std::string path;          // the .vdb file
    std::string grid;          // empty: the file's first float grid
    std::string emissionGrid;  // empty: no emission; a temperature grid when material.temperature
    VolumeMaterial material;   // checked by readVolumes (checkVolumeMaterial)
    VolumeFieldNames names;
    // What the file's messages call it, in place of its file name (an upload's scratch file is
    // "cars.zip:smoke/fog.vdb" to its client); empty: the file name.
    std::string label;
    // How the package stores its bricks (and the device holds them): NanoVDB float leaves, or
    // Fp16 / Fp8 leaves quantized when the package is written (core/VolumeLeaf.h).
    VolumeCodec codec = VolumeCodec::Float;
};

// The material's ranges: albedo in [0, 1], density scale in [0, kMaxVolumeDensity], anisotropy
// in (-1, 1), emission in [0, kMaxVolumeDensity]. A message begins with the field's name
// ("--volume-density -1.000000 is outside [0, 1e18]").
Status checkVolumeMaterial(const VolumeMaterial& material, const VolumeFieldNames& names);

struct VolumeReadOptions {
    // Read each .vdb in a child process (fork), as assimp's formats are read: a crash or a hang
    // of OpenVDB on a hostile file (past kVdbReadSecondsLimit) fails the import by the file's
    // name instead of ending the caller, and the child, not the caller, is the kernel's first
    // choice when memory runs out (OpenVDB allocates what a file's length fields say), and it
    // may take at most 1 GiB + 64 x the file's size (VolumeSources.cpp kVdbMemoryBaseBytes). The
    // volume comes back through a pipe, its bricks through a temporary file, and is checked
    // again (checkVolume, and each brick when it is read). The render service sets it; the CLI
    // reads in its own process.
    bool childProcess = false;
};

// How long one .vdb may take in a child process before it is killed and the import fails.
constexpr int kVdbReadSecondsLimit = 600;

// Every source in order, at most kMaxVolumes: its material checked, then its grid opened
// (openVdbVolume: the bricks stay in the file), or with options.childProcess opened in a child
// process that writes the bricks to an unlinked temporary file (in $TMPDIR, as large as the
// bricks) from which the returned volume's source reads them back, each checked again. Returns the first error ("65 volumes exceed the limit of 64", a material's
// field by its name, or readVdbVolume's message naming the file and the grid).
Result<std::vector<Volume>> readVolumes(const std::vector<VolumeSource>& sources,
                                        const VolumeReadOptions& options = {});

}  // namespace vastray
