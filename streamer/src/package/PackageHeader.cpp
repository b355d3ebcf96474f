#include "package/PackageHeader.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>

#include "package/PackageFormat.h"
#include "vastray/core/Checksum.h"
#include "vastray/core/VertexAttributes.h"
#include "vastray/core/Microfacet.h"
#include "vastray/core/Utf8.h"
#include "vastray/streamer/Import.h"

namespace vastray {
namespace {

std::string formatReal(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", v);
    return text;
}

std::string hex32(uint32_t v) {
    char text[16];
    std::snprintf(text, sizeof text, "%08x", v);
    return text;
}

// Every float the reader trusts from the header: the checksum only proves the bytes are the
// ones written, not that a writer (or someone who recomputed it) wrote sane values. A NaN
// bound or grid origin rendered sky; a grid range of 1e300 overflowed dequantization.
}  // namespace

Status checkStoredBox(const std::string& what, const Aabb& box) {
    static const char* kAxes = "xyz";
    for (int a = 0; a < 3; ++a) {
        for (float v : {box.lo[a], box.hi[a]}) {
            if (!std::isfinite(v)) return Status::error(what + " " + kAxes[a] + " " + formatReal(v) + " is not finite");
            if (std::fabs(v) > kMaxAbsCoordinate)
                return Status::error(what + " " + kAxes[a] + " " + formatReal(v) +
                                     " lies beyond the coordinate limit of +-1e18");
        }
        if (box.lo[a] > box.hi[a])
            return Status::error(what + " are inverted on " + kAxes[a] + " (" + formatReal(box.lo[a]) +
                                 " > " + formatReal(box.hi[a]) + ")");
    }
    return Status::ok();
}

namespace {

Status checkGrid(const QuantizationGrid& grid) {
    if (grid.bits > 30) return Status::error("header: quantization grid of " + std::to_string(grid.bits) + " bits (limit 30)");
    static const char* kAxes = "xyz";
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(grid.origin[a]) || std::fabs(grid.origin[a]) > kMaxAbsCoordinate)
            return Status::error(std::string("header: grid origin ") + kAxes[a] + " " + formatReal(grid.origin[a]) +
                                 " is not a finite coordinate within +-1e18");
    // The range is the scene's largest extent: at most twice the coordinate limit.
    if (!(grid.range > 0) || !(grid.range <= 2.0 * kMaxAbsCoordinate))
        return Status::error("header: grid range " + formatReal(grid.range) + " is outside (0, 2e18]");
    return Status::ok();
}

}  // namespace


Status checksumMismatch(const std::string& name, uint64_t stored, uint64_t computed) {
    char text[80];
    std::snprintf(text, sizeof text, " checksum mismatch (stored 0x%016llx, computed 0x%016llx)",
                  (unsigned long long)stored, (unsigned long long)computed);
    return Status::error(name + text);
}

std::vector<uint8_t> serializeHeader(const PackageInfo& info, const SectionLayout& layout) {
    ByteWriter out;
    out.putBytes(format::kMagic, 8);
    out.put(format::kVersion);
    out.put(format::kHeaderBytes);
    for (uint64_t v : {info.fileBytes, info.triangleCount, info.referenceCount, info.chunkSizeBytes,
                       info.maxChunkResidentBytes, info.degenerateDropped, info.collapsedDropped})
        out.put(v);
    out.put((info.defaultDoubleSided ? uint32_t(format::kDefaultDoubleSided) : 0u) |
            (info.codec == GeometryCodec::Meshopt ? uint32_t(format::kMeshoptChunks) : 0u) |
            (info.hasNormals ? uint32_t(format::kHasNormals) : 0u) | (info.hasColors ? uint32_t(format::kHasColors) : 0u) |
            (info.hasUvs ? uint32_t(format::kHasUvs) : 0u));
    out.put(info.grid.bits);
    out.put(layout.materialCount);
    out.put(layout.topNodeCount);
    out.put(layout.chunkCount);
    out.put(layout.volumeCount);
    out.put(info.bounds.lo);
    out.put(info.bounds.hi);
    for (double v : info.grid.origin) out.put(v);
    out.put(info.grid.range);
    for (uint64_t v : {layout.materialsOffset, layout.treeOffset, layout.directoryOffset, layout.blobsOffset,
                       layout.materialsChecksum, layout.treeChecksum, layout.directoryChecksum})
        out.put(v);
    out.put(layout.camerasOffset), out.put(layout.camerasChecksum), out.put(layout.cameraCount), out.put(layout.lightCount);
    out.put(layout.volumesOffset), out.put(layout.volumesChecksum);
    out.padTo(format::kHeaderBytes - 8);
    out.put(checksum64(out.bytes().data(), out.size()));
    return std::move(out.bytes());
}

