// Density volumes (core/Volume.h, core/src/Volume.cpp) in GLSL, step for step: trilinear
// density over bricks, a DDA over the brick cells, delta tracking (free flight) and ratio
// tracking (transmittance) with the cells' majorants, and the Henyey-Greenstein phase function.
// docs/RENDERING.md, "Volumes", specifies them. Needs WavefrontState.glsl, Random.glsl and
// Shading.glsl before it.
// Paged volumes (a pool of brick slots, docs/RENDERING.md "Volumes out of core"): a read whose
// brick is absent asks for it (WavefrontParams::volumeDemand), sets volumeMissed and reads 0;
// the tracking then only walks on, asking for the absent bricks of the cells the ray crosses,
// and the caller drops the whole shading of the path, which waits and shades again from the
// start once the bricks are resident. A shading that finishes has read only resident bricks,
// the same values as in core: paged and in-core renders are equal bit for bit.
#ifndef VASTRAY_VOLUME_GLSL
#define VASTRAY_VOLUME_GLSL

const uint kVolumeBrickSize = 8u;
const uint kNoBrick = 0xFFFFFFFFu;
const uint kMaxVolumeSteps = 65536u;
const uint kDimVolume = 16u;

layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer VolumeArray { WavefrontVolume v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer VolumeUints { uint v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer VolumeFloats { float v[]; };

// The random numbers of one path vertex: key and the next dimension's offset from kDimVolume.
struct VolumeRandom {
    uint pixel, sampleIndex, bounce, seed, counter;
};
float nextVolumeRandom(inout VolumeRandom r) {
    return randomFloat(r.pixel, r.sampleIndex, r.bounce, kDimVolume + r.counter++, r.seed);
}

uvec3 volumeCells(WavefrontVolume v) { return uvec3(v.cellsX, v.cellsY, v.cellsZ); }

bool volumeMissed = false;  // this invocation read an absent brick (paged volumes)
uint volumePath = 0u;       // the path this invocation shades: its bricks' priority (lower first)

// requestBrick: asks the pager for an absent brick (its cell table entry), at the priority of
// the lowest path that asks.
void requestBrick(WavefrontVolume v, uint entry) {
    atomicMin(RwUintArray(ParamsRef(pc.params).p.volumeDemand).v[v.brickBase + (entry & ~kBrickAbsent)], volumePath);
    volumeMissed = true;
}

// relativeVoxel: the voxel of `voxels` (the density's or the emission grid's) at index
// coordinates from the brick grid's origin; 0 outside.
float relativeVoxel(WavefrontVolume v, uint64_t voxels, ivec3 r) {
    const uvec3 cells = volumeCells(v);
    if (any(lessThan(r, ivec3(0))) || any(greaterThanEqual(uvec3(r), cells * kVolumeBrickSize))) return 0.0;
    const uvec3 c = uvec3(r) / kVolumeBrickSize, o = uvec3(r) % kVolumeBrickSize;
    const uint brick = VolumeUints(v.brickOf).v[c.x + cells.x * (c.y + cells.y * c.z)];
    if (brick == kNoBrick) return 0.0;
    if ((brick & kBrickAbsent) != 0u) {
        requestBrick(v, brick);
        return 0.0;
    }
    return VolumeFloats(voxels).v[brick * 512u + o.x + kVolumeBrickSize * (o.y + kVolumeBrickSize * o.z)];
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

// volumeEmission: the emitted radiance at a world point (an emission grid; else 0).
vec3 volumeEmission(WavefrontVolume v, vec3 p) {
    if (v.emissionVoxels == 0ul) return vec3(0.0);
    const float w[12] = v.worldToIndex;
    const vec3 i = vec3(w[0] * p.x + w[1] * p.y + w[2] * p.z + w[3], w[4] * p.x + w[5] * p.y + w[6] * p.z + w[7],
                        w[8] * p.x + w[9] * p.y + w[10] * p.z + w[11]);
    const float value = relativeValue(v, v.emissionVoxels, i - vec3(float(v.originX), float(v.originY), float(v.originZ)));
    return vec3(v.emitR, v.emitG, v.emitB) * value;
}

// pageCell (paged volumes): the bricks that sampling in `cell` may read (its own and those of the
// cells after it along each axis, for the trilinear reads) are asked for when absent, and their
// slots marked used (by the lowest path) when resident and nothing was missed.
void pageCell(WavefrontVolume v, ivec3 cell, uint64_t used) {
    const uvec3 cells = volumeCells(v);
    for (uint n = 0u; n < 8u; ++n) {
        const uvec3 c = uvec3(cell) + uvec3(n & 1u, (n >> 1) & 1u, n >> 2);
        if (any(greaterThanEqual(c, cells))) continue;
        const uint entry = VolumeUints(v.brickOf).v[c.x + cells.x * (c.y + cells.y * c.z)];
        if (entry == kNoBrick) continue;
        if ((entry & kBrickAbsent) != 0u)
            requestBrick(v, entry);
        else if (!volumeMissed && RwUintArray(used).v[entry] > volumePath)
            atomicMin(RwUintArray(used).v[entry], volumePath);
    }
}

// Tracks one volume along the world ray within [0, tMax): with `ratio` false, delta tracking;
// returns the first real collision's t, or tMax. With `ratio` true, ratio tracking: multiplies
// `transmittance` and returns tMax. Cells are walked front to back (cellRay and walkCells).
// Paged: a cell it samples marks its brick's slot used; once volumeMissed is set it samples no
// more, asks for the absent bricks of the cells with density it crosses, and returns tMax.
float trackVolume(WavefrontVolume v, vec3 origin, vec3 direction, float tMax, bool ratio, inout VolumeRandom rnd,
                  inout float transmittance) {
    const float w[12] = v.worldToIndex;
    const vec3 p = vec3(w[0] * origin.x + w[1] * origin.y + w[2] * origin.z + w[3],
                        w[4] * origin.x + w[5] * origin.y + w[6] * origin.z + w[7],
                        w[8] * origin.x + w[9] * origin.y + w[10] * origin.z + w[11]);
    const vec3 d = vec3(w[0] * direction.x + w[1] * direction.y + w[2] * direction.z,
                        w[4] * direction.x + w[5] * direction.y + w[6] * direction.z,
                        w[8] * direction.x + w[9] * direction.y + w[10] * direction.z);
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
    const uint64_t used = ParamsRef(pc.params).p.volumeUsed;  // 0: in core
    uint steps = 0u;
    float t = tEnter;
    while (t < tExit) {
        const int axis = tNext.x <= tNext.y ? (tNext.x <= tNext.z ? 0 : 2) : (tNext.y <= tNext.z ? 1 : 2);
        const float end = min(tNext[axis], tExit);
        if (end > t) {
            const uint index = uint(cell.x) + cells.x * (uint(cell.y) + cells.y * uint(cell.z));
            const float majorant = majorants.v[index] * scale;
            if (majorant > 0.0 && used != 0ul) pageCell(v, cell, used);
            if (majorant > 0.0 && !volumeMissed) {
                float s = t;
                for (;;) {
                    s -= log(1.0 - nextVolumeRandom(rnd)) / majorant;
                    if (!(s < end)) break;
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

// sampleVolumeCollision: the nearest real collision among the volumes before tMax.
bool sampleVolumeCollision(WavefrontParams p, vec3 origin, vec3 direction, float tMax, inout VolumeRandom rnd,
                           out float tCollision, out uint which) {
    bool found = false;
    tCollision = tMax, which = 0u;
    float unused = 1.0;
    for (uint i = 0u; i < p.volumeCount; ++i) {
        const float t = trackVolume(VolumeArray(p.volumes).v[i], origin, direction, tMax, false, rnd, unused);
        if (t < tMax) tMax = t, found = true, tCollision = t, which = i;
    }
    return found;
}

// volumeTransmittance: ratio tracking through every volume up to tMax.
float volumeTransmittance(WavefrontParams p, vec3 origin, vec3 direction, float tMax, inout VolumeRandom rnd) {
    float transmittance = 1.0;
    for (uint i = 0u; i < p.volumeCount && transmittance > 0.0; ++i)
        trackVolume(VolumeArray(p.volumes).v[i], origin, direction, tMax, true, rnd, transmittance);
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
