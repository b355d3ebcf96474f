#include "import/AssimpTextures.h"

#include <assimp/GltfMaterial.h>
#include <assimp/material.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <set>
#include <tuple>

#include "import/ChildProcess.h"
#include "import/ImportCommon.h"
#include "import/TextureFiles.h"

namespace vastray::import {
namespace {


struct SlotTypes {
    TextureSlot slot;
    aiTextureType preferred, fallback;
};
constexpr SlotTypes kSlots[] = {{TextureSlot::BaseColor, aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE},
                                {TextureSlot::Normal, aiTextureType_NORMALS, aiTextureType_NORMAL_CAMERA},
                                {TextureSlot::Emissive, aiTextureType_EMISSIVE, aiTextureType_EMISSION_COLOR},
                                {TextureSlot::Occlusion, aiTextureType_AMBIENT_OCCLUSION,
                                 aiTextureType_AMBIENT_OCCLUSION}};

class Reader {
public:
    Reader(const aiScene& scene, const std::string& folder, const std::string& fileName, ImportReport& report)
        : scene_(scene), fileName_(fileName), report_(report), folder_(folder), files_(folder, fileName) {}

    Result<AssimpTextures> read() {
        AssimpTextures out;
        for (unsigned i = 0; i < scene_.mNumMaterials; ++i) {
            const aiMaterial& material = *scene_.mMaterials[i];
            const std::string where = "material " + std::to_string(i) + " ('" + material.GetName().C_Str() + "') ";
            auto textures = readMaterial(material, where);
            if (!textures) return textures.status();
            if (Status st = readOpacity(material, i, *textures, out.masks); !st.isOk())
                return st.withContext(fileName_ + ": " + where + "opacity map: ");
            const bool masked = !out.masks.empty() && out.masks.back().material == i;
            out.alphaCutoffs.push_back(gltfAlphaCutoff(material, *textures, masked));
            out.materials.push_back(*textures);
        }
        files_.warn(report_);
        const char* without = "their maps are rendered without them";
        report_.warnUnused("opacity maps with another UV transform or wrap mode than the base colour map",
                           opacitySampling_, "rendered opaque: a mask is baked into the base colour map texel for texel");
        report_.warnUnused("materials with glTF alphaMode MASK without a base colour map", maskWithoutMap_,
                           "rendered opaque");
        report_.warnUnused("materials with glTF alphaMode BLEND", blend_, "rendered opaque");
        report_.warnUnused("texture maps without a glTF slot (specular, height, lightmap, ...)", otherMaps_,
                           "materials use their factors there");
        report_.warnUnused("metalness and roughness maps in two images", separatePbr_,
                           "glTF's one metallic-roughness image is not assembled from two");
        report_.warnUnused("layered texture maps (a second map of one kind)", layered_, "the first one is read");
        report_.warnUnused("texture maps on a second UV set", otherUvSet_, without);
        report_.warnUnused("projected texture maps (sphere, box, ...)", projected_, without);
        report_.warnUnused("texture maps with an uncompressed embedded image", uncompressed_, without);
        report_.warnUnused("texture maps whose file lies outside the model's folder", outside_, without);
        out.textures = std::move(files_.textures());
        return out;
    }

private:
    Result<MaterialTextures> readMaterial(const aiMaterial& material, const std::string& where) {
        MaterialTextures t;
        std::set<aiTextureType> read = {aiTextureType_OPACITY};  // readOpacity's
        baseColorType_ = aiTextureType_NONE;
        for (const SlotTypes& s : kSlots) {
            const aiTextureType type =
                material.GetTextureCount(s.preferred) > 0 ? s.preferred : s.fallback;
            if (material.GetTextureCount(type) == 0) continue;
            read.insert(type);
            if (s.slot == TextureSlot::BaseColor) baseColorType_ = type;
            if (Status st = bind(material, type, slotEncoding(s.slot), t.slots[uint32_t(s.slot)]); !st.isOk())
                return st.withContext(fileName_ + ": " + where + textureSlotName(s.slot) + ": ");
        }
        aiString metal, rough;
        const bool hasMetal = material.GetTexture(aiTextureType_METALNESS, 0, &metal) == AI_SUCCESS;
        const bool hasRough = material.GetTexture(aiTextureType_DIFFUSE_ROUGHNESS, 0, &rough) == AI_SUCCESS;
        if (hasMetal && hasRough && std::strcmp(metal.C_Str(), rough.C_Str()) == 0) {
            read.insert(aiTextureType_METALNESS);
            read.insert(aiTextureType_DIFFUSE_ROUGHNESS);
            TextureBinding& b = t.slots[uint32_t(TextureSlot::MetallicRoughness)];
            if (Status st = bind(material, aiTextureType_METALNESS, slotEncoding(TextureSlot::MetallicRoughness), b);
                !st.isOk())
                return st.withContext(fileName_ + ": " + where + "metallicRoughnessTexture: ");
        } else if (hasMetal || hasRough) {
            read.insert(aiTextureType_METALNESS);
            read.insert(aiTextureType_DIFFUSE_ROUGHNESS);
            ++separatePbr_;
        }
        for (int type = aiTextureType_NONE + 1; type <= AI_TEXTURE_TYPE_MAX; ++type) {
            const unsigned count = material.GetTextureCount(aiTextureType(type));
            if (read.count(aiTextureType(type)))
                layered_ += count > 1 ? count - 1 : 0;
            else
                otherMaps_ += count;
        }
        return t;
    }