Result<SectionLayout> parseHeader(const uint8_t* bytes, size_t size, PackageInfo& info) {
    if (size < format::kHeaderBytes) return Status::error("file is too short to be a package");
    if (std::memcmp(bytes, format::kMagic, 8) != 0) return Status::error("not a vastray package (bad magic)");
    ByteReader in(bytes + 8, format::kHeaderBytes - 8);
    uint32_t headerBytes = 0, flags = 0;
    in.get(info.formatVersion);
    in.get(headerBytes);
    if (info.formatVersion < format::kOldestReadableVersion || info.formatVersion > format::kVersion)
        return Status::error("package format version " + std::to_string(info.formatVersion) +
                             " is not supported (this vastray reads " + std::to_string(format::kOldestReadableVersion) +
                             " to " + std::to_string(format::kVersion) + "): re-import the mesh with this vastray");
    uint64_t stored = 0;
    std::memcpy(&stored, bytes + format::kHeaderBytes - 8, 8);
    if (headerBytes != format::kHeaderBytes) return Status::error("header size " + std::to_string(headerBytes) +
                                                                  " is not " + std::to_string(format::kHeaderBytes));
    if (const uint64_t computed = checksum64(bytes, format::kHeaderBytes - 8); stored != computed)
        return checksumMismatch("header", stored, computed);
    SectionLayout layout;
    for (uint64_t* v : {&info.fileBytes, &info.triangleCount, &info.referenceCount, &info.chunkSizeBytes,
                        &info.maxChunkResidentBytes, &info.degenerateDropped, &info.collapsedDropped})
        in.get(*v);
    in.get(flags);
    in.get(info.grid.bits);
    in.get(layout.materialCount);
    in.get(layout.topNodeCount);
    in.get(layout.chunkCount);
    in.get(layout.volumeCount);  // version 3: a reserved 0
    in.get(info.bounds.lo);
    in.get(info.bounds.hi);
    for (double& v : info.grid.origin) in.get(v);
    in.get(info.grid.range);
    for (uint64_t* v : {&layout.materialsOffset, &layout.treeOffset, &layout.directoryOffset, &layout.blobsOffset,
                        &layout.materialsChecksum, &layout.treeChecksum, &layout.directoryChecksum})
        in.get(*v);
    in.get(layout.camerasOffset), in.get(layout.camerasChecksum), in.get(layout.cameraCount), in.get(layout.lightCount);
    in.get(layout.volumesOffset), in.get(layout.volumesChecksum);  // version 3: zero padding
    if (info.formatVersion < 4 && (layout.volumeCount != 0 || layout.volumesOffset != 0 || layout.volumesChecksum != 0))
        return Status::error("header: a version 3 package with volume fields");
    if (layout.volumeCount > kMaxVolumes)
        return Status::error("header: volume count " + std::to_string(layout.volumeCount) + " exceeds the limit of " +
                             std::to_string(kMaxVolumes));
    if (layout.cameraCount > format::kMaxCameras)
        return Status::error("header: camera count " + std::to_string(layout.cameraCount) + " exceeds the limit of " +
                             std::to_string(format::kMaxCameras));
    if (info.formatVersion < format::kFirstLightsVersion && layout.lightCount != 0)
        return Status::error("header: the field after the camera count is not 0 (a version " +
                             std::to_string(info.formatVersion) + " package has no lights)");
    if (layout.lightCount > kMaxLights)
        return Status::error("header: light count " + std::to_string(layout.lightCount) + " exceeds the limit of " +
                             std::to_string(kMaxLights));
    info.defaultDoubleSided = (flags & format::kDefaultDoubleSided) != 0;
    info.codec = (flags & format::kMeshoptChunks) ? GeometryCodec::Meshopt : GeometryCodec::Draco;
    info.hasNormals = (flags & format::kHasNormals) != 0;
    info.hasColors = (flags & format::kHasColors) != 0;
    info.hasUvs = (flags & format::kHasUvs) != 0;
    if (!in.ok()) return Status::error("truncated header");
    if (flags & ~format::kKnownHeaderFlags) return Status::error("header has unknown flags " + std::to_string(flags));
    if (info.hasUvs && info.formatVersion < format::kFirstUvVersion)
        return Status::error("header: a version " + std::to_string(info.formatVersion) +
                             " package with the texture coordinate flag (version " +
                             std::to_string(format::kFirstUvVersion) + " brought them)");
    VASTRAY_TRY(checkGrid(info.grid));
    VASTRAY_TRY(checkStoredBox("header: scene bounds", info.bounds));
    if (layout.materialCount == 0 || layout.materialCount > format::kMaxMaterials || layout.chunkCount > format::kMaxChunks)
        return Status::error("header counts out of range");
    if (info.triangleCount > info.referenceCount) return Status::error("header has fewer references than triangles");
    return layout;
}

