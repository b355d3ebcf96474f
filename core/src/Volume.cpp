#include "vastray/core/Volume.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vastray/core/Blackbody.h"
#include "vastray/core/Sampling.h"
#include "vastray/core/VecMath.h"
#include "vastray/core/VolumeLeaf.h"

namespace vastray {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

Vec3f affinePoint(const std::array<float, 12>& m, Vec3f p) {
    return {m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3], m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
            m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]};
}
Vec3f linearPart(const std::array<float, 12>& m, Vec3f v) {
    return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[4] * v.x + m[5] * v.y + m[6] * v.z,
            m[8] * v.x + m[9] * v.y + m[10] * v.z};
}

// The voxel of `voxels` (the density's, or the emission grid's, in the same bricks) at
// `relative` index coordinates (from the brick grid's origin); 0 outside.
float relativeVoxel(const Volume& v, const std::vector<float>& voxels, int64_t x, int64_t y, int64_t z) {
    const int64_t size = kVolumeBrickSize;
    if (x < 0 || y < 0 || z < 0 || x >= size * v.brickCells[0] || y >= size * v.brickCells[1] ||
        z >= size * v.brickCells[2])
        return 0.0f;
    const uint64_t cell = uint64_t(x / size) + v.brickCells[0] * (uint64_t(y / size) + v.brickCells[1] * uint64_t(z / size));
    const uint32_t brick = v.brickOf[cell];
    if (brick == kNoBrick) return 0.0f;
    return voxels[uint64_t(brick) * kVolumeBrickVoxels + uint64_t(x % size) + size * (uint64_t(y % size) + size * uint64_t(z % size))];
}

// Trilinear interpolation of `voxels` at relative index coordinates r (in voxels from the
// grid's origin).
float relativeValue(const Volume& v, const std::vector<float>& voxels, Vec3f r) {
    const float bx = std::floor(r.x), by = std::floor(r.y), bz = std::floor(r.z);
    const float fx = r.x - bx, fy = r.y - by, fz = r.z - bz;
    // Points outside the grid (by more than a voxel) have density 0; the bound keeps the
    // conversion to integers defined.
    const float limit = float(kVolumeBrickSize) * float(1u << 24);
    if (!(bx >= -1.0f && by >= -1.0f && bz >= -1.0f && bx < limit && by < limit && bz < limit)) return 0.0f;
    const int64_t x = int64_t(bx), y = int64_t(by), z = int64_t(bz);
    const float c00 = relativeVoxel(v, voxels, x, y, z) * (1.0f - fx) + relativeVoxel(v, voxels, x + 1, y, z) * fx;
    const float c10 = relativeVoxel(v, voxels, x, y + 1, z) * (1.0f - fx) + relativeVoxel(v, voxels, x + 1, y + 1, z) * fx;
    const float c01 = relativeVoxel(v, voxels, x, y, z + 1) * (1.0f - fx) + relativeVoxel(v, voxels, x + 1, y, z + 1) * fx;
    const float c11 = relativeVoxel(v, voxels, x, y + 1, z + 1) * (1.0f - fx) + relativeVoxel(v, voxels, x + 1, y + 1, z + 1) * fx;
    const float c0 = c00 * (1.0f - fy) + c10 * fy;
    const float c1 = c01 * (1.0f - fy) + c11 * fy;
    return c0 * (1.0f - fz) + c1 * fz;
}

float relativeDensity(const Volume& v, Vec3f r) { return relativeValue(v, v.voxels, r); }

// The ray in the brick grid's cell units: cell c covers [c, c + 1) on each axis.
struct CellRay {
    Vec3f origin, direction;
};
CellRay cellRay(const Volume& v, Vec3f origin, Vec3f direction) {
    const Vec3f p = affinePoint(v.worldToIndex, origin);
    const Vec3f d = linearPart(v.worldToIndex, direction);
    const float inverse = 1.0f / float(kVolumeBrickSize);
    const Vec3f gridOrigin{float(v.origin[0]), float(v.origin[1]), float(v.origin[2])};
    return {(p - gridOrigin) * inverse, d * inverse};
}

