#pragma once
// Byte layout of the .vast package (docs/PACKAGE_FORMAT.md is the prose version).
//
//   header     kHeaderBytes, fixed; ends with the XXH64 of its own preceding bytes
//   materials  materialCount × kMaterialBytes
//   top tree   topNodeCount × 8 (KdNode)
//   directory  chunkCount × kDirectoryEntryBytes
//   cameras    cameraCount × kCameraBytes (version 3)
//   volumes    volumeCount × kVolumeRecordBytes (version 4)
//   lights     lightCount × kLightBytes, then the XXH64 of those records (version 7; the count
//              is the header's field after the camera count, 0 before version 7)
//   emitters   (version 12) the emitter count (u32) and a 0 word, then count × emitterBytes, then
//              the XXH64 of the count, the word and the records
//   textures   the texture head, kTextureHeadBytes (version 10; TextureSection.h)
//   blobs      one per chunk, in chunk-id order, at the offsets the directory gives
//   volume data  one per volume (brick table, voxels), at the offsets its record gives; from
//                version 6: cell table and brick index (one checksum), then each brick alone
//   texture pages, texture table  (version 10): one zstd frame per page, then the table the
//                head points to, which ends the file
#include <cstdint>

#include "vastray/core/Volume.h"
#include "vastray/core/VolumeLeaf.h"