std::vector<uint8_t> serializeMaterials(const std::vector<Material>& materials) {
    ByteWriter out;
    for (const Material& m : materials) {
        out.put(m.baseColor);
        out.put(m.emissive);
        out.put(uint32_t(m.doubleSided ? 1 : 0));
        out.put(m.metallic), out.put(m.roughness), out.put(m.specular), out.put(m.alphaCutoff);
        out.putFixedString(cutUtf8(m.name, format::kMaterialNameBytes), format::kMaterialNameBytes);  // whole characters
        out.put(m.specularColor), out.put(m.clearcoat), out.put(m.clearcoatRoughness);
        out.put(m.alphaBlend ? format::kMaterialAlphaBlend : 0u);  // flags (version 12)
        out.put(m.ior), out.put(uint32_t(0));                       // ior (version 13), a reserved word
        for (const TextureBinding& b : m.textures.slots) out.put(b.texture), out.put(b.transform);
        out.put(m.textures.normalScale), out.put(m.textures.occlusionStrength), out.put(uint32_t(0)), out.put(uint32_t(0));
    }
    return std::move(out.bytes());
}

namespace {

// A material's maps as a reader checks them: each texture index one of the package's or
// kNoTexture, each UV transform entry finite within +-kMaxUvTransformEntry (what the importers'
// limit allows), the normal scale within +-kMaxUvTransformValue, the occlusion strength in [0, 1].
std::string mapsProblem(const MaterialTextures& t, uint32_t textureCount) {
    for (uint32_t s = 0; s < kTextureSlotCount; ++s) {
        const TextureBinding& b = t.slots[s];
        const std::string slot = textureSlotName(TextureSlot(s));
        if (b.texture != kNoTexture && b.texture >= textureCount)
            return slot + " names texture " + std::to_string(b.texture) + " of " + std::to_string(textureCount);
        for (float v : b.transform)
            if (!(std::fabs(v) <= kMaxUvTransformEntry))
                return slot + " UV transform value " + std::to_string(v) + " is outside +-4e6";
    }
    if (!(std::fabs(t.normalScale) <= kMaxUvTransformValue))
        return "normal scale " + std::to_string(t.normalScale) + " is outside +-1e6";
    if (!(t.occlusionStrength >= 0.0f && t.occlusionStrength <= 1.0f))
        return "occlusion strength " + std::to_string(t.occlusionStrength) + " is outside [0, 1]";
    return "";
}

}  // namespace