// Calls visit(cell, t0, t1) for each brick cell the ray crosses within [0, tMax), front to
// back (a 3D DDA, Amanatides and Woo 1987), until visit returns false.
template <typename Visit>
void walkCells(const Volume& v, const CellRay& r, float tMax, Visit&& visit) {
    float tEnter = 0.0f, tExit = tMax;
    for (int a = 0; a < 3; ++a) {
        const float size = float(v.brickCells[a]);
        if (r.direction[a] == 0.0f) {
            if (!(r.origin[a] >= 0.0f && r.origin[a] < size)) return;
            continue;
        }
        float t0 = (0.0f - r.origin[a]) / r.direction[a], t1 = (size - r.origin[a]) / r.direction[a];
        if (t0 > t1) std::swap(t0, t1);
        tEnter = std::fmax(tEnter, t0);
        tExit = std::fmin(tExit, t1);
    }
    if (!(tEnter < tExit)) return;
    int64_t cell[3], step[3];
    float tNext[3], tDelta[3];
    for (int a = 0; a < 3; ++a) {
        const float p = r.origin[a] + r.direction[a] * tEnter;
        cell[a] = std::clamp<int64_t>(int64_t(std::floor(p)), 0, int64_t(v.brickCells[a]) - 1);
        if (r.direction[a] > 0.0f) {
            step[a] = 1, tDelta[a] = 1.0f / r.direction[a];
            tNext[a] = (float(cell[a] + 1) - r.origin[a]) / r.direction[a];
        } else if (r.direction[a] < 0.0f) {
            step[a] = -1, tDelta[a] = -1.0f / r.direction[a];
            tNext[a] = (float(cell[a]) - r.origin[a]) / r.direction[a];
        } else {
            step[a] = 0, tDelta[a] = kInfinity, tNext[a] = kInfinity;
        }
    }
    float t = tEnter;
    while (t < tExit) {
        const int axis = tNext[0] <= tNext[1] ? (tNext[0] <= tNext[2] ? 0 : 2) : (tNext[1] <= tNext[2] ? 1 : 2);
        const float end = std::fmin(tNext[axis], tExit);
        const uint64_t index = uint64_t(cell[0]) + v.brickCells[0] * (uint64_t(cell[1]) + v.brickCells[1] * uint64_t(cell[2]));
        if (end > t && !visit(index, t, end)) return;
        t = std::fmax(t, end);
        cell[axis] += step[axis];
        if (cell[axis] < 0 || cell[axis] >= int64_t(v.brickCells[axis])) return;
        tNext[axis] += tDelta[axis];
    }
}

// Tracks one volume along the ray within [0, tMax), cell by cell with the cells' majorants:
// without `transmittance`, delta tracking (returns the first real collision's t, or tMax); with
// it, ratio tracking (multiplies *transmittance, returns tMax). The optical depth to the next
// tentative collision is drawn once on entry (whether or not the ray meets the grid) and after
// each tentative collision, and spent cell by cell (majorant x length): which numbers a ray
// draws depends on its collisions alone, not on the cells it crosses, so a ray that ends on a
// cell boundary (a surface on a volume's face) draws the same numbers whether rounding ends it
// just before the boundary or in a sliver past it. Delta tracking draws, at each tentative
// collision, the acceptance and then (rejected) the next depth.
float trackVolume(const Volume& v, Vec3f origin, Vec3f direction, float tMax, RandomKey key, uint32_t seed,
                  uint32_t* counter, float* transmittance) {
    const CellRay r = cellRay(v, origin, direction);
    const float scale = v.material.densityScale;
    auto depth = [&] { return -std::log(1.0f - randomFloat(key, kDimVolume + (*counter)++, seed)); };
    float tau = depth();  // the majorant's optical depth to the next tentative collision
    float result = tMax;
    uint32_t steps = 0;
    walkCells(v, r, tMax, [&](uint64_t cell, float t0, float t1) {
        const float majorant = v.majorant[cell] * scale;
        if (!(majorant > 0.0f)) return true;
        float t = t0;
        for (;;) {
            const float next = t + tau / majorant;
            if (!(next < t1)) {
                tau = std::fmax(0.0f, tau - majorant * (t1 - t));
                return true;
            }
            t = next;
            if (!transmittance && ++steps > kMaxVolumeSteps) {
                result = t;
                return false;
            }
            const float density = relativeDensity(v, (r.origin + r.direction * t) * float(kVolumeBrickSize)) * scale;
            if (transmittance) {
                *transmittance *= std::fmax(0.0f, 1.0f - density / majorant);
                if (++steps > kMaxVolumeSteps) *transmittance = 0.0f;
                if (!(*transmittance > 0.0f)) return false;
            } else if (randomFloat(key, kDimVolume + (*counter)++, seed) * majorant < density) {
                result = t;
                return false;
            }
            tau = depth();
        }
    });
    return result;
}

}  // namespace

float volumeVoxel(const Volume& volume, int32_t i, int32_t j, int32_t k) {
    return relativeVoxel(volume, volume.voxels, int64_t(i) - volume.origin[0], int64_t(j) - volume.origin[1],
                         int64_t(k) - volume.origin[2]);
}

