// importMesh (dispatch by extension) and finalizeMesh, the validation step every importer
// ends with.
#include "vastray/streamer/Import.h"

#include <cmath>
#include <cstdio>
#include <limits>

#include "import/ImportCommon.h"
#include "vastray/core/Microfacet.h"

namespace vastray {
namespace {

std::string formatVertex(Vec3f p) {
    char text[96];
    std::snprintf(text, sizeof text, "(%.9g, %.9g, %.9g)", p.x, p.y, p.z);
    return text;
}

Status checkPositions(const TriangleMesh& mesh) {
    if (mesh.positions.size() > std::numeric_limits<uint32_t>::max())
        return Status::error("vertex count " + std::to_string(mesh.positions.size()) +
                             " exceeds the uint32 index range");
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        const Vec3f p = mesh.positions[i];
        if (!isFinite(p))
            return Status::error("vertex " + std::to_string(i) + " has a non-finite coordinate " + formatVertex(p));
        if (std::fabs(p.x) > kMaxAbsCoordinate || std::fabs(p.y) > kMaxAbsCoordinate ||
            std::fabs(p.z) > kMaxAbsCoordinate)
            return Status::error("vertex " + std::to_string(i) + " " + formatVertex(p) +
                                 " lies beyond the coordinate limit of +-1e18 (larger values overflow float "
                                 "arithmetic in the partition and the tracer)");
    }
    return Status::ok();
}

Status checkIndices(const TriangleMesh& mesh) {
    if (mesh.indices.size() % 3 != 0)
        return Status::error("index count " + std::to_string(mesh.indices.size()) +
                             " is not a multiple of 3");
    const uint64_t vertexCount = mesh.positions.size();
    for (size_t i = 0; i < mesh.indices.size(); ++i) {
        if (mesh.indices[i] >= vertexCount)
            return Status::error("triangle " + std::to_string(i / 3) + " index " +
                                 std::to_string(mesh.indices[i]) + " >= vertex count " +
                                 std::to_string(vertexCount));
    }
    if (!mesh.materialIds.empty() && mesh.materialIds.size() != mesh.indices.size() / 3)
        return Status::error("material id count does not match the triangle count");
    for (size_t t = 0; t < mesh.materialIds.size(); ++t) {
        if (mesh.materialIds[t] >= mesh.materials.size())
            return Status::error("triangle " + std::to_string(t) + " material " +
                                 std::to_string(mesh.materialIds[t]) + " >= material count " +
                                 std::to_string(mesh.materials.size()));
    }
    return Status::ok();
}

// The metallic-roughness factors are fractions (glTF 2.0 spec 3.9.2; core/Microfacet.h).
Status checkMaterials(const TriangleMesh& mesh) {
    for (size_t i = 0; i < mesh.materials.size(); ++i)
        if (const std::string problem = materialFactorProblem(mesh.materials[i]); !problem.empty())
            return Status::error("material " + std::to_string(i) + " ('" + mesh.materials[i].name + "'): " + problem);
    return Status::ok();
}

// Zero area is decided in double so that thin but valid float triangles survive.
bool isDegenerate(const TriangleMesh& mesh, const uint32_t* t) {
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return true;
    const Vec3f a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
    if (a == b || b == c || a == c) return true;
    const double ux = double(b.x) - a.x, uy = double(b.y) - a.y, uz = double(b.z) - a.z;
    const double vx = double(c.x) - a.x, vy = double(c.y) - a.y, vz = double(c.z) - a.z;
    const double cx = uy * vz - uz * vy, cy = uz * vx - ux * vz, cz = ux * vy - uy * vx;
    return cx == 0.0 && cy == 0.0 && cz == 0.0;
}

// Compacts indices and material ids in place; no second copy of the mesh is made.
uint64_t dropDegenerates(TriangleMesh& mesh) {
    const uint64_t count = mesh.triangleCount();
    const bool hasIds = !mesh.materialIds.empty();
    uint64_t kept = 0;
    for (uint64_t t = 0; t < count; ++t) {
        const uint32_t* tri = &mesh.indices[t * 3];
        if (isDegenerate(mesh, tri)) continue;
        if (kept != t) {
            for (int k = 0; k < 3; ++k) mesh.indices[kept * 3 + k] = tri[k];
            if (hasIds) mesh.materialIds[kept] = mesh.materialIds[t];
        }
        ++kept;
    }
    mesh.indices.resize(kept * 3);
    if (hasIds) mesh.materialIds.resize(kept);
    return count - kept;
}

Status checkUvs(const TriangleMesh& mesh) {
    if (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size())
        return Status::error("texture coordinates are not one per vertex (" + std::to_string(mesh.uvs.size()) +
                             " for " + std::to_string(mesh.positions.size()) + " vertices)");
    for (size_t i = 0; i < mesh.uvs.size(); ++i)
        if (const std::string problem = import::uvProblem(mesh.uvs[i][0], mesh.uvs[i][1]); !problem.empty())
            return Status::error("vertex " + std::to_string(i) + " texture coordinate " + problem);
    return Status::ok();
}

void applySidedness(const ImportOptions& options, std::vector<Material>& materials) {
    if (options.sidedness == ImportOptions::Sidedness::FromFile) return;
    const bool doubleSided = options.sidedness == ImportOptions::Sidedness::ForceDoubleSided;
    for (Material& m : materials) m.doubleSided = doubleSided;
}

// A package keeps kMaxSceneCameraNameBytes of a camera's name: a longer one is cut here, where
// the report can say so, rather than silently by the writer; `render --camera` takes either.
void shortenCameraNames(TriangleMesh& mesh, ImportReport& report) {
    for (size_t i = 0; i < mesh.cameras.size(); ++i) {
        std::string& name = mesh.cameras[i].name;
        std::string stored = storedCameraName(name);
        if (stored == name) continue;
        report.warnings.push_back("camera " + std::to_string(i) + " name '" + name + "' (" +
                                  std::to_string(name.size()) + " bytes) is stored as '" + stored + "' (" +
                                  std::to_string(stored.size()) + " bytes; names are kept to " +
                                  std::to_string(kMaxSceneCameraNameBytes) + "); --camera takes either");
        name = std::move(stored);
    }
}

}  // namespace