Result<std::vector<Material>> parseMaterials(const std::vector<uint8_t>& bytes, uint32_t count, uint32_t version,
                                             uint32_t textureCount) {
    ByteReader in(bytes.data(), bytes.size());
    std::vector<Material> materials(count);
    for (uint32_t i = 0; i < count; ++i) {
        Material& m = materials[i];
        uint32_t doubleSided = 0;
        in.get(m.baseColor);
        in.get(m.emissive);
        in.get(doubleSided);
        uint32_t reserved[4] = {0, 0, 0, 0};
        if (version >= format::kFirstCutoutVersion)
            in.get(m.metallic), in.get(m.roughness), in.get(m.specular), in.get(m.alphaCutoff);
        else if (version >= 5)
            in.get(m.metallic), in.get(m.roughness), in.get(m.specular), in.get(reserved[0]);
        in.getFixedString(m.name, format::kMaterialNameBytes);
        m.name = validUtf8(m.name);  // a forged or older package may hold a split character
        if (version >= format::kFirstSpecularColorVersion) {
            in.get(m.specularColor), in.get(m.clearcoat), in.get(m.clearcoatRoughness);
            for (int r = 1; r < 4; ++r) in.get(reserved[r]);
        }
        // Version 12: the first word after the coat holds flags; 13: the second the ior (else 1.5).
        uint32_t flags = 0;
        if (version >= format::kFirstEmittersVersion) std::swap(flags, reserved[1]);
        if (version >= format::kFirstCoatMapsVersion) std::memcpy(&m.ior, &reserved[2], 4), reserved[2] = 0;
        uint32_t mapsReserved[2] = {0, 0};
        if (version >= format::kFirstTextureVersion) {
            for (uint32_t slot = 0; slot < format::materialMaps(version); ++slot)
                in.get(m.textures.slots[slot].texture), in.get(m.textures.slots[slot].transform);
            in.get(m.textures.normalScale), in.get(m.textures.occlusionStrength);
            in.get(mapsReserved[0]), in.get(mapsReserved[1]);
        }
        m.doubleSided = doubleSided != 0;
        if (!in.ok()) break;
        const std::string what = "material " + std::to_string(i) + " ('" + m.name + "')";
        if (flags & ~format::kKnownMaterialFlags) return Status::error(what + " has unknown flags " + std::to_string(flags));
        m.alphaBlend = (flags & format::kMaterialAlphaBlend) != 0;
        if (const std::string problem = materialFactorProblem(m); !problem.empty())
            return Status::error(what + ": " + problem);
        for (uint32_t r : reserved)
            if (r != 0) return Status::error(what + " has a non-zero reserved field");
        if (mapsReserved[0] != 0 || mapsReserved[1] != 0) return Status::error(what + " has a non-zero reserved field");
        if (const std::string problem = mapsProblem(m.textures, textureCount); !problem.empty())
            return Status::error(what + ": " + problem);
        for (float v : m.baseColor)
            if (!std::isfinite(v)) return Status::error(what + " has a non-finite colour");
        for (float v : m.emissive)
            if (!std::isfinite(v)) return Status::error(what + " has a non-finite emission");
    }
    if (!in.ok()) return Status::error("truncated materials");
    return materials;
}

static_assert(format::kCameraNameBytes == kMaxSceneCameraNameBytes);
static_assert(format::materialMaps(format::kVersion) == kTextureSlotCount);

std::vector<uint8_t> serializeCameras(const std::vector<SceneCamera>& cameras) {
    ByteWriter out;
    for (const SceneCamera& c : cameras) {
        out.putFixedString(storedCameraName(c.name), format::kCameraNameBytes);  // importers cut it already
        out.put(c.camera.eye), out.put(c.camera.target), out.put(c.camera.up), out.put(c.camera.fovYDegrees);
    }
    return std::move(out.bytes());
}

Result<std::vector<SceneCamera>> parseCameras(const std::vector<uint8_t>& bytes, uint32_t count) {
    ByteReader in(bytes.data(), bytes.size());
    std::vector<SceneCamera> cameras(count);
    for (uint32_t i = 0; i < count; ++i) {
        SceneCamera& c = cameras[i];
        in.getFixedString(c.name, format::kCameraNameBytes);
        c.name = validUtf8(c.name);
        in.get(c.camera.eye), in.get(c.camera.target), in.get(c.camera.up), in.get(c.camera.fovYDegrees);
        if (!in.ok()) return Status::error("truncated cameras");
        VASTRAY_TRY(validateCamera(c.camera).withContext("camera " + std::to_string(i) + " '" + c.name + "': "));
    }
    return cameras;
}

static_assert(format::kLightNameBytes == kMaxLightNameBytes);

