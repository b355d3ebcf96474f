#pragma once
// Mesh importers: OBJ, PLY (ASCII, binary LE/BE), glTF 2.0 (.gltf/.glb, with
// KHR_draco_mesh_compression) of our own, and the formats of kAssimpFormats (and glTF 1.0)
// through assimp. Each returns a validated world-space TriangleMesh or an
// error that names the file and the element ("bunny.ply: face 1203 index 40122 >= vertex
// count 35947"). None throws; none trusts a count it has not bounded by the file size.
#include <cstdint>
#include <string>
#include <vector>

#include "vastray/core/Mesh.h"
#include "vastray/core/Result.h"

namespace vastray {

// Every coordinate lies within +-kMaxAbsCoordinate. Beyond it the scene's extent, the
// partition's split planes and the tracer's squared distances overflow float (coordinates
// near 3e38 imported into a package with no chunks). Importers check it after transforms;
// the package reader holds a package's bounds and grid to it as well.
constexpr float kMaxAbsCoordinate = 1e18f;

struct ImportOptions {
    // Overrides every material's doubleSided flag when set (CLI --double-sided/--single-sided).
    enum class Sidedness { FromFile, ForceDoubleSided, ForceSingleSided };
    Sidedness sidedness = Sidedness::FromFile;
};

// What an importer saw and what it did about it.
struct ImportReport {
    std::string format;                // "obj", "ply-ascii", "ply-binary-le", "ply-binary-be", "gltf", "glb"
    uint64_t inputTriangles = 0;       // after polygon/strip/fan triangulation, before dropping
    uint64_t degenerateDropped = 0;    // repeated index, coincident positions or zero area
    uint64_t verticesRead = 0;
    uint64_t normalsRead = 0;          // shading normals, carried into the package (TriangleMesh::normals)
    uint64_t coloursRead = 0;          // vertex colours, carried likewise (TriangleMesh::colors)
    uint64_t texcoordsRead = 0;        // one UV set; carried (TriangleMesh::uvs) when textureMaps > 0
    // Texture maps the file's materials reference (glTF textureInfos, MTL map_*/bump/norm/...,
    // assimp material textures): without one, UVs are read by nothing and not kept.
    uint64_t textureMaps = 0;
    uint64_t primitivesSkipped = 0;    // glTF points/lines primitives (no triangles to render)
    // What the file holds and the package does not carry, one line per kind ("3 animations
    // read but not used"), for `vastray import` and the service's job messages.
    std::vector<std::string> warnings;

    void warnUnused(const std::string& what, uint64_t count, const std::string& consequence = "") {
        if (count > 0)
            warnings.push_back(std::to_string(count) + " " + what + " read but not used" +
                               (consequence.empty() ? "" : " (" + consequence + ")"));
    }
};

struct ImportedMesh {
    TriangleMesh mesh;
    ImportReport report;
};

// The formats read through assimp, by extension: those its Debian 12 build reads well that
// studios and scanners write. Others it knows are refused by name: each reader is attack
// surface for an upload, and these are the ones the hostile-input sweep covers.
inline constexpr const char* kAssimpFormats[] = {"stl", "off", "fbx", "dae", "3ds", "3mf", "ac",
                                                 "ase", "dxf", "lwo", "ms3d", "x",  "x3d"};

// Picks the importer by extension (.obj, .ply, .gltf, .glb, kAssimpFormats; case-insensitive).
Result<ImportedMesh> importMesh(const std::string& path, const ImportOptions& options = {});

Result<ImportedMesh> importObj(const std::string& path, const ImportOptions& options = {});
Result<ImportedMesh> importPly(const std::string& path, const ImportOptions& options = {});
Result<ImportedMesh> importGltf(const std::string& path, const ImportOptions& options = {});
Result<ImportedMesh> importWithAssimp(const std::string& path, const ImportOptions& options = {});
bool assimpReads(const std::string& path);  // extension in kAssimpFormats
// ".stl, .off, ..." (kAssimpFormats), for messages that list what is read.
std::string assimpFormatList();

// Shared last step of every importer: rejects NaN/Inf positions and out-of-range indices,
// per-vertex normals, colours or UVs that are not one per vertex, UVs not finite or beyond
// +-kMaxAbsUv (naming the vertex), drops UVs when no material has a texture map, drops degenerate triangles
// (counted in report), guarantees at least one material and applies the sidedness override.
// Cuts camera names a package could not keep whole (storedCameraName), a warning each.
// `fileName` prefixes every message.
Status finalizeMesh(const std::string& fileName, const ImportOptions& options, ImportedMesh& imported);

}  // namespace vastray
