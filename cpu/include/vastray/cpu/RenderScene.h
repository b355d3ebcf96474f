#pragma once
// The whole scene in core, as the Embree reference renders it: one flat triangle list,
// no partitioning. From a mesh file the triangles are the imported mesh's; from a .vast
// package every chunk is decoded and a triangle referenced by several cells is kept once.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "vastray/core/Emitters.h"
#include "vastray/core/Mesh.h"
#include "vastray/core/Texture.h"
#include "vastray/core/Result.h"
#include "vastray/core/Volume.h"

namespace vastray {

class PackageReader;

struct RenderScene {
    TriangleMesh mesh;
    // Per triangle of `mesh`: its index in the imported mesh. Empty: the identity.
    std::vector<uint32_t> primitiveIds;
    // What a render without --eye frames: the mesh's bounds, or a package's recorded bounds
    // (so that every backend rendering the package frames it identically).
    Aabb bounds;
    // A package's density volumes (PackageReader::readVolumes); null: none. A render uses them
    // when its RenderOptions::volumes is set to them.
    std::shared_ptr<const std::vector<Volume>> volumes;
    // The textures the materials' maps name, every page decoded (a package's pages, or an
    // imported file's images made into pages as import does); empty without maps.
    std::vector<DecodedTexture> textures;
    // The emissive triangles next-event estimation samples (core/Emitters.h): a package's, or an
    // imported file's as import would store them (applySceneEmitters makes the table).
    std::vector<EmissiveTriangle> emitters;

    uint32_t primitiveId(uint32_t triangle) const {
        return primitiveIds.empty() ? triangle : primitiveIds[triangle];
    }
};

// By extension: .vast is a scene package, anything else goes to importMesh().
Result<RenderScene> loadRenderScene(const std::string& path);
// Decodes every chunk; duplicated references (same primitive id) are dropped.
Result<RenderScene> renderSceneFromPackage(const PackageReader& reader);

}  // namespace vastray