std::vector<uint8_t> serializeLights(const std::vector<PunctualLight>& lights) {
    ByteWriter out;
    for (const PunctualLight& l : lights) {
        out.putFixedString(storedCameraName(l.name), format::kLightNameBytes);  // importers cut it already
        out.put(uint32_t(l.type)), out.put(l.color), out.put(l.intensity), out.put(l.range);
        out.put(l.innerConeAngle), out.put(l.outerConeAngle), out.put(l.position), out.put(l.direction);
        out.put(uint32_t(0)), out.put(uint32_t(0));
    }
    out.put(checksum64(out.bytes().data(), out.size()));
    return std::move(out.bytes());
}

Result<std::vector<PunctualLight>> parseLights(const std::vector<uint8_t>& bytes, uint32_t count) {
    const uint64_t recordBytes = uint64_t(count) * format::kLightBytes;
    if (bytes.size() != recordBytes + 8) return Status::error("truncated lights");
    uint64_t stored = 0;
    std::memcpy(&stored, bytes.data() + recordBytes, 8);
    if (const uint64_t computed = checksum64(bytes.data(), recordBytes); computed != stored)
        return checksumMismatch("lights", stored, computed);
    ByteReader in(bytes.data(), recordBytes);
    std::vector<PunctualLight> lights(count);
    for (uint32_t i = 0; i < count; ++i) {
        PunctualLight& l = lights[i];
        uint32_t type = 0, reserved0 = 0, reserved1 = 0;
        in.getFixedString(l.name, format::kLightNameBytes);
        l.name = validUtf8(l.name);
        in.get(type), in.get(l.color), in.get(l.intensity), in.get(l.range);
        in.get(l.innerConeAngle), in.get(l.outerConeAngle), in.get(l.position), in.get(l.direction);
        in.get(reserved0), in.get(reserved1);
        if (!in.ok()) return Status::error("truncated lights");
        const std::string what = "light " + std::to_string(i) + " '" + l.name + "': ";
        if (reserved0 != 0 || reserved1 != 0) return Status::error(what + "its reserved words are not 0");
        l.type = LightType(type);
        VASTRAY_TRY(validateLight(l).withContext(what));
    }
    return lights;
}

std::vector<uint8_t> serializeEmitters(const std::vector<EmissiveTriangle>& emitters) {
    ByteWriter out;
    out.put(uint32_t(emitters.size())), out.put(uint32_t(0));
    for (const EmissiveTriangle& e : emitters)
        out.put(e.v0), out.put(e.v1), out.put(e.v2), out.put(e.material), out.put(e.t0), out.put(e.t1), out.put(e.t2);
    out.put(checksum64(out.bytes().data(), out.size()));
    return std::move(out.bytes());
}

Result<uint32_t> parseEmittersHead(const std::vector<uint8_t>& bytes) {
    ByteReader in(bytes.data(), bytes.size());
    uint32_t count = 0, reserved = 0;
    in.get(count), in.get(reserved);
    if (!in.ok()) return Status::error("truncated emitters");
    if (reserved != 0) return Status::error("emitters: the word after the count is not 0");
    if (count > kMaxEmitters)
        return Status::error("emitters: count " + std::to_string(count) + " exceeds the limit of " +
                             std::to_string(kMaxEmitters));
    return count;
}

