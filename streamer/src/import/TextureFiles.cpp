#include "import/TextureFiles.h"

#include <algorithm>

#include "import/GltfTextures.h"
#include "import/ImportCommon.h"
#include "vastray/core/ImageFile.h"

namespace vastray::import {

Result<uint32_t> TextureFiles::addFile(const std::string& relative, TextureWrap wrapS, TextureWrap wrapT,
                                       TextureEncoding encoding) {
    std::string name = relative;
    std::replace(name.begin(), name.end(), '\\', '/');  // Windows exporters' separators
    std::string why;
    if (!isSafeRelativeUri(name, why)) return Status::error("image '" + relative + "' " + why);
    const std::string key = std::filesystem::path(name).lexically_normal().generic_string();
    const std::filesystem::path file = folder_ / key;
    if (!insideFolder(folder_, file))
        return Status::error("image '" + relative + "' resolves outside the model's folder (a link)");
    auto cached = fileBytes_.find(key);
    if (cached == fileBytes_.end()) {
        std::vector<uint8_t> bytes;
        std::error_code ec;
        if (std::filesystem::is_regular_file(file, ec))
            if (auto read = readWholeFile(file.string())) bytes.assign(read->begin(), read->end());
        cached = fileBytes_.emplace(key, std::move(bytes)).first;
    }
    if (cached->second.empty()) {
        ++missing_;
        return kNoTexture;
    }
    return addBytes(key, "'" + key + "' of " + modelName_, cached->second, wrapS, wrapT, encoding);
}

Result<uint32_t> TextureFiles::addBytes(const std::string& key, const std::string& label, std::vector<uint8_t> bytes,
                                        TextureWrap wrapS, TextureWrap wrapT, TextureEncoding encoding) {
    const std::string extension = imageSignatureExtension(bytes);
    if (extension == ".ktx2") {  // read where its format is (core/ImageFile.h); a broken one fails
        auto ktx2 = describeKtx2Image(label, bytes);
        if (!ktx2) return ktx2.status();
        if (!ktx2->readable) {
            ++unknown_;
            return kNoTexture;
        }
    } else if (extension != ".png" && extension != ".jpg") {
        ++unknown_;
        return kNoTexture;
    }
    const auto [it, added] = textureOf_.try_emplace({key, wrapS, wrapT, encoding}, uint32_t(textures_.size()));
    if (!added) return it->second;
    if (textures_.size() >= kMaxSceneTextures) {
        textureOf_.erase(it);
        return Status::error("more than " + std::to_string(kMaxSceneTextures) +
                             " textures (image, wrap modes and encoding) in one scene");
    }
    TextureSource source;
    source.name = label;
    source.extension = extension;
    source.bytes = std::move(bytes);
    source.wrapS = wrapS;
    source.wrapT = wrapT;
    source.encoding = encoding;
    textures_.push_back(std::move(source));
    return it->second;
}

void TextureFiles::warn(ImportReport& report) const {
    report.warnUnused("texture maps whose image file is missing or unreadable", missing_,
                      "their maps are rendered without them");
    report.warnUnused("texture maps with an image neither PNG, JPEG nor a KTX2 of a format read here", unknown_,
                      "their maps are rendered without them");
}

}  // namespace vastray::import
