// Every format we do not read ourselves (STL, OFF, FBX, Collada, 3DS, glTF 1.0, ...) through
// assimp (Debian libassimp-dev), behind the same interface and the same last step as our own
// importers: node transforms baked into world space, polygons triangulated by assimp,
// points and lines skipped and counted, then finalizeMesh's validation and named errors.
// Cameras and punctual lights are placed by their nodes (lights: AssimpLights.h); materials'
// texture maps and their images travel with the mesh (AssimpTextures.h); opacity masks on
// another image are baked in the parent (AlphaMask.h).
// Files assimp opens besides the model (a Collada's external parts, say) must lie inside
// the model's folder, as glTF URIs and OBJ mtllib names must.
// assimp runs in a child process (fork): its readers crash on hostile files (the fuzzer found a
// 794-byte Collada file that segfaults assimp 5.2.5), and a crash or a hang there must fail the
// import, not the CLI or the server that called it. The child sends the triangles back through
// a pipe (ChildProcess.h; the answer's encoding: AssimpAnswer.h); finalizeMesh's validation runs
// in the caller, as for every other importer.
#include <assimp/DefaultIOSystem.h>
#include <assimp/camera.h>
#include <assimp/Importer.hpp>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "import/AssimpAnswer.h"
#include "import/AssimpLights.h"
#include "import/AssimpTextures.h"
#include "import/ChildProcess.h"
#include "import/ImportCommon.h"
#include "vastray/core/Camera.h"
#include "vastray/core/VecMath.h"
#include "vastray/core/VertexAttributes.h"
#include "vastray/streamer/Import.h"

namespace vastray {
namespace {

// Refuses every path outside the model's folder and anything but a regular file (a FIFO
// would block fopen for ever); the first refusal is reported instead of assimp's message.
class FolderIoSystem : public Assimp::DefaultIOSystem {
public:
    explicit FolderIoSystem(std::string folder) : folder_(std::move(folder)) {}

    bool Exists(const char* file) const override { return allowed(file) && DefaultIOSystem::Exists(file); }

    Assimp::IOStream* Open(const char* file, const char* mode) override {
        if (std::string(mode).find_first_of("wa+") != std::string::npos) return refuse(file, "opened for writing");
        if (!allowed(file)) return refuse(file, "outside the model folder");
        std::error_code ec;
        if (!std::filesystem::is_regular_file(file, ec)) return refuse(file, "not a regular file");
        return DefaultIOSystem::Open(file, mode);
    }

    const std::string& violation() const { return violation_; }

private:
    // assimp names the files it opens as the model path was given (relative to the working
    // directory, or absolute) or joined onto its folder; both resolve the same way here.
    bool allowed(const char* file) const { return import::insideFolder(folder_, file); }

    Assimp::IOStream* refuse(const char* file, const char* why) {
        if (violation_.empty()) violation_ = "'" + import::fileNameOf(file) + "' is " + why + "; refused";
        return nullptr;
    }