Result<std::vector<EmissiveTriangle>> parseEmitters(const std::vector<uint8_t>& bytes, uint32_t count,
                                                    const std::vector<Material>& materials, uint64_t textureCount,
                                                    uint32_t version) {
    const uint64_t covered = format::kEmittersHeadBytes + uint64_t(count) * format::emitterBytes(version);
    if (bytes.size() != covered + 8) return Status::error("truncated emitters");
    uint64_t stored = 0;
    std::memcpy(&stored, bytes.data() + covered, 8);
    if (const uint64_t computed = checksum64(bytes.data(), covered); computed != stored)
        return checksumMismatch("emitters", stored, computed);
    ByteReader in(bytes.data() + format::kEmittersHeadBytes, covered - format::kEmittersHeadBytes);
    std::vector<EmissiveTriangle> emitters(count);
    for (uint32_t i = 0; i < count; ++i) {
        EmissiveTriangle& e = emitters[i];
        in.get(e.v0), in.get(e.v1), in.get(e.v2), in.get(e.material);
        if (version >= format::kFirstEmitterUvVersion) in.get(e.t0), in.get(e.t1), in.get(e.t2);
        if (!in.ok()) return Status::error("truncated emitters");
        const std::string what = "emitter " + std::to_string(i) + ": ";
        for (const std::array<float, 2>& t : {e.t0, e.t1, e.t2})
            for (float x : t)
                if (!(std::fabs(x) <= kMaxAbsUv))
                    return Status::error(what + "corner UV " + std::to_string(x) + " is not within +-" +
                                         std::to_string(kMaxAbsUv));
        for (const Vec3f& v : {e.v0, e.v1, e.v2})
            for (int axis = 0; axis < 3; ++axis)
                if (!(std::fabs(v[axis]) <= kMaxAbsCoordinate))
                    return Status::error(what + "corner coordinate " + std::to_string(v[axis]) + " is not within +-" +
                                         std::to_string(kMaxAbsCoordinate));
        if (e.material >= materials.size())
            return Status::error(what + "material " + std::to_string(e.material) + " of " +
                                 std::to_string(materials.size()));
        if (!isSampledEmitter(materials[e.material], textureCount))
            return Status::error(what + "material " + std::to_string(e.material) + " ('" + materials[e.material].name +
                                 "') is not an emitter next-event estimation samples");
    }
    return emitters;
}

std::vector<uint8_t> serializeVolumeRecords(const std::vector<PackageVolume>& volumes) {
    ByteWriter out;
    for (const PackageVolume& p : volumes) {
        const size_t start = out.size();
        const Volume& v = p.volume;
        out.putFixedString(cutUtf8(v.name, format::kVolumeNameBytes), format::kVolumeNameBytes);
        out.put(v.indexToWorld);
        out.put(v.origin);
        out.put(v.brickCells);
        out.put(p.brickCount);
        out.put(v.material.albedo);
        out.put(v.material.densityScale);
        out.put(v.material.anisotropy);
        out.put(uint32_t((p.hasEmission ? 1 : 0) | (p.hasEmission && v.material.temperature ? 2 : 0) |
                         (uint32_t(v.codec) << 2)));
        out.put(p.offset), out.put(p.size), out.put(p.checksum);
        out.put(v.material.emission);
        out.padTo(start + format::kVolumeRecordBytes);
    }
    return std::move(out.bytes());
}

Result<std::vector<PackageVolume>> parseVolumeRecords(const std::vector<uint8_t>& bytes, uint32_t count,
                                                      uint32_t version) {
    std::vector<PackageVolume> volumes(count);
    for (uint32_t i = 0; i < count; ++i) {
        if (bytes.size() < uint64_t(i + 1) * format::kVolumeRecordBytes) return Status::error("truncated volume records");
        ByteReader in(bytes.data() + uint64_t(i) * format::kVolumeRecordBytes, format::kVolumeRecordBytes);
        PackageVolume& p = volumes[i];
        Volume& v = p.volume;
        uint32_t flags = 0;
        in.getFixedString(v.name, format::kVolumeNameBytes);
        v.name = validUtf8(v.name);
        in.get(v.indexToWorld);
        in.get(v.origin);
        in.get(v.brickCells);
        in.get(p.brickCount);
        in.get(v.material.albedo);
        in.get(v.material.densityScale);
        in.get(v.material.anisotropy);
        in.get(flags);
        in.get(p.offset), in.get(p.size), in.get(p.checksum);
        in.get(v.material.emission);
        const std::string name = "volume " + std::to_string(i) + " '" + v.name + "': ";
        if (!in.ok()) return Status::error(name + "truncated record");
        // Bit 0: an emission grid; bit 1: it is a temperature in kelvin (a reader before bit 1
        // was defined refuses it as unknown, so format 6 carries it); from version 14 bits 2-3:
        // the bricks' codec (core/VolumeLeaf.h).
        uint32_t codec = 0;
        if (version >= format::kFirstLeafBricksVersion) codec = (flags >> 2) & 3u, flags &= ~(3u << 2);
        if (codec >= kVolumeCodecCount) return Status::error(name + "unknown brick codec " + std::to_string(codec));
        if (flags > 3) return Status::error(name + "unknown flags " + std::to_string(flags));
        if (flags == 2) return Status::error(name + "flags 2: a temperature grid without an emission grid");
        p.hasEmission = (flags & 1) != 0;
        v.material.temperature = (flags & 2) != 0;
        v.codec = VolumeCodec(codec);
        if (p.brickCount > kMaxVolumeBricks)
            return Status::error(name + std::to_string(p.brickCount) + " bricks exceed the limit of " +
                                 std::to_string(kMaxVolumeBricks));
        // checkVolume on the record alone: an empty table stands for the cells until the data is read.
        Volume shape = v;
        shape.brickOf.assign(0, 0);
        shape.codec = VolumeCodec::Float;  // (its bricks stay in the file: any codec)
        const double cells = double(v.brickCells[0]) * v.brickCells[1] * v.brickCells[2];
        if (cells > double(kMaxVolumeBrickCells))
            return Status::error(name + "brick grid of " + std::to_string(v.brickCells[0]) + " x " +
                                 std::to_string(v.brickCells[1]) + " x " + std::to_string(v.brickCells[2]) +
                                 " cells exceeds the limit of " + std::to_string(kMaxVolumeBrickCells));
        shape.brickOf.assign(shape.cellCount(), kNoBrick);
        if (const std::string problem = checkVolume(shape); !problem.empty()) return Status::error(name + problem);
        if (p.size != format::volumeDataBytes(version, v.cellCount(), p.brickCount, v.codec, p.hasEmission))
            return Status::error(name + "data of " + std::to_string(p.size) + " bytes does not match its " +
                                 std::to_string(v.cellCount()) + " cells and " + std::to_string(p.brickCount) + " bricks");
        if (!finishVolumeTransform(v)) return Status::error(name + "the index-to-world map is not invertible");
        VASTRAY_TRY(checkStoredBox(name + "bounds", v.worldBounds));
    }
    return volumes;
}

