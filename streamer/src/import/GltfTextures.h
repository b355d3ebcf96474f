#pragma once
// The textures of a glTF model's materials (core/MaterialTextures.h): each material's five
// core maps and KHR_materials_clearcoat's coat and coat roughness maps, with their KHR_texture_transform, and the scene's textures they name, one per image,
// sampler wrap modes and encoding. The images' encoded bytes come from the loader (GltfLoader.cpp
// keeps them, from a data URI or a buffer view) or, for an image in a file of its own, from
// that file, read here for the images a map uses only, inside the model's folder only (the
// rules of glTF buffer URIs: isSafeRelativeUri, insideFolder); nothing is decoded here.
#include <string>
#include <vector>

#include "import/TinyGltf.h"
#include "vastray/core/MaterialTextures.h"
#include "vastray/core/Result.h"
#include "vastray/streamer/Import.h"

namespace vastray::import {

// One map of a glTF material as its textureInfo gives it: the texture index (-1: none), the UV
// set and the textureInfo's extensions (KHR_texture_transform).
struct GltfMapInfo {
    TextureSlot slot;
    int index = -1;
    int texCoord = 0;
    tinygltf::ExtensionMap extensions;
};
// The maps of material `g` the renderer reads, by TextureSlot: glTF's five, then
// KHR_materials_clearcoat's clearcoatTexture and clearcoatRoughnessTexture (its
// clearcoatNormalTexture is not read). A coat textureInfo that is not an object with an integer
// index counts as none (GltfSchema has refused such a file before).
std::vector<GltfMapInfo> gltfMaterialMaps(const tinygltf::Material& g);

// At most this many distinct textures (image, wrap modes, encoding) in one scene.
constexpr uint32_t kMaxSceneTextures = 4096;

struct GltfTextures {
    std::vector<MaterialTextures> materials;  // one per glTF material, in order
    std::vector<TextureSource> textures;
};

// Errors name the file, the material, the map and the limit ("scene.gltf: material 2 ('Brick')
// normalTexture: texture 9 does not exist"); an image URI outside `folder` is refused as a
// buffer's is. Images are PNG, JPEG or KTX2 (KHR_texture_basisu's source first, the texture's own
// source its fallback where the KTX2's format is not read: core/ImageFile.h). A map whose image is
// in a format not read here (WebP, a KTX2 block format, ...) or whose file is missing is left out,
// warned once per kind in `report`.
Result<GltfTextures> readGltfTextures(const tinygltf::Model& model, const std::string& fileName,
                                      const std::string& folder, ImportReport& report);

}  // namespace vastray::import