    // An opacity map (the first): a mask for bakeAlphaMasks, its channel the alpha when its image
    // has one, else the luminance. With a base colour map it must share its UV transform and wrap
    // modes (it is baked texel for texel); the same file name as the base colour map's is its own
    // image (its alpha then cuts as it is).
    Status readOpacity(const aiMaterial& material, uint32_t index, const MaterialTextures& t,
                       std::vector<AlphaMaskRequest>& masks) {
        if (material.GetTextureCount(aiTextureType_OPACITY) == 0) return Status::ok();
        TextureBinding mask;
        if (Status st = bind(material, aiTextureType_OPACITY, TextureEncoding::Linear, mask); !st.isOk()) return st;
        if (mask.texture == kNoTexture) return Status::ok();  // counted by bind
        const TextureBinding& base = t.slots[uint32_t(TextureSlot::BaseColor)];
        bool same = false;
        if (base.texture != kNoTexture) {
            const TextureSource &b = files_.textures()[base.texture], &m = files_.textures()[mask.texture];
            if (base.transform != mask.transform || b.wrapS != m.wrapS || b.wrapT != m.wrapT)
                return ++opacitySampling_, Status::ok();
            aiString basePath, maskPath;
            material.GetTexture(baseColorType_, 0, &basePath);
            material.GetTexture(aiTextureType_OPACITY, 0, &maskPath);
            same = std::strcmp(basePath.C_Str(), maskPath.C_Str()) == 0;
        }
        masks.push_back({index, mask.texture, MaskChannel::Auto, mask.transform, same});
        return Status::ok();
    }

    // glTF 2.0's alphaMode through assimp: MASK with a base colour map (or an opacity mask, which
    // makes one: `masked`) is a cut-out at alphaCutoff (default 0.5, clamped to [0, 1]); MASK without one and
    // BLEND are counted (rendered opaque).
    float gltfAlphaCutoff(const aiMaterial& material, const MaterialTextures& t, bool masked) {
        aiString mode;
        if (material.Get(AI_MATKEY_GLTF_ALPHAMODE, mode) != AI_SUCCESS) return 0.0f;
        if (std::strcmp(mode.C_Str(), "BLEND") == 0) return ++blend_, 0.0f;
        if (std::strcmp(mode.C_Str(), "MASK") != 0) return 0.0f;
        if (t.slots[uint32_t(TextureSlot::BaseColor)].texture == kNoTexture && !masked) return ++maskWithoutMap_, 0.0f;
        float cutoff = 0.5f;
        material.Get(AI_MATKEY_GLTF_ALPHACUTOFF, cutoff);
        return std::isfinite(cutoff) ? std::clamp(cutoff, 0.0f, 1.0f) : 0.5f;
    }