float volumeDensity(const Volume& volume, Vec3f p) {
    const Vec3f gridOrigin{float(volume.origin[0]), float(volume.origin[1]), float(volume.origin[2])};
    return relativeDensity(volume, p - gridOrigin);
}

Vec3f volumeEmission(const Volume& volume, Vec3f worldPoint) {
    if (volume.emissionVoxels.empty()) return {};
    const Vec3f gridOrigin{float(volume.origin[0]), float(volume.origin[1]), float(volume.origin[2])};
    const float value = relativeValue(volume, volume.emissionVoxels, affinePoint(volume.worldToIndex, worldPoint) - gridOrigin);
    const auto& e = volume.material.emission;
    if (volume.material.temperature)
        return mul(Vec3f{e[0], e[1], e[2]}, blackbodyRadiance(blackbodyTable().data(), value));
    return Vec3f{e[0], e[1], e[2]} * value;
}

bool finishVolumeTransform(Volume& v) {
    const auto& m = v.indexToWorld;
    for (float x : m)
        if (!std::isfinite(x)) return false;
    const double a = m[0], b = m[1], c = m[2], d = m[4], e = m[5], f = m[6], g = m[8], h = m[9], i = m[10];
    const double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
    double scale = 0;
    for (double x : {a, b, c, d, e, f, g, h, i}) scale = std::max(scale, std::fabs(x));
    if (!(std::fabs(det) > 1e-12 * scale * scale * scale) || !std::isfinite(det)) return false;
    const double inv[9] = {(e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det,
                           (f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det,
                           (d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det};
    for (int r = 0; r < 3; ++r) {
        double t = 0;
        for (int k = 0; k < 3; ++k) {
            v.worldToIndex[4 * r + k] = float(inv[3 * r + k]);
            t -= inv[3 * r + k] * m[4 * k + 3];
        }
        v.worldToIndex[4 * r + 3] = float(t);
    }
    v.worldBounds = Aabb();
    for (int corner = 0; corner < 8; ++corner) {
        Vec3f p;
        for (int a = 0; a < 3; ++a)
            p[a] = float(double(v.origin[a]) + ((corner >> a) & 1 ? double(kVolumeBrickSize) * v.brickCells[a] : 0.0));
        v.worldBounds.extend(affinePoint(v.indexToWorld, p));
    }
    for (float x : v.worldToIndex)
        if (!std::isfinite(x)) return false;
    return isFinite(v.worldBounds.lo) && isFinite(v.worldBounds.hi);
}

Aabb boundsWithVolumes(Aabb bounds, const std::vector<Volume>* volumes) {
    if (volumes)
        for (const Volume& v : *volumes) bounds.extend(v.worldBounds);
    return bounds;
}

void computeVolumeMajorants(Volume& v) {
    std::vector<float> brickMax(v.brickCount(), 0.0f);
    for (uint64_t b = 0; b < brickMax.size(); ++b) {
        const float* voxels = &v.voxels[b * kVolumeBrickVoxels];
        brickMax[b] = *std::max_element(voxels, voxels + kVolumeBrickVoxels);
    }
    computeVolumeMajorants(v, brickMax);
}

void computeVolumeMajorants(Volume& v, std::span<const float> brickMaximum) {
    const uint64_t cells = v.cellCount();
    auto brickMax = [&](uint64_t c) { return v.brickOf[c] == kNoBrick ? 0.0f : brickMaximum[v.brickOf[c]]; };
    v.majorant.assign(cells, 0.0f);
    const uint64_t nx = v.brickCells[0], ny = v.brickCells[1], nz = v.brickCells[2];
    for (uint64_t z = 0; z < nz; ++z)
        for (uint64_t y = 0; y < ny; ++y)
            for (uint64_t x = 0; x < nx; ++x) {
                float m = 0.0f;
                for (uint64_t dz = 0; dz < 2 && z + dz < nz; ++dz)
                    for (uint64_t dy = 0; dy < 2 && y + dy < ny; ++dy)
                        for (uint64_t dx = 0; dx < 2 && x + dx < nx; ++dx)
                            m = std::max(m, brickMax((x + dx) + nx * ((y + dy) + ny * (z + dz))));
                v.majorant[x + nx * (y + ny * z)] = m;
            }
}

namespace {

Status checkBrickNumber(const Volume& v, uint64_t brick) {
    if (brick < v.brickCount()) return Status::ok();
    return Status::error("volume '" + v.name + "': brick " + std::to_string(brick) + " does not exist (" +
                         std::to_string(v.brickCount()) + " bricks)");
}

}  // namespace

Status readVolumeBrick(const Volume& v, uint64_t brick, float* density, float* emission) {
    VASTRAY_TRY(checkBrickNumber(v, brick));
    if (v.bricks.source)
        return v.bricks.source->readBrick(v.bricks.volume, uint32_t(brick), density, emission, nullptr);
    const uint64_t first = brick * kVolumeBrickVoxels;
    std::copy_n(v.voxels.data() + first, kVolumeBrickVoxels, density);
    if (!v.emissionVoxels.empty()) std::copy_n(v.emissionVoxels.data() + first, kVolumeBrickVoxels, emission);
    return Status::ok();
}

Status readVolumeLeaves(const Volume& v, VolumeCodec codec, uint64_t brick, std::array<int32_t, 3> origin,
                        float* density, float* emission, uint8_t* leaves) {
    VASTRAY_TRY(checkBrickNumber(v, brick));
    if (v.bricks.source && v.bricks.source->leafCodec(v.bricks.volume) == codec)
        return v.bricks.source->readBrick(v.bricks.volume, uint32_t(brick), density, emission, leaves);
    VASTRAY_TRY(readVolumeBrick(v, brick, density, emission));
    encodeVolumeLeaf(codec, origin, density, leaves);
    if (v.hasEmission()) encodeVolumeLeaf(codec, origin, emission, leaves + volumeLeafBytes(codec));
    return Status::ok();
}

std::array<int32_t, 3> volumeCellOrigin(const Volume& v, uint64_t cell) {
    const uint64_t nx = v.brickCells[0], nxy = nx * v.brickCells[1];
    const int32_t size = int32_t(kVolumeBrickSize);
    return {v.origin[0] + size * int32_t(cell % nx), v.origin[1] + size * int32_t(cell % nxy / nx),
            v.origin[2] + size * int32_t(cell / nxy)};
}

std::vector<std::array<int32_t, 3>> volumeBrickOrigins(const Volume& v) {
    std::vector<std::array<int32_t, 3>> origins(v.brickCount());
    for (uint64_t c = 0; c < v.brickOf.size(); ++c)
        if (v.brickOf[c] != kNoBrick && v.brickOf[c] < origins.size()) origins[v.brickOf[c]] = volumeCellOrigin(v, c);
    return origins;
}

std::string checkBrickTable(std::span<const uint32_t> brickOf, uint64_t bricks) {
    std::vector<uint32_t> owner(bricks, kNoBrick);  // the cell naming each brick (cells < 2^24)
    for (uint64_t c = 0; c < brickOf.size(); ++c) {
        const uint32_t b = brickOf[c];
        if (b == kNoBrick) continue;
        if (b >= bricks)
            return "cell " + std::to_string(c) + " names brick " + std::to_string(b) + " of " + std::to_string(bricks);
        if (owner[b] != kNoBrick)
            return "cells " + std::to_string(owner[b]) + " and " + std::to_string(c) + " both name brick " +
                   std::to_string(b) + " (a brick belongs to one cell)";
        owner[b] = uint32_t(c);
    }
    return {};
}

std::string checkVolume(const Volume& v) {
    for (int a = 0; a < 3; ++a) {
        if (v.brickCells[a] == 0) return "the brick grid has no cells";
        if (v.origin[a] % int32_t(kVolumeBrickSize) != 0) return "the brick grid's origin is not a multiple of 8";
        if (int64_t(v.origin[a]) + int64_t(kVolumeBrickSize) * v.brickCells[a] > std::numeric_limits<int32_t>::max())
            return "the brick grid reaches beyond the index range of 32-bit integers";
    }
    const double cells = double(v.brickCells[0]) * v.brickCells[1] * v.brickCells[2];
    if (cells > double(kMaxVolumeBrickCells))
        return "the brick grid has " + std::to_string(uint64_t(cells)) + " cells, more than the limit of " +
               std::to_string(kMaxVolumeBrickCells);
    if (v.brickOf.size() != v.cellCount()) return "the brick table does not have one entry per cell";
    if (v.voxels.size() % kVolumeBrickVoxels != 0) return "the voxels are not whole bricks";
    if (uint32_t(v.codec) >= kVolumeCodecCount)
        return "its codec " + std::to_string(uint32_t(v.codec)) + " is not one vastray knows";
    if (v.brickCount() > kMaxVolumeBricks)
        return std::to_string(v.brickCount()) + " bricks, more than the limit of " + std::to_string(kMaxVolumeBricks);
    if (std::string problem = checkBrickTable(v.brickOf, v.brickCount()); !problem.empty()) return problem;
    for (uint64_t i = 0; i < v.voxels.size(); ++i)
        if (!(v.voxels[i] >= 0.0f && v.voxels[i] <= kMaxVolumeDensity))
            return "brick " + std::to_string(i / kVolumeBrickVoxels) + " voxel " + std::to_string(i % kVolumeBrickVoxels) +
                   " has density " + std::to_string(v.voxels[i]) + " (not in [0, 1e18])";
    if (!v.emissionVoxels.empty() && v.emissionVoxels.size() != v.voxels.size())
        return "the emission grid does not have one voxel per density voxel";
    for (uint64_t i = 0; i < v.emissionVoxels.size(); ++i)
        if (!(v.emissionVoxels[i] >= 0.0f && v.emissionVoxels[i] <= kMaxVolumeDensity))
            return "brick " + std::to_string(i / kVolumeBrickVoxels) + " emission voxel " +
                   std::to_string(i % kVolumeBrickVoxels) + " has the value " + std::to_string(v.emissionVoxels[i]) +
                   " (not in [0, 1e18])";
    if (v.material.temperature)
        for (uint64_t i = 0; i < v.emissionVoxels.size(); ++i)
            if (!(v.emissionVoxels[i] <= kMaxTemperature))
                return "brick " + std::to_string(i / kVolumeBrickVoxels) + " temperature voxel " +
                       std::to_string(i % kVolumeBrickVoxels) + " has the value " + std::to_string(v.emissionVoxels[i]) +
                       " (not in [0, 1e5] K)";
    for (float x : v.indexToWorld)
        if (!std::isfinite(x)) return "the index-to-world map is not finite";
    const VolumeMaterial& m = v.material;
    for (float a : m.albedo)
        if (!(a >= 0.0f && a <= 1.0f)) return "the albedo " + std::to_string(a) + " is not in [0, 1]";
    if (!(m.densityScale >= 0.0f && m.densityScale <= kMaxVolumeDensity))
        return "the density scale " + std::to_string(m.densityScale) + " is not in [0, 1e18]";
    if (!(m.anisotropy > -1.0f && m.anisotropy < 1.0f))
        return "the anisotropy " + std::to_string(m.anisotropy) + " is not in (-1, 1)";
    for (float e : m.emission)
        if (!(e >= 0.0f && e <= kMaxVolumeDensity)) return "the emission " + std::to_string(e) + " is not in [0, 1e18]";
    return {};
}

bool sampleVolumeCollision(const std::vector<Volume>& volumes, Vec3f origin, Vec3f direction, float tMax,
                           RandomKey key, uint32_t seed, uint32_t* counter, VolumeCollision* collision) {
    // The nearest of independent free flights, one per volume, samples the sum of their
    // extinctions: each later volume only needs to look before the nearest so far.
    bool found = false;
    for (uint32_t i = 0; i < volumes.size(); ++i) {
        const float t = trackVolume(volumes[i], origin, direction, tMax, key, seed, counter, nullptr);
        if (t < tMax) {
            tMax = t, found = true;
            *collision = {t, i};
        }
    }
    return found;
}

float volumeTransmittance(const std::vector<Volume>& volumes, Vec3f origin, Vec3f direction, float tMax,
                          RandomKey key, uint32_t seed, uint32_t* counter) {
    float transmittance = 1.0f;
    for (const Volume& v : volumes) {
        trackVolume(v, origin, direction, tMax, key, seed, counter, &transmittance);
        if (!(transmittance > 0.0f)) return 0.0f;
    }
    return transmittance;
}

float henyeyGreenstein(float g, Vec3f travel, Vec3f scattered) {
    const float cosine = dot(travel, scattered);
    const float denominator = 1.0f + g * g - 2.0f * g * cosine;
    return (1.0f - g * g) / (4.0f * kPi * denominator * std::sqrt(std::fmax(denominator, 0.0f)));
}

Vec3f sampleHenyeyGreenstein(float g, Vec3f travel, float u1, float u2) {
    float cosine;
    if (std::fabs(g) < 1e-3f) {
        cosine = 1.0f - 2.0f * u1;
    } else {
        const float s = (1.0f - g * g) / (1.0f - g + 2.0f * g * u1);
        cosine = (1.0f + g * g - s * s) / (2.0f * g);
    }
    cosine = std::clamp(cosine, -1.0f, 1.0f);
    const float sine = std::sqrt(std::fmax(0.0f, 1.0f - cosine * cosine));
    const float phi = 2.0f * kPi * u2;
    return normalize(frameAround(travel).toWorld({sine * std::cos(phi), sine * std::sin(phi), cosine}));
}

}  // namespace vastray