    std::string folder_;
    std::string violation_;
};

Material convertMaterial(const aiMaterial& source, size_t index) {
    Material m;
    aiString name;
    m.name = source.Get(AI_MATKEY_NAME, name) == AI_SUCCESS && name.length > 0 ? name.C_Str()
                                                                               : "material " + std::to_string(index);
    aiColor4D colour;
    if (source.Get(AI_MATKEY_BASE_COLOR, colour) == AI_SUCCESS || source.Get(AI_MATKEY_COLOR_DIFFUSE, colour) == AI_SUCCESS)
        m.baseColor = {colour.r, colour.g, colour.b, 1.0f};
    float opacity = 1.0f;
    if (source.Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS) m.baseColor[3] = opacity;
    aiColor3D emissive;
    if (source.Get(AI_MATKEY_COLOR_EMISSIVE, emissive) == AI_SUCCESS) m.emissive = {emissive.r, emissive.g, emissive.b};
    int twoSided = 1;  // formats without the flag (STL, OFF) are drawn from both sides, as OBJ is
    if (source.Get(AI_MATKEY_TWOSIDED, twoSided) == AI_SUCCESS) m.doubleSided = twoSided != 0;
    // Metallic-roughness where the file has it (assimp's PBR keys: FBX, glTF 1.0 through assimp,
    // ...; out of range refused by finalizeMesh); else a Phong-style specular colour and
    // shininess as a dielectric layer, unless the shading model has no highlight.
    float metallic = 0.0f, roughness = 1.0f, shininess = 0.0f;
    const bool hasMetallic = source.Get(AI_MATKEY_METALLIC_FACTOR, metallic) == AI_SUCCESS;
    const bool hasRoughness = source.Get(AI_MATKEY_ROUGHNESS_FACTOR, roughness) == AI_SUCCESS;
    // Diffuse-only models (Collada's lambert is Gouraud, with a default specular colour of 0.4
    // that it does not use) have no layer; a file without a shading model is taken as Phong.
    int shading = aiShadingMode_Phong;
    source.Get(AI_MATKEY_SHADING_MODEL, shading);
    const bool highlights = shading == aiShadingMode_Phong || shading == aiShadingMode_Blinn ||
                            shading == aiShadingMode_CookTorrance || shading == aiShadingMode_Fresnel;
    aiColor3D specular;
    if (hasMetallic || hasRoughness) {
        m.metallic = metallic, m.roughness = roughness, m.specular = 1.0f;
    } else if (highlights && source.Get(AI_MATKEY_COLOR_SPECULAR, specular) == AI_SUCCESS) {
        source.Get(AI_MATKEY_SHININESS, shininess);
        import::setPhongSpecular(m, std::max({specular.r, specular.g, specular.b}), shininess);
    }
    return m;
}

// What the scene holds that the package does not carry, once per kind.
void warnAboutUnused(const aiScene& scene, ImportReport& report) {
    uint64_t normals = 0, texcoords = 0, colours = 0, bones = 0, morphs = 0;
    for (unsigned i = 0; i < scene.mNumMeshes; ++i) {
        const aiMesh& mesh = *scene.mMeshes[i];
        if (mesh.HasNormals()) normals += mesh.mNumVertices;
        if (mesh.HasTextureCoords(0)) texcoords += mesh.mNumVertices;
        if (mesh.HasVertexColors(0)) colours += mesh.mNumVertices;
        bones += mesh.mNumBones;
        morphs += mesh.mNumAnimMeshes;
    }
    report.normalsRead += normals;
    report.coloursRead += colours;
    report.texcoordsRead += texcoords;
    report.warnUnused("skin bones", bones);
    report.warnUnused("morph targets", morphs);
    report.warnUnused("animations", scene.mNumAnimations);
}

// Texture maps the scene's materials reference, of every kind: UVs are kept only with one.
uint64_t textureMapCount(const aiScene& scene) {
    uint64_t maps = 0;
    for (unsigned i = 0; i < scene.mNumMaterials; ++i)
        for (int type = aiTextureType_NONE + 1; type <= AI_TEXTURE_TYPE_MAX; ++type)
            maps += scene.mMaterials[i]->GetTextureCount(aiTextureType(type));
    return maps;
}

// The scene's perspective cameras in world space, in the file's order (read before
// post-processing, while the node tree that places them is whole). An aiCamera sits at
// mPosition looking along mLookAt with mUp, in the frame of the node of its name.
// mHorizontalFOV is the full horizontal angle as assimp 5.2's Collada and FBX readers store it
// (its header said "half" until assimp PR #3912 corrected it; issue #2256); with mAspect
// (width / height) it gives the vertical angle we store; a file that states no aspect is taken
// as square. The image's aspect ratio is the render's --resolution, as for glTF cameras.
// Orthographic cameras, cameras no node places and degenerate ones are counted in `notUsed`.
std::vector<SceneCamera> worldCameras(const aiScene& scene, uint64_t& notUsed) {
    std::vector<SceneCamera> cameras;
    for (unsigned i = 0; i < scene.mNumCameras; ++i) {
        const aiCamera& c = *scene.mCameras[i];
        const aiNode* node = scene.mRootNode ? scene.mRootNode->FindNode(c.mName) : nullptr;
        if (!node || c.mOrthographicWidth != 0.0f || !(c.mHorizontalFOV > 0.0f)) {
            ++notUsed;
            continue;
        }
        const aiMatrix4x4 m = import::nodeToWorld(*node);
        const aiMatrix3x3 r(m);
        const aiVector3D eye = m * c.mPosition, forward = r * c.mLookAt, up = r * c.mUp;
        const float aspect = std::isfinite(c.mAspect) && c.mAspect > 0.0f ? c.mAspect : 1.0f;
        SceneCamera camera;
        camera.name = c.mName.length > 0 ? c.mName.C_Str() : "camera " + std::to_string(i);
        camera.camera.eye = {eye.x, eye.y, eye.z};
        const Vec3f direction = normalize(Vec3f{forward.x, forward.y, forward.z});
        camera.camera.target = camera.camera.eye + direction * std::max(1.0f, length(camera.camera.eye));
        camera.camera.up = normalize(Vec3f{up.x, up.y, up.z});
        camera.camera.fovYDegrees =
            float(2.0 * std::atan(std::tan(0.5 * double(c.mHorizontalFOV)) / double(aspect)) * 180.0 / 3.14159265358979323846);
        if (!validateCamera(camera.camera).isOk()) {
            ++notUsed;
            continue;
        }
        cameras.push_back(std::move(camera));
    }
    return cameras;
}

// Normals (world space after aiProcess_PreTransformVertices) and the first colour set, taken as
// sRGB-encoded like OBJ's and PLY's. The mesh has them on every vertex or on none: parts without
// get kNoNormal and white once some part has them. With `uvs` (a material has a texture map)
// the first UV set likewise, (0, 0) on parts without, v flipped: assimp's texture space has v
// up, the package keeps glTF's (docs/RENDERING.md). finalizeMesh checks the values.
void appendAttributes(const aiMesh& part, uint64_t base, bool uvs, TriangleMesh& mesh) {
    if (uvs && part.HasTextureCoords(0)) {
        mesh.uvs.resize(base, {0.0f, 0.0f});
        for (unsigned v = 0; v < part.mNumVertices; ++v)
            mesh.uvs.push_back({part.mTextureCoords[0][v].x, 1.0f - part.mTextureCoords[0][v].y});
    } else if (!mesh.uvs.empty()) {
        mesh.uvs.resize(base + part.mNumVertices, {0.0f, 0.0f});
    }
    if (part.HasNormals()) {
        mesh.normals.resize(base, kNoNormal);
        for (unsigned v = 0; v < part.mNumVertices; ++v)
            mesh.normals.push_back(encodeOctahedral({part.mNormals[v].x, part.mNormals[v].y, part.mNormals[v].z}));
    } else if (!mesh.normals.empty()) {
        mesh.normals.resize(base + part.mNumVertices, kNoNormal);
    }
    if (part.HasVertexColors(0)) {
        auto byte = [](float c) { return uint8_t(std::lround(std::clamp(std::isfinite(c) ? c : 0.0f, 0.0f, 1.0f) * 255.0f)); };
        mesh.colors.resize(base, kWhiteColor);
        for (unsigned v = 0; v < part.mNumVertices; ++v) {
            const aiColor4D& c = part.mColors[0][v];
            mesh.colors.push_back(packSrgb8(byte(c.r), byte(c.g), byte(c.b)));
        }
    } else if (!mesh.colors.empty()) {
        mesh.colors.resize(base + part.mNumVertices, kWhiteColor);
    }
}

Status appendMeshes(const aiScene& scene, ImportedMesh& out) {
    TriangleMesh& mesh = out.mesh;
    for (unsigned i = 0; i < scene.mNumMaterials; ++i) mesh.materials.push_back(convertMaterial(*scene.mMaterials[i], i));
    out.report.textureMaps = textureMapCount(scene);
    for (unsigned i = 0; i < scene.mNumMeshes; ++i) {
        const aiMesh& part = *scene.mMeshes[i];
        if (!(part.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) {
            ++out.report.primitivesSkipped;
            continue;
        }
        const uint64_t base = mesh.positions.size();
        if (base + part.mNumVertices > std::numeric_limits<uint32_t>::max())
            return Status::error("total vertex count " + std::to_string(base + part.mNumVertices) +
                                 " exceeds the uint32 index range");
        out.report.verticesRead += part.mNumVertices;
        for (unsigned v = 0; v < part.mNumVertices; ++v)
            mesh.positions.push_back({part.mVertices[v].x, part.mVertices[v].y, part.mVertices[v].z});
        appendAttributes(part, base, out.report.textureMaps > 0, mesh);
        if (part.mMaterialIndex >= mesh.materials.size())
            return Status::error("mesh " + std::to_string(i) + ": material " + std::to_string(part.mMaterialIndex) +
                                 " does not exist");
        for (unsigned f = 0; f < part.mNumFaces; ++f) {
            const aiFace& face = part.mFaces[f];
            if (face.mNumIndices != 3) continue;  // points and lines left by SortByPType
            for (int k = 0; k < 3; ++k) {
                if (face.mIndices[k] >= part.mNumVertices)
                    return Status::error("mesh " + std::to_string(i) + " face " + std::to_string(f) + ": index " +
                                         std::to_string(face.mIndices[k]) + " >= vertex count " +
                                         std::to_string(part.mNumVertices));
                mesh.indices.push_back(uint32_t(base + face.mIndices[k]));
            }
            mesh.materialIds.push_back(part.mMaterialIndex);
        }
    }
    return Status::ok();
}

// The child's part: assimp's read and the conversion to our mesh, without finalizeMesh.
Result<ImportedMesh> readWithAssimp(const std::string& path, std::vector<import::AlphaMaskRequest>& masks) {
    const std::string name = import::fileNameOf(path);
    auto fd = import::openRegularFile(path);  // a FIFO or a folder is refused before assimp sees it
    if (!fd) return fd.status();
    ::close(*fd);
    Assimp::Importer importer;
    auto* io = new FolderIoSystem(import::directoryOf(path));
    importer.SetIOHandler(io);  // owned by the importer from here on
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    // Read first, count what the scene holds (pre-transforming drops animations and bones),
    // then triangulate, bake node transforms into world space and sort out points and lines.
    const aiScene* scene = importer.ReadFile(path, aiProcess_ValidateDataStructure);
    ImportReport unused;
    std::vector<SceneCamera> cameras;
    std::vector<PunctualLight> lights;
    uint64_t camerasNotUsed = 0;
    if (scene) {
        warnAboutUnused(*scene, unused);
        cameras = worldCameras(*scene, camerasNotUsed);
        unused.warnUnused("cameras", camerasNotUsed, "orthographic, placed by no node, or placed degenerately");
        auto read = import::assimpLights(*scene, unused);
        if (!read) return read.status().withContext(name + ": ");
        lights = std::move(*read);
    }
    if (scene && !(scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
        scene = importer.ApplyPostProcessing(aiProcess_Triangulate | aiProcess_PreTransformVertices |
                                             aiProcess_SortByPType | aiProcess_ValidateDataStructure);
    if (!io->violation().empty()) return import::errorIn(name, io->violation());
    if (!scene) {
        std::string why = importer.GetErrorString();
        while (!why.empty() && (why.back() == '\n' || why.back() == ' ')) why.pop_back();
        for (size_t at; (at = why.find(path)) != std::string::npos;) why.replace(at, path.size(), name);
        return import::errorIn(name, "assimp: " + (why.empty() ? std::string("import failed") : why));
    }
    if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)
        return import::errorIn(name, "assimp: the file describes no complete scene (no meshes)");
    ImportedMesh imported;
    imported.report.format = "assimp-" + import::lowerExtension(path);
    imported.report.normalsRead = unused.normalsRead;
    imported.report.coloursRead = unused.coloursRead;
    imported.report.texcoordsRead = unused.texcoordsRead;
    imported.report.warnings = std::move(unused.warnings);
    imported.mesh.cameras = std::move(cameras);
    imported.mesh.lights = std::move(lights);
    if (Status s = appendMeshes(*scene, imported); !s.isOk()) return s.withContext(name + ": ");
    auto textures = import::assimpTextures(*scene, import::directoryOf(path), name, imported.report);
    if (!textures) return textures.status();
    for (size_t i = 0; i < textures->materials.size(); ++i) {
        imported.mesh.materials[i].textures = textures->materials[i];
        imported.mesh.materials[i].alphaCutoff = textures->alphaCutoffs[i];
    }
    imported.mesh.textures = std::move(textures->textures);
    masks = std::move(textures->masks);
    return imported;
}

// How long assimp may take on one file before its process is killed and the import fails.
constexpr int kAssimpSecondsLimit = 600;

// The memory assimp's process may take beyond what it inherits (ChildReader::memoryLimitBytes):
// kAssimpMemoryBaseBytes plus kAssimpMemoryPerFileByte times the model file's size. A header
// may claim any count, and assimp allocates (and zeroes) what it claims before reading a vertex:
// invalid/OutOfMemory.off of assimp-testmodels (309 bytes) claims 353535235358 vertices, which
// assimp's 32-bit count keeps as 1347917086, and took ~20 GB and ~45 s before assimp refused it.
// Honest files need far less: the child's address space grew by 4.9x the file's size for a
// 100 MB binary STL (2 M triangles) and by 3.9x for a 55 MB text OFF (2 M triangles): assimp's
// scene, the converted mesh and the encoded answer. The multiple leaves room for compressed
// formats (3MF is a zip, FBX arrays are deflated), the base for small files with large external
// parts; texture files raise the limit as they are read (AssimpTextures.cpp).
constexpr uint64_t kAssimpMemoryBaseBytes = uint64_t(4) << 30;
constexpr uint64_t kAssimpMemoryPerFileByte = 64;

// The child process's limits for `path` (its memory limit by the rule above).
import::ChildReader assimpReader(const std::string& path) {
    std::error_code ec;
    const uint64_t size = std::filesystem::file_size(path, ec);
    const uint64_t limit =
        kAssimpMemoryBaseBytes + (ec ? 0 : std::min<uint64_t>(size, uint64_t(1) << 40) * kAssimpMemoryPerFileByte);
    return {"assimp", "assimp", kAssimpSecondsLimit, limit,
            import::memoryLimitText(kAssimpMemoryBaseBytes) + " + " + std::to_string(kAssimpMemoryPerFileByte) +
                " x the file's size + 4 x its texture files'"};
}

// readWithAssimp's error, or what it says once the child ran out of its memory limit (assimp
// catches std::bad_alloc and reports only its name).
Status limitedError(const std::string& path, const Status& error) {
    if (!import::childRanOutOfMemory()) return error;
    const std::string name = import::fileNameOf(path);
    std::string why = error.message();
    if (why.rfind(name + ": ", 0) == 0) why.erase(0, name.size() + 2);
    return import::errorIn(name,
                           import::outOfMemoryText(assimpReader(path), import::childMemoryLimit()) + " (" + why + ")");
}

// In the child: readWithAssimp's answer, encoded, to the parent. Only this thread exists
// here: no locks of other threads' making are taken (assimp logs nothing without a logger;
// malloc is fork-safe in glibc).
void childReads(int fd, const std::string& path) {
    std::vector<uint8_t> answer;
    try {
        std::vector<import::AlphaMaskRequest> masks;
        Result<ImportedMesh> read = readWithAssimp(path, masks);
        if (!read) read = limitedError(path, read.status());
        answer = import::encodeAssimpAnswer(read, masks);
    } catch (const std::exception& e) {
        answer = import::encodeAssimpAnswer(
            limitedError(path, import::errorIn(import::fileNameOf(path), std::string("assimp: ") + e.what())));
    } catch (...) {
        answer = import::encodeAssimpAnswer(import::errorIn(import::fileNameOf(path), "assimp: unknown exception"));
    }
    import::writeToParent(fd, answer.data(), answer.size());
}

// Runs readWithAssimp in a child process and returns its answer; a child that crashes, is
// killed, or outlives kAssimpSecondsLimit fails the import by the file's name; one that reaches
// its memory limit (assimpReader) fails it naming the limit.
Result<ImportedMesh> readInChildProcess(const std::string& path) {
    const std::string name = import::fileNameOf(path);
    Result<ImportedMesh> imported = Status::error("no answer");
    std::vector<import::AlphaMaskRequest> masks;
    const Status status = import::runInChildProcess(
        name, assimpReader(path), [&](int fd) { childReads(fd, path); },
        [&](import::ChildAnswer& in) {
            std::vector<uint8_t> answer;
            if (!in.readToEnd(answer)) return import::errorIn(name, "reading the assimp process's answer: " + in.error());
            imported = import::decodeAssimpAnswer(name, answer, masks);
            return imported.status();
        });
    if (!status.isOk()) return status;
    // The masks are baked here, where the image module may be loaded (the child is a fork).
    if (Status s = import::bakeAlphaMasks(imported->mesh, masks); !s.isOk()) return s.withContext(name + ": ");
    return imported;
}

Result<ImportedMesh> importWithAssimpUnguarded(const std::string& path, const ImportOptions& options) {
    auto imported = readInChildProcess(path);
    if (!imported) return imported.status();
    if (Status s = finalizeMesh(import::fileNameOf(path), options, *imported); !s.isOk()) return s;
    return imported;
}

}  // namespace

bool assimpReads(const std::string& path) {
    const std::string ext = import::lowerExtension(path);
    for (const char* allowed : kAssimpFormats)
        if (ext == allowed) return Assimp::Importer().IsExtensionSupported("." + ext);
    return false;
}

Result<ImportedMesh> importWithAssimp(const std::string& path, const ImportOptions& options) {
    return import::guarded(path, [&]() -> Result<ImportedMesh> { return importWithAssimpUnguarded(path, options); });
}

}  // namespace vastray
