// Every format we do not read ourselves (STL, OFF, FBX, Collada, 3DS, glTF 1.0, ...) through
// assimp (Debian libassimp-dev), behind the same interface and the same last step as our own
// importers: node transforms baked into world space, polygons triangulated by assimp,
// points and lines skipped and counted, then finalizeMesh's validation and named errors.
// Files assimp opens besides the model (a Collada's external parts, say) must lie inside
// the model's folder, as glTF URIs and OBJ mtllib names must.
#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <filesystem>
#include <limits>
#include <unistd.h>

#include "import/ImportCommon.h"
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
    report.texcoordsRead += texcoords;
    report.warnUnused("vertex colours", colours, "a scan renders grey");
    report.warnUnused("skin bones", bones);
    report.warnUnused("morph targets", morphs);
    report.warnUnused("animations", scene.mNumAnimations);
    report.warnUnused("cameras", scene.mNumCameras);
    report.warnUnused("lights", scene.mNumLights);
    report.warnUnused("embedded textures", scene.mNumTextures);
}

Status appendMeshes(const aiScene& scene, ImportedMesh& out) {
    TriangleMesh& mesh = out.mesh;
    for (unsigned i = 0; i < scene.mNumMaterials; ++i) mesh.materials.push_back(convertMaterial(*scene.mMaterials[i], i));
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

Result<ImportedMesh> importWithAssimpUnguarded(const std::string& path, const ImportOptions& options) {
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
    if (scene) warnAboutUnused(*scene, unused);
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
    imported.report.texcoordsRead = unused.texcoordsRead;
    imported.report.warnings = std::move(unused.warnings);
    if (Status s = appendMeshes(*scene, imported); !s.isOk()) return s.withContext(name + ": ");
    if (Status s = finalizeMesh(name, options, imported); !s.isOk()) return s;
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