    // The binding of the first map of `type`: kNoTexture (counted) when it cannot be read here.
    Status bind(const aiMaterial& material, aiTextureType type, TextureEncoding encoding, TextureBinding& out) {
        aiString path;
        aiTextureMapping mapping = aiTextureMapping_UV;
        unsigned uvIndex = 0;
        aiTextureMapMode modes[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
        if (material.GetTexture(type, 0, &path, &mapping, &uvIndex, nullptr, nullptr, modes) != AI_SUCCESS)
            return Status::error("assimp names no texture");
        if (mapping != aiTextureMapping_UV) return ++projected_, Status::ok();
        if (uvIndex != 0) return ++otherUvSet_, Status::ok();
        aiUVTransform uv;
        if (material.Get(AI_MATKEY_UVTRANSFORM(type, 0), uv) == AI_SUCCESS) {
            for (float v : {float(uv.mTranslation.x), float(uv.mTranslation.y), float(uv.mScaling.x),
                            float(uv.mScaling.y), float(uv.mRotation)})
                if (!std::isfinite(v) || std::fabs(v) > kMaxUvTransformValue)
                    return Status::error("UV transform value " + std::to_string(v) + " is outside +-1e6");
            out.transform = assimpUvTransform(uv.mTranslation.x, uv.mTranslation.y, uv.mScaling.x, uv.mScaling.y,
                                              uv.mRotation);
        }
        const TextureWrap wrapS = wrapOf(modes[0]), wrapT = wrapOf(modes[1]);
        auto texture = textureOf(path.C_Str(), wrapS, wrapT, encoding);
        if (!texture) return texture.status();
        out.texture = *texture;
        return Status::ok();
    }

    // Decal (transparent outside [0, 1]) is the nearest clamp.
    static TextureWrap wrapOf(aiTextureMapMode mode) {
        if (mode == aiTextureMapMode_Clamp || mode == aiTextureMapMode_Decal) return TextureWrap::Clamp;
        return mode == aiTextureMapMode_Mirror ? TextureWrap::Mirror : TextureWrap::Repeat;
    }

    Result<uint32_t> textureOf(const std::string& path, TextureWrap wrapS, TextureWrap wrapT, TextureEncoding encoding) {
        if (const aiTexture* embedded = scene_.GetEmbeddedTexture(path.c_str())) {
            unsigned index = 0;
            while (index < scene_.mNumTextures && scene_.mTextures[index] != embedded) ++index;
            if (embedded->mHeight != 0 || !embedded->pcData) return ++uncompressed_, kNoTexture;
            const uint8_t* bytes = reinterpret_cast<const uint8_t*>(embedded->pcData);
            const std::string name = embedded->mFilename.length ? embedded->mFilename.C_Str() : path;
            return files_.addBytes("*" + std::to_string(index),
                                   "embedded image " + std::to_string(index) + " ('" + name + "') of " + fileName_,
                                   std::vector<uint8_t>(bytes, bytes + embedded->mWidth), wrapS, wrapT, encoding);
        }
        std::string why;
        std::string name = path;
        std::replace(name.begin(), name.end(), '\\', '/');
        if (!isSafeRelativeUri(name, why)) return ++outside_, kNoTexture;  // FBX often names absolute paths
        // Held here up to four times (the file's bytes, the texture's, the answer's, growth): the
        // child's memory limit (AssimpImporter.cpp) grows by that for each new texture.
        if (sampled_.insert({name, int(wrapS), int(wrapT), int(encoding)}).second) {
            std::error_code ec;
            const uint64_t size = std::filesystem::file_size(folder_ / name, ec);
            if (!ec) allowMoreChildMemory(4 * size);
        }
        return files_.addFile(name, wrapS, wrapT, encoding);
    }

    const aiScene& scene_;
    const std::string& fileName_;
    ImportReport& report_;
    std::filesystem::path folder_;
    std::set<std::tuple<std::string, int, int, int>> sampled_;  // texture files' samplings seen
    TextureFiles files_;
    uint64_t otherMaps_ = 0, separatePbr_ = 0, layered_ = 0, otherUvSet_ = 0, projected_ = 0, uncompressed_ = 0,
             outside_ = 0, opacitySampling_ = 0, maskWithoutMap_ = 0, blend_ = 0;
    aiTextureType baseColorType_ = aiTextureType_NONE;  // the current material's base colour map's kind
};

}  // namespace

UvTransform assimpUvTransform(float translationU, float translationV, float scaleU, float scaleV, float rotation) {
    // v-up: uv' = S R (uv + t - c) + c with c = (0.5, 0.5), R counter-clockwise.
    const float c = std::cos(rotation), s = std::sin(rotation);
    const float a00 = scaleU * c, a01 = -scaleU * s, a10 = scaleV * s, a11 = scaleV * c;
    const float du = translationU - 0.5f, dv = translationV - 0.5f;
    return vUpToVDown({a00, a01, a00 * du + a01 * dv + 0.5f, a10, a11, a10 * du + a11 * dv + 0.5f});
}

Result<AssimpTextures> assimpTextures(const aiScene& scene, const std::string& folder, const std::string& fileName,
                                      ImportReport& report) {
    return Reader(scene, folder, fileName, report).read();
}

}  // namespace vastray::import
