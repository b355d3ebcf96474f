#pragma once
// Forged volume data for tests of the package reader's checks (format 14, docs/PACKAGE_FORMAT.md,
// "Volumes").
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "TestTmp.h"
#include "vastray/core/Checksum.h"
#include "vastray/core/VolumeLeaf.h"
#include "vastray/streamer/PackageBuilder.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray::test {

// One small triangle with its corner at (c, c, c), out of the view: a package holds a mesh, and
// these tests look at its volumes.
inline TriangleMesh farTriangle(float c) {
    TriangleMesh mesh;
    mesh.positions = {{c, c, c}, {c + 1, c, c}, {c, c + 1, c}};
    mesh.indices = {0, 1, 2};
    mesh.materials.push_back(Material{"far"});
    return mesh;
}

// A package of `mesh` and `volumes` (64 KiB chunks) named NAME.vast in the test folder `folder`.
inline std::string writeVolumePackage(const std::string& folder, const std::string& name, TriangleMesh mesh,
                                      std::vector<Volume> volumes) {
    const std::filesystem::path dir = testTmpDir(folder);
    std::filesystem::create_directories(dir);
    const std::string path = (dir / (name + ".vast")).string();
    PackageBuildOptions options;
    options.chunkSizeBytes = 64 << 10;
    options.progress = Progress::Mode::None;
    options.volumes = std::move(volumes);
    auto report = buildPackage(std::move(mesh), path, options);
    EXPECT_TRUE(report) << report.message();
    return path;
}

inline std::vector<uint8_t> fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