Status finalizeMesh(const std::string& fileName, const ImportOptions& options, ImportedMesh& imported) {
    TriangleMesh& mesh = imported.mesh;
    const std::string prefix = fileName + ": ";
    if (mesh.materials.empty()) mesh.materials.push_back(Material{"default"});
    if (Status s = checkPositions(mesh); !s.isOk()) return s.withContext(prefix);
    if (Status s = checkIndices(mesh); !s.isOk()) return s.withContext(prefix);
    if (Status s = checkMaterials(mesh); !s.isOk()) return s.withContext(prefix);
    if ((!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size()) ||
        (!mesh.colors.empty() && mesh.colors.size() != mesh.positions.size()))
        return Status::error(prefix + "per-vertex normals or colours are not one per vertex (" +
                             std::to_string(mesh.normals.size()) + " normals, " + std::to_string(mesh.colors.size()) +
                             " colours, " + std::to_string(mesh.positions.size()) + " vertices)");
    if (imported.report.textureMaps == 0) mesh.uvs.clear();  // read by nothing: not stored
    if (Status s = checkUvs(mesh); !s.isOk()) return s.withContext(prefix);
    imported.report.inputTriangles = mesh.triangleCount();
    if (mesh.triangleCount() == 0) return Status::error(prefix + "no triangles");
    imported.report.degenerateDropped = dropDegenerates(mesh);
    if (mesh.triangleCount() == 0)
        return Status::error(prefix + "all " + std::to_string(imported.report.inputTriangles) +
                             " triangles are degenerate");
    applySidedness(options, mesh.materials);
    ImportReport& report = imported.report;
    if (mesh.normals.empty()) report.warnUnused("shading normals", report.normalsRead, "shading stays faceted");
    if (mesh.colors.empty()) report.warnUnused("vertex colours", report.coloursRead, "a scan renders grey");
    if (mesh.uvs.empty())
        report.warnUnused("texture coordinates", report.texcoordsRead, "no material has a texture map");
    if (mesh.uvs.empty() && !mesh.textures.empty()) {
        // Maps without texture coordinates cannot be sampled: rendered with the factors alone.
        report.warnUnused("textures", mesh.textures.size(), "the mesh has no texture coordinates to map them with");
        mesh.textures.clear();
        for (Material& m : mesh.materials) m.textures = MaterialTextures{};
    }
    uint64_t occluded = 0;
    for (const Material& m : mesh.materials)
        occluded += m.textures.slots[uint32_t(TextureSlot::Occlusion)].texture != kNoTexture;
    if (occluded > 0)
        report.warnings.push_back(std::to_string(occluded) +
                                  " materials' occlusion maps: stored, not applied by design (the path tracer "
                                  "computes occlusion itself; docs/RENDERING.md, \"Normal maps\")");
    shortenCameraNames(mesh, report);
    return Status::ok();
}

std::string assimpFormatList() {
    std::string list;
    for (const char* format : kAssimpFormats) list += std::string(list.empty() ? "" : ", ") + "." + format;
    return list;
}

Result<ImportedMesh> importMesh(const std::string& path, const ImportOptions& options) {
    const std::string ext = import::lowerExtension(path);
    if (ext == "obj") return importObj(path, options);
    if (ext == "ply") return importPly(path, options);
    if (ext == "gltf" || ext == "glb") return importGltf(path, options);
    if (assimpReads(path)) return importWithAssimp(path, options);
    return import::errorIn(import::fileNameOf(path),
                           "unknown mesh format '" + (ext.empty() ? std::string("(no extension)") : "." + ext) +
                               "' (supported: .obj, .ply, .gltf, .glb, " + assimpFormatList() + ")");
}

}  // namespace vastray
