// Density volumes (core/Volume.h, core/src/Volume.cpp) in GLSL, step for step: trilinear
// density over bricks, a DDA over the brick cells, delta tracking (free flight) and ratio
// tracking (transmittance) with the cells' majorants, and the Henyey-Greenstein phase function.
// docs/RENDERING.md, "Volumes", specifies them. Needs WavefrontState.glsl, Random.glsl and
// Shading.glsl before it.
// Paged volumes (a pool of brick slots, docs/RENDERING.md "Volumes out of core"): before a cell
// is sampled its bricks must be resident; when one is not, the tracking parks there (a
// VolumePark: the cell, the walk's state and the random counter at the cell's start), asks
// for the bricks of that cell and of the next few along the ray (WavefrontParams::volumeDemand)
// and sets volumeMissed; the shading writes the park record and nothing else, and when the
// path shades again it resumes the tracking at that cell. Every value the tracking reads is a
// resident brick's, the same as in core, and a resumed walk continues with the same numbers:
// paged and in-core renders are equal bit for bit. A parked walk also marks the resident bricks
// it will read when it resumes (keepCell), which the pager then does not evict.
#ifndef VASTRAY_VOLUME_GLSL
#define VASTRAY_VOLUME_GLSL

const uint kVolumeBrickSize = 8u;
const uint kNoBrick = 0xFFFFFFFFu;
const uint kMaxVolumeSteps = 65536u;
const uint kDimVolume = 16u;

layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer VolumeArray { WavefrontVolume v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer VolumeUints { uint v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer VolumeFloats { float v[]; };

// Bricks are NanoVDB leaf nodes (core/VolumeLeaf.h), read with NanoVDB's own GLSL access
// (PNanoVDB.h) over buffer device addresses: a pnanovdb_buf_t is the address of one leaf.
#define PNANOVDB_GLSL
#define PNANOVDB_BUF_CUSTOM
#define pnanovdb_buf_t uint64_t
uint pnanovdb_buf_read_uint32(pnanovdb_buf_t buf, uint byte_offset) { return VolumeUints(buf).v[byte_offset >> 2u]; }
uvec2 pnanovdb_buf_read_uint64(pnanovdb_buf_t buf, uint byte_offset) {
    return uvec2(pnanovdb_buf_read_uint32(buf, byte_offset), pnanovdb_buf_read_uint32(buf, byte_offset + 4u));
}
#define pnanovdb_grid_type_t uint
#define PNANOVDB_GRID_TYPE_GET(grid_typeIn, nameIn) pnanovdb_grid_type_constants[grid_typeIn].nameIn
#include "nanovdb/PNanoVDB.h"

// Codecs (core/Volume.h's VolumeCodec), in the low bits of WavefrontVolume::leaves.
const uint kCodecFloat = 0u, kCodecFp16 = 1u, kCodecFp8 = 2u;
// Where a leaf's value table starts in what the device keeps of it (the leaf from its minimum on,
// core/VolumeLeaf.h's kVolumeLeafDeviceOffset = 80): NanoVDB's leaf_off_table, 96 for float, Fp16
// and Fp8 alike, less 80 (VolumeLeafTest checks both against PNanoVDB's tables); a quantized
// leaf's minimum and quantum, which PNanoVDB reads 16 and 12 bytes before the table, are the
// slot's first 8 bytes. The kernels do not index PNanoVDB's per-grid-type table
// (pnanovdb_grid_type_constants), which unoptimized SPIR-V copies (2.2 KB) into each call that
// reads it (the H100's driver removed it: no difference, PERF_NOTES 76).
const uint kLeafTableOffset = 16u;

// Which codecs the render's volumes use (wf_shade.comp's specialization constants 13-15, after its
// own; Wavefront.cpp's shadeConstants): a scene of one codec compiles that one read only.
layout(constant_id = 13) const bool kVolumeFloat = true;
layout(constant_id = 14) const bool kVolumeFp16 = true;
layout(constant_id = 15) const bool kVolumeFp8 = true;
const bool kOneVolumeCodec = uint(kVolumeFloat) + uint(kVolumeFp16) + uint(kVolumeFp8) == 1u;

// The value of voxel `o` (0-7 per axis) of the leaf at `leaf`, in the volume's codec, read as
// PNanoVDB reads a leaf's value: float at the table plus 4 per voxel in NanoVDB's order
// (pnanovdb_leaf_coord_to_offset), Fp16 and Fp8 through pnanovdb_leaf_fp16/fp8_read_float.
float leafValue(uint leaves, uint64_t leaf, ivec3 o) {
    pnanovdb_address_t table;
    table.byte_offset = kLeafTableOffset;
    const uint codec = leaves & 15u;
    if (kVolumeFp16 && (kOneVolumeCodec || codec == kCodecFp16)) return pnanovdb_leaf_fp16_read_float(leaf, table, o);
    if (kVolumeFp8 && (kOneVolumeCodec || codec == kCodecFp8)) return pnanovdb_leaf_fp8_read_float(leaf, table, o);
    return pnanovdb_read_float(leaf, pnanovdb_address_offset(table, 4u * pnanovdb_leaf_coord_to_offset(o)));
}

// The random numbers of one path vertex: key and the next dimension's offset from kDimVolume.
struct VolumeRandom {
    uint pixel, sampleIndex, bounce, seed, counter;
};
float nextVolumeRandom(inout VolumeRandom r) {
    return randomFloat(r.pixel, r.sampleIndex, r.bounce, kDimVolume + r.counter++, r.seed);
}
// The majorant's optical depth to the next tentative collision (core's trackVolume: drawn on
// entry and after each tentative collision, spent cell by cell).
float nextVolumeDepth(inout VolumeRandom r) { return -log(1.0 - nextVolumeRandom(r)); }

uvec3 volumeCells(WavefrontVolume v) { return uvec3(v.cellsX, v.cellsY, v.cellsZ); }

bool volumeMissed = false;  // this invocation's tracking parked (paged volumes)

// Kinds of request for a brick: one a parked walk waits for, one it asks for ahead.
const uint kWaitAsk = 0u, kAheadAsk = 1u;

// requestBrick: asks the pager for an absent brick (its cell table entry): counts a walk that
// waits for it (kWaitAsk) or asks for it ahead (kAheadAsk).
void requestBrick(WavefrontVolume v, uint entry, uint kind) {
    const uint brick = v.brickBase + (entry & ~kBrickAbsent);
    RwUintArray demand = RwUintArray(ParamsRef(pc.params).p.volumeDemand);
    atomicAdd(demand.v[kind * ParamsRef(pc.params).p.volumeBrickCount + brick], 1u);
    volumeMissed = true;
}

// relativeVoxel: the voxel of `voxels` (the density's or the emission grid's leaves) at index
// coordinates from the brick grid's origin; 0 outside.
float relativeVoxel(WavefrontVolume v, uint64_t voxels, ivec3 r) {
    const uvec3 cells = volumeCells(v);
    if (any(lessThan(r, ivec3(0))) || any(greaterThanEqual(uvec3(r), cells * kVolumeBrickSize))) return 0.0;
    const uvec3 c = uvec3(r) / kVolumeBrickSize, o = uvec3(r) % kVolumeBrickSize;
    const uint brick = VolumeUints(v.brickOf).v[c.x + cells.x * (c.y + cells.y * c.z)];
    if (brick == kNoBrick) return 0.0;
    if ((brick & kBrickAbsent) != 0u) {
        requestBrick(v, brick, kWaitAsk);
        return 0.0;
    }
    return leafValue(v.leaves, voxels + uint64_t(brick) * (v.leaves & ~15u), ivec3(o));
}

// relativeValue: trilinear, the same order of operations.
float relativeValue(WavefrontVolume v, uint64_t voxels, vec3 r) {
    const vec3 b = floor(r), f = r - b;
    const float limit = float(kVolumeBrickSize) * 16777216.0;
    if (!(all(greaterThanEqual(b, vec3(-1.0))) && all(lessThan(b, vec3(limit))))) return 0.0;
    const ivec3 i = ivec3(b);
    const float c00 = relativeVoxel(v, voxels, i) * (1.0 - f.x) + relativeVoxel(v, voxels, i + ivec3(1, 0, 0)) * f.x;
    const float c10 = relativeVoxel(v, voxels, i + ivec3(0, 1, 0)) * (1.0 - f.x) + relativeVoxel(v, voxels, i + ivec3(1, 1, 0)) * f.x;
    const float c01 = relativeVoxel(v, voxels, i + ivec3(0, 0, 1)) * (1.0 - f.x) + relativeVoxel(v, voxels, i + ivec3(1, 0, 1)) * f.x;
    const float c11 = relativeVoxel(v, voxels, i + ivec3(0, 1, 1)) * (1.0 - f.x) + relativeVoxel(v, voxels, i + ivec3(1, 1, 1)) * f.x;
    const float c0 = c00 * (1.0 - f.y) + c10 * f.y;
    const float c1 = c01 * (1.0 - f.y) + c11 * f.y;
    return c0 * (1.0 - f.z) + c1 * f.z;
}

float relativeDensity(WavefrontVolume v, vec3 r) { return relativeValue(v, v.voxels, r); }

// The blackbody table's nodes (core/Blackbody.h's constants).
const uint kBlackbodyTableSize = 4096u;
const float kBlackbodyMinKelvin = 100.0;
const float kMaxTemperature = 1e5;

// blackbodyRadiance: core's blackbodyRadiance, step for step (linear in the node index between
// log-spaced nodes).
vec3 blackbodyRadiance(uint64_t table, float kelvin) {
    const float last = float(kBlackbodyTableSize - 1u);
    const float scale = last / log(kMaxTemperature / kBlackbodyMinKelvin);
    const float x = kelvin > kBlackbodyMinKelvin ? min(log(kelvin / kBlackbodyMinKelvin) * scale, last) : 0.0;
    const uint i = min(uint(x), kBlackbodyTableSize - 2u);
    const float f = x - float(i);
    VolumeFloats t = VolumeFloats(table);
    const uint a = 3u * i;
    return vec3(t.v[a], t.v[a + 1u], t.v[a + 2u]) * (1.0 - f) + vec3(t.v[a + 3u], t.v[a + 4u], t.v[a + 5u]) * f;
}

// volumeEmission: the emitted radiance at a world point (an emission grid, or a temperature
// grid's blackbody radiance; else 0).
vec3 volumeEmission(WavefrontVolume v, vec3 p) {
    if (v.emissionVoxels == 0ul) return vec3(0.0);
    const float w[12] = v.worldToIndex;
    const vec3 i = vec3(w[0] * p.x + w[1] * p.y + w[2] * p.z + w[3], w[4] * p.x + w[5] * p.y + w[6] * p.z + w[7],
                        w[8] * p.x + w[9] * p.y + w[10] * p.z + w[11]);
    const float value = relativeValue(v, v.emissionVoxels, i - vec3(float(v.originX), float(v.originY), float(v.originZ)));
    if (v.blackbody != 0ul) return vec3(v.emitR, v.emitG, v.emitB) * blackbodyRadiance(v.blackbody, value);
    return vec3(v.emitR, v.emitG, v.emitB) * value;
}

// pageCell (paged volumes): the bricks that sampling in `cell` may read (its own and those of the
// cells after it along each axis, for the trilinear reads) are asked for when absent.
void pageCell(WavefrontVolume v, ivec3 cell, uint kind) {
    const uvec3 cells = volumeCells(v);
    for (uint n = 0u; n < 8u; ++n) {
        const uvec3 c = uvec3(cell) + uvec3(n & 1u, (n >> 1) & 1u, n >> 2);
        if (any(greaterThanEqual(c, cells))) continue;
        const uint entry = VolumeUints(v.brickOf).v[c.x + cells.x * (c.y + cells.y * c.z)];
        if (entry != kNoBrick && (entry & kBrickAbsent) != 0u) requestBrick(v, entry, kind);
    }
}

// keepCell (paged volumes): a walk parked at `cell` reads, once it resumes there, bricks of the
// cells within one cell of it (its trilinear reads touch the cells after it; rounding reaches one
// back); it marks the slots of those that are resident (the counters after the asks: one per
// slot), so that the pager does not evict them while it waits (DeviceVolumes::page).
void keepCell(WavefrontVolume v, ivec3 cell) {
    const ivec3 cells = ivec3(volumeCells(v));
    RwUintArray demand = RwUintArray(ParamsRef(pc.params).p.volumeDemand);
    const uint kept = 2u * ParamsRef(pc.params).p.volumeBrickCount;
    for (uint n = 0u; n < 27u; ++n) {
        const ivec3 c = cell + ivec3(int(n % 3u), int((n / 3u) % 3u), int(n / 9u)) - ivec3(1);
        if (any(lessThan(c, ivec3(0))) || any(greaterThanEqual(c, cells))) continue;
        const uint index = uint(c.x) + uint(cells.x) * (uint(c.y) + uint(cells.y) * uint(c.z));
        const uint entry = VolumeUints(v.brickOf).v[index];
        if (entry == kNoBrick || (entry & kBrickAbsent) != 0u) continue;
        if (demand.v[kept + entry] == 0u) atomicOr(demand.v[kept + entry], 1u);
    }
}

// Where a paged volume's tracking parked (per path, WavefrontParams::volumePark: four uvec4).
// phase: kParkNone, or the tracking it parked in: free flight (value: the nearest collision so
// far, found/which/tCollision: its volume and t) or transmittance (value: the transmittance so
// far, found/which/tCollision: the free flight's result); volume: the volume being tracked;
// counter, steps, cell, tNext, t, tau (the optical depth left to the next tentative collision):
// the walk's state at the start of the cell it waits at.
const uint kParkNone = 0u, kParkFreeFlight = 1u, kParkTransmittance = 2u;
// Cells along the ray past the one a tracking parks at whose bricks it asks for too.
const uint kPrefetchCells = 4u;
struct VolumePark {
    uint phase, volume, counter, steps;
    ivec3 cell;
    float t;
    vec3 tNext;
    float value, tCollision;
    uint which;
    bool found;
    float tau;
};

VolumePark noPark() { return VolumePark(kParkNone, 0u, 0u, 0u, ivec3(0), 0.0, vec3(0.0), 0.0, 0.0, 0u, false, 0.0); }

VolumePark loadPark(WavefrontParams p, uint j) {
    if (p.volumePark == 0ul) return noPark();
    UVec4Array a = UVec4Array(p.volumePark);
    const uvec4 w0 = a.v[4u * j], w1 = a.v[4u * j + 1u], w2 = a.v[4u * j + 2u], w3 = a.v[4u * j + 3u];
    return VolumePark(w0.x, w0.y, w0.z, w0.w, ivec3(w1.xyz), uintBitsToFloat(w1.w), uintBitsToFloat(w2.xyz),
                      uintBitsToFloat(w2.w), uintBitsToFloat(w3.x), w3.y, w3.z != 0u, uintBitsToFloat(w3.w));
}

void storePark(WavefrontParams p, uint j, VolumePark k) {
    UVec4Array a = UVec4Array(p.volumePark);
    a.v[4u * j] = uvec4(k.phase, k.volume, k.counter, k.steps);
    a.v[4u * j + 1u] = uvec4(uvec3(k.cell), floatBitsToUint(k.t));
    a.v[4u * j + 2u] = uvec4(floatBitsToUint(k.tNext), floatBitsToUint(k.value));
    a.v[4u * j + 3u] = uvec4(floatBitsToUint(k.tCollision), k.which, k.found ? 1u : 0u, floatBitsToUint(k.tau));
}

// Tracks one volume along the world ray within [0, tMax): with `ratio` false, delta tracking;
// returns the first real collision's t, or tMax. With `ratio` true, ratio tracking: multiplies
// `transmittance` and returns tMax. Cells are walked front to back (cellRay and walkCells); the
// optical depth to the next tentative collision is drawn first (whether or not the ray meets the
// grid) and after each tentative collision, and spent cell by cell, as core does.
// Paged: with `resume` the walk starts at park's cell and state instead of the ray's entry; at
// a cell with an absent brick it parks (fills park's walk state, rnd's counter and
// transmittance back at the cell's start), asks for the
// bricks of the next kPrefetchCells cells too, and returns tMax with volumeMissed set.
float trackVolume(WavefrontVolume v, vec3 origin, vec3 direction, float tMax, bool ratio, inout VolumeRandom rnd,
                  inout float transmittance, bool resume, inout VolumePark park) {
    const float w[12] = v.worldToIndex;
    const vec3 p = vec3(w[0] * origin.x + w[1] * origin.y + w[2] * origin.z + w[3],
                        w[4] * origin.x + w[5] * origin.y + w[6] * origin.z + w[7],
                        w[8] * origin.x + w[9] * origin.y + w[10] * origin.z + w[11]);
    const vec3 d = vec3(w[0] * direction.x + w[1] * direction.y + w[2] * direction.z,
                        w[4] * direction.x + w[5] * direction.y + w[6] * direction.z,
                        w[8] * direction.x + w[9] * direction.y + w[10] * direction.z);
    float tau = resume ? park.tau : nextVolumeDepth(rnd);
    const float inverse = 1.0 / float(kVolumeBrickSize);
    const vec3 ro = (p - vec3(float(v.originX), float(v.originY), float(v.originZ))) * inverse, rd = d * inverse;
    const uvec3 cells = volumeCells(v);
    float tEnter = 0.0, tExit = tMax;
    for (int a = 0; a < 3; ++a) {
        const float size = float(cells[a]);
        if (rd[a] == 0.0) {
            if (!(ro[a] >= 0.0 && ro[a] < size)) return tMax;
            continue;
        }
        float t0 = (0.0 - ro[a]) / rd[a], t1 = (size - ro[a]) / rd[a];
        if (t0 > t1) { const float s = t0; t0 = t1; t1 = s; }
        tEnter = max(tEnter, t0);
        tExit = min(tExit, t1);
    }
    if (!(tEnter < tExit)) return tMax;
    ivec3 cell, stepDir;
    vec3 tNext, tDelta;
    for (int a = 0; a < 3; ++a) {
        const float q = ro[a] + rd[a] * tEnter;
        cell[a] = clamp(int(floor(q)), 0, int(cells[a]) - 1);
        if (rd[a] > 0.0) {
            stepDir[a] = 1, tDelta[a] = 1.0 / rd[a];
            tNext[a] = (float(cell[a] + 1) - ro[a]) / rd[a];
        } else if (rd[a] < 0.0) {
            stepDir[a] = -1, tDelta[a] = -1.0 / rd[a];
            tNext[a] = (float(cell[a]) - ro[a]) / rd[a];
        } else {
            stepDir[a] = 0, tDelta[a] = kInfinity, tNext[a] = kInfinity;
        }
    }
    const float scale = v.densityScale;
    VolumeFloats majorants = VolumeFloats(v.majorant);
    const bool paged = ParamsRef(pc.params).p.volumeDemand != 0ul;
    uint steps = 0u;
    float t = tEnter;
    if (resume) cell = park.cell, tNext = park.tNext, t = park.t, steps = park.steps;
    uint prefetch = 0u;  // parked: cells with density whose bricks were asked for since
    while (t < tExit) {
        const int axis = tNext.x <= tNext.y ? (tNext.x <= tNext.z ? 0 : 2) : (tNext.y <= tNext.z ? 1 : 2);
        const float end = min(tNext[axis], tExit);
        if (end > t) {
            const uint index = uint(cell.x) + cells.x * (uint(cell.y) + cells.y * uint(cell.z));
            const float majorant = majorants.v[index] * scale;
            if (volumeMissed) {
                if (majorant > 0.0) {
                    pageCell(v, cell, kAheadAsk);
                    if (++prefetch >= kPrefetchCells) return tMax;
                }
            } else if (majorant > 0.0) {
                // The cell's start: where a walk that misses a brick in it parks.
                const uint startCounter = rnd.counter, startSteps = steps;
                const float startTransmittance = transmittance, startTau = tau;
                if (paged) pageCell(v, cell, kWaitAsk);
                float s = t;
                while (!volumeMissed) {
                    const float next = s + tau / majorant;
                    if (!(next < end)) {
                        tau = max(0.0, tau - majorant * (end - s));
                        break;
                    }
                    s = next;
                    if (!ratio && ++steps > kMaxVolumeSteps) return s;
                    const float density = relativeDensity(v, (ro + rd * s) * float(kVolumeBrickSize)) * scale;
                    if (volumeMissed) break;
                    if (ratio) {
                        transmittance *= max(0.0, 1.0 - density / majorant);
                        if (++steps > kMaxVolumeSteps) transmittance = 0.0;
                        if (!(transmittance > 0.0)) return tMax;
                    } else if (nextVolumeRandom(rnd) * majorant < density) {
                        return s;
                    }
                    tau = nextVolumeDepth(rnd);
                }
                if (volumeMissed) {
                    rnd.counter = startCounter, steps = startSteps, transmittance = startTransmittance, tau = startTau;
                    park.cell = cell, park.tNext = tNext, park.t = t, park.steps = steps, park.counter = rnd.counter;
                    park.tau = tau;
                    keepCell(v, cell);
                }
            }
        }
        t = max(t, end);
        cell[axis] += stepDir[axis];
        if (cell[axis] < 0 || cell[axis] >= int(cells[axis])) break;
        tNext[axis] += tDelta[axis];
    }
    return tMax;
}

// sampleVolumeCollision: the nearest real collision among the volumes before tMax. Paged: a
// park in free flight resumes there; a tracking that parks fills park (phase kParkFreeFlight)
// and returns false with volumeMissed set.
bool sampleVolumeCollision(WavefrontParams p, vec3 origin, vec3 direction, float tMax, inout VolumeRandom rnd,
                           out float tCollision, out uint which, inout VolumePark park) {
    bool found = false;
    tCollision = tMax, which = 0u;
    float unused = 1.0;
    const bool resume = park.phase == kParkFreeFlight;
    uint first = 0u;
    if (resume) {
        first = park.volume, tMax = park.value, found = park.found, tCollision = park.tCollision, which = park.which;
        rnd.counter = park.counter;
    }
    for (uint i = first; i < p.volumeCount; ++i) {
        const float t = trackVolume(VolumeArray(p.volumes).v[i], origin, direction, tMax, false, rnd, unused,
                                    resume && i == first, park);
        if (volumeMissed) {
            park.phase = kParkFreeFlight, park.volume = i, park.value = tMax;
            park.found = found, park.tCollision = tCollision, park.which = which;
            return false;
        }
        if (t < tMax) tMax = t, found = true, tCollision = t, which = i;
    }
    return found;
}

// volumeTransmittance: ratio tracking through every volume up to tMax. Paged: a park in
// transmittance resumes there; a tracking that parks fills park (phase kParkTransmittance; the
// caller keeps the free flight's result in it) and returns 0 with volumeMissed set.
float volumeTransmittance(WavefrontParams p, vec3 origin, vec3 direction, float tMax, inout VolumeRandom rnd,
                          inout VolumePark park) {
    float transmittance = 1.0;
    const bool resume = park.phase == kParkTransmittance;
    uint first = 0u;
    if (resume) first = park.volume, transmittance = park.value, rnd.counter = park.counter;
    for (uint i = first; i < p.volumeCount && transmittance > 0.0; ++i) {
        trackVolume(VolumeArray(p.volumes).v[i], origin, direction, tMax, true, rnd, transmittance, resume && i == first,
                    park);
        if (volumeMissed) {
            park.phase = kParkTransmittance, park.volume = i, park.value = transmittance;
            return 0.0;
        }
    }
    return transmittance > 0.0 ? transmittance : 0.0;
}

float henyeyGreenstein(float g, vec3 travel, vec3 scattered) {
    const float cosine = dot(travel, scattered);
    const float denominator = 1.0 + g * g - 2.0 * g * cosine;
    return (1.0 - g * g) / (4.0 * kPi * denominator * sqrt(max(denominator, 0.0)));
}

vec3 sampleHenyeyGreenstein(float g, vec3 travel, float u1, float u2) {
    float cosine;
    if (abs(g) < 1e-3) {
        cosine = 1.0 - 2.0 * u1;
    } else {
        const float s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u1);
        cosine = (1.0 + g * g - s * s) / (2.0 * g);
    }
    cosine = clamp(cosine, -1.0, 1.0);
    const float sine = sqrt(max(0.0, 1.0 - cosine * cosine));
    const float phi = 2.0 * kPi * u2;
    return normalize(toWorld(travel, vec3(sine * cos(phi), sine * sin(phi), cosine)));
}

// unshadowedMediumLight: the sun's or (withMap) the environment map's light scattered by the
// phase function towards the ray, the volume's albedo and the path's throughput not applied;
// false: no shadow ray. Needs Environment.glsl.
bool mediumDirectLight(WavefrontParams p, bool withMap, vec3 travel, float g, uint pixel, uint sampleIndex,
                       uint bounce, out vec3 light, out vec3 direction) {
    const float pickSun = withMap ? p.sunPick : 1.0;
    light = vec3(0.0);
    direction = vec3(p.sunX, p.sunY, p.sunZ);
    if (pickSun >= 1.0 || (pickSun > 0.0 && randomFloat(pixel, sampleIndex, bounce, kDimLightPick, p.seed) < pickSun)) {
        const vec3 irradiance = vec3(p.sunR, p.sunG, p.sunB);
        if (!(maxComponent(irradiance) > 0.0)) return false;
        light = irradiance * (henyeyGreenstein(g, travel, direction) / pickSun);
        return true;
    }
    vec3 radiance;
    float pdf;
    direction = sampleEnvironment(p, randomFloat(pixel, sampleIndex, bounce, kDimLightU, p.seed),
                                  randomFloat(pixel, sampleIndex, bounce, kDimLightV, p.seed), radiance, pdf);
    if (!(pdf > 0.0)) return false;
    const float phase = henyeyGreenstein(g, travel, direction);
    const float lightPdf = (1.0 - pickSun) * pdf;
    light = radiance * (phase * powerHeuristic(lightPdf, phase) / lightPdf);
    return true;
}

#endif  // VASTRAY_VOLUME_GLSL