inline void writeBytes(const std::string& path, const std::vector<uint8_t>& bytes) {
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// Recomputes the checksums over the volume records (their offset is at byte 232 of the header,
// their XXH64 at 240) and the header's own (bytes 248..255), after a record was changed.
inline void resealRecordsAndHeader(std::vector<uint8_t>& bytes, uint64_t recordAt) {
    const uint64_t records = checksum64(bytes.data() + recordAt, 256);
    std::memcpy(bytes.data() + 256 - 16, &records, 8);
    const uint64_t header = checksum64(bytes.data(), 248);
    std::memcpy(bytes.data() + 248, &header, 8);
}

// A stored brick's bytes in volume `p` (format 14: its leaves in the volume's codec).
inline uint64_t storedBrickBytes(const PackageVolume& p) {
    return uint64_t(volumeLeafBytes(p.volume.codec)) * (p.hasEmission ? 2 : 1);
}
// The file offset of brick `brick`'s first byte (its density leaf's) in the data of volume `p`.
inline uint64_t brickOffset(const PackageVolume& p, uint64_t brick) {
    return p.offset + 4 * p.volume.cellCount() + 16ull * p.brickCount + brick * storedBrickBytes(p);
}
// The file offset of voxel `index` (x fastest) of brick `brick` of a float-codec volume `p`: in
// the NanoVDB float leaf, the f32 at byte 96 + 4 * (x * 64 + y * 8 + z) (NanoVDB orders z fastest).
inline uint64_t voxelOffset(const PackageVolume& p, uint64_t brick, uint32_t index) {
    const uint32_t x = index % 8, y = index / 8 % 8, z = index / 64;
    return brickOffset(p, brick) + 96 + 4 * (x * 64 + y * 8 + z);
}

// The bytes of a format 14 package whose only volume is `p`, changed by `change`, then with every
// checksum over the volume recomputed as a forger would: each brick's in the brick index, the
// table's in the record, the records' and the header's. Offsets: the header keeps the records'
// offset 24 bytes and their checksum 16 bytes before its own checksum (bytes 248..255); a record
// keeps its data's checksum at byte 180.
inline std::vector<uint8_t> forgeVolumeData(std::vector<uint8_t> bytes, const PackageVolume& p,
                                            const std::function<void(std::vector<uint8_t>&)>& change) {
    change(bytes);
    const uint64_t brickBytes = storedBrickBytes(p);
    const uint64_t index = p.offset + 4 * p.volume.cellCount();
    for (uint64_t b = 0; b < p.brickCount; ++b) {
        const uint64_t sum = checksum64(bytes.data() + brickOffset(p, b), brickBytes);
        std::memcpy(bytes.data() + index + 16 * b, &sum, 8);
    }
    uint64_t recordAt = 0;
    std::memcpy(&recordAt, bytes.data() + 256 - 24, 8);
    const uint64_t table = checksum64(bytes.data() + p.offset, brickOffset(p, 0) - p.offset);
    std::memcpy(bytes.data() + recordAt + 180, &table, 8);
    resealRecordsAndHeader(bytes, recordAt);
    return bytes;
}

// A package's u64 at byte `at`, and setting one (the forgers below move offsets).
inline uint64_t word64(const std::vector<uint8_t>& bytes, uint64_t at) {
    uint64_t v = 0;
    std::memcpy(&v, bytes.data() + at, 8);
    return v;
}
inline void setWord64(std::vector<uint8_t>& bytes, uint64_t at, uint64_t v) { std::memcpy(bytes.data() + at, &v, 8); }

// A format 7 package without lights laid out as before format 7: its light section (no records,
// only their 8-byte checksum, right after the volume records) taken out and every offset after it
// moved back by 8 (the blobs' in the header and the directory, each volume's data in its record),
// with the directory's, the records' and the header's checksums recomputed. Header fields: file
// bytes at 16, chunk and volume counts at 88 and 92, directory and blobs offsets at 168 and 176,
// the directory's XXH64 at 200, the records' offset and XXH64 at 232 and 240; a directory entry
// starts with its blob's offset, a volume record keeps its data's offset at byte 164.
inline std::vector<uint8_t> withoutLightSection(std::vector<uint8_t> bytes) {
    auto get = [&](uint64_t at) { return word64(bytes, at); };
    auto set = [&](uint64_t at, uint64_t v) { setWord64(bytes, at, v); };
    uint32_t chunks = 0, volumes = 0;
    std::memcpy(&chunks, bytes.data() + 88, 4);
    std::memcpy(&volumes, bytes.data() + 92, 4);
    const uint64_t records = get(232), directory = get(168), lights = records + 256ull * volumes;
    bytes.erase(bytes.begin() + int64_t(lights), bytes.begin() + int64_t(lights + 8));
    set(16, bytes.size());
    set(176, get(176) - 8);
    for (uint64_t c = 0; c < chunks; ++c) set(directory + 72 * c, get(directory + 72 * c) - 8);
    set(200, checksum64(bytes.data() + directory, 72ull * chunks));
    for (uint64_t v = 0; v < volumes; ++v) set(records + 256 * v + 164, get(records + 256 * v + 164) - 8);
    set(240, checksum64(bytes.data() + records, 256ull * volumes));
    set(248, checksum64(bytes.data(), 248));
    return bytes;
}

// A format 12 package without emitters laid out as format 11: its emitter section (a count of 0, a
// reserved word and the checksum: 16 bytes right after the light section, which ends 8 bytes after
// the volume records when there are no lights) taken out and every offset after it moved back by 16
// (the blobs' in the header and the directory, each volume's data in its record, the texture table's
// in the texture head right before the blobs), with the directory's, the records', the texture
// head's and the header's checksums recomputed. Header fields as withoutLightSection's.
inline std::vector<uint8_t> withoutEmitterSection(std::vector<uint8_t> bytes) {
    auto get = [&](uint64_t at) { return word64(bytes, at); };
    auto set = [&](uint64_t at, uint64_t v) { setWord64(bytes, at, v); };
    uint32_t chunks = 0, volumes = 0;
    std::memcpy(&chunks, bytes.data() + 88, 4);
    std::memcpy(&volumes, bytes.data() + 92, 4);
    const uint64_t records = get(232), directory = get(168), emitters = records + 256ull * volumes + 8;
    bytes.erase(bytes.begin() + int64_t(emitters), bytes.begin() + int64_t(emitters + 16));
    set(16, bytes.size());
    set(176, get(176) - 16);
    for (uint64_t c = 0; c < chunks; ++c) set(directory + 72 * c, get(directory + 72 * c) - 16);
    for (uint64_t v = 0; v < volumes; ++v) set(records + 256 * v + 164, get(records + 256 * v + 164) - 16);
    const uint64_t head = get(176) - 32;  // the texture head: count, reserved, table offset and size, XXH64
    set(head + 8, get(head + 8) - 16);
    set(head + 24, checksum64(bytes.data() + head, 24));
    const uint32_t eleven = 11;
    std::memcpy(bytes.data() + 8, &eleven, 4);
    set(200, checksum64(bytes.data() + directory, 72ull * chunks));
    set(240, checksum64(bytes.data() + records, 256ull * volumes));
    set(248, checksum64(bytes.data(), 248));
    return bytes;
}

// A format 10 package without textures laid out as format 9: each material record's last 156
// bytes (its maps, none here) and the 32-byte texture head (right before the first blob) taken
// out, every offset after them moved back (the tree's, the directory's, the blobs', the cameras'
// and the volume records' in the header at 160, 168, 176, 208 and 232, the blobs' in the
// directory, each volume's data in its record), the version set to 9 and the materials' (at 184),
// directory's, records' and header's checksums recomputed; the material count is at 80. A package
// without textures has no texture table, so nothing else changes.
inline std::vector<uint8_t> withoutTextures(std::vector<uint8_t> bytes) {
    auto get = [&](uint64_t at) { return word64(bytes, at); };
    auto set = [&](uint64_t at, uint64_t v) { setWord64(bytes, at, v); };
    uint32_t materials = 0, chunks = 0, volumes = 0;
    std::memcpy(&materials, bytes.data() + 80, 4);
    std::memcpy(&chunks, bytes.data() + 88, 4);
    std::memcpy(&volumes, bytes.data() + 92, 4);
    for (uint32_t m = materials; m-- > 0;) {
        const int64_t end = 256 + 300 * int64_t(m + 1);
        bytes.erase(bytes.begin() + end - 156, bytes.begin() + end);
    }
    const uint64_t maps = 156ull * materials;
    for (uint64_t at : {160, 168, 208, 232}) set(at, get(at) - maps);
    const uint64_t head = get(176) - maps - 32;  // the texture head ends where the blobs begin
    bytes.erase(bytes.begin() + int64_t(head), bytes.begin() + int64_t(head + 32));
    const uint64_t moved = maps + 32;
    set(176, get(176) - moved);
    const uint64_t directory = get(168), records = get(232);
    for (uint64_t c = 0; c < chunks; ++c) set(directory + 72 * c, get(directory + 72 * c) - moved);
    for (uint64_t v = 0; v < volumes; ++v) set(records + 256 * v + 164, get(records + 256 * v + 164) - moved);
    const uint32_t nine = 9;
    std::memcpy(bytes.data() + 8, &nine, 4);
    set(16, bytes.size());
    set(184, checksum64(bytes.data() + 256, 144ull * materials));
    set(200, checksum64(bytes.data() + directory, 72ull * chunks));
    set(240, checksum64(bytes.data() + records, 256ull * volumes));
    set(248, checksum64(bytes.data(), 248));
    return bytes;
}

// The package with `cut` bytes taken out of each material record (of `recordBytes`) at `from`
// within it, laid out as format `version`: every offset after the materials moved back by `cut`
// per material (the tree's, the directory's, the blobs', the cameras' and the volume records' in
// the header at 160, 168, 176, 208 and 232, the blobs' in the directory, each volume's data in
// its record, and from format 10 the texture table's in the texture head right before the blobs),
// with the materials' checksum (at 184), the directory's, the records', the texture head's and the
// header's recomputed; the material count is at 80. A package without textures (no texture table)
// has no other offset to move.
inline std::vector<uint8_t> withoutMaterialBytes(std::vector<uint8_t> bytes, uint64_t recordBytes, uint64_t from,
                                                 uint64_t cut, uint32_t version) {
    auto get = [&](uint64_t at) { return word64(bytes, at); };
    auto set = [&](uint64_t at, uint64_t v) { setWord64(bytes, at, v); };
    uint32_t materials = 0, chunks = 0, volumes = 0;
    std::memcpy(&materials, bytes.data() + 80, 4);
    std::memcpy(&chunks, bytes.data() + 88, 4);
    std::memcpy(&volumes, bytes.data() + 92, 4);
    for (uint32_t m = materials; m-- > 0;) {
        const int64_t at = 256 + int64_t(recordBytes) * int64_t(m) + int64_t(from);
        bytes.erase(bytes.begin() + at, bytes.begin() + at + int64_t(cut));
    }
    const uint64_t moved = cut * materials;
    for (uint64_t at : {160, 168, 176, 208, 232}) set(at, get(at) - moved);
    const uint64_t directory = get(168), records = get(232);
    for (uint64_t c = 0; c < chunks; ++c) set(directory + 72 * c, get(directory + 72 * c) - moved);
    for (uint64_t v = 0; v < volumes; ++v) set(records + 256 * v + 164, get(records + 256 * v + 164) - moved);
    uint32_t stored = 0;  // the version it had
    std::memcpy(&stored, bytes.data() + 8, 4);
    if (stored >= 10) {
        const uint64_t head = get(176) - 32;  // count, reserved, table offset and size, XXH64
        set(head + 8, get(head + 8) - moved);
        set(head + 24, checksum64(bytes.data() + head, 24));
    }
    std::memcpy(bytes.data() + 8, &version, 4);
    set(16, bytes.size());
    set(184, checksum64(bytes.data() + 256, (recordBytes - cut) * materials));
    set(200, checksum64(bytes.data() + directory, 72ull * chunks));
    set(240, checksum64(bytes.data() + records, 256ull * volumes));
    set(248, checksum64(bytes.data(), 248));
    return bytes;
}

// A format 8 package laid out as format 7: each material record's last 32 bytes (the specular
// colour, white here, and five zero words) taken out (withoutMaterialBytes).
inline std::vector<uint8_t> withoutSpecularColours(std::vector<uint8_t> bytes) {
    return withoutMaterialBytes(std::move(bytes), 144, 112, 32, 7);
}

// A format 16 package laid out as format 15: each directory entry's flags (its last u32, at 44 of
// 72 bytes) zeroed, as format 15 reserves it, with the directory's and the header's checksums
// recomputed. A package of an older format is returned as it is.
inline std::vector<uint8_t> withoutChunkFlags(std::vector<uint8_t> bytes) {
    uint32_t version = 0, chunks = 0;
    std::memcpy(&version, bytes.data() + 8, 4);
    if (version < 16) return bytes;
    std::memcpy(&chunks, bytes.data() + 88, 4);
    const uint64_t directory = word64(bytes, 168);
    for (uint64_t c = 0; c < chunks; ++c) std::memset(bytes.data() + directory + 72 * c + 44, 0, 4);
    const uint32_t fifteen = 15;
    std::memcpy(bytes.data() + 8, &fifteen, 4);
    setWord64(bytes, 200, checksum64(bytes.data() + directory, 72ull * chunks));
    setWord64(bytes, 248, checksum64(bytes.data(), 248));
    return bytes;
}

// A format 15 package laid out as format 14: each emitter record's corner UVs (its last 24 of 64
// bytes) taken out and every offset after the emitter section moved back by as much (the blobs'
// in the header and the directory, each volume's data in its record, the texture table's in the
// texture head), with the emitters', the directory's, the records', the texture head's and the
// header's checksums recomputed. The emitter section follows the volume records and the light
// section (128 bytes a light, then 8); the header keeps the light count at byte 228. A package of
// an older format is returned as it is.
inline std::vector<uint8_t> withoutEmitterUvs(std::vector<uint8_t> bytes) {
    bytes = withoutChunkFlags(std::move(bytes));  // (format 16's flags first)
    auto get = [&](uint64_t at) { return word64(bytes, at); };
    auto set = [&](uint64_t at, uint64_t v) { setWord64(bytes, at, v); };
    uint32_t version = 0, chunks = 0, volumes = 0, lights = 0, count = 0;
    std::memcpy(&version, bytes.data() + 8, 4);
    if (version < 15) return bytes;
    std::memcpy(&chunks, bytes.data() + 88, 4);
    std::memcpy(&volumes, bytes.data() + 92, 4);
    std::memcpy(&lights, bytes.data() + 228, 4);
    const uint64_t records = get(232), directory = get(168), emitters = records + 256ull * volumes + 128ull * lights + 8;
    std::memcpy(&count, bytes.data() + emitters, 4);
    for (uint32_t e = count; e-- > 0;) {
        const int64_t at = int64_t(emitters + 8 + 64ull * e + 40);
        bytes.erase(bytes.begin() + at, bytes.begin() + at + 24);
    }
    const uint64_t covered = 8 + 40ull * count, moved = 24ull * count;
    set(emitters + covered, checksum64(bytes.data() + emitters, covered));
    set(176, get(176) - moved);
    for (uint64_t c = 0; c < chunks; ++c) set(directory + 72 * c, get(directory + 72 * c) - moved);
    for (uint64_t v = 0; v < volumes; ++v) set(records + 256 * v + 164, get(records + 256 * v + 164) - moved);
    const uint64_t head = get(176) - 32;  // count, reserved, table offset and size, XXH64
    set(head + 8, get(head + 8) - moved);
    set(head + 24, checksum64(bytes.data() + head, 24));
    const uint32_t fourteen = 14;
    std::memcpy(bytes.data() + 8, &fourteen, 4);
    set(16, bytes.size());
    set(200, checksum64(bytes.data() + directory, 72ull * chunks));
    set(240, checksum64(bytes.data() + records, 256ull * volumes));
    set(248, checksum64(bytes.data(), 248));
    return bytes;
}

// A format 13 package laid out as format 12: each material record's ior (the word at 136,
// reserved before 13) zeroed and its coat maps (two of 28 bytes, after the five maps of format
// 10, none here) taken out (withoutMaterialBytes).
inline std::vector<uint8_t> withoutCoatMaps(std::vector<uint8_t> bytes) {
    bytes = withoutEmitterUvs(std::move(bytes));  // (format 15's records first)
    uint32_t materials = 0;
    std::memcpy(&materials, bytes.data() + 80, 4);
    for (uint32_t m = 0; m < materials; ++m) std::memset(bytes.data() + 256 + 356 * size_t(m) + 136, 0, 4);
    return withoutMaterialBytes(std::move(bytes), 356, 144 + 5 * 28, 2 * 28, 12);
}

// The same package in format version 5, whose only volume is `p` (the last bytes of the file): its
// data whole (cell table, every brick's densities, then every brick's emission) under one checksum,
// as versions 4 and 5 store it. `current` is the format 10 package without lights or textures
// that holds `p`.
inline std::vector<uint8_t> asVersion5(const std::vector<uint8_t>& current, PackageVolume p) {
    uint32_t materials = 0;
    std::memcpy(&materials, current.data() + 80, 4);
    const std::vector<uint8_t> bytes =
        withoutLightSection(withoutSpecularColours(withoutTextures(withoutEmitterSection(withoutCoatMaps(current)))));
    // The light section's checksum, the emitter section, the texture head, the colours and the maps
    // (the coat's and the five before them) no longer lie before it.
    p.offset -= 8 + 16 + 32 + (32ull + 156ull + 56ull) * materials;
    // Version 14's leaves decoded (NanoVDB's float leaves: the values exactly) into 512 f32 a brick.
    const uint64_t voxelBytes = 4ull * kVolumeBrickVoxels, leafBytes = volumeLeafBytes(p.volume.codec);
    std::vector<uint8_t> out(bytes.begin(), bytes.begin() + int64_t(p.offset + 4 * p.volume.cellCount()));
    std::vector<float> voxels(kVolumeBrickVoxels);
    for (int part = 0; part < (p.hasEmission ? 2 : 1); ++part)
        for (uint64_t b = 0; b < p.brickCount; ++b) {
            EXPECT_EQ(decodeVolumeLeaf(p.volume.codec, bytes.data() + brickOffset(p, b) + part * leafBytes, voxels.data()), "");
            const auto* at = reinterpret_cast<const uint8_t*>(voxels.data());
            out.insert(out.end(), at, at + voxelBytes);
        }
    const uint32_t five = 5;
    const uint64_t fileBytes = out.size(), size = out.size() - p.offset;
    const uint64_t data = checksum64(out.data() + p.offset, size);
    uint64_t recordAt = 0;
    std::memcpy(&recordAt, out.data() + 256 - 24, 8);
    std::memcpy(out.data() + 8, &five, 4);
    std::memcpy(out.data() + 16, &fileBytes, 8);
    std::memcpy(out.data() + recordAt + 172, &size, 8);
    std::memcpy(out.data() + recordAt + 180, &data, 8);
    resealRecordsAndHeader(out, recordAt);
    return out;
}

}  // namespace vastray::test