std::vector<uint8_t> serializeDirectory(const std::vector<ChunkInfo>& chunks) {
    ByteWriter out;
    for (const ChunkInfo& c : chunks) {
        for (uint64_t v : {c.offset, c.size, c.checksum, c.residentBytes}) out.put(v);
        const uint32_t layout =
            (c.flags & kChunkIndexDeltas16) != 0 ? format::kDirectoryIndexDeltas16 | c.longTriangles : 0u;
        for (uint32_t v : {c.triangleCount, c.vertexCount, c.bvhNodeCount, layout}) out.put(v);
        out.put(c.cell.lo);
        out.put(c.cell.hi);
    }
    return std::move(out.bytes());
}

Result<std::vector<ChunkInfo>> parseDirectory(const std::vector<uint8_t>& bytes, uint32_t count, uint32_t version) {
    ByteReader in(bytes.data(), bytes.size());
    std::vector<ChunkInfo> chunks(count);
    const uint32_t longMask = (1u << format::kDirectoryLongTriangleBits) - 1;
    for (uint32_t i = 0; i < count; ++i) {
        ChunkInfo& c = chunks[i];
        c.id = i;
        const std::string name = "chunk " + std::to_string(i) + ": ";
        for (uint64_t* v : {&c.offset, &c.size, &c.checksum, &c.residentBytes}) in.get(*v);
        uint32_t layout = 0;
        for (uint32_t* v : {&c.triangleCount, &c.vertexCount, &c.bvhNodeCount, &layout}) in.get(*v);
        if (version < format::kFirstChunkFlagsVersion) {
            if (layout != 0) return Status::error(name + "reserved directory field is not 0");
        } else if (layout != 0) {
            if ((layout & format::kDirectoryIndexDeltas16) == 0 || (layout & ~(format::kDirectoryIndexDeltas16 | longMask)) != 0)
                return Status::error(name + "unknown index layout 0x" + hex32(layout) + " in its directory entry");
            c.flags = kChunkIndexDeltas16;
            c.longTriangles = layout & longMask;
            if (c.longTriangles > c.triangleCount)
                return Status::error(name + std::to_string(c.longTriangles) + " long triangles of " +
                                     std::to_string(c.triangleCount));
        }
        in.get(c.cell.lo);
        in.get(c.cell.hi);
    }
    if (!in.ok()) return Status::error("truncated chunk directory");
    return chunks;
}

}  // namespace vastray
