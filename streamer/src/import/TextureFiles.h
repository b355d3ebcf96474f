#pragma once
// The textures of an OBJ's or an assimp scene's materials (core/MaterialTextures.h), gathered
// one map at a time: an image file beside the model, read inside the model's folder only (the
// rules of mtllib names and glTF URIs: isSafeRelativeUri, insideFolder), or bytes the model
// embeds; PNG and JPEG by their signature. One TextureSource per image, wrap modes and encoding;
// nothing is decoded here (import decodes them when it stores them).
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "vastray/core/MaterialTextures.h"
#include "vastray/core/Result.h"
#include "vastray/streamer/Import.h"

namespace vastray::import {

// A UV transform `m` stated in a v-up texture space (OBJ's vt, MTL, assimp: v = 0 at the
// image's bottom) as the package needs it, in glTF's v-down space where UVs are stored as
// g = 1 - v: sampling at v' = m3 u + m4 v + m5 means g' = 1 - v' with v = 1 - g, so
// u' = m0 u - m1 g + (m1 + m2) and g' = -m3 u + m4 g + (1 - m4 - m5).
inline UvTransform vUpToVDown(const UvTransform& m) {
    return {m[0], -m[1], m[1] + m[2], -m[3], m[4], 1.0f - m[4] - m[5]};
}

class TextureFiles {
public:
    // `folder`: the model's folder; `modelName`: what texture names say they belong to.
    TextureFiles(std::filesystem::path folder, std::string modelName)
        : folder_(std::move(folder)), modelName_(std::move(modelName)) {}

    // The texture of the image file `relative` (to the model's folder; '\' is read as '/'), or
    // kNoTexture when the file is missing or neither PNG, JPEG nor a KTX2 of a format read
    // (counted, see warn); a broken KTX2 container is an error naming it. A name
    // that leaves the folder is an error naming it.
    Result<uint32_t> addFile(const std::string& relative, TextureWrap wrapS, TextureWrap wrapT,
                             TextureEncoding encoding);
    // The texture of embedded bytes, told apart by `key` ("*0" for assimp's first); `label`
    // names it in `info` and errors.
    Result<uint32_t> addBytes(const std::string& key, const std::string& label, std::vector<uint8_t> bytes,
                              TextureWrap wrapS, TextureWrap wrapT, TextureEncoding encoding);

    // One warning per kind of map left out.
    void warn(ImportReport& report) const;
    std::vector<TextureSource>& textures() { return textures_; }

private:
    std::filesystem::path folder_;
    std::string modelName_;
    std::vector<TextureSource> textures_;
    std::map<std::tuple<std::string, TextureWrap, TextureWrap, TextureEncoding>, uint32_t> textureOf_;
    std::map<std::string, std::vector<uint8_t>> fileBytes_;  // each file read once, whatever its sampling
    uint64_t missing_ = 0, unknown_ = 0;
};

}  // namespace vastray::import
