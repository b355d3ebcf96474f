// Structs that cross the host/device line for the device wavefront (wf_*.comp): the render's
// parameters, kept in device memory and read by every kernel through one address, and the one
// push-constant block all wavefront kernels share. Compiled both as C++ (layout checked by
// static_assert) and as GLSL (scalar members only, 64-bit members first, so std430 and C++ agree).
// GLSL needs GL_EXT_shader_explicit_arithmetic_types_int64 enabled before including this.
#ifndef VASTRAY_GPU_SHARED_WAVEFRONT_TYPES_H
#define VASTRAY_GPU_SHARED_WAVEFRONT_TYPES_H

#ifdef __cplusplus
#include <cstddef>
#include <cstdint>
namespace vastray::gpu {
using uint = uint32_t;
#endif

const uint kWavefrontWorkgroupSize = 64u;

// Path flags: the low kPathFlagBits bits of a path's word (WavefrontParams::pathInfo .y), above
// them its bounce (kPathBounceBits: the closest-hit ray's, at most kMaxDepthLimit + 1) and its
// sample index (the high 16 bits: at most kMaxSamplesPerPixel - 1).
const uint kPathFlagBits = 5u;
const uint kPathBounceShift = 5u;
const uint kPathBounceBits = 11u;
const uint kPathSampleShift = 16u;
const uint kPathAlive = 1u;          // has a closest-hit ray to trace at the next stream
const uint kPathShadowPending = 2u;  // has a shadow ray in the current stream
const uint kPathCameraHit = 4u;      // its camera ray hit geometry (alpha)
// A path's walk bits: its rays still being walked (the walk clears its ray's bit with an atomic,
// and the last of a path's rays to finish queues the path for shading). They lie in its word
// (kPathWalkShift up) where the path state lies in device memory; with the state in host memory
// in a byte a path of their own on the device, so that those atomics do not cross the bus
// (WavefrontParams::walkBits, walkBitsApart).
const uint kWalkClosest = 1u;  // its closest-hit ray
const uint kWalkShadow = 2u;   // its shadow ray
const uint kPathWalkShift = 3u;

// Walk state flags (rayState .x), besides kHitFound and kHitFrontFacing.
const uint kRayPending = 4u;      // still to be walked: started, or parked at a cell whose chunk was not resident
const uint kRayFromSurface = 8u;  // leaves a surface: hits within t's rounding error are refused
// rayState .x above its flags, for a parked ray: the cells it has done (traced) among the
// kRayDoneBits cells that follow, in the order of its walk, the first one it waits for (bit i:
// the (i + 1)-th such cell; cells before the first one it waits for are all done or pruned).
const uint kRayDoneShift = 8u;
const uint kRayDoneBits = 24u;

// The ray queues (2 * pathCapacity ray indices each): the walk queue, the rays generate and shade
// start, which every walk pass walks (and empties); and two park queues, the rays a paging step
// parks (WavefrontPush::parkQueue) and those the step before parked, which only the step's first
// pass walks: nothing else becomes resident during a step (docs/RENDERING.md, "Paging steps").
const uint kWalkQueue = 0u;
const uint kParkQueue = 1u;  // and kParkQueue + 1
// The queue of paths ready to shade (WavefrontParams::queues, queueCounts), and the queue of
// paths whose shading read a volume brick or a texture page that was not resident (volumes or
// textures paged through a pool of slots): they shade again once the host has loaded what they
// asked for. wf_aov.comp uses both for the pixels whose albedo waits for a texture page.
const uint kShadeQueue = 3u;
const uint kShadeWaitQueue = 4u;
// Streamed waves (out of core): the two queues of path groups whose block of samples is done or
// that have none (pathCapacity entries each): wf_generate takes one and appends those it could
// not give a pixel to the other (2 * kGroupQueue + 1 - q: kGroupQueue is odd, no XOR). With
// restarts in the shading (kKernelRestartGroups) the shading restarts the groups it
// ends and queues only the idle ones; wf_generate then runs once a paging step, for those.
const uint kGroupQueue = 5u;
const uint kQueueCount = 7u;

// WavefrontPush::kernelFlags.
// wf_shade.comp, streamed waves: restart the groups whose block it ends (common/StreamGroups.glsl),
// else queue them on groupQueue for wf_generate.comp.
const uint kKernelRestartGroups = 1u;

// Streamed waves: the most tiles open at once (the window; a tile holds about a wave's groups, so
// a window wider than 16 tiles needs an output buffer larger than the wave: PoolPlan::outputPixels),
// and a group's state (WavefrontParams::groupState .x) between blocks.
const uint kMaxWindowTiles = 32u;
const uint kGroupIdle = 0xffffffffu;

// A paged volume's cell table entry (WavefrontVolume::brickOf) for a brick that is not resident:
// the brick's index within the volume with this bit set (kNoBrick, all ones, has no brick).
const uint kBrickAbsent = 0x80000000u;

// WavefrontPush::mode of wf_generate.comp.
const uint kGeneratePaths = 0u;  // jittered camera rays of (pixel, sample) paths
const uint kGenerateAov = 1u;    // one unjittered ray through each pixel centre
const uint kGenerateStream = 2u; // streamed waves: the groups of queue pc.groupQueue add their finished
                                 // block to their pixel's sum and start their next block or pixel;
                                 // with pc.pixelCount = G > 0 every group 0..G-1 instead (all idle)

// WavefrontPush::mode of wf_aov.comp: every pixel of the tile, or the pixels of kShadeQueue (those
// whose albedo waited for texture pages, which are resident now).
const uint kAovPixels = 0u;
const uint kAovRetry = 1u;

// WavefrontPush::mode of wf_walk.comp and wf_shade.comp: a tile's wave (the cost AOV's pixel of
// path j is j / sampleCount), or streamed waves (its group's window pixel; a group whose block's
// last path ends is queued on pc.groupQueue).
const uint kWaveTiled = 0u;
const uint kWaveStreamed = 1u;

// Device bytes per path of the state arrays (one ray origin both its rays share, two rays'
// directions and walk states, the closest hit's record, three path vectors and its pixel and
// word, a slot in each of the three ray queues for each ray, a slot in the shade queue and one
// in the volume wait queue, and per two paths a group's state and a slot in each of the two
// group queues: streamed waves' groups have two paths or more) and per tile pixel (the sum, the
// colour and the AOVs at most). The host sizes waves from the budget with these.
const uint kBytesPerPath = 16u + 2u * (16u + 8u) + 3u * 16u + 3u * 16u + 8u + 3u * 2u * 4u + 2u * 4u + (8u + 2u * 4u) / 2u;
const uint kBytesPerTilePixel = 16u + 16u + 4u + 12u + 12u + 4u + 4u + 8u + 8u;
// Per path besides, when the render reads the scene's texture coordinates: the closest hit's UV
// and its triangle's world area per unit of UV area (WavefrontParams::hitUv, kHitUvFloats
// floats); with normal maps too, the hit's UV derivatives (hitFrame, 6 floats).
const uint kHitUvFloats = 3u;
const uint kBytesPerPathUv = 4u * kHitUvFloats;
const uint kBytesPerPathFrame = 24u;

// A material as the shading kernel reads it (vastray::Material).
struct WavefrontMaterial {
    float baseR, baseG, baseB;
    float emitR, emitG, emitB;
    uint doubleSided;
    float metallic;
    float roughness;
    float specular;
    float specularColorR, specularColorG, specularColorB;  // KHR_materials_specular's colour factor
    float clearcoat, clearcoatRoughness;                    // KHR_materials_clearcoat's factors
    uint alphaBlend;  // 1: a blend (core isBlended): the walk keeps a hit with the probability of its alpha
    // Its maps (core/MaterialTextures.h, common/MaterialMaps.glsl): the texture (an index into
    // WavefrontParams::textures, or kNoGpuTexture) and the UV transform (row-major 2 x 3) of the
    // base colour, metallic-roughness, emissive and normal maps, and the normal map's scale. The
    // occlusion map is not applied (by design: docs/RENDERING.md, "Normal maps").
    uint baseColorMap, metallicRoughnessMap, emissiveMap, normalMap;
    float baseColorUv[6];
    float metallicRoughnessUv[6];
    float emissiveUv[6];
    float normalUv[6];
    float normalScale;
    float alphaCutoff;  // a cut-out's (Material::alphaCutoff; 0: opaque): the walk's any-hit test
    float baseAlpha;    // the base colour factor's alpha, which the cut-out test multiplies
    // Sampled emissive triangles (core/Emitters.h): the density per unit area with which
    // next-event estimation's emitter branch draws a point on a triangle of this material
    // (EmitterTable::areaDensity); 0: not sampled (its emission is found by chance alone).
    float emitterDensity;
    // KHR_materials_clearcoat's maps (package format 13): the coat weight's (R) and the coat
    // roughness's (G), as the maps above; read only where the coat's factor is above 0.
    uint clearcoatMap, clearcoatRoughnessMap;
    float clearcoatUv[6];
    float clearcoatRoughnessUv[6];
    float dielectricF0;  // the specular layer's F0 for its ior (core iorF0: KHR_materials_ior)
    uint padding0;
};

// An emissive triangle as next-event estimation picks it (vastray::EmitterEntry): its corners,
// its material, and its alias column (kept when u < keep, else `alias`).
struct WavefrontEmitter {
    float v0x, v0y, v0z;
    uint material;
    float v1x, v1y, v1z;
    float keep;
    float v2x, v2y, v2z;
    uint alias;
    float t0u, t0v, t1u, t1v, t2u, t2v;  // the corners' UVs (an emissive map reads the point's)
    float padding0, padding1;
};

// A punctual light as the shading kernel reads it (vastray::LightEntry, core/Light.h): type
// (vastray::LightType), colour times intensity, the spot's falloff, its pick probability and the
// running sum of those (the last is 1).
struct WavefrontLight {
    float posX, posY, posZ;
    uint type;
    float dirX, dirY, dirZ;  // unit: where the light shines
    float cdf;
    float radiantR, radiantG, radiantB;
    float pick;
    float coneScale, coneOffset;
    uint padding0, padding1;
};

// The metallic-roughness albedo tables' side (core/Microfacet.h's kMicrofacetTableSide; the
// tables: two of side x side floats, then side floats).
const uint kMicrofacetSide = 32u;

// A density volume as the shading kernel reads it (core/Volume.h): its brick table (uint per
// cell), majorants (float per cell), bricks as NanoVDB leaves of its codec (`leaves` bytes apart)
// and the emission grid's leaves of the same bricks (0: none), its map from world to index space (row-major
// 3 x 4), brick grid and material. Paged (a pool of brick slots): the table holds each cell's
// slot (or kBrickAbsent | brick), voxels and emissionVoxels are the pools' slot arrays, and
// brickBase is the volume's first brick among all volumes' (WavefrontParams::volumeDemand).
struct WavefrontVolume {
    uint64_t brickOf;
    uint64_t majorant;
    uint64_t voxels;
    uint64_t emissionVoxels;
    float worldToIndex[12];
    int originX, originY, originZ;
    uint cellsX, cellsY, cellsZ;
    float albedoR, albedoG, albedoB;
    float densityScale;
    float anisotropy;
    float emitR, emitG, emitB;
    uint brickBase;
    uint leaves;  // its bricks' NanoVDB leaves from their minimum on: their stride in bytes (a multiple of 16) | codec
    uint64_t blackbody;  // a temperature grid's table (core/Blackbody.h, vec3 per node); 0: radiance
};

// Everything a render's kernels read, written by the host once per render. Addresses are
// buffer device addresses. Rays and their walk states are arrays of 2 * pathCapacity entries:
// path j's closest-hit ray at j, its shadow ray at pathCapacity + j; the hit records (closest-hit
// rays only) have pathCapacity entries.
struct WavefrontParams {
    uint64_t slotTable;    // ChunkSlot per slot
    uint64_t topNodes;     // the package's top-level tree (KdNode; a leaf's first word is its chunk)
    uint64_t chunkSlots;   // per chunk: its slot, or kWalkNoHit when not resident
    uint64_t touched;      // per chunk: set to 1 when a ray traces one of its cells
    uint64_t demand;       // per chunk: rays parked at one of its cells (last walk pass); [chunkCount]:
                           // all parked rays; [chunkCount + 1]: rays started (camera, shadow, bounce)
    uint64_t ahead;        // per chunk: parked rays (of the last walk pass) that wait for one of its
                           // cells besides the first one they wait for
    uint64_t materials;    // WavefrontMaterial per material
    uint64_t rayOrigin;    // vec4 per path: the origin both its rays start from, and (w) its ray
                           // cone's width there (core/RayCone.h; 0 without textures): a shadow
                           // ray and the bounce start at the same scattering event
    uint64_t rayDirection; // vec4 per ray: direction, tMax (the walk starts at t = 0)
    uint64_t rayState;     // uvec2: walk flags (kHitFound, kHitFrontFacing, kRayPending,
                           // kRayFromSurface) and the cells done beyond the first it waits for
                           // (kRayDoneShift), the top-level leaf of that first cell + 1 or 0
    uint64_t hitPosition;  // vec4 per path: its closest hit's position, t
    uint64_t hitNormal;    // uvec4 per path: geometric normal's float bits (not normalized), shading normal
                           // (octahedral code at the hit, or kNoNormal; core/VertexAttributes.h)
    uint64_t hitIds;       // uvec4 per path: primitive, material, chunk, colour at the hit (10-bit linear
                           // channels; white without vertex colours)
    uint64_t throughput;   // vec4 per path: throughput, and the solid-angle density of the bounce
                           // that started its closest-hit ray (environment maps' MIS weight)
    uint64_t radiance;     // vec4 per path: radiance, and (w) its ray cone's spread angle (0 without textures)
    uint64_t pendingSun;   // vec4 per path: next-event estimation's light (the sun's or the
                           // environment map's), added if the shadow ray is unblocked
    uint64_t pathInfo;     // uvec2 per path: pixel, and its word: flags, the bounce of its closest-hit
                           // ray and its sample (kPathFlagBits, kPathBounceShift, kPathSampleShift)
    uint64_t walkBits;     // the paths' walk bits (kWalkClosest, kWalkShadow): with walkBitsApart a
                           // byte a path, four paths a word, in a buffer of their own on the device
                           // (the state lies in host memory); else pathInfo (each path's word)
    uint64_t queues;       // three ray queues of 2 * pathCapacity ray indices each (queue q at
                           // queues + q * 8 * pathCapacity bytes): the walk queue and the two park
                           // queues (kWalkQueue, kParkQueue); then the shade queue (kShadeQueue) of
                           // pathCapacity path indices: the paths whose rays are all walked; the
                           // volume wait queue (pathCapacity); the two group queues (groupCapacity)
    uint64_t queueCounts;  // kQueueCount uints: the entries of each queue
    uint64_t queueArgs;    // per queue a VkDispatchIndirectCommand (x, 1, 1): x = the workgroups of
                           // one thread per entry (the walk and shading are dispatched from them)
    uint64_t accum;        // vec4 per tile pixel: radiance sum, camera hits
    uint64_t outColor;     // vec4 per tile pixel: mean radiance, alpha
    uint64_t outDepth;     // float per tile pixel
    uint64_t outNormal;    // float[3] per tile pixel
    uint64_t outAlbedo;    // float[3] per tile pixel
    uint64_t outPrimId;    // uint per tile pixel
    uint64_t outChunkId;   // uint per tile pixel
    uint64_t outCost;      // uint[2] per tile pixel: cells traced, triangles tested
    uint64_t envRgb;       // the environment map (core/EnvironmentMap.h), when the render has one:
    uint64_t envDensity;   // float[3] per texel, its density, the rows' CDF (envHeight + 1) and
    uint64_t envMarginal;  // each row's CDF (envWidth + 1 per row)
    uint64_t envConditional;
    uint64_t volumes;      // WavefrontVolume per volume (volumeCount)
    uint64_t volumeDemand; // paged volumes (0: in core): per brick (brickBase + brick), the parked walks
                           // that wait for it; then per brick the walks that ask for it ahead; then
                           // per slot the parked walks that keep its brick (Volume.glsl's keepCell)
    uint64_t volumePark;   // paged volumes: per path four uvec4, where its volume tracking parked
                           // (common/Volume.glsl, VolumePark; zero: nowhere)
    uint64_t microfacet;   // the metallic-roughness BSDF's albedo tables (core/Microfacet.h,
                           // kMicrofacetTableFloats floats) when some material is glossy
    uint64_t groupState;   // streamed waves: uvec2 per group of sampleCount >= 2 paths (groupCapacity
                           // entries, (pathCapacity + 1) / 2): paths of its block
                           // still running (kGroupIdle: no block), its pixel's index in the window's
                           // outputs (ring slot * tilePixels + pixel in the tile)
    uint64_t stream;       // streamed waves (table buffer): StreamWindow
    uint64_t lights;       // WavefrontLight per punctual light (lightCount)
    uint64_t hitUv;        // kHitUvFloats floats per path: texture coordinates at its closest hit and
                           // its triangle's world area per unit of UV area (core/RayCone.h
                           // worldPerUvArea), written when the hit's slot holds UVs (kSlotUvs); 0
                           // when the render reads none
    uint64_t outUv;        // float[2] per tile pixel: the uv AOV
    uint64_t textures;        // the render's textures (gpu/src/DeviceTextures.h): GpuTexture per texture,
    uint64_t texturePages;    // the page table (a pool slot, or kTexturePageAbsent, per page of every
    uint64_t texturePool;     // texture), the pool (kGpuTexturePageWords per slot) and, paged, per page
    uint64_t textureDemand;   // the paths waiting that read it (0: in core, no page is ever absent)
    uint64_t hitFrame;        // float[6] per path: dp/du and dp/dv of its closest hit's triangle in its
                              // normal map's texture space (core/NormalMap.h uvDerivatives; zero: no
                              // frame), written by the walk; 0 when no material has a normal map
    uint64_t emitters;        // WavefrontEmitter per sampled emissive triangle (emitterCount)
    float eyeX, eyeY, eyeZ;
    float forwardX, forwardY, forwardZ;
    float rightX, rightY, rightZ;  // scaled by the half width of the image plane
    float upX, upY, upZ;           // scaled by its half height
    float width, height;
    float zenithR, zenithG, zenithB;
    float horizonR, horizonG, horizonB;
    float groundR, groundG, groundB;
    float skyUpX, skyUpY, skyUpZ;  // unit: the sky's zenith (Environment::up)
    float sunX, sunY, sunZ;  // unit
    float sunR, sunG, sunB;  // irradiance; zero: no sun
    float aoDistance;        // 0: unbounded
    float boundsLoX, boundsLoY, boundsLoZ;  // the package bounds (the top-level tree's)
    float boundsHiX, boundsHiY, boundsHiZ;
    uint imageWidth;
    uint materialCount;
    uint seed;
    uint samplesPerPixel;
    uint maxDepth;
    uint aovs;         // vastray::AovFlags
    uint pathCapacity; // paths the state arrays hold
    uint chunkCount;
    uint topNodeCount;
    uint envWidth, envHeight;  // texels of the environment map; 0: none
    float sunPick;             // the probability that next-event estimation picks the sun
                               // (sunPickProbability; 1: never the environment map)
    float envTangentX, envTangentY, envTangentZ;        // the map's frame (environmentFrame; its
    float envBitangentX, envBitangentY, envBitangentZ;  // normal is skyUp)
    uint volumeCount;
    uint volumeBrickCount;  // paged volumes: all volumes' bricks
    uint tilePixels;        // streamed waves: a window tile's pixels at most (its outputs' stride)
    uint lightCount;        // punctual lights (0: none)
    float punctualPick;     // the probability that next-event estimation picks a punctual light
                            // (punctualPickProbability; 0: never)
    float cameraSpread;     // ray cones (core/RayCone.h): a camera ray's spread angle and the most a
    float scatterSpread;    // scattering event adds; both 0 with --texture-lod finest (level 0)
    uint emitterCount;      // sampled emissive triangles (0: none)
    float emitterPick;      // the probability that next-event estimation picks one
                            // (emitterPickProbability; 0: never)
    uint walkBitsApart;     // 1: walkBits is a byte a path of its own; 0: the walk bits lie in the path words
};

// Streamed waves (out of core): the open tiles, oldest first, from which groups take pixels. The
// host writes it before each paging step; the kernels take window pixels with `cursor` (window
// pixel k lies in the first tile whose running pixel count exceeds k) and count each tile's
// finished pixels in `done` (by ring slot). A tile (uvec4): first image pixel, width, pixels,
// ring slot (its outputs start at slot * tilePixels).
struct StreamWindow {
    uint cursor;
    uint tileCount;
    uint padding0, padding1;
    uint done[kMaxWindowTiles];
    uint tiles[4 * kMaxWindowTiles];
};

// One block for every wavefront kernel. A wave is the tile's pixels times samples [firstSample,
// firstSample + sampleCount); path j of the wave is the tile's pixel j / sampleCount, sample
// firstSample + j % sampleCount. A tile is a rectangle of tileWidth columns whose top-left pixel
// is firstPixel: its pixel i (0 <= i < pixelCount, row by row) is the image's pixel firstPixel +
// (i / tileWidth) * imageWidth + i % tileWidth.
struct WavefrontPush {
    uint64_t params;
    uint firstPixel;
    uint pixelCount;
    uint firstSample;
    uint sampleCount;
    uint kernelFlags;  // kKernelRestartGroups
    uint parkQueue; // wf_walk.comp: the queue its parked rays join (kParkQueue or kParkQueue + 1)
    uint mode;     // wf_generate.comp: kGeneratePaths or kGenerateAov; wf_accumulate.comp: 1 = resolve too
    uint queue;    // wf_walk.comp: the queue it walks (kWalkQueue, or the other park queue);
                   // wf_generate.comp, wf_shade.comp: the queue their new rays are appended to
    uint tileWidth;
    uint groupQueue;  // wf_generate.comp (kGenerateStream): the group queue it takes groups from
                      // (kGroupQueue or kGroupQueue + 1; it appends idle ones to the other);
                      // wf_shade.comp: the one it queues the groups it ends on (kKernelRestartGroups: idle ones)
    // wf_walk.comp with kPackedPositions: the package grid's origin and step (floats, exact), a
    // vertex at origin + float(m) * step (vastray::QuantizationGrid::packedPosition).
    float gridOriginX, gridOriginY, gridOriginZ, gridStep;
};

#ifdef __cplusplus
static_assert(sizeof(WavefrontMaterial) == 64 + 4 * 4 + 4 * 6 * 4 + 4 * 4 + 2 * 4 + 2 * 6 * 4 + 2 * 4 &&
              offsetof(WavefrontMaterial, baseColorMap) == 64 && offsetof(WavefrontMaterial, clearcoatMap) == 192);
static_assert(sizeof(WavefrontLight) == 64);
static_assert(sizeof(WavefrontEmitter) == 80);
static_assert(offsetof(WavefrontParams, eyeX) == 48 * 8 && sizeof(WavefrontParams) % 8 == 0);
static_assert(sizeof(StreamWindow) == 16 + 4 * kMaxWindowTiles + 16 * kMaxWindowTiles);
static_assert(sizeof(WavefrontVolume) == 4 * 8 + 12 * 4 + 6 * 4 + 8 * 4 + 2 * 4 + 8);
static_assert(sizeof(WavefrontPush) == 64 && offsetof(WavefrontPush, tileWidth) == 40 && offsetof(WavefrontPush, gridStep) == 60);
}  // namespace vastray::gpu
#endif

#endif  // VASTRAY_GPU_SHARED_WAVEFRONT_TYPES_H
