#include "vastray/cpu/RenderScene.h"

#include <algorithm>
#include <filesystem>

#include "vastray/streamer/Import.h"
#include "vastray/streamer/PackageBuilder.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {
namespace {

// Appends the chunk's triangles whose primitive id has not been seen yet. The chunk's
// vertices are appended whole: a few unused ones are cheaper than a remap.
Status appendChunk(const DecodedChunk& chunk, const PackageInfo& info, const std::string& path,
                   std::vector<uint8_t>& seen, RenderScene& scene) {
    const auto base = uint32_t(scene.mesh.positions.size());
    if (chunk.normals.empty() == info.hasNormals || chunk.colors.empty() == info.hasColors ||
        chunk.uvs.empty() == info.hasUvs)
        return Status::error(path + ": chunk " + std::to_string(chunk.id) +
                             ": its vertex attributes disagree with the header's");
    scene.mesh.positions.insert(scene.mesh.positions.end(), chunk.positions.begin(), chunk.positions.end());
    scene.mesh.normals.insert(scene.mesh.normals.end(), chunk.normals.begin(), chunk.normals.end());
    scene.mesh.colors.insert(scene.mesh.colors.end(), chunk.colors.begin(), chunk.colors.end());
    scene.mesh.uvs.insert(scene.mesh.uvs.end(), chunk.uvs.begin(), chunk.uvs.end());
    for (size_t t = 0; t < chunk.primitiveIds.size(); ++t) {
        const uint32_t id = chunk.primitiveIds[t];
        if (id >= seen.size())
            return Status::error(path + ": chunk " + std::to_string(chunk.id) + ": primitive id " +
                                 std::to_string(id) + " >= " + std::to_string(seen.size()));
        if (seen[id]) continue;
        seen[id] = 1;
        for (int corner = 0; corner < 3; ++corner)
            scene.mesh.indices.push_back(base + chunk.indices[3 * t + corner]);
        scene.mesh.materialIds.push_back(chunk.materialIds.empty() ? 0u : chunk.materialIds[t]);
        scene.primitiveIds.push_back(id);
    }
    return Status::ok();
}

}  // namespace

Result<RenderScene> renderSceneFromPackage(const PackageReader& reader) {
    const PackageInfo& info = reader.info();
    RenderScene scene;
    scene.bounds = info.bounds;
    scene.mesh.materials = info.materials;
    scene.mesh.cameras = info.cameras;
    scene.mesh.lights = info.lights;
    scene.emitters = info.emitters;
    if (scene.mesh.materials.empty()) scene.mesh.materials.push_back(Material{"default"});
    // Ids count every imported triangle, those that quantization collapsed included.
    std::vector<uint8_t> seen(info.triangleCount + info.collapsedDropped, 0);
    for (const ChunkInfo& chunkInfo : info.chunks) {
        auto chunk = reader.readChunk(chunkInfo.id);
        if (!chunk) return chunk.status();
        VASTRAY_TRY(appendChunk(*chunk, info, reader.path(), seen, scene));
    }
    // Every page of every texture (this renderer holds the whole scene in memory).
    for (uint32_t t = 0; t < info.textures.size(); ++t) {
        const PackageTexture& x = info.textures[t];
        DecodedTexture& texture = scene.textures.emplace_back();
        texture.layout = x.layout;
        texture.wrapS = x.wrapS, texture.wrapT = x.wrapT, texture.encoding = x.encoding;
        texture.pages.resize(size_t(x.layout.pageCount) * kTexturePageBytes);
        for (uint32_t p = 0; p < x.layout.pageCount; ++p)
            VASTRAY_TRY(reader.readTexturePage(t, p, texture.pages.data() + size_t(p) * kTexturePageBytes));
    }
    if (!info.volumes.empty()) {
        auto volumes = reader.readVolumes();
        if (!volumes) return volumes.status();
        scene.volumes = std::move(volumes).value();
    }
    return scene;
}

Result<RenderScene> loadRenderScene(const std::string& path) {
    if (isPackagePath(path)) {
        auto reader = PackageReader::open(path);
        if (!reader) return reader.status();
        return renderSceneFromPackage(**reader);
    }
    auto imported = importMesh(path);
    if (!imported) return imported.status();
    RenderScene scene;
    scene.mesh = std::move(imported->mesh);
    for (const TextureSource& source : scene.mesh.textures) {  // as import would store them
        auto texture = decodeTexture(source);
        if (!texture) return texture.status();
        scene.textures.push_back(std::move(texture).value());
    }
    scene.bounds = scene.mesh.bounds();
    scene.emitters = collectEmitters(scene.mesh, scene.textures.size());
    if (scene.emitters.size() > kMaxEmitters) scene.emitters.clear();  // as import leaves them out
    return scene;
}

}  // namespace vastray
