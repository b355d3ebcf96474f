#include "import/AssimpAnswer.h"

#include "import/GltfTextures.h"
#include "import/ImportCommon.h"
#include "package/ByteIo.h"
#include "vastray/core/Camera.h"
#include "vastray/core/Light.h"
#include "vastray/core/MaterialTextures.h"

namespace vastray::import {
namespace {

// Strings and arrays each after their uint64 length; ByteReader's reads never pass the end.
void putText(ByteWriter& w, const std::string& text) {
    w.put(uint64_t(text.size()));
    w.putBytes(text.data(), text.size());
}
template <typename T>
void putCounted(ByteWriter& w, const std::vector<T>& values) {
    w.put(uint64_t(values.size()));
    w.putArray(values);
}
bool getText(ByteReader& r, std::string& text) {
    uint64_t size = 0;
    if (!r.get(size) || size > r.remaining()) return false;
    text.assign(reinterpret_cast<const char*>(r.current()), size);
    return r.skip(size);
}
template <typename T>
bool getCounted(ByteReader& r, std::vector<T>& values) {
    uint64_t count = 0;
    return r.get(count) && r.getArray(values, count);
}

void encodeReport(ByteWriter& w, const ImportReport& report) {
    putText(w, report.format);
    w.put(report.verticesRead), w.put(report.normalsRead), w.put(report.coloursRead);
    w.put(report.texcoordsRead), w.put(report.textureMaps);
    w.put(report.primitivesSkipped);
    w.put(uint64_t(report.warnings.size()));
    for (const std::string& warning : report.warnings) putText(w, warning);
}

// The materials' factors; their maps follow the textures (encodeTextures).
void encodeMaterials(ByteWriter& w, const std::vector<Material>& materials) {
    w.put(uint64_t(materials.size()));
    for (const Material& material : materials) {
        putText(w, material.name);
        w.put(material.baseColor), w.put(material.emissive), w.put(uint8_t(material.doubleSided));
        w.put(material.metallic), w.put(material.roughness), w.put(material.specular);
        w.put(material.alphaCutoff);
    }
}

void encodeCamerasAndLights(ByteWriter& w, const TriangleMesh& mesh) {
    w.put(uint64_t(mesh.cameras.size()));
    for (const SceneCamera& camera : mesh.cameras) {
        putText(w, camera.name);
        w.put(camera.camera.eye), w.put(camera.camera.target), w.put(camera.camera.up);
        w.put(camera.camera.fovYDegrees);
    }
    w.put(uint64_t(mesh.lights.size()));
    for (const PunctualLight& l : mesh.lights) {
        putText(w, l.name);
        w.put(uint32_t(l.type)), w.put(l.color), w.put(l.intensity), w.put(l.range);
        w.put(l.innerConeAngle), w.put(l.outerConeAngle), w.put(l.position), w.put(l.direction);
    }
}

// The textures, then each material's maps of them.
void encodeTextures(ByteWriter& w, const TriangleMesh& mesh) {
    w.put(uint64_t(mesh.textures.size()));
    for (const TextureSource& t : mesh.textures) {
        putText(w, t.name), putText(w, t.extension), putCounted(w, t.bytes);
        w.put(uint32_t(t.wrapS)), w.put(uint32_t(t.wrapT)), w.put(uint32_t(t.encoding));
    }
    for (const Material& material : mesh.materials) {
        for (const TextureBinding& b : material.textures.slots) w.put(b.texture), w.put(b.transform);
        w.put(material.textures.normalScale), w.put(material.textures.occlusionStrength);
    }
}

void encodeMasks(ByteWriter& w, const std::vector<AlphaMaskRequest>& masks) {
    w.put(uint64_t(masks.size()));
    for (const AlphaMaskRequest& mask : masks)
        w.put(mask.material), w.put(mask.mask), w.put(uint8_t(mask.channel)), w.put(mask.transform),
            w.put(uint8_t(mask.sameImageAsBase));
}

// The report encodeReport wrote; counts above the answer's size are refused before any resize.
bool decodeReport(ByteReader& r, size_t answerBytes, ImportReport& report) {
    uint64_t warnings = 0;
    if (!getText(r, report.format) || !r.get(report.verticesRead) || !r.get(report.normalsRead) ||
        !r.get(report.coloursRead) || !r.get(report.texcoordsRead) || !r.get(report.textureMaps) ||
        !r.get(report.primitivesSkipped) || !r.get(warnings) || warnings > answerBytes)
        return false;
    report.warnings.resize(warnings);
    for (std::string& warning : report.warnings)
        if (!getText(r, warning)) return false;
    return true;
}

// The materials' factors encodeMaterials wrote, each alpha cutoff within [0, 1].
bool decodeMaterials(ByteReader& r, size_t answerBytes, std::vector<Material>& materials) {
    uint64_t count = 0;
    if (!r.get(count) || count > answerBytes) return false;
    materials.resize(count);
    for (Material& material : materials) {
        uint8_t doubleSided = 1;
        if (!getText(r, material.name) || !r.get(material.baseColor) || !r.get(material.emissive) ||
            !r.get(doubleSided) || !r.get(material.metallic) || !r.get(material.roughness) ||
            !r.get(material.specular) || !r.get(material.alphaCutoff) ||
            !(material.alphaCutoff >= 0.0f && material.alphaCutoff <= 1.0f))
            return false;
        material.doubleSided = doubleSided != 0;
    }
    return true;
}

// The cameras encodeCamerasAndLights wrote, each one validateCamera accepts.
bool decodeCameras(ByteReader& r, size_t answerBytes, std::vector<SceneCamera>& cameras) {
    uint64_t count = 0;
    if (!r.get(count) || count > answerBytes) return false;
    cameras.resize(count);
    for (SceneCamera& camera : cameras)
        if (!getText(r, camera.name) || !r.get(camera.camera.eye) || !r.get(camera.camera.target) ||
            !r.get(camera.camera.up) || !r.get(camera.camera.fovYDegrees) ||
            !validateCamera(camera.camera).isOk())
            return false;
    return true;
}

// The lights encodeCamerasAndLights wrote, each within validateLight's limits (the child
// checked them).
bool decodeLights(ByteReader& r, size_t answerBytes, std::vector<PunctualLight>& lights) {
    uint64_t count = 0;
    if (!r.get(count) || count > answerBytes || count > kMaxLights) return false;
    lights.resize(count);
    for (PunctualLight& l : lights) {
        uint32_t type = 0;
        if (!getText(r, l.name) || !r.get(type) || !r.get(l.color) || !r.get(l.intensity) ||
            !r.get(l.range) || !r.get(l.innerConeAngle) || !r.get(l.outerConeAngle) || !r.get(l.position) ||
            !r.get(l.direction))
            return false;
        l.type = LightType(type);
        if (!validateLight(l).isOk()) return false;
    }
    return true;
}

// The textures and the materials' maps encodeTextures wrote: PNG, JPEG or KTX2, known wrap
// modes and encodings, each map's texture one of them.
bool decodeTextures(ByteReader& r, size_t answerBytes, TriangleMesh& mesh) {
    uint64_t count = 0;
    if (!r.get(count) || count > answerBytes || count > kMaxSceneTextures) return false;
    mesh.textures.resize(count);
    for (TextureSource& t : mesh.textures) {
        uint32_t wrapS = 0, wrapT = 0, encoding = 0;
        if (!getText(r, t.name) || !getText(r, t.extension) || !getCounted(r, t.bytes) || !r.get(wrapS) ||
            !r.get(wrapT) || !r.get(encoding) || wrapS > 2 || wrapT > 2 || encoding > 1 ||
            imageSignatureExtension(t.bytes) != t.extension ||
            (t.extension != ".png" && t.extension != ".jpg" && t.extension != ".ktx2"))
            return false;
        t.wrapS = TextureWrap(wrapS), t.wrapT = TextureWrap(wrapT), t.encoding = TextureEncoding(encoding);
    }
    for (Material& material : mesh.materials) {
        for (TextureBinding& b : material.textures.slots)
            if (!r.get(b.texture) || !r.get(b.transform) || (b.texture != kNoTexture && b.texture >= count))
                return false;
        if (!r.get(material.textures.normalScale) || !r.get(material.textures.occlusionStrength))
            return false;
    }
    return true;
}

// The opacity masks encodeMasks wrote, each of a material and a texture there are.
bool decodeMasks(ByteReader& r, size_t answerBytes, const TriangleMesh& mesh,
                 std::vector<AlphaMaskRequest>& masks) {
    uint64_t count = 0;
    if (!r.get(count) || count > answerBytes || count > mesh.materials.size()) return false;
    masks.resize(count);
    for (AlphaMaskRequest& mask : masks) {
        uint8_t channel = 0, same = 0;
        if (!r.get(mask.material) || !r.get(mask.mask) || !r.get(channel) || !r.get(mask.transform) ||
            !r.get(same) || mask.material >= mesh.materials.size() || mask.mask >= mesh.textures.size() ||
            channel > kMaskChannelMax || same > 1)
            return false;
        mask.channel = MaskChannel(channel), mask.sameImageAsBase = same != 0;
    }
    return true;
}

}  // namespace

std::vector<uint8_t> encodeAssimpAnswer(const Result<ImportedMesh>& result,
                                        const std::vector<AlphaMaskRequest>& masks) {
    ByteWriter w;
    if (!result) {
        w.put(uint8_t(0));
        putText(w, result.message());
        return std::move(w.bytes());
    }
    const ImportedMesh& m = *result;
    w.put(uint8_t(1));
    encodeReport(w, m.report);
    encodeMaterials(w, m.mesh.materials);
    putCounted(w, m.mesh.positions), putCounted(w, m.mesh.indices), putCounted(w, m.mesh.materialIds);
    putCounted(w, m.mesh.normals), putCounted(w, m.mesh.colors), putCounted(w, m.mesh.uvs);
    encodeCamerasAndLights(w, m.mesh);
    encodeTextures(w, m.mesh);
    encodeMasks(w, masks);
    return std::move(w.bytes());
}

Result<ImportedMesh> decodeAssimpAnswer(const std::string& name, const std::vector<uint8_t>& bytes,
                                        std::vector<AlphaMaskRequest>& masks) {
    const Status malformed = errorIn(name, "the assimp reader process sent a malformed answer");
    ByteReader r(bytes.data(), bytes.size());
    uint8_t ok = 0;
    if (!r.get(ok)) return malformed;
    if (!ok) {
        std::string message;
        if (!getText(r, message) || r.remaining() != 0) return malformed;
        return Status::error(message);
    }
    ImportedMesh m;
    const size_t n = bytes.size();
    if (!decodeReport(r, n, m.report) || !decodeMaterials(r, n, m.mesh.materials) ||
        !getCounted(r, m.mesh.positions) || !getCounted(r, m.mesh.indices) ||
        !getCounted(r, m.mesh.materialIds) || !getCounted(r, m.mesh.normals) ||
        !getCounted(r, m.mesh.colors) || !getCounted(r, m.mesh.uvs) ||
        !decodeCameras(r, n, m.mesh.cameras) || !decodeLights(r, n, m.mesh.lights) ||
        !decodeTextures(r, n, m.mesh) || !decodeMasks(r, n, m.mesh, masks) || r.remaining() != 0)
        return malformed;
    return m;
}

}  // namespace vastray::import
