#pragma once
// Serialization of the package's header, materials and directory, shared by writer and reader.
#include <cstdint>
#include <string>
#include <vector>

#include "package/ByteIo.h"
#include "vastray/core/Result.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {

struct SectionLayout {
    uint64_t materialsOffset = 0, treeOffset = 0, directoryOffset = 0, blobsOffset = 0;
    uint64_t materialsChecksum = 0, treeChecksum = 0, directoryChecksum = 0;
    uint32_t materialCount = 0, topNodeCount = 0, chunkCount = 0;
    uint64_t camerasOffset = 0, camerasChecksum = 0;  // the cameras lie between directory and blobs
    uint32_t cameraCount = 0;
    // The volume records lie between cameras and blobs; their data after the blobs.
    uint64_t volumesOffset = 0, volumesChecksum = 0;
    uint32_t volumeCount = 0;
    // The lights (version 7) lie between the volume records and the blobs; their count is the
    // header's word after the camera count, their checksum the section's last 8 bytes.
    uint32_t lightCount = 0;
};

// "NAME checksum mismatch (stored 0x..., computed 0x...)": what a reader says of a section,
// the header or a chunk whose XXH64 is not the one recorded.
Status checksumMismatch(const std::string& name, uint64_t stored, uint64_t computed);

std::vector<uint8_t> serializeHeader(const PackageInfo& info, const SectionLayout& layout);
// Checks magic, version and the header's own checksum; fills the scalar fields of `info`.
Result<SectionLayout> parseHeader(const uint8_t* bytes, size_t size, PackageInfo& info);

// A box read from a package: finite, within +-kMaxAbsCoordinate, not inverted. `what`
// starts the message ("chunk 3: cell bounds x nan is not finite").
Status checkStoredBox(const std::string& what, const Aabb& box);

std::vector<uint8_t> serializeMaterials(const std::vector<Material>& materials);
std::vector<uint8_t> serializeCameras(const std::vector<SceneCamera>& cameras);
// Each camera valid (validateCamera): "camera 2 'Orbit': ..." otherwise.
Result<std::vector<SceneCamera>> parseCameras(const std::vector<uint8_t>& bytes, uint32_t count);
// Version 5 records (format::materialBytes) carry the metallic-roughness factors, each in [0, 1];
// older ones are read as Lambertian (metallic 0, roughness 1, specular 0). Version 8 records add
// the specular colour (each channel in [0, kMaxSpecularColor]; before, white) and the clear coat's
// weight and roughness (each in [0, 1]; before, no coat). A record out of
// range: "material 2 ('Gold'): metallic 2 is outside [0, 1]". Version 10 records add the maps: each
// texture index below `textureCount` (or kNoTexture), transforms finite within +-1e6, the
// occlusion strength in [0, 1] ("material 2 ('Brick'): normalTexture names texture 9 of 3").
Result<std::vector<Material>> parseMaterials(const std::vector<uint8_t>& bytes, uint32_t count, uint32_t version,
                                             uint32_t textureCount);

// The lights section (format::lightsSectionBytes): the records, then their XXH64.
std::vector<uint8_t> serializeLights(const std::vector<PunctualLight>& lights);
// Checks the section's checksum and each light (validateLight): "light 2 'Lamp': ..." otherwise.
Result<std::vector<PunctualLight>> parseLights(const std::vector<uint8_t>& bytes, uint32_t count);

// The emitters section (format::emittersSectionBytes): the count and a 0 word, the records, then
// the XXH64 of all of that.
std::vector<uint8_t> serializeEmitters(const std::vector<EmissiveTriangle>& emitters);
// The count from the section's first kEmittersHeadBytes (at most kMaxEmitters, the word after it 0).
Result<uint32_t> parseEmittersHead(const std::vector<uint8_t>& bytes);
// The whole section of a package of format `version`: its checksum, each corner finite within
// +-kMaxAbsCoordinate, each UV (version 15) within +-kMaxAbsUv, each material one of `materials`
// that isSampledEmitter among `textureCount` textures ("emitter 4: material 9 of 3").
Result<std::vector<EmissiveTriangle>> parseEmitters(const std::vector<uint8_t>& bytes, uint32_t count,
                                                    const std::vector<Material>& materials, uint64_t textureCount,
                                                    uint32_t version);

std::vector<uint8_t> serializeVolumeRecords(const std::vector<PackageVolume>& volumes);
// Each record's fields checked (limits, map, material, the data's size for the format `version`);
// data offsets are checked by the reader.
Result<std::vector<PackageVolume>> parseVolumeRecords(const std::vector<uint8_t>& bytes, uint32_t count,
                                                      uint32_t version);

std::vector<uint8_t> serializeDirectory(const std::vector<ChunkInfo>& chunks);
Result<std::vector<ChunkInfo>> parseDirectory(const std::vector<uint8_t>& bytes, uint32_t count, uint32_t version);

}  // namespace vastray