namespace vastray::format {

constexpr char kMagic[8] = {'V', 'A', 'S', 'T', 'R', 'A', 'Y', '\0'};
// 2: chunk trees are 4-wide BVHs (Bvh4Node), triangles in leaf order (was: KD nodes and references).
// 3: chunks may carry per-vertex shading normals and colours (chunk flags, header flags).
// 4: volumes (density grids in bricks; a version 3 package, which has none, is still read).
// 5: materials carry metallic, roughness and specular (16 bytes more each; a version 3 or 4
//    package is still read, its materials Lambertian as they were imported).
// 6: a volume's data is read one brick at a time: its cell table and a brick index (per brick
//    its own XXH64 and largest density) under the record's checksum, then the bricks (a version
//    3, 4 or 5 package is still read, each volume's data whole).
// 7: punctual lights (glTF KHR_lights_punctual) in a section after the volume records (a version
//    3 to 6 package, which has none, is still read).
// 8: materials carry KHR_materials_specular's colour factor and KHR_materials_clearcoat's two
//    factors (32 bytes more each: the colour, the coat and its roughness, three reserved words,
//    after the name; a version 3 to 7 package is still read, its specular colour white and no
//    coat, the glTF defaults).
// 9: chunks may carry one UV set, two f32 per vertex (header flag kHasUvs, chunk flag
//    kChunkHasUvs; a version 3 to 8 package, which has none, is still read).
// 10: textures (a head after the lights, each texture's mip-mapped pages and a table at the end
//     of the file) and materials that name them (156 bytes more each: per map its texture and
//     UV transform, the normal scale and occlusion strength; a version 3 to 9 package, which
//     has none, is still read).
// 11: materials may carry an alpha cut-out's cutoff (glTF alphaMode MASK with a base colour map),
//     an f32 in the word after the specular factor, reserved (zero) before; a version 3 to 10
//     package, which has none, is still read.
// 12: the emissive triangles next-event estimation samples, in a section after the lights (a
//     version 3 to 11 package, which has none, is still read: its emitters are hit by chance only);
//     a material's first reserved word after the coat holds flags (bit 0: alpha blending).
// 13: materials carry KHR_materials_clearcoat's two maps after the five of version 10 (56 bytes
//     more each: the coat's and the coat roughness's texture and UV transform) and
//     KHR_materials_ior's index of refraction (an f32 in the second word after the coat, reserved
//     before); a version 3 to 12 package is still read, its coats unmapped and its ior 1.5.
// 14: a volume's bricks are NanoVDB leaf nodes of its codec (float, Fp16 or Fp8: record flags bits
//     2-3; core/VolumeLeaf.h) where they were 512 f32 each; a version 3 to 13 package is still
//     read, its bricks float.
// 15: an emitter record carries its corners' UVs (6 × f32 after the material: 64 bytes), and a
//     triangle with an emissive map is sampled, the point reading the map; a version 12 to 14
//     package, which samples no mapped triangle, is still read.
// 16: a directory entry's last u32 (reserved, zero, before) holds the chunk's index layout on the
//     device: bit 31 kChunkIndexDeltas16 (8 bytes a triangle, 16-bit offsets from its first
//     index), bits 0-26 its long triangles (whose offsets do not fit), bits 27-30 zero; a version
//     3 to 15 package is still read, its chunks' indices kept in 12 bytes a triangle on the device.
constexpr uint32_t kVersion = 16;
constexpr uint32_t kFirstChunkFlagsVersion = 16;
constexpr uint32_t kDirectoryIndexDeltas16 = 1u << 31;
constexpr uint32_t kDirectoryLongTriangleBits = 27;
constexpr uint32_t kFirstLeafBricksVersion = 14;
constexpr uint32_t kFirstEmitterUvVersion = 15;
constexpr uint32_t kFirstCoatMapsVersion = 13;
constexpr uint32_t kFirstEmittersVersion = 12;
constexpr uint32_t kMaterialAlphaBlend = 1u;  // Material::alphaBlend (version 12)
constexpr uint32_t kKnownMaterialFlags = kMaterialAlphaBlend;
constexpr uint32_t kFirstCutoutVersion = 11;
constexpr uint32_t kFirstUvVersion = 9;
constexpr uint32_t kFirstTextureVersion = 10;
constexpr uint32_t kFirstLightsVersion = 7;
constexpr uint32_t kOldestReadableVersion = 3;
constexpr uint32_t kHeaderBytes = 256;
constexpr uint32_t kMaterialNameBytes = 64;
constexpr uint32_t kMaterialBytesBefore5 = 4 * 4 + 3 * 4 + 4 + kMaterialNameBytes;
constexpr uint32_t kMaterialBytesBefore8 = kMaterialBytesBefore5 + 4 * 4;
constexpr uint32_t kFirstSpecularColorVersion = 8;
constexpr uint32_t kMaterialBytesBefore10 = kMaterialBytesBefore8 + 3 * 4 + 2 * 4 + 3 * 4;
// Per map (core/MaterialTextures.h, kTextureSlotCount of them): texture index, UV transform (6 × f32).
constexpr uint32_t kMaterialMapBytes = 4 + 6 * 4;
// Maps a material record holds: glTF's five (version 10), then the coat's two (version 13).
constexpr uint32_t materialMaps(uint32_t version) {
    return version >= kFirstCoatMapsVersion ? 7 : version >= kFirstTextureVersion ? 5 : 0;
}
constexpr uint32_t kMaterialBytesBefore13 = kMaterialBytesBefore10 + 5 * kMaterialMapBytes + 4 * 4;
constexpr uint32_t kMaterialBytes = kMaterialBytesBefore10 + 7 * kMaterialMapBytes + 4 * 4;
constexpr uint32_t materialBytes(uint32_t version) {
    return version >= kFirstCoatMapsVersion        ? kMaterialBytes
           : version >= kFirstTextureVersion       ? kMaterialBytesBefore13
           : version >= kFirstSpecularColorVersion ? kMaterialBytesBefore10
           : version >= 5                          ? kMaterialBytesBefore8
                                                   : kMaterialBytesBefore5;
}
// The texture head after the lights (version 10; before, nothing).
constexpr uint64_t textureHeadBytes(uint32_t version) { return version >= kFirstTextureVersion ? 32 : 0; }
constexpr uint32_t kDirectoryEntryBytes = 4 * 8 + 4 * 4 + 6 * 4;
constexpr uint32_t kCameraNameBytes = 64;
constexpr uint32_t kCameraBytes = kCameraNameBytes + 10 * 4;  // name, eye, target, up, fov (degrees)
constexpr uint32_t kLightNameBytes = 64;
// name, type, colour, intensity, range, inner and outer cone angle, position, direction, two 0 words
constexpr uint32_t kLightBytes = kLightNameBytes + 4 + 3 * 4 + 4 * 4 + 6 * 4 + 2 * 4;
// The lights section: its records and their XXH64 (version 7; before, nothing).
constexpr uint64_t lightsSectionBytes(uint32_t version, uint64_t lights) {
    return version >= kFirstLightsVersion ? lights * kLightBytes + 8 : 0;
}
// An emitter: its three corners (9 × f32) and its material (u32); from version 15 then its
// corners' UVs (6 × f32).
constexpr uint32_t emitterBytes(uint32_t version) { return version >= kFirstEmitterUvVersion ? 16 * 4 : 10 * 4; }
// The emitters section (version 12; before, nothing): its head (count, a 0 word), the records, their XXH64.
constexpr uint64_t kEmittersHeadBytes = 8;
constexpr uint64_t emittersSectionBytes(uint32_t version, uint64_t emitters) {
    return version >= kFirstEmittersVersion ? kEmittersHeadBytes + emitters * emitterBytes(version) + 8 : 0;
}
constexpr uint32_t kVolumeNameBytes = 64;
constexpr uint32_t kVolumeRecordBytes = 256;
constexpr uint32_t kFirstBrickwiseVersion = 6;
constexpr uint32_t kVolumeBrickEntryBytes = 16;  // version 6 brick index: XXH64, largest density (f32), 0 (u32)
// A stored brick's bytes: its densities, then (with an emission grid) its emission values: 512 f32
// each before version 14, a leaf of the volume's codec each from it (volumeLeafBytes).
inline uint64_t volumeBrickBytes(uint32_t version, VolumeCodec codec, bool emission) {
    const uint64_t one = version >= kFirstLeafBricksVersion ? volumeLeafBytes(codec) : 4ull * kVolumeBrickVoxels;
    return one * (emission ? 2 : 1);
}
// The part of a volume's data its record's checksum covers: the cell table, and from version 6
// the brick index (before: the whole data).
constexpr uint64_t volumeTableBytes(uint32_t version, uint64_t cells, uint64_t bricks) {
    return 4 * cells + (version >= kFirstBrickwiseVersion ? kVolumeBrickEntryBytes * bricks : 0);
}
inline uint64_t volumeDataBytes(uint32_t version, uint64_t cells, uint64_t bricks, VolumeCodec codec,
                                bool emission) {
    return volumeTableBytes(version, cells, bricks) + bricks * volumeBrickBytes(version, codec, emission);
}

// Upper bounds a reader enforces before allocating anything.
constexpr uint32_t kMaxMaterials = 1u << 20;
constexpr uint32_t kMaxChunks = 1u << 24;
constexpr uint32_t kMaxCameras = 1u << 16;

constexpr char kChunkMagic[4] = {'V', 'C', 'H', 'K'};
constexpr uint32_t kChunkVersion = 3;
constexpr uint32_t kChunkHeaderBytes = 64;
constexpr uint32_t kChunkHasMaterialIds = 1u;
constexpr uint32_t kChunkMeshoptGeometry = 2u;  // geometry stream is meshoptimizer's, not Draco's
constexpr uint32_t kChunkHasNormals = 4u;  // the geometry stream carries octahedral normals
constexpr uint32_t kChunkHasColors = 8u;   // the geometry stream carries sRGB8 colours
constexpr uint32_t kChunkHasUvs = 16u;     // the geometry stream carries texture coordinates (version 9)
constexpr uint32_t kChunkKnownFlags =
    kChunkHasMaterialIds | kChunkMeshoptGeometry | kChunkHasNormals | kChunkHasColors | kChunkHasUvs;

// kHasNormals / kHasColors / kHasUvs: every chunk carries them (a scene has them on all its
// vertices or on none: vertices the file gave none get kNoNormal / kWhiteColor / (0, 0)).
enum HeaderFlags : uint32_t {
    kDefaultDoubleSided = 1u,
    kMeshoptChunks = 2u,
    kHasNormals = 4u,
    kHasColors = 8u,
    kHasUvs = 16u,  // version 9
};
constexpr uint32_t kKnownHeaderFlags = kDefaultDoubleSided | kMeshoptChunks | kHasNormals | kHasColors | kHasUvs;

}  // namespace vastray::format
