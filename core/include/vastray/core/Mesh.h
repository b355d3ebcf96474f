#pragma once
// The in-core triangle mesh every importer produces and every later stage reads:
// world-space positions, shared vertex indices, one material id per triangle, optional
// per-vertex shading normals, colours and texture coordinates.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "vastray/core/Aabb.h"
#include "vastray/core/Camera.h"
#include "vastray/core/Light.h"
#include "vastray/core/MaterialTextures.h"
#include "vastray/core/Vec3.h"

namespace vastray {

struct Material {
    std::string name;
    std::array<float, 4> baseColor{0.8f, 0.8f, 0.8f, 1.0f};  // linear RGBA
    std::array<float, 3> emissive{0.0f, 0.0f, 0.0f};         // linear RGB radiance
    // glTF 2.0 metallic-roughness (core/Microfacet.h): metallic and specular 0 is the Lambertian
    // base alone (every importer's default but glTF's, which follows the glTF defaults).
    float metallic = 0.0f;   // [0, 1]
    float roughness = 1.0f;  // [0, 1], perceptual (GGX alpha = roughness^2)
    float specular = 0.0f;   // [0, 1], the dielectric specular layer's weight (KHR_materials_specular)
    // KHR_materials_specular's specularColorFactor: the layer's F0 is min(0.04 this, 1) per channel;
    // [0, kMaxSpecularColor] (core/Microfacet.h).
    std::array<float, 3> specularColor{1.0f, 1.0f, 1.0f};
    // KHR_materials_clearcoat: the coat's weight and perceptual roughness, each [0, 1]; a clear
    // GGX layer (F0 0.04) over everything above (core/Microfacet.h). 0: no coat.
    float clearcoat = 0.0f;
    float clearcoatRoughness = 0.0f;
    bool doubleSided = true;
    // glTF alphaMode MASK with a base colour map: where baseColor[3] times the map's alpha (level
    // 0) is below alphaCutoff the surface is cut out, for every ray (docs/RENDERING.md,
    // "Cut-outs"). 0: opaque. In [0, 1]; without a base colour map the importers leave it 0 (a
    // factor alone below the cutoff removes the triangles at import).
    float alphaCutoff = 0.0f;
    // glTF alphaMode BLEND (and MTL d below 1, assimp opacity below 1): the surface is there with
    // probability baseColor[3] times the base colour map's alpha (level 0) where it has one, for
    // every ray (stochastic transparency: docs/RENDERING.md, "Blending"). A blend
    // whose alpha is 1 with no map is opaque.
    bool alphaBlend = false;
    // KHR_materials_ior: the dielectric layer's index of refraction, which sets its F0 (((ior - 1) /
    // (ior + 1))^2, 0.04 at glTF's default 1.5; core/Microfacet.h iorF0); 0 (the extension's
    // value for a layer that reflects everything: F0 1) or in [1, kMaxIor]. The coat keeps 1.5.
    float ior = 1.5f;
    // The maps it reads (glTF's five and the coat's two), each a texture of the mesh's `textures` or kNoTexture.
    MaterialTextures textures{};
};

struct TriangleMesh {
    std::vector<Vec3f> positions;      // world space
    std::vector<uint32_t> indices;     // 3 per triangle, into positions
    std::vector<uint32_t> materialIds; // one per triangle, or empty: every triangle uses material 0
    // Per vertex, or empty (core/VertexAttributes.h): octahedral shading normals (kNoNormal where
    // the file gave none) and packed sRGB8 colours (kWhiteColor where it gave none).
    std::vector<uint32_t> normals;
    std::vector<uint32_t> colors;
    // Per vertex, or empty: one UV set (u, v) as the file gave it, |u|, |v| <= kMaxAbsUv; kept
    // only when a material references a texture map ((0, 0) where a mesh of the file had none).
    std::vector<std::array<float, 2>> uvs;
    std::vector<Material> materials;   // at least one once imported
    // The textures the materials' maps name, as the file gave them (encoded images); empty when
    // no map was read. Import decodes them into the package's pages (core/Texture.h).
    std::vector<TextureSource> textures;
    std::vector<SceneCamera> cameras;  // the file's cameras, in its order (glTF); often none
    std::vector<PunctualLight> lights; // the file's placed lights (glTF KHR_lights_punctual); often none

    uint64_t triangleCount() const { return indices.size() / 3; }
    uint32_t materialOf(uint64_t triangle) const {
        return materialIds.empty() ? 0u : materialIds[triangle];
    }
    Aabb bounds() const {
        Aabb b;
        for (const Vec3f& p : positions) b.extend(p);
        return b;
    }
};

}  // namespace vastray
