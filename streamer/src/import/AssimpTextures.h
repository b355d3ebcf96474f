#pragma once
// The texture maps of an assimp scene's materials in glTF's five slots (core/MaterialTextures.h),
// read in the assimp child process: BASE_COLOR (else DIFFUSE) the base colour, NORMALS (else
// NORMAL_CAMERA) the normal map, EMISSIVE (else EMISSION_COLOR) the emissive map,
// AMBIENT_OCCLUSION the occlusion map, and METALNESS with DIFFUSE_ROUGHNESS the
// metallic-roughness map when both name one image (glTF's layout: roughness G, metallic B; two
// images are not combined, warned). An image is a file inside the model's folder
// (TextureFiles.h) or one the file embeds (aiScene::mTextures, PNG or JPEG bytes). Wrap modes
// from aiTextureMapMode; aiUVTransform (assimp's TransformUVCoords convention) becomes the UV
// transform. An OPACITY map is a cut-out's mask (AlphaMask.h: on the base colour map's own image
// its alpha cuts as it is; another image is baked into the base colour map's alpha in the parent
// process); glTF 2.0's alphaMode MASK and alphaCutoff ($mat.gltf.alphaMode, .alphaCutoff) with a
// base colour map make a cut-out at that cutoff. Other maps, maps on a second UV set, projected
// maps and uncompressed embedded images are left out, warned once per kind.
#include <string>
#include <vector>

#include "import/AlphaMask.h"
#include "vastray/core/MaterialTextures.h"
#include "vastray/core/Result.h"
#include "vastray/streamer/Import.h"

struct aiScene;
struct aiUVTransform;

namespace vastray::import {

struct AssimpTextures {
    std::vector<MaterialTextures> materials;  // one per aiMaterial, in order
    std::vector<TextureSource> textures;
    std::vector<float> alphaCutoffs;          // one per aiMaterial: glTF MASK's cutoff, else 0
    std::vector<AlphaMaskRequest> masks;      // opacity maps, for bakeAlphaMasks
};

// Errors name the material, the map and the limit; `folder` is the model's folder.
Result<AssimpTextures> assimpTextures(const aiScene& scene, const std::string& folder, const std::string& fileName,
                                      ImportReport& report);

// assimp's UV transform (TransformUVCoords: translate by mTranslation, then rotate by mRotation
// counter-clockwise and scale by mScaling about (0.5, 0.5), all in assimp's v-up space) in the
// package's v-down space.
UvTransform assimpUvTransform(float translationU, float translationV, float scaleU, float scaleV, float rotation);

}  // namespace vastray::import
