#pragma once
// Density volumes from OpenVDB files (.vdb): one float grid, read into vastray's bricked
// Volume (core/Volume.h). Like the mesh importers it returns a checked volume or an error that
// names the file, the grid and the limit or value at fault ("smoke.vdb: grid 'density': voxel
// (3, 4, 5) has density nan; ..."); it never throws. docs/HARDENING.md, "Volumes (.vdb)",
// lists what it refuses.
#include <cstdint>
#include <string>

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
// emissionVoxels: read in the density's bricks only).
Result<Volume> readVdbVolume(const std::string& path, const std::string& gridName,
                             const VolumeMaterial& material, const std::string& emissionGrid = {});

}  // namespace vastray
